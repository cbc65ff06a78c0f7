//! Sky: radiance `lerp(bottom, top, ½(1 + ω·up))` over the whole sphere of directions, sampled
//! uniformly.

use super::LightSample;
use glam::{Vec2, Vec3};
use stratapt_sampling::warp;

pub fn sample(up: Vec3, top: Vec3, bottom: Vec3, u: Vec2) -> Option<LightSample> {
    let wi = warp::uniform_sphere(u);
    let radiance = radiance(up, top, bottom, wi);
    Some(LightSample::unoffset(
        wi,
        f32::INFINITY,
        radiance,
        pdf(),
        false,
    ))
}

pub fn pdf() -> f32 {
    warp::uniform_sphere_pdf()
}

pub fn radiance(up: Vec3, top: Vec3, bottom: Vec3, wi: Vec3) -> Vec3 {
    bottom.lerp(top, 0.5 * (1.0 + wi.dot(up)))
}
