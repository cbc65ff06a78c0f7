//! Pixel-filter importance sampling: offsets from the pixel centre, in pixels, distributed
//! exactly as the (normalized) filter, so every sample carries weight 1.

use glam::Vec2;

/// Box of full width `width`: offset in `[-width/2, width/2)²`.
pub fn box_filter(u: Vec2, width: f32) -> Vec2 {
    (u - Vec2::splat(0.5)) * width
}
/// Separable tent of radius `radius`, by inverting its CDF per axis.
///
/// Per axis: `u < ½ → −r + r√(2u)`, else `r − r√(2(1 − u))`; the result lies in `[-r, r]²`.
pub fn tent(u: Vec2, radius: f32) -> Vec2 {
    Vec2::new(tent_1d(u.x, radius), tent_1d(u.y, radius))
}
/// Density of [`tent`] at offset `p` (per unit area): `t(p.x) t(p.y)`, `t(x) = max(0, r − |x|) / r²`.
pub fn tent_pdf(p: Vec2, radius: f32) -> f32 {
    let t = |x: f32| (radius - x.abs()).max(0.0) / (radius * radius);
    t(p.x) * t(p.y)
}
/// One axis of [`tent`]: the inverse of the tent's CDF.
fn tent_1d(u: f32, r: f32) -> f32 {
    if u < 0.5 {
        -r + r * (2.0 * u).max(0.0).sqrt()
    } else {
        r - r * (2.0 * (1.0 - u)).max(0.0).sqrt()
    }
}
/// Untruncated isotropic Gaussian with standard deviation `sigma` (Box–Muller; uses `1 − u.x`
/// so the logarithm never sees 0).
pub fn gaussian(u: Vec2, sigma: f32) -> Vec2 {
    // Radius from the Rayleigh inverse CDF, angle uniform.
    let r = sigma * (-2.0 * (1.0 - u.x).ln()).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * u.y;
    Vec2::new(r * phi.cos(), r * phi.sin())
}
/// Density of [`gaussian`] at offset `p` (per unit area): `exp(−|p|²/2σ²) / (2πσ²)`.
pub fn gaussian_pdf(p: Vec2, sigma: f32) -> f32 {
    let s2 = sigma * sigma;
    (-p.length_squared() / (2.0 * s2)).exp() / (std::f32::consts::TAU * s2)
}
