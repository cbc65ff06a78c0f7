//! Warps: maps from `[0,1)^k` to points and directions, each with the density it produces.
//!
//! Convention: local directions have `z` up (the normal); every `*_pdf` is with respect to the
//! measure named in its doc (solid angle unless stated). Every warp has a chi-square test and a
//! pdf-integrates-to-one test.

pub mod filter;
pub mod ggx;
pub mod line;
pub mod spherical_rectangle;
pub mod spherical_triangle;

use glam::{Vec2, Vec3};

/// Uniform direction on the upper hemisphere (z ≥ 0).
pub fn uniform_hemisphere(u: Vec2) -> Vec3 {
    unimplemented!("{u}")
}
/// Solid-angle pdf of [`uniform_hemisphere`]: 1 / 2π.
pub fn uniform_hemisphere_pdf() -> f32 {
    std::f32::consts::FRAC_1_PI * 0.5
}

/// Cosine-weighted direction on the upper hemisphere (Malley's method over [`concentric_disk`]).
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    unimplemented!("{u}")
}
/// Solid-angle pdf of [`cosine_hemisphere`]: max(cos θ, 0) / π.
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * std::f32::consts::FRAC_1_PI
}

/// Uniform direction on the unit sphere.
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    unimplemented!("{u}")
}
/// Solid-angle pdf of [`uniform_sphere`]: 1 / 4π.
pub fn uniform_sphere_pdf() -> f32 {
    std::f32::consts::FRAC_1_PI * 0.25
}

/// Uniform point on the unit disk, Shirley–Chiu concentric map.
pub fn concentric_disk(u: Vec2) -> Vec2 {
    unimplemented!("{u}")
}

/// Uniform direction in the cone around +z with `cos θ ≥ cos_max`.
pub fn uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    unimplemented!("{u} {cos_max}")
}
/// Solid-angle pdf of [`uniform_cone`]: 1 / (2π (1 − cos_max)).
pub fn uniform_cone_pdf(cos_max: f32) -> f32 {
    unimplemented!("{cos_max}")
}

/// Uniform barycentrics `(b0, b1, b2)` on a triangle (area measure: pdf = 1 / area).
pub fn uniform_triangle(u: Vec2) -> Vec3 {
    unimplemented!("{u}")
}
