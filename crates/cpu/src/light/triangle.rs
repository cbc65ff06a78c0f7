//! Emissive triangle: uniform solid-angle sampling of the spherical triangle (Arvo 1995) when
//! it is not seen under a small angle and its solid angle is moderate, uniform area sampling
//! otherwise. One-sided: emits on the side of (b − a) × (c − a).
//!
//! The sampled point is computed relative to the shading point `p` (`a − p`, exact or nearly so
//! when the two are close, plus the edges' parts), as precisely 10⁵ from the origin as at it.

use super::{area_to_solid_angle, plane_distance, seen_small, use_spherical, LightSample};
use glam::{Vec2, Vec3};
use stratapt_sampling::warp::{self, spherical_triangle};
use stratapt_scene::shared::{GAMMA_16, GAMMA_6};

/// The solid angle of triangle `abc` seen from `p` if the spherical method applies (not
/// [`seen_small`], a moderate solid angle), else `None` (area sampling).
pub(super) fn spherical(a: Vec3, b: Vec3, c: Vec3, p: Vec3) -> Option<f32> {
    let (ab, ac, bc) = (b - a, c - a, c - b);
    let diameter_sq = ab.dot(ab).max(ac.dot(ac)).max(bc.dot(bc));
    if seen_small(diameter_sq, (a - p) + (ab + ac) / 3.0) {
        return None;
    }
    let solid_angle = spherical_triangle::solid_angle(p, a, b, c);
    use_spherical(solid_angle).then_some(solid_angle)
}

pub fn sample(a: Vec3, b: Vec3, c: Vec3, le: Vec3, p: Vec3, u: Vec2) -> Option<LightSample> {
    let n = (b - a).cross(c - a);
    let area = 0.5 * n.length();
    let n = n.normalize_or_zero();
    // Only the front side emits; a point on the plane sees nothing.
    if n.dot(p - a) <= 0.0 || area <= 0.0 {
        return None;
    }
    if let Some(solid_angle) = spherical(a, b, c, p) {
        let (wi, _) = spherical_triangle::sample(p, a, b, c, u)?;
        let dist = plane_distance(a, n, p, wi);
        if !(dist > 0.0 && dist.is_finite()) {
            return None;
        }
        // The point's distance from the plane: the rounding of the plane distance and of the
        // normal, relative to the distances involved.
        let err = Vec3::splat(GAMMA_16 * ((a - p).length() + dist));
        return Some(LightSample {
            wi,
            dist,
            radiance: le,
            pdf: 1.0 / solid_angle,
            delta: false,
            n,
            err,
        });
    }
    let bary = warp::uniform_triangle(u);
    // One difference of far-apart coordinates at most (`a − p`), the edges' parts small: exact
    // when p is near the light, one rounding of the distance when it is far.
    let (pa, ab, ac) = (a - p, b - a, c - a);
    let v = pa + ab * bary.y + ac * bary.z;
    let dist = v.length();
    let wi = v / dist;
    let pdf = area_to_solid_angle(area, n, wi, dist, false);
    (pdf > 0.0).then_some(LightSample {
        wi,
        dist,
        radiance: le,
        pdf,
        delta: false,
        n,
        // As pbrt-v4 bounds a point from barycentrics: γ₆ of its terms.
        err: GAMMA_6 * (pa.abs() + ab.abs() + ac.abs()),
    })
}

pub fn pdf(a: Vec3, b: Vec3, c: Vec3, p: Vec3, wi: Vec3) -> f32 {
    let n = (b - a).cross(c - a);
    let area = 0.5 * n.length();
    let n = n.normalize_or_zero();
    if n.dot(p - a) <= 0.0 || area <= 0.0 {
        return 0.0;
    }
    if let Some(solid_angle) = spherical(a, b, c, p) {
        return 1.0 / solid_angle;
    }
    area_to_solid_angle(area, n, wi, plane_distance(a, n, p, wi), false)
}
