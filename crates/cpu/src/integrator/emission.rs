//! Emission found by a ray — on a surface, or from the environment when it escapes — and its
//! weight under the strategy:
//! - the camera ray, and a ray leaving a delta lobe: counted in full (NEE cannot reach it);
//! - `light`: not counted (NEE estimates it);
//! - `mis`: power heuristic of the BSDF pdf against `select_pdf · light pdf` (Veach 1997, §9.2);
//! - `uniform`, `cosine`, `bsdf`: counted in full.

use super::{power_heuristic, Integrator, PrevVertex};
use crate::intersect::Hit;
use crate::light;
use glam::Vec3;
use stratapt_scene::records::{light_flag, prim_kind, NONE};
use stratapt_scene::Strategy;

impl Integrator<'_> {
    /// Radiance emitted by the surface at `hit` towards the ray's origin, weighted.
    pub(crate) fn emitted(&self, hit: &Hit, dir: Vec3, prev: &PrevVertex, time: f32) -> Vec3 {
        let prim = self.scene.geometry.surface(hit.prim);
        let le = Vec3::from_array(self.scene.materials[prim.material as usize].emission);
        if le == Vec3::ZERO {
            return Vec3::ZERO;
        }
        // One-sided emitters are dark from behind; spheres and two-sided lights emit from both
        // sides.
        let two_sided = prim.kind == prim_kind::SPHERE
            || self
                .scene
                .lights
                .get(prim.light as usize)
                .is_some_and(|l| l.has(light_flag::TWO_SIDED));
        if !two_sided && hit.ng.dot(dir) >= 0.0 {
            return Vec3::ZERO;
        }
        let weight = self.hit_weight(
            prev,
            prim.light,
            |light, prepared| light::pdf_prepared(light, prepared, prev.p, dir),
            time,
        );
        le * weight
    }

    /// Radiance of the environment (sky, sun cones) along an escaping ray, weighted.
    pub(crate) fn escaped(&self, dir: Vec3, prev: &PrevVertex, time: f32) -> Vec3 {
        let mut sum = Vec3::ZERO;
        for &index in &self.environment {
            let (light, prepared) = self.light(index, time);
            let le = light::escaped_radiance_prepared(&light, &prepared, dir);
            if le != Vec3::ZERO {
                sum += le
                    * self.hit_weight(
                        prev,
                        index,
                        |l, prepared| light::pdf_prepared(l, prepared, prev.p, dir),
                        time,
                    );
            }
        }
        sum
    }

    /// Weight of emission reached by a ray from `prev`, for light `index` (or `NONE`) whose
    /// solid-angle sampling pdf from `prev` is given by `light_pdf`.
    fn hit_weight(
        &self,
        prev: &PrevVertex,
        index: u32,
        light_pdf: impl Fn(&stratapt_scene::records::Light, &light::Prepared) -> f32,
        time: f32,
    ) -> f32 {
        if prev.specular {
            return 1.0;
        }
        match self.strategy() {
            Strategy::Light => 0.0,
            Strategy::Mis if index != NONE => {
                let (light, prepared) = self.light(index, time);
                let select_pdf = self.scene.lights[index as usize].select_pdf;
                power_heuristic(prev.pdf, select_pdf * light_pdf(&light, &prepared))
            }
            _ => 1.0,
        }
    }
}
