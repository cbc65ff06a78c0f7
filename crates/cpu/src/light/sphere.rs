//! Emissive sphere: from outside, uniform sampling of the cone of directions it subtends, with
//! the sampled point placed exactly on the sphere and a small-angle series for the cone's size
//! (pbrt-v4 `Sphere::Sample`, after Shirley & Wang); from inside or on it, uniform area
//! sampling (points of the far side from just outside are occluded by the sphere itself).
//! Spheres emit from both sides of their surface.

use super::{area_to_solid_angle, LightSample};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;
use stratapt_sampling::{warp, Frame};

use stratapt_scene::shared::{SPHERE_INSIDE as INSIDE, SPHERE_SMALL_SIN2 as SMALL_SIN2};

/// Whether `p`, at squared distance `d2` from the centre, samples by area (inside or on it).
fn inside(d2: f32, radius: f32) -> bool {
    d2 <= radius * radius * INSIDE
}

/// `1 − cos θmax` of the subtended cone, accurate for small cones.
fn one_minus_cos_max(sin2_max: f32) -> f32 {
    if sin2_max < SMALL_SIN2 {
        0.5 * sin2_max
    } else {
        1.0 - (1.0 - sin2_max).max(0.0).sqrt()
    }
}

pub fn sample(center: Vec3, radius: f32, le: Vec3, p: Vec3, u: Vec2) -> Option<LightSample> {
    let d2 = (center - p).length_squared();
    if inside(d2, radius) {
        return sample_area(center, radius, le, p, u);
    }
    // Direction in the cone: cos θ uniform in [cos θmax, 1].
    let sin2_max = radius * radius / d2;
    let sin_max = sin2_max.sqrt();
    let one_minus_cos_max = one_minus_cos_max(sin2_max);
    let (sin2, cos) = if sin2_max < SMALL_SIN2 {
        let sin2 = sin2_max * u.x;
        (sin2, (1.0 - sin2).sqrt())
    } else {
        let cos = 1.0 - one_minus_cos_max * u.x;
        (1.0 - cos * cos, cos)
    };
    // Angle α at the centre between the axis and the sampled point.
    let cos_alpha = sin2 / sin_max + cos * (1.0 - sin2 / sin2_max).max(0.0).sqrt();
    let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    let frame = Frame::from_normal((center - p) / d2.sqrt());
    let n = -frame.to_world(Vec3::new(
        sin_alpha * phi.cos(),
        sin_alpha * phi.sin(),
        cos_alpha,
    ));
    let x = center + radius * n;
    let v = x - p;
    let dist = v.length();
    let pdf = 1.0 / (2.0 * PI * one_minus_cos_max);
    Some(LightSample {
        wi: v / dist,
        dist,
        radiance: le,
        pdf,
        delta: false,
    })
}

pub fn pdf(center: Vec3, radius: f32, p: Vec3, wi: Vec3, dist: f32) -> f32 {
    let d2 = (center - p).length_squared();
    if inside(d2, radius) {
        let n = (p + wi * dist - center) / radius;
        return area_to_solid_angle(4.0 * PI * radius * radius, n, wi, dist, true);
    }
    // A cone of no solid angle (a point-sized sphere) cannot be hit: pdf 0, not 1/0.
    let omc = one_minus_cos_max(radius * radius / d2);
    if omc > 0.0 {
        1.0 / (2.0 * PI * omc)
    } else {
        0.0
    }
}

/// From inside: a uniform point on the sphere.
fn sample_area(center: Vec3, radius: f32, le: Vec3, p: Vec3, u: Vec2) -> Option<LightSample> {
    let n = warp::uniform_sphere(u);
    let v = center + radius * n - p;
    let dist = v.length();
    let wi = v / dist;
    let pdf = area_to_solid_angle(4.0 * PI * radius * radius, n, wi, dist, true);
    (pdf > 0.0 && pdf.is_finite()).then_some(LightSample {
        wi,
        dist,
        radiance: le,
        pdf,
        delta: false,
    })
}
