//! Warps: maps from `[0,1)^k` to points and directions, each with the density it produces.
//!
//! Convention: local directions have `z` up (the normal); every `*_pdf` is with respect to the
//! measure named in its doc (solid angle unless stated). Every warp has a chi-square test and a
//! pdf-integrates-to-one test.

pub mod equal_area;
pub mod filter;
pub mod ggx;
pub mod line;
pub mod piecewise;
pub mod spherical_rectangle;
pub mod spherical_triangle;

use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, TAU};

use glam::{Vec2, Vec3};

/// Uniform direction on the upper hemisphere (z ≥ 0).
pub fn uniform_hemisphere(u: Vec2) -> Vec3 {
    // cos θ uniform in [0, 1): equal solid angle per slice (Archimedes).
    let z = u.x;
    let r = ((1.0 - z) * (1.0 + z)).max(0.0).sqrt();
    let phi = TAU * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}
/// Solid-angle pdf of [`uniform_hemisphere`]: 1 / 2π.
pub fn uniform_hemisphere_pdf() -> f32 {
    std::f32::consts::FRAC_1_PI * 0.5
}

/// Cosine-weighted direction on the upper hemisphere (Malley's method over [`concentric_disk`]).
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    // Uniform on the disk, lifted onto the hemisphere (Malley).
    let d = concentric_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}
/// Solid-angle pdf of [`cosine_hemisphere`]: max(cos θ, 0) / π.
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * std::f32::consts::FRAC_1_PI
}

/// Uniform direction on the unit sphere.
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    // z uniform in (-1, 1]; sin θ from 1 − z² = 4 u (1 − u), exact near the poles.
    let z = 1.0 - 2.0 * u.x;
    let r = 2.0 * (u.x * (1.0 - u.x)).max(0.0).sqrt();
    let phi = TAU * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}
/// Solid-angle pdf of [`uniform_sphere`]: 1 / 4π.
pub fn uniform_sphere_pdf() -> f32 {
    std::f32::consts::FRAC_1_PI * 0.25
}

/// Uniform point on the unit disk, Shirley–Chiu concentric map.
pub fn concentric_disk(u: Vec2) -> Vec2 {
    // Map to [-1, 1]² and send concentric squares to concentric circles.
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, FRAC_PI_4 * (o.y / o.x))
    } else {
        (o.y, FRAC_PI_2 - FRAC_PI_4 * (o.x / o.y))
    };
    r * Vec2::new(theta.cos(), theta.sin())
}
/// Area pdf of [`concentric_disk`] on the unit disk: 1 / π.
pub fn concentric_disk_pdf() -> f32 {
    std::f32::consts::FRAC_1_PI
}

/// Uniform direction in the cone around +z with `cos θ ≥ cos_max`.
///
/// `1 − cos θ = u.x (1 − cos_max)` is formed directly, so narrow cones (`cos_max` near 1) keep
/// their precision; `cos_max` is clamped to `[-1, 1]`.
pub fn uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    let one_minus_cos = u.x * (1.0 - cos_max.clamp(-1.0, 1.0));
    let z = 1.0 - one_minus_cos;
    let r = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
    let phi = TAU * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}
/// Solid-angle pdf of [`uniform_cone`]: 1 / (2π (1 − cos_max)).
/// Infinite for a degenerate cone (`cos_max ≥ 1`, a delta direction).
pub fn uniform_cone_pdf(cos_max: f32) -> f32 {
    1.0 / (TAU * (1.0 - cos_max.clamp(-1.0, 1.0)))
}

/// Uniform barycentrics `(b0, b1, b2)` on a triangle (area measure: pdf = 1 / area).
///
/// Heitz 2019, "A Low-Distortion Map Between Triangle and Square": keeps the strata of `u`
/// compact, unlike the square-root map.
pub fn uniform_triangle(u: Vec2) -> Vec3 {
    let (b0, b1) = if u.x < u.y {
        let b0 = 0.5 * u.x;
        (b0, u.y - b0)
    } else {
        let b1 = 0.5 * u.y;
        (u.x - b1, b1)
    };
    Vec3::new(b0, b1, 1.0 - b0 - b1)
}
