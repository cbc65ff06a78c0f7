//! Spot light (pbrt-v4's `SpotLight`): a point light whose intensity falls off with the angle
//! θ from its axis as `smoothstep(cos_end, cos_start, cos θ)`: full inside the inner cone, zero
//! outside the outer one, a smooth cubic between (a delta light, as a point light).

use super::LightSample;
use glam::Vec3;

/// pbrt-v4's `SmoothStep`: 0 below `a`, 1 above `b`, `t²(3 − 2t)` between; a step at `a` when
/// `a = b`.
pub fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    if a == b {
        return if x < a { 0.0 } else { 1.0 };
    }
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The spot at `position` shining along unit `axis` with cone cosines `cos_end` (edge) and
/// `cos_start` (full intensity), seen from `p`.
pub fn sample(
    position: Vec3,
    axis: Vec3,
    cos_end: f32,
    cos_start: f32,
    intensity: Vec3,
    p: Vec3,
) -> Option<LightSample> {
    let v = position - p;
    let dist2 = v.length_squared();
    if dist2 <= 0.0 {
        return None;
    }
    let dist = dist2.sqrt();
    let wi = v / dist;
    let falloff = smoothstep(cos_end, cos_start, -wi.dot(axis));
    if falloff <= 0.0 {
        return None;
    }
    Some(LightSample::unoffset(
        wi,
        dist,
        intensity * (falloff / dist2),
        1.0,
        true,
    ))
}
