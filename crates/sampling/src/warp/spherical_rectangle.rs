//! Uniform solid-angle sampling of a rectangle: Ureña, Fajardo, King 2013, "An Area-Preserving
//! Parametrization for Spherical Rectangles" (EGSR).

use glam::{Vec2, Vec3};

/// Solid angle subtended by the rectangle `corner + s·ex + t·ey`, `s, t ∈ [0,1]`, from `p`.
pub fn solid_angle(p: Vec3, corner: Vec3, ex: Vec3, ey: Vec3) -> f32 {
    unimplemented!("{p} {corner} {ex} {ey}")
}
/// A point on the rectangle whose direction from `p` is uniform over its solid angle, with the
/// solid-angle pdf `1 / Ω`; `None` when `p` lies in the rectangle's plane or Ω is degenerate.
pub fn sample(p: Vec3, corner: Vec3, ex: Vec3, ey: Vec3, u: Vec2) -> Option<(Vec3, f32)> {
    unimplemented!("{p} {corner} {ex} {ey} {u}")
}
