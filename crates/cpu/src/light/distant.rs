//! Distant (sun-like) light: a uniform cone of directions around `dir` with `cos θ ≥ cos_max`,
//! or a single direction when `cos_max ≥ 1` (delta: `radiance` is then the irradiance).

use super::LightSample;
use glam::{Vec2, Vec3};
use stratapt_sampling::{warp, Frame};

pub fn sample(dir: Vec3, cos_max: f32, le: Vec3, u: Vec2) -> Option<LightSample> {
    let dist = f32::INFINITY;
    if cos_max >= 1.0 {
        return Some(LightSample::unoffset(dir, dist, le, 1.0, true));
    }
    let wi = Frame::from_normal(dir).to_world(warp::uniform_cone(u, cos_max));
    let pdf = warp::uniform_cone_pdf(cos_max);
    Some(LightSample::unoffset(wi, dist, le, pdf, false))
}

pub fn pdf(dir: Vec3, cos_max: f32, wi: Vec3) -> f32 {
    if cos_max < 1.0 && wi.dot(dir) >= cos_max {
        warp::uniform_cone_pdf(cos_max)
    } else {
        0.0
    }
}

/// Radiance seen by an escaping ray: `le` inside the cone (never for a delta direction).
pub fn radiance(dir: Vec3, cos_max: f32, le: Vec3, wi: Vec3) -> Vec3 {
    if cos_max < 1.0 && wi.dot(dir) >= cos_max {
        le
    } else {
        Vec3::ZERO
    }
}
