//! Line light: a thin diffuse tube from `a` to `b` whose element `dl` emits `I · sin θ · dl` at
//! angle θ to the line. No direction can hit it: it is sampled by a uniform point along its
//! length (length pdf 1 / len), and the unit-pdf radiance is `I sin θ · len / dist²`.

use super::LightSample;
use glam::{Vec2, Vec3};
use stratapt_sampling::warp;

pub fn sample(a: Vec3, b: Vec3, intensity: Vec3, p: Vec3, u: Vec2) -> Option<LightSample> {
    // The point relative to `p` (its endpoints' differences from `p` are exact or nearly so far
    // from the origin, where the point itself would round to the coordinates' grid).
    let v = warp::line::segment(a - p, b - p, u.x);
    let dist2 = v.length_squared();
    if dist2 <= 0.0 {
        return None;
    }
    let dist = dist2.sqrt();
    let wi = v / dist;
    let axis = b - a;
    // len · sin θ = |wi × (b − a)|.
    let len_sin = wi.cross(axis).length();
    let radiance = intensity * (len_sin / dist2);
    Some(LightSample::unoffset(wi, dist, radiance, 1.0, true))
}
