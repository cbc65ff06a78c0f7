//! Pixel-filter importance sampling: offsets from the pixel centre, in pixels, distributed
//! exactly as the (normalized) filter, so every sample carries weight 1.

use glam::Vec2;

/// Box of full width `width`: offset in `[-width/2, width/2)²`.
pub fn box_filter(u: Vec2, width: f32) -> Vec2 {
    (u - Vec2::splat(0.5)) * width
}
/// Separable tent of radius `radius`, by inverting its CDF per axis.
pub fn tent(u: Vec2, radius: f32) -> Vec2 {
    unimplemented!("{u} {radius}")
}
/// Untruncated isotropic Gaussian with standard deviation `sigma` (Box–Muller; uses `1 − u.x`
/// so the logarithm never sees 0).
pub fn gaussian(u: Vec2, sigma: f32) -> Vec2 {
    unimplemented!("{u} {sigma}")
}
