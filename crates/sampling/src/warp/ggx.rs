//! GGX / Trowbridge–Reitz microfacet distribution: evaluation and visible-normal sampling.
//! All vectors in the local shading frame (z = normal); `alpha` is the GGX roughness α.

use glam::{Vec2, Vec3};

/// Normal distribution D(h).
pub fn d(h: Vec3, alpha: f32) -> f32 {
    unimplemented!("{h} {alpha}")
}
/// Smith Λ(w).
pub fn lambda(w: Vec3, alpha: f32) -> f32 {
    unimplemented!("{w} {alpha}")
}
/// Smith masking G1(w) = 1 / (1 + Λ(w)).
pub fn g1(w: Vec3, alpha: f32) -> f32 {
    1.0 / (1.0 + lambda(w, alpha))
}
/// Height-correlated masking-shadowing G2(wo, wi) = 1 / (1 + Λ(wo) + Λ(wi)).
pub fn g2(wo: Vec3, wi: Vec3, alpha: f32) -> f32 {
    1.0 / (1.0 + lambda(wo, alpha) + lambda(wi, alpha))
}
/// Sample a visible normal h for the view direction `wo` (wo.z > 0): Heitz 2018,
/// "Sampling the GGX Distribution of Visible Normals" (JCGT 7(4)).
pub fn sample_vndf(wo: Vec3, alpha: f32, u: Vec2) -> Vec3 {
    unimplemented!("{wo} {alpha} {u}")
}
/// Density of [`sample_vndf`] over h: D_wo(h) = G1(wo) max(0, wo·h) D(h) / wo.z.
pub fn vndf_pdf(wo: Vec3, h: Vec3, alpha: f32) -> f32 {
    unimplemented!("{wo} {h} {alpha}")
}
