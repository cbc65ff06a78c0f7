//! Lights: placement at the ray's time, sampling from a shading point, and the solid-angle pdf
//! of that sampling for directions found by BSDF sampling (for MIS). `sample` and `pdf` make the
//! same choice of method from the same inputs, so they always agree.
//!
//! Delta lights (point, line, distant with a zero cone) return `delta: true` with `pdf = 1` and
//! a `radiance` that already holds what a unit-pdf estimator needs (intensity / dist², …);
//! their `pdf` for any direction is 0 (no direction can hit them).

pub mod disk;
pub mod distant;
pub mod line;
pub mod point;
pub mod rectangle;
pub mod sky;
pub mod sphere;
pub mod triangle;

use crate::intersect::pose_at;
use glam::{Vec2, Vec3};
use stratapt_scene::gpu::{light_kind, Light, Motion};
use stratapt_scene::shared::GAMMA_3;

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
}

/// The light with its geometry placed in world space at normalized shutter time `time`.
///
/// Moving lights are assumed to be scaled uniformly (`scale.x` scales disk and sphere radii).
pub fn placed(light: &Light, motions: &[Motion], time: f32) -> Light {
    let Some(pose) = pose_at(motions, light.motion, time) else {
        return *light;
    };
    let v = Vec3::from_array;
    let mut out = *light;
    let point = |a: [f32; 3]| pose.point_to_world(v(a)).to_array();
    let vector = |a: [f32; 3]| pose.vector_to_world(v(a)).to_array();
    let direction = |a: [f32; 3]| (pose.rotation() * v(a)).normalize().to_array();
    match light.kind {
        light_kind::TRIANGLE | light_kind::LINE => {
            out.p0 = point(light.p0);
            out.p1 = point(light.p1);
            out.p2 = point(light.p2);
        }
        light_kind::RECTANGLE => {
            out.p0 = point(light.p0);
            out.p1 = vector(light.p1);
            out.p2 = vector(light.p2);
        }
        light_kind::DISK => {
            out.p0 = point(light.p0);
            out.p1 = pose.normal_to_world(v(light.p1)).to_array();
            out.p2[0] = light.p2[0] * pose.scale().x;
        }
        light_kind::SPHERE => {
            out.p0 = point(light.p0);
            out.p2[0] = light.p2[0] * pose.scale().x;
        }
        light_kind::POINT => out.p0 = point(light.p0),
        light_kind::DISTANT | light_kind::SKY => out.p0 = direction(light.p0),
        _ => {}
    }
    out
}

/// What sampling a light needs that does not depend on the shading point (a rectangle's
/// frame): computed once per static light by the integrator, per placement for a moving one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prepared {
    rectangle: Option<rectangle::Frame>,
}

impl Prepared {
    /// For `light` as placed (world space).
    pub fn of(light: &Light) -> Self {
        let (_, b, c) = geometry(light);
        Self {
            rectangle: (light.kind == light_kind::RECTANGLE).then(|| rectangle::Frame::new(b, c)),
        }
    }

    /// The rectangle's frame: prepared, or computed from its edges `ex`, `ey`.
    fn rectangle(&self, ex: Vec3, ey: Vec3) -> rectangle::Frame {
        self.rectangle
            .unwrap_or_else(|| rectangle::Frame::new(ex, ey))
    }
}

/// Sample a direction from `p` towards `light` (world-space, already [`placed`]).
pub fn sample(light: &Light, p: Vec3, u: Vec2) -> Option<LightSample> {
    sample_prepared(light, &Prepared::of(light), p, u)
}

/// [`sample`] with the light's [`Prepared`] part.
pub fn sample_prepared(
    light: &Light,
    prepared: &Prepared,
    p: Vec3,
    u: Vec2,
) -> Option<LightSample> {
    let (a, b, c) = geometry(light);
    let le = Vec3::from_array(light.radiance);
    let s = match light.kind {
        light_kind::TRIANGLE => triangle::sample(a, b, c, le, p, u),
        light_kind::RECTANGLE => rectangle::sample(&prepared.rectangle(b, c), a, b, c, le, p, u),
        light_kind::DISK => disk::sample(a, b, c.x, le, p, u),
        light_kind::SPHERE => sphere::sample(a, c.x, le, p, u),
        light_kind::LINE => line::sample(a, b, le, p, u),
        light_kind::POINT => point::sample(a, le, p),
        light_kind::DISTANT => distant::sample(a, c.x, le, u),
        light_kind::SKY => sky::sample(a, b, le, u),
        _ => None,
    }?;
    // A zero or infinite pdf, and radiance that overflows (a point light at a point 10⁻²⁰
    // away), give no sample rather than a NaN or infinity downstream.
    (s.pdf > 0.0 && s.pdf.is_finite() && s.wi.is_finite() && s.radiance.is_finite()).then_some(s)
}

/// Whether `p`, whose coordinates are within `err` of a surface point, lies in the plane of the
/// planar `light` (triangle, rectangle, disk) to within that error and the rounding of the test.
/// A point in a planar light's plane receives nothing from it, but rounding can put it a hair in
/// front, where sampling finds the light at grazing incidence: a point on a light, or on a
/// coplanar neighbour, lit by itself.
pub fn in_plane(light: &Light, p: Vec3, err: Vec3) -> bool {
    in_plane_prepared(light, &Prepared::of(light), p, err)
}

/// [`in_plane`] with the light's [`Prepared`] part.
pub fn in_plane_prepared(light: &Light, prepared: &Prepared, p: Vec3, err: Vec3) -> bool {
    let (a, b, c) = geometry(light);
    let n = match light.kind {
        light_kind::TRIANGLE => (b - a).cross(c - a).normalize_or_zero(),
        light_kind::RECTANGLE => prepared.rectangle(b, c).normal(),
        light_kind::DISK => b.normalize_or_zero(),
        _ => return false,
    };
    if n == Vec3::ZERO {
        return false;
    }
    let d = p - a;
    let slack = n.abs().dot(err + GAMMA_3 * (p.abs() + a.abs()));
    n.dot(d).abs() <= slack
}

/// Solid-angle pdf with which [`sample`] picks direction `wi` from `p`, for a ray that reached
/// the light at distance `dist` (ignored by directional lights).
pub fn pdf(light: &Light, p: Vec3, wi: Vec3, dist: f32) -> f32 {
    pdf_prepared(light, &Prepared::of(light), p, wi, dist)
}

/// [`pdf`] with the light's [`Prepared`] part.
pub fn pdf_prepared(light: &Light, prepared: &Prepared, p: Vec3, wi: Vec3, dist: f32) -> f32 {
    let (a, b, c) = geometry(light);
    match light.kind {
        light_kind::TRIANGLE => triangle::pdf(a, b, c, p, wi, dist),
        light_kind::RECTANGLE => rectangle::pdf(&prepared.rectangle(b, c), a, p, wi, dist),
        light_kind::DISK => disk::pdf(a, b, c.x, p, wi, dist),
        light_kind::SPHERE => sphere::pdf(a, c.x, p, wi, dist),
        light_kind::DISTANT => distant::pdf(a, c.x, wi),
        light_kind::SKY => sky::pdf(),
        _ => 0.0,
    }
}

/// Radiance an escaping ray in direction `wi` receives from a directional light (sky or sun
/// cone; 0 for delta directions and for every other kind).
pub fn escaped_radiance(light: &Light, wi: Vec3) -> Vec3 {
    let (a, b, c) = geometry(light);
    let le = Vec3::from_array(light.radiance);
    match light.kind {
        light_kind::DISTANT => distant::radiance(a, c.x, le, wi),
        light_kind::SKY => sky::radiance(a, b, le, wi),
        _ => Vec3::ZERO,
    }
}

fn geometry(light: &Light) -> (Vec3, Vec3, Vec3) {
    (
        Vec3::from_array(light.p0),
        Vec3::from_array(light.p1),
        Vec3::from_array(light.p2),
    )
}

pub(crate) use stratapt_scene::shared::{MAX_SPHERICAL_SOLID_ANGLE, MIN_SPHERICAL_SOLID_ANGLE};

pub(crate) fn use_spherical(solid_angle: f32) -> bool {
    solid_angle > MIN_SPHERICAL_SOLID_ANGLE && solid_angle < MAX_SPHERICAL_SOLID_ANGLE
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
