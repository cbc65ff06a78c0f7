//! Emissive rectangle `corner + s·ex + t·ey`: uniform solid-angle sampling of the spherical
//! rectangle (Ureña, Fajardo, King 2013) when its solid angle is moderate, uniform area
//! sampling otherwise (and for parallelograms, which a sheared motion could produce).
//! One-sided: emits on the side of ex × ey.

use super::{area_to_solid_angle, use_spherical, LightSample};
use glam::{Vec2, Vec3};
use stratapt_sampling::warp::spherical_rectangle;

/// The spherical rectangle if the spherical method applies (a moderate solid angle), else
/// `None` (area sampling). Set up once: it holds the solid angle and draws the sample.
fn spherical(p: Vec3, corner: Vec3, ex: Vec3, ey: Vec3) -> Option<spherical_rectangle::Setup> {
    let orthogonal = ex.dot(ey).abs() <= 1e-4 * ex.length() * ey.length();
    if !orthogonal {
        return None;
    }
    let rect = spherical_rectangle::Setup::new(p, corner, ex, ey)?;
    use_spherical(rect.solid_angle()).then_some(rect)
}

pub fn sample(corner: Vec3, ex: Vec3, ey: Vec3, le: Vec3, p: Vec3, u: Vec2) -> Option<LightSample> {
    let n = ex.cross(ey);
    let area = n.length();
    let n = n.normalize_or_zero();
    if n.dot(p - corner) <= 0.0 || area <= 0.0 {
        return None;
    }
    let (x, pdf_spherical) = match spherical(p, corner, ex, ey) {
        Some(rect) => (
            rect.sample(corner, ex, ey, u),
            Some(1.0 / rect.solid_angle()),
        ),
        None => (corner + u.x * ex + u.y * ey, None),
    };
    let v = x - p;
    let dist = v.length();
    let wi = v / dist;
    let pdf = pdf_spherical.unwrap_or_else(|| area_to_solid_angle(area, n, wi, dist, false));
    (pdf > 0.0 && dist > 0.0).then_some(LightSample {
        wi,
        dist,
        radiance: le,
        pdf,
        delta: false,
    })
}

pub fn pdf(corner: Vec3, ex: Vec3, ey: Vec3, p: Vec3, wi: Vec3, dist: f32) -> f32 {
    let n = ex.cross(ey);
    let area = n.length();
    let n = n.normalize_or_zero();
    if n.dot(p - corner) <= 0.0 || area <= 0.0 {
        return 0.0;
    }
    match spherical(p, corner, ex, ey) {
        Some(rect) => 1.0 / rect.solid_angle(),
        None => area_to_solid_angle(area, n, wi, dist, false),
    }
}
