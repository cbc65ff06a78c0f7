//! Uniform solid-angle sampling of a spherical triangle: Arvo 1995, "Stratified Sampling of
//! Spherical Triangles" (SIGGRAPH '95).

use glam::{Vec2, Vec3};

/// Solid angle subtended by triangle `(a, b, c)` from point `p` (Van Oosterom & Strackee 1983).
pub fn solid_angle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f32 {
    unimplemented!("{p} {a} {b} {c}")
}
/// A unit direction from `p` uniformly distributed over the solid angle of `(a, b, c)`, with its
/// solid-angle pdf `1 / Ω`; `None` when the triangle is degenerate as seen from `p`.
pub fn sample(p: Vec3, a: Vec3, b: Vec3, c: Vec3, u: Vec2) -> Option<(Vec3, f32)> {
    unimplemented!("{p} {a} {b} {c} {u}")
}
