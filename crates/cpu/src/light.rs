//! Lights: placement at the ray's time, sampling from a shading point, and the solid-angle pdf
//! of that sampling for directions found by BSDF sampling (for MIS). `sample` and `pdf` make the
//! same choice of method from the same inputs, so they always agree.
//!
//! Delta lights (point, spot, line, distant with a zero cone) return `delta: true` with `pdf = 1` and
//! a `radiance` that already holds what a unit-pdf estimator needs (intensity / dist², …);
//! their `pdf` for any direction is 0 (no direction can hit them).

pub mod disk;
pub mod distant;
pub mod environment;
pub mod line;
pub mod point;
pub mod rectangle;
pub mod sky;
pub mod sphere;
pub mod spot;
pub mod triangle;

use crate::intersect::pose_at;
use glam::{Vec2, Vec3};
use stratapt_scene::records::{light_flag, light_kind, Light, Motion};
use stratapt_scene::shared::{GAMMA_3, IN_PLANE_COS};

/// The kinds of light, as the CPU renderer tells them apart: the stored [`Light::kind`] (one of
/// [`light_kind`], shared with the GPU) converted once, where the light is [`Prepared`], so that
/// every dispatch is an exhaustive `match` and a new kind does not compile until each handles it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightKind {
    Triangle,
    Rectangle,
    Disk,
    Sphere,
    Line,
    Point,
    Distant,
    Sky,
    Environment,
    /// An environment map in pbrt-v4's octahedral layout.
    Octahedral,
    /// pbrt-v4's spot light.
    Spot,
}

impl LightKind {
    pub const ALL: [LightKind; 11] = [
        Self::Triangle,
        Self::Rectangle,
        Self::Disk,
        Self::Sphere,
        Self::Line,
        Self::Point,
        Self::Distant,
        Self::Sky,
        Self::Environment,
        Self::Octahedral,
        Self::Spot,
    ];

    /// The kind stored as `kind`; `None` for a value that is none of [`light_kind`] (such a
    /// light gives no light: no sample, a zero pdf, no radiance).
    pub fn of(kind: u32) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.stored() == kind)
    }

    /// The value [`Light::kind`] stores for this kind.
    pub fn stored(self) -> u32 {
        match self {
            Self::Triangle => light_kind::TRIANGLE,
            Self::Rectangle => light_kind::RECTANGLE,
            Self::Disk => light_kind::DISK,
            Self::Sphere => light_kind::SPHERE,
            Self::Line => light_kind::LINE,
            Self::Point => light_kind::POINT,
            Self::Distant => light_kind::DISTANT,
            Self::Sky => light_kind::SKY,
            Self::Environment => light_kind::ENVIRONMENT,
            Self::Octahedral => light_kind::OCTAHEDRAL,
            Self::Spot => light_kind::SPOT,
        }
    }
}

/// A sampled direction towards a light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the shading point towards the light.
    pub wi: Vec3,
    /// Distance to the sampled point (`f32::INFINITY` for directional lights).
    pub dist: f32,
    /// Emitted radiance arriving along `wi` (delta lights: the unit-pdf equivalent).
    pub radiance: Vec3,
    /// Solid-angle pdf (1 for delta lights).
    pub pdf: f32,
    pub delta: bool,
    /// Unit normal of the light's surface at the sampled point (zero for points, lines and
    /// directions): the shadow ray ends off the surface on the shading point's side of it.
    pub n: Vec3,
    /// Bound on each coordinate's distance of the sampled point `p + v` from the light's
    /// surface, for `v` as sampling computed it (relative to the shading point); the rounding of
    /// `p + wi·dist` itself is the shadow ray's to add (pbrt-v4's error bound of a light sample).
    pub err: Vec3,
}

impl LightSample {
    /// A sample of a light with no surface (point, line, direction): its end is not offset.
    pub(crate) fn unoffset(wi: Vec3, dist: f32, radiance: Vec3, pdf: f32, delta: bool) -> Self {
        Self {
            wi,
            dist,
            radiance,
            pdf,
            delta,
            n: Vec3::ZERO,
            err: Vec3::ZERO,
        }
    }
}

/// The light with its geometry placed in world space at normalized shutter time `time`.
///
/// Moving lights are assumed to be scaled uniformly (`scale.x` scales disk and sphere radii).
pub fn placed(light: &Light, motions: &[Motion], time: f32) -> Light {
    // An environment map does not move (the loader gives it no motion).
    place(light, LightKind::of(light.kind), motions, time)
}

/// [`placed`], with the [`Prepared`] part of the placed light, for a light prepared unplaced.
pub fn placed_prepared<'a>(
    light: &Light,
    prepared: &Prepared<'a>,
    motions: &[Motion],
    time: f32,
) -> (Light, Prepared<'a>) {
    let placed = place(light, prepared.kind, motions, time);
    let mut again = Prepared::of_kind(&placed, prepared.kind, &[]);
    again.environment = prepared.environment;
    (placed, again)
}

/// [`placed`] for a light of `kind`.
fn place(light: &Light, kind: Option<LightKind>, motions: &[Motion], time: f32) -> Light {
    let Some(pose) = pose_at(motions, light.motion, time) else {
        return *light;
    };
    let Some(kind) = kind else {
        return *light;
    };
    let v = Vec3::from_array;
    let mut out = *light;
    let point = |a: [f32; 3]| pose.point_to_world(v(a)).to_array();
    let vector = |a: [f32; 3]| pose.vector_to_world(v(a)).to_array();
    let direction = |a: [f32; 3]| (pose.rotation() * v(a)).normalize().to_array();
    match kind {
        LightKind::Triangle | LightKind::Line => {
            out.p0 = point(light.p0);
            out.p1 = point(light.p1);
            out.p2 = point(light.p2);
        }
        LightKind::Rectangle => {
            out.p0 = point(light.p0);
            out.p1 = vector(light.p1);
            out.p2 = vector(light.p2);
        }
        LightKind::Disk => {
            out.p0 = point(light.p0);
            out.p1 = pose.normal_to_world(v(light.p1)).to_array();
            out.p2[0] = light.p2[0] * pose.scale().x;
        }
        LightKind::Sphere => {
            out.p0 = point(light.p0);
            out.p2[0] = light.p2[0] * pose.scale().x;
        }
        LightKind::Point => out.p0 = point(light.p0),
        LightKind::Spot => {
            out.p0 = point(light.p0);
            out.p1 = direction(light.p1);
        }
        LightKind::Distant | LightKind::Sky => out.p0 = direction(light.p0),
        LightKind::Environment | LightKind::Octahedral => {}
    }
    out
}

/// What sampling a light needs that does not depend on the shading point (its [`LightKind`], a
/// rectangle's frame, an environment map's data in the scene's tables): computed once per
/// static light by the integrator, per placement for a moving one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prepared<'a> {
    /// `None` for a stored kind that is none of [`light_kind`].
    kind: Option<LightKind>,
    rectangle: Option<rectangle::Prepared>,
    /// An environment map's; `None` (no light) when the tables do not hold it.
    environment: Option<environment::Environment<'a>>,
}

impl<'a> Prepared<'a> {
    /// For `light` as placed (world space), with the scene's
    /// [`tables`](stratapt_scene::FlatScene::tables) an environment map reads.
    pub fn of(light: &Light, tables: &'a [f32]) -> Self {
        Self::of_kind(light, LightKind::of(light.kind), tables)
    }

    /// For `light` as placed, its kind already known.
    fn of_kind(light: &Light, kind: Option<LightKind>, tables: &'a [f32]) -> Self {
        let (_, b, c) = geometry(light);
        Self {
            kind,
            rectangle: (kind == Some(LightKind::Rectangle)).then(|| rectangle::Prepared::new(b, c)),
            environment: match kind {
                Some(LightKind::Environment | LightKind::Octahedral) => {
                    environment::Environment::of(light, tables)
                }
                _ => None,
            },
        }
    }

    /// The light's kind; `None` for a stored kind that is none of [`light_kind`].
    pub fn kind(&self) -> Option<LightKind> {
        self.kind
    }

    /// The rectangle's frame: prepared, or computed from its edges `ex`, `ey`.
    fn rectangle(&self, ex: Vec3, ey: Vec3) -> rectangle::Prepared {
        self.rectangle
            .unwrap_or_else(|| rectangle::Prepared::new(ex, ey))
    }
}

/// Sample a direction from `p` towards `light` (world-space, already [`placed`]).
pub fn sample(light: &Light, p: Vec3, u: Vec2) -> Option<LightSample> {
    sample_prepared(light, &Prepared::of(light, &[]), p, u)
}

/// A two-sided triangle, rectangle or disk ([`light_flag::TWO_SIDED`]) seen from behind, turned
/// round to face `p` (a triangle's winding reversed, a rectangle's edges swapped, a disk's normal
/// negated), with a rectangle's [`Prepared`] part for the turned edges; `None` for every other
/// light and point, which sample and weigh the light as it is.
fn turned_to(light: &Light, prepared: &Prepared, p: Vec3) -> Option<(Light, Prepared<'static>)> {
    if !light.has(light_flag::TWO_SIDED) {
        return None;
    }
    let (a, b, c) = geometry(light);
    let mut turned = *light;
    match prepared.kind? {
        LightKind::Triangle if (b - a).cross(c - a).dot(p - a) <= 0.0 => {
            (turned.p1, turned.p2) = (light.p2, light.p1);
        }
        LightKind::Rectangle if b.cross(c).dot(p - a) <= 0.0 => {
            (turned.p1, turned.p2) = (light.p2, light.p1);
        }
        LightKind::Disk if b.dot(p - a) <= 0.0 => turned.p1 = (-b).to_array(),
        _ => return None,
    }
    let prepared = Prepared::of_kind(&turned, prepared.kind, &[]);
    Some((turned, prepared))
}

/// [`sample`] with the light's [`Prepared`] part.
pub fn sample_prepared(
    light: &Light,
    prepared: &Prepared,
    p: Vec3,
    u: Vec2,
) -> Option<LightSample> {
    match turned_to(light, prepared, p) {
        Some((turned, prepared)) => sample_facing(&turned, &prepared, p, u),
        None => sample_facing(light, prepared, p, u),
    }
}

/// [`sample_prepared`] of a light as it faces `p` (turned, if two-sided, by [`turned_to`]).
fn sample_facing(light: &Light, prepared: &Prepared, p: Vec3, u: Vec2) -> Option<LightSample> {
    let kind = prepared.kind?;
    let (a, b, c) = geometry(light);
    let le = Vec3::from_array(light.radiance);
    let s = match kind {
        LightKind::Triangle => triangle::sample(a, b, c, le, p, u),
        LightKind::Rectangle => rectangle::sample(&prepared.rectangle(b, c), a, b, c, le, p, u),
        LightKind::Disk => disk::sample(a, b, c.x, le, p, u),
        LightKind::Sphere => sphere::sample(a, c.x, le, p, u),
        LightKind::Line => line::sample(a, b, le, p, u),
        LightKind::Point => point::sample(a, le, p),
        LightKind::Spot => spot::sample(a, b, c.x, c.y, le, p),
        LightKind::Distant => distant::sample(a, c.x, le, u),
        LightKind::Sky => sky::sample(a, b, le, u),
        LightKind::Environment | LightKind::Octahedral => prepared.environment?.sample(u),
    }?;
    // A zero or infinite pdf, and radiance that overflows (a point light at a point 10⁻²⁰
    // away), give no sample rather than a NaN or infinity downstream.
    (s.pdf > 0.0 && s.pdf.is_finite() && s.wi.is_finite() && s.radiance.is_finite()).then_some(s)
}

/// Whether `p`, whose coordinates are within `err` of a surface point, lies on a surface in the
/// plane of the planar `light` (triangle, rectangle, disk): the surface's geometric normal `ng`
/// parallel to the light's (to [`IN_PLANE_COS`]), and `p` in its plane to within that error and
/// the rounding of the test. A point in a planar light's plane receives nothing from it, but
/// rounding can put it a hair in front, where sampling finds the light at grazing incidence: a
/// point on a light, or on a coplanar neighbour, lit by itself.
///
/// The normals tell a coplanar neighbour from a point of another surface that the error bound
/// cannot tell from the plane: 10⁵ from the origin the slack is 0.08 units, and the points of
/// a unit box's faces that near a neighbouring face lost that face's light (half their
/// irradiance at the edge), which darkened the light sampling estimate inside the box
/// (measured: docs/measurements/far-from-the-origin.md#what-was-lost-and-why).
pub fn in_plane(light: &Light, p: Vec3, err: Vec3, ng: Vec3) -> bool {
    in_plane_prepared(light, &Prepared::of(light, &[]), p, err, ng)
}

/// [`in_plane`] with the light's [`Prepared`] part.
pub fn in_plane_prepared(light: &Light, prepared: &Prepared, p: Vec3, err: Vec3, ng: Vec3) -> bool {
    let Some(kind) = prepared.kind else {
        return false;
    };
    let (a, b, c) = geometry(light);
    let n = match kind {
        LightKind::Triangle => (b - a).cross(c - a).normalize_or_zero(),
        LightKind::Rectangle => prepared.rectangle(b, c).normal(),
        LightKind::Disk => b.normalize_or_zero(),
        LightKind::Sphere
        | LightKind::Line
        | LightKind::Point
        | LightKind::Spot
        | LightKind::Distant
        | LightKind::Sky
        | LightKind::Environment
        | LightKind::Octahedral => return false,
    };
    if n == Vec3::ZERO || n.dot(ng).abs() < IN_PLANE_COS {
        return false;
    }
    let d = p - a;
    let slack = n.abs().dot(err + GAMMA_3 * (p.abs() + a.abs()));
    n.dot(d).abs() <= slack
}

/// Solid-angle pdf with which [`sample`] picks direction `wi` from `p`.
///
/// Where the pdf depends on the point the ray along `wi` reaches (area sampling), that point is
/// found from `p` and the light's geometry (the plane's distance, the sphere's far root), not
/// from a hit point: 10⁵ from the origin a hit point and the shading point both round to the
/// 1/128 grid, and the distance between them carried that rounding into the MIS weights of
/// BSDF-sampled hits, enough to move the estimate inside a unit emitting sphere there (measured:
/// docs/measurements/far-from-the-origin.md#what-was-lost-and-why).
pub fn pdf(light: &Light, p: Vec3, wi: Vec3) -> f32 {
    pdf_prepared(light, &Prepared::of(light, &[]), p, wi)
}

/// [`pdf`] with the light's [`Prepared`] part.
pub fn pdf_prepared(light: &Light, prepared: &Prepared, p: Vec3, wi: Vec3) -> f32 {
    match turned_to(light, prepared, p) {
        Some((turned, prepared)) => pdf_facing(&turned, &prepared, p, wi),
        None => pdf_facing(light, prepared, p, wi),
    }
}

/// [`pdf_prepared`] of a light as it faces `p` (turned, if two-sided, by [`turned_to`]).
fn pdf_facing(light: &Light, prepared: &Prepared, p: Vec3, wi: Vec3) -> f32 {
    let Some(kind) = prepared.kind else {
        return 0.0;
    };
    let (a, b, c) = geometry(light);
    match kind {
        LightKind::Triangle => triangle::pdf(a, b, c, p, wi),
        LightKind::Rectangle => rectangle::pdf(&prepared.rectangle(b, c), a, p, wi),
        LightKind::Disk => disk::pdf(a, b, c.x, p, wi),
        LightKind::Sphere => sphere::pdf(a, c.x, p, wi),
        LightKind::Distant => distant::pdf(a, c.x, wi),
        LightKind::Sky => sky::pdf(),
        LightKind::Environment | LightKind::Octahedral => {
            prepared.environment.map_or(0.0, |e| e.pdf(wi))
        }
        // No direction can hit a point or a line.
        LightKind::Line | LightKind::Point | LightKind::Spot => 0.0,
    }
}

/// Radiance an escaping ray in direction `wi` receives from a directional light (sky,
/// environment map or sun cone; 0 for delta directions and for every other kind).
pub fn escaped_radiance(light: &Light, wi: Vec3) -> Vec3 {
    escaped_radiance_prepared(light, &Prepared::of(light, &[]), wi)
}

/// [`escaped_radiance`] with the light's [`Prepared`] part.
pub fn escaped_radiance_prepared(light: &Light, prepared: &Prepared, wi: Vec3) -> Vec3 {
    let Some(kind) = prepared.kind else {
        return Vec3::ZERO;
    };
    let (a, b, c) = geometry(light);
    let le = Vec3::from_array(light.radiance);
    match kind {
        LightKind::Distant => distant::radiance(a, c.x, le, wi),
        LightKind::Sky => sky::radiance(a, b, le, wi),
        LightKind::Environment | LightKind::Octahedral => {
            prepared.environment.map_or(Vec3::ZERO, |e| e.radiance(wi))
        }
        LightKind::Triangle
        | LightKind::Rectangle
        | LightKind::Disk
        | LightKind::Sphere
        | LightKind::Line
        | LightKind::Point
        | LightKind::Spot => Vec3::ZERO,
    }
}

fn geometry(light: &Light) -> (Vec3, Vec3, Vec3) {
    (
        Vec3::from_array(light.p0),
        Vec3::from_array(light.p1),
        Vec3::from_array(light.p2),
    )
}

pub(crate) use stratapt_scene::shared::{
    AREA_SAMPLED_ANGULAR_SIZE_SQ, MAX_SPHERICAL_SOLID_ANGLE, MIN_SPHERICAL_SOLID_ANGLE,
};

/// Whether a polygon light of squared diameter `diameter_sq` whose centre lies at `centre` from
/// the shading point is seen under a small angle ([`AREA_SAMPLED_ANGULAR_SIZE_SQ`]): sampled by
/// area, with no spherical setup.
pub(crate) fn seen_small(diameter_sq: f32, centre: Vec3) -> bool {
    diameter_sq < AREA_SAMPLED_ANGULAR_SIZE_SQ * centre.dot(centre)
}

pub(crate) fn use_spherical(solid_angle: f32) -> bool {
    solid_angle > MIN_SPHERICAL_SOLID_ANGLE && solid_angle < MAX_SPHERICAL_SOLID_ANGLE
}

/// The distance along `wi` from `p` to the plane through `a` of normal `n` (relative to `p`, so
/// as precise far from the origin as at it); negative or not finite where `wi` does not reach
/// it.
pub(crate) fn plane_distance(a: Vec3, n: Vec3, p: Vec3, wi: Vec3) -> f32 {
    (a - p).dot(n) / wi.dot(n)
}

/// Area-measure pdf `1 / area` of a point at `dist` along `wi` on a surface of unit normal `n`,
/// converted to solid angle: `dist² / (|cos θ_light| · area)`; 0 when seen edge-on or from the
/// back of a one-sided emitter (`two_sided == false`).
pub(crate) fn area_to_solid_angle(area: f32, n: Vec3, wi: Vec3, dist: f32, two_sided: bool) -> f32 {
    let cos = -n.dot(wi);
    let cos = if two_sided { cos.abs() } else { cos };
    // Edge-on, from behind, no area, or an undefined normal (NaN): no density; a product that
    // underflows is not divided by, and one that overflows (10²⁰ scales) is no density either,
    // so that sampling refuses the light and a BSDF ray that hits it keeps its full weight.
    let denom = cos * area;
    if !(cos > 0.0 && area > 0.0 && denom > 0.0) {
        return 0.0;
    }
    let pdf = dist * dist / denom;
    if pdf.is_finite() {
        pdf
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests;
