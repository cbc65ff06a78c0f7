//! Emissive rectangle `corner + s·ex + t·ey`: uniform solid-angle sampling of the spherical
//! rectangle (Ureña, Fajardo, King 2013) when it is not seen under a small angle and its solid
//! angle is moderate, uniform area sampling otherwise (and for parallelograms, which a sheared
//! motion could produce).
//! One-sided: emits on the side of ex × ey.
//!
//! The sampled point is computed relative to the shading point `p` (`corner − p` plus the
//! edges' fractions), as precisely 10⁵ from the origin as at it.

use super::{area_to_solid_angle, plane_distance, seen_small, use_spherical, LightSample};
use glam::{Vec2, Vec3};
use stratapt_sampling::warp::spherical_rectangle;
use stratapt_scene::shared::GAMMA_5;

/// What sampling a rectangle needs that does not depend on the shading point: its unit normal,
/// area, half diagonal and squared diagonal (its diameter), and (edges perpendicular) its
/// spherical basis. A static light's is computed once; the same bits as computing it per
/// sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prepared {
    n: Vec3,
    area: f32,
    /// `(ex + ey) / 2`, from the corner to the centre, and `|ex|² + |ey|²`.
    half_diagonal: Vec3,
    diagonal_sq: f32,
    spherical: Option<spherical_rectangle::Basis>,
}

impl Prepared {
    pub fn new(ex: Vec3, ey: Vec3) -> Self {
        let n = ex.cross(ey);
        let area = n.length();
        let orthogonal = ex.dot(ey).abs() <= 1e-4 * ex.length() * ey.length();
        Self {
            n: n.normalize_or_zero(),
            area,
            half_diagonal: 0.5 * (ex + ey),
            diagonal_sq: ex.dot(ex) + ey.dot(ey),
            spherical: orthogonal
                .then(|| spherical_rectangle::Basis::new(ex, ey))
                .flatten(),
        }
    }

    /// The unit normal (the emitting side), zero for a degenerate rectangle.
    pub fn normal(&self) -> Vec3 {
        self.n
    }
}

/// The spherical rectangle seen from `p` if the spherical method applies (not [`seen_small`],
/// a moderate solid angle), else `None` (area sampling). Set up once: it holds the solid angle
/// and draws the sample.
pub(super) fn spherical(
    prepared: &Prepared,
    p: Vec3,
    corner: Vec3,
) -> Option<spherical_rectangle::Setup> {
    if seen_small(prepared.diagonal_sq, (corner - p) + prepared.half_diagonal) {
        return None;
    }
    let rect = spherical_rectangle::Setup::from_basis(prepared.spherical.as_ref()?, p, corner)?;
    use_spherical(rect.solid_angle()).then_some(rect)
}

pub fn sample(
    prepared: &Prepared,
    corner: Vec3,
    ex: Vec3,
    ey: Vec3,
    le: Vec3,
    p: Vec3,
    u: Vec2,
) -> Option<LightSample> {
    let (n, area) = (prepared.n, prepared.area);
    if n.dot(p - corner) <= 0.0 || area <= 0.0 {
        return None;
    }
    // The point relative to p: the spherical method places it on the rectangle at `corner − p`.
    let pc = corner - p;
    let (v, pdf_spherical) = match spherical(prepared, p, corner) {
        Some(rect) => (rect.sample(pc, ex, ey, u), Some(1.0 / rect.solid_angle())),
        None => (pc + u.x * ex + u.y * ey, None),
    };
    let dist = v.length();
    let wi = v / dist;
    let pdf = pdf_spherical.unwrap_or_else(|| area_to_solid_angle(area, n, wi, dist, false));
    (pdf > 0.0 && dist > 0.0).then_some(LightSample {
        wi,
        dist,
        radiance: le,
        pdf,
        delta: false,
        n,
        err: GAMMA_5 * (pc.abs() + ex.abs() + ey.abs()),
    })
}

pub fn pdf(prepared: &Prepared, corner: Vec3, p: Vec3, wi: Vec3) -> f32 {
    let (n, area) = (prepared.n, prepared.area);
    if n.dot(p - corner) <= 0.0 || area <= 0.0 {
        return 0.0;
    }
    match spherical(prepared, p, corner) {
        Some(rect) => 1.0 / rect.solid_angle(),
        None => area_to_solid_angle(area, n, wi, plane_distance(corner, n, p, wi), false),
    }
}
