//! Next-event estimation: pick a light from the strategy's alias table with the light-select
//! dimension, a point or direction on it with the light-point dimensions, and trace a shadow
//! ray. Under `mis` the contribution of a non-delta light is weighted by the power heuristic
//! against the BSDF's pdf (Veach 1997, §9.2).

use super::{power_heuristic, Integrator};
use crate::bsdf::ShadingPoint;
use crate::intersect::Ray;
use crate::light::{self, LightKind, LightSample};
use crate::offset::{offset_ray_origin, spawn_origin};
use glam::Vec3;
use stratapt_sampling::PathSampler;
use stratapt_scene::shared::GAMMA_5;
use stratapt_scene::Strategy;

/// Shadow rays stop this fraction short of the light's point, so that the light's own surface
/// (and the surfaces it touches) never occlude it.
pub use stratapt_scene::shared::SHADOW_STOP_SHORT;

/// The shadow ray from surface point `p` (error bound `err`, geometric normal `ng`) towards the
/// light sample `ls`, drawn from the point `from` (`p` moved off its surface on the side of `ng`).
///
/// Both ends are moved off their surfaces by their error bounds (pbrt-v4's `SpawnRayTo` between
/// two interactions): the origin off `p`'s surface ([`spawn_origin`]), the sampled point off the
/// light's surface towards `p` ([`offset_ray_origin`] with the sample's bound plus the rounding
/// of `from + wi·dist`). The ray is aimed from the one at the other and stops
/// [`SHADOW_STOP_SHORT`] of the way short.
/// - Aiming at the sampled point rather than keeping `wi`: a sideways shift `δ` of the origin
///   moves the ray's entry into a sphere light near its silhouette earlier by about `δ / cos θ`,
///   past the stop-short margin at grazing angles, where the light would shadow itself
///   (measured: docs/measurements/far-from-the-origin.md#shadow-rays-that-graze-a-sphere-light).
/// - Moving the end off the light: 10⁵ from the origin a unit-sized light's sampled point
///   rounds to the coordinates' grid of 1/128, on either side of the surface; the margin
///   alone left it behind the surface for about half the samples, which the light itself then
///   shadowed, darkening the light strategy from 10⁴ from the origin on (measured:
///   docs/measurements/far-from-the-origin.md#what-was-lost-and-why).
pub fn shadow_ray(p: Vec3, err: Vec3, ng: Vec3, from: Vec3, ls: &LightSample) -> Ray {
    let origin = spawn_origin(p, err, ng, ls.wi);
    if !ls.dist.is_finite() {
        return Ray::new(origin, ls.wi, f32::INFINITY);
    }
    let v = ls.wi * ls.dist;
    let mut end = from + v;
    if ls.n != Vec3::ZERO {
        let towards_p = if ls.n.dot(ls.wi) > 0.0 { -ls.n } else { ls.n };
        end = offset_ray_origin(end, ls.err + GAMMA_5 * (from.abs() + v.abs()), towards_p);
    }
    let to_light = end - origin;
    // Both ends within each other's rounding (a point touching the light): nothing between.
    if !(to_light.dot(ls.wi) > 0.0) {
        return Ray::new(origin, ls.wi, 0.0);
    }
    let len = to_light.length();
    Ray::new(origin, to_light / len, len * (1.0 - SHADOW_STOP_SHORT))
}

/// The point next-event estimation samples a light (its [`light::Prepared`] part) from, at
/// shading point `sp`:
/// - a light BSDF sampling can reach too (a surface, a sun's cone, the sky, an environment map): `sp.p` moved off
///   its surface on the side of `wo`, where the BSDF ray leaves from and where MIS evaluates
///   light pdfs for what it finds. 10⁵ from the origin that offset is 4 % of a unit object, and
///   sampling from the surface point itself put the two strategies' pdfs for one direction on
///   different triangles near a box's edges, and MIS lost more than either strategy alone.
/// - a point or line light: `sp.p` itself. Nothing weighs against it, and its 1/dist² falloff
///   would see the offset (a point light 1 away, 10⁵ from the origin, would come out too
///   bright).
///
/// Both errors measured: docs/measurements/far-from-the-origin.md#what-was-lost-and-why.
pub fn sampled_from(prepared: &light::Prepared, sp: &ShadingPoint) -> Vec3 {
    match prepared.kind() {
        Some(LightKind::Point | LightKind::Spot | LightKind::Line) => sp.p,
        Some(
            LightKind::Triangle
            | LightKind::Rectangle
            | LightKind::Disk
            | LightKind::Sphere
            | LightKind::Distant
            | LightKind::Sky
            | LightKind::Environment
            | LightKind::Octahedral,
        )
        | None => offset_ray_origin(sp.p, sp.err, sp.ng),
    }
}

impl Integrator<'_> {
    /// Light reaching `sp` directly from one sampled light, reflected towards `wo`.
    pub(crate) fn next_event(
        &self,
        sp: &ShadingPoint,
        wo: Vec3,
        samples: &PathSampler,
        dims: u32,
        time: f32,
    ) -> Vec3 {
        let (Some(select_dim), Some(point_dim)) =
            (self.layout.light_select, self.layout.light_point)
        else {
            return Vec3::ZERO;
        };
        if self.nee_table.is_empty() {
            return Vec3::ZERO;
        }
        // ---- Choose a light, then a direction towards it -----------------------------------
        // One light leaves nothing to choose: only its point is drawn (the point `sample_1d_2d`
        // would give).
        let (u_select, u_point) = match self.nee_table.len() {
            1 => (0.0, samples.sample_2d(dims + point_dim)),
            _ => samples.sample_1d_2d(dims + select_dim, dims + point_dim),
        };
        let (light_index, select_pdf) =
            stratapt_scene::light_table::select(self.nee_table, u_select);
        let (light, prepared) = self.light(light_index as u32, time);
        if light::in_plane_prepared(&light, &prepared, sp.p, sp.err, sp.ng) {
            return Vec3::ZERO;
        }
        let from = sampled_from(&prepared, sp);
        let Some(ls) = light::sample_prepared(&light, &prepared, from, u_point) else {
            return Vec3::ZERO;
        };
        if ls.radiance == Vec3::ZERO || select_pdf <= 0.0 {
            return Vec3::ZERO;
        }
        let f = sp.eval(wo, ls.wi);
        if f == Vec3::ZERO {
            return Vec3::ZERO;
        }
        // ---- Visibility ----------------------------------------------------------------------
        let shadow = shadow_ray(sp.p, sp.err, sp.ng, from, &ls);
        if self.accel.occluded(&shadow, time) {
            return Vec3::ZERO;
        }
        // ---- Estimate, MIS-weighted against BSDF sampling ------------------------------------
        let light_pdf = select_pdf * ls.pdf;
        let weight = if ls.delta || self.strategy() != Strategy::Mis {
            1.0
        } else {
            power_heuristic(light_pdf, sp.pdf(wo, ls.wi, self.strategy()))
        };
        f * ls.radiance * (weight / light_pdf)
    }
}
