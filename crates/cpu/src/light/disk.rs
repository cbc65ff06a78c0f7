//! Emissive disk: uniform area sampling (concentric map), converted to solid angle.
//! One-sided: emits on the side of its normal.

use super::{area_to_solid_angle, LightSample};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;
use stratapt_sampling::{warp, Frame};

pub fn sample(
    center: Vec3,
    normal: Vec3,
    radius: f32,
    le: Vec3,
    p: Vec3,
    u: Vec2,
) -> Option<LightSample> {
    if normal.dot(p - center) <= 0.0 {
        return None;
    }
    let frame = Frame::from_normal(normal);
    let d = warp::concentric_disk(u) * radius;
    let x = center + frame.s * d.x + frame.t * d.y;
    let v = x - p;
    let dist = v.length();
    let wi = v / dist;
    let pdf = area_to_solid_angle(PI * radius * radius, normal, wi, dist, false);
    (pdf > 0.0).then_some(LightSample {
        wi,
        dist,
        radiance: le,
        pdf,
        delta: false,
    })
}

pub fn pdf(center: Vec3, normal: Vec3, radius: f32, p: Vec3, wi: Vec3, dist: f32) -> f32 {
    if normal.dot(p - center) <= 0.0 {
        return 0.0;
    }
    area_to_solid_angle(PI * radius * radius, normal, wi, dist, false)
}
