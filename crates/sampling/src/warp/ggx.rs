//! GGX / Trowbridge–Reitz microfacet distribution: evaluation and visible-normal sampling.
//! All vectors in the local shading frame (z = normal); `alpha` is the anisotropic GGX
//! roughness (αx, αy) along the frame's x and y axes (equal for an isotropic surface).
//!
//! Preconditions: unit vectors, both alphas `> 0` (an exactly smooth surface is a delta lobe
//! and belongs to the caller's specular path), `wo.z > 0` where stated.

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};

/// Normal distribution D(h).
///
/// Written as `1 / (π αx αy q²)`, `q = (h.x/αx)² + (h.y/αy)² + h.z²`, which stays finite and
/// exact for tiny α (the textbook `α² / (π (cos²θ (α² − 1) + 1)²)` cancels and underflows there).
pub fn d(h: Vec3, alpha: Vec2) -> f32 {
    if h.z <= 0.0 {
        return 0.0;
    }
    let (sx, sy) = (h.x / alpha.x, h.y / alpha.y);
    let q = sx * sx + sy * sy + h.z * h.z;
    1.0 / (PI * alpha.x * alpha.y * q * q)
}
/// Smith Λ(w).
///
/// `Λ = (√(1 + a) − 1) / 2 = a / (2 (1 + √(1 + a)))`, `a = ((αx w.x)² + (αy w.y)²) / w.z²`
/// (α² tan²θ with the α of `w`'s azimuth): no cancellation for small `a`, +∞ at grazing `w` (so
/// G1 = 0 there).
pub fn lambda(w: Vec3, alpha: Vec2) -> f32 {
    if w.x == 0.0 && w.y == 0.0 {
        return 0.0;
    }
    let (sx, sy) = (alpha.x * w.x, alpha.y * w.y);
    let a = (sx * sx + sy * sy) / (w.z * w.z);
    if !a.is_finite() {
        return f32::INFINITY;
    }
    a / (2.0 * (1.0 + (1.0 + a).sqrt()))
}
/// Smith masking G1(w) = 1 / (1 + Λ(w)).
pub fn g1(w: Vec3, alpha: Vec2) -> f32 {
    1.0 / (1.0 + lambda(w, alpha))
}
/// Which Smith masking-shadowing function a GGX surface uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Masking {
    /// Height-correlated `1 / (1 + Λ(wo) + Λ(wi))` (Heitz 2014, pbrt-v4): exact for the Smith
    /// microsurface.
    #[default]
    Correlated,
    /// Separable `G1(wo) G1(wi)` (Walter et al. 2007, Mitsuba 3): ignores that a point hidden
    /// from one direction tends to be hidden from the other, so it shadows more (never less).
    Separable,
}

/// Masking-shadowing G2(wo, wi) of the form `masking`. `wi` may lie below the surface
/// (transmission): Λ depends on the direction's slope only.
pub fn g2(wo: Vec3, wi: Vec3, alpha: Vec2, masking: Masking) -> f32 {
    match masking {
        Masking::Correlated => 1.0 / (1.0 + lambda(wo, alpha) + lambda(wi, alpha)),
        Masking::Separable => g1(wo, alpha) * g1(wi, alpha),
    }
}
/// Sample a visible normal h for the view direction `wo` (wo.z > 0): Heitz 2018,
/// "Sampling the GGX Distribution of Visible Normals" (JCGT 7(4)).
pub fn sample_vndf(wo: Vec3, alpha: Vec2, u: Vec2) -> Vec3 {
    // Stretch the view direction to the hemisphere configuration (α = 1).
    let vh = Vec3::new(alpha.x * wo.x, alpha.y * wo.y, wo.z).normalize_or(Vec3::Z);
    // Orthonormal basis around it (T1 horizontal).
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let t1 = if len2 > 0.0 {
        Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt()
    } else {
        Vec3::X
    };
    let t2 = vh.cross(t1);
    // Uniform point on the disk, warped onto the projected visible half-disk.
    let r = u.x.sqrt();
    let (sin_phi, cos_phi) = (TAU * u.y).sin_cos();
    let p1 = r * cos_phi;
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * sin_phi;
    // Lift onto the hemisphere, then unstretch back to the ellipsoid.
    let pz = (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    let nh = p1 * t1 + p2 * t2 + pz * vh;
    Vec3::new(alpha.x * nh.x, alpha.y * nh.y, nh.z.max(0.0)).normalize_or(Vec3::Z)
}
/// Density of [`sample_vndf`] over h: D_wo(h) = G1(wo) max(0, wo·h) D(h) / wo.z.
pub fn vndf_pdf(wo: Vec3, h: Vec3, alpha: Vec2) -> f32 {
    if wo.z <= 0.0 {
        return 0.0;
    }
    g1(wo, alpha) * wo.dot(h).max(0.0) * d(h, alpha) / wo.z
}
/// Mirror `wo` about the microfacet normal `h`: `2 (wo·h) h − wo`.
pub fn reflect(wo: Vec3, h: Vec3) -> Vec3 {
    2.0 * wo.dot(h) * h - wo
}
/// Solid-angle density of `wi = reflect(wo, h)` with `h` from [`sample_vndf`]: the Jacobian
/// `1 / (4 |wo·h|)` of the reflection applied to [`vndf_pdf`], `h = normalize(wo + wi)`;
/// simplified to `G1(wo) D(h) / (4 wo.z)` (0 where `wo·h ≤ 0`). `wi` may lie below the horizon.
pub fn reflection_pdf(wo: Vec3, wi: Vec3, alpha: Vec2) -> f32 {
    let h = (wo + wi).normalize_or_zero();
    if wo.z <= 0.0 || wo.dot(h) <= 0.0 {
        return 0.0;
    }
    g1(wo, alpha) * d(h, alpha) / (4.0 * wo.z)
}
