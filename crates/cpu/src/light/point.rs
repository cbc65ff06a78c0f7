//! Point light: intensity / dist² from its one position (a delta light).

use super::LightSample;
use glam::Vec3;

pub fn sample(position: Vec3, intensity: Vec3, p: Vec3) -> Option<LightSample> {
    let v = position - p;
    let dist2 = v.length_squared();
    if dist2 <= 0.0 {
        return None;
    }
    let dist = dist2.sqrt();
    Some(LightSample::unoffset(
        v / dist,
        dist,
        intensity / dist2,
        1.0,
        true,
    ))
}
