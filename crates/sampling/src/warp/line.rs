//! Uniform sampling along a segment.

use glam::Vec3;

/// Point at fraction `u` along the segment from `a` to `b` (length-measure pdf 1 / |b − a|).
pub fn segment(a: Vec3, b: Vec3, u: f32) -> Vec3 {
    a + (b - a) * u
}
