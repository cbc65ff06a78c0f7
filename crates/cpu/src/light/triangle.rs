//! Emissive triangle: uniform solid-angle sampling of the spherical triangle (Arvo 1995) when
//! its solid angle is moderate, uniform area sampling otherwise. One-sided: emits on the side
//! of (b − a) × (c − a).

use super::{area_to_solid_angle, use_spherical, LightSample};
use glam::{Vec2, Vec3};
use stratapt_sampling::warp::{self, spherical_triangle};

pub fn sample(a: Vec3, b: Vec3, c: Vec3, le: Vec3, p: Vec3, u: Vec2) -> Option<LightSample> {
    let n = (b - a).cross(c - a);
    let area = 0.5 * n.length();
    let n = n.normalize_or_zero();
    // Only the front side emits; a point on the plane sees nothing.
    if n.dot(p - a) <= 0.0 || area <= 0.0 {
        return None;
    }
    let solid_angle = spherical_triangle::solid_angle(p, a, b, c);
    if use_spherical(solid_angle) {
        let (wi, _) = spherical_triangle::sample(p, a, b, c, u)?;
        // Distance to the triangle's plane along wi.
        let dist = (a - p).dot(n) / wi.dot(n);
        if !(dist > 0.0 && dist.is_finite()) {
            return None;
        }
        return Some(LightSample {
            wi,
            dist,
            radiance: le,
            pdf: 1.0 / solid_angle,
            delta: false,
        });
    }
    let bary = warp::uniform_triangle(u);
    let x = a * bary.x + b * bary.y + c * bary.z;
    let v = x - p;
    let dist = v.length();
    let wi = v / dist;
    let pdf = area_to_solid_angle(area, n, wi, dist, false);
    (pdf > 0.0).then_some(LightSample {
        wi,
        dist,
        radiance: le,
        pdf,
        delta: false,
    })
}

pub fn pdf(a: Vec3, b: Vec3, c: Vec3, p: Vec3, wi: Vec3, dist: f32) -> f32 {
    let n = (b - a).cross(c - a);
    let area = 0.5 * n.length();
    let n = n.normalize_or_zero();
    if n.dot(p - a) <= 0.0 || area <= 0.0 {
        return 0.0;
    }
    let solid_angle = spherical_triangle::solid_angle(p, a, b, c);
    if use_spherical(solid_angle) {
        return 1.0 / solid_angle;
    }
    area_to_solid_angle(area, n, wi, dist, false)
}
