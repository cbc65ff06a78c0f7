//! Emissive disk: uniform area sampling (concentric map), converted to solid angle.
//! One-sided: emits on the side of its normal.

use super::{area_to_solid_angle, plane_distance, LightSample};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;
use stratapt_sampling::{warp, Frame};
use stratapt_scene::shared::GAMMA_5;

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
    // Relative to p, as precise far from the origin as at it.
    let pc = center - p;
    let v = pc + frame.s * d.x + frame.t * d.y;
    let dist = v.length();
    let wi = v / dist;
    let pdf = area_to_solid_angle(PI * radius * radius, normal, wi, dist, false);
    (pdf > 0.0).then_some(LightSample {
        wi,
        dist,
        radiance: le,
        pdf,
        delta: false,
        n: normal,
        err: GAMMA_5 * (pc.abs() + Vec3::splat(radius)),
    })
}

pub fn pdf(center: Vec3, normal: Vec3, radius: f32, p: Vec3, wi: Vec3) -> f32 {
    if normal.dot(p - center) <= 0.0 {
        return 0.0;
    }
    let dist = plane_distance(center, normal, p, wi);
    area_to_solid_angle(PI * radius * radius, normal, wi, dist, false)
}
