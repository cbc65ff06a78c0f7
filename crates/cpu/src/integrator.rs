//! The path integrator: one estimator per [`Strategy`], consuming the sample dimensions of
//! [`DimLayout`] from fixed positions.
//!
//! A path has at most `max_depth` scattering vertices (`k = 0` is the first hit); the ray
//! leaving vertex `max_depth − 1` still gathers the emission it finds (see the crate docs).
//! At every non-delta vertex: next-event estimation (NEE) of the lights the strategy samples
//! (`nee`), then BSDF sampling of the continuation; emission found by a ray is weighted by
//! `emission` (counted, MIS-weighted, or left to NEE). Russian roulette starts at vertex
//! [`ROULETTE_START`] when another scattering vertex can follow.
//!
//! Veach 1997, "Robust Monte Carlo Methods for Light Transport Simulation", ch. 9 (MIS) and
//! §10.4.1 (path tracing with NEE); pbrt-v4 `PathIntegrator::Li`.

mod emission;
mod nee;
pub use nee::{shadow_ray, SHADOW_STOP_SHORT};

pub(crate) use stratapt_sampling::mis::power_heuristic;

use crate::accel::Accel;
use crate::bsdf::ShadingPoint;
use crate::camera;
use crate::intersect::Ray;
use crate::light;
use glam::Vec3;
use stratapt_sampling::{PathSampler, Sampler};
use stratapt_scene::records::{material_kind, AliasEntry, Light, NONE};
use stratapt_scene::shared::{MAX_SURVIVAL, MIN_SURVIVAL, ROULETTE_START};
use stratapt_scene::{DimLayout, Effects, FlatScene, RenderSettings, Strategy};

/// A path tracer for one scene and one set of render settings.
pub struct Integrator<'a> {
    scene: &'a FlatScene,
    accel: &'a Accel<'a>,
    settings: RenderSettings,
    sampler: Sampler,
    effects: Effects,
    layout: DimLayout,
    /// The table NEE draws lights from: every light when the strategy samples lights, else only
    /// the unhittable ones.
    nee_table: &'a [AliasEntry],
    /// Lights an escaping ray can see (sky, sun cones).
    environment: Vec<u32>,
    /// Each stored light's [`light::Prepared`] part: a static light's as is; a moving light
    /// keeps its kind from it and is prepared again where it is placed.
    prepared: Vec<light::Prepared<'a>>,
}

/// What the emission at the next hit must know about the vertex the ray left.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PrevVertex {
    /// Where the ray left the vertex: its shading point offset off the surface (unused for the
    /// camera). Light pdfs for MIS are evaluated from here, as `next_event` samples from here.
    pub p: Vec3,
    /// Solid-angle pdf of the sampled direction.
    pub pdf: f32,
    /// The camera, or a delta lobe: emission is always counted in full.
    pub specular: bool,
}

impl<'a> Integrator<'a> {
    /// The integrator over `accel`'s scene.
    pub fn new(accel: &'a Accel<'a>, settings: &RenderSettings) -> Self {
        let scene = accel.scene();
        let effects = Effects::of(scene, settings);
        let nee_table = if settings.strategy.samples_lights() {
            &scene.light_table
        } else {
            &scene.unhittable_table
        };
        let environment = scene.environment_lights().map(|i| i as u32).collect();
        let prepared = scene
            .lights
            .iter()
            .map(|l| light::Prepared::of(l, &scene.tables))
            .collect();
        Self {
            scene,
            accel,
            settings: *settings,
            sampler: Sampler::new(settings.sampler, settings.pattern_spp, settings.seed),
            layout: DimLayout::new(&effects),
            effects,
            nee_table,
            environment,
            prepared,
        }
    }

    pub fn layout(&self) -> &DimLayout {
        &self.layout
    }

    pub fn effects(&self) -> &Effects {
        &self.effects
    }

    /// One sample of pixel `pixel`: a camera ray through the pixel filter, lens and shutter,
    /// then [`Integrator::radiance`].
    pub fn sample_pixel(&self, pixel: [u32; 2], index: u32) -> Vec3 {
        let samples = self.sampler.path(pixel, index);
        // The shutter instant is drawn with the position in the pixel, so that the samples of
        // each stretch of the shutter are spread over the pixel.
        let (time, u_pixel) = match self.layout.time {
            Some(d) => samples.sample_1d_2d(d, self.layout.pixel),
            None => (0.0, samples.sample_2d(self.layout.pixel)),
        };
        let u_lens = self.layout.lens.map(|d| samples.sample_2d(d));
        let (origin, dir) = camera::generate_ray(&self.scene.camera, pixel, u_pixel, u_lens, time);
        self.radiance(origin, dir, time, &samples, self.layout.first_vertex)
    }

    /// Radiance arriving at `origin` from direction `-dir` (`dir` unit), estimated by one path
    /// whose vertex `k` draws its dimensions from block `first_dim + k · per_vertex` of
    /// `samples`.
    pub fn radiance(
        &self,
        origin: Vec3,
        dir: Vec3,
        time: f32,
        samples: &PathSampler,
        first_dim: u32,
    ) -> Vec3 {
        let scene = self.scene;
        let max_depth = self.settings.max_depth;
        let mut radiance = Vec3::ZERO;
        let mut throughput = Vec3::ONE;
        // Product of η² over refractions, undoing the 1/η² radiance scaling for roulette.
        let mut eta_scale = 1.0;
        let mut ray = Ray::new(origin, dir, f32::INFINITY);
        let mut prev = PrevVertex {
            p: origin,
            pdf: 0.0,
            specular: true,
        };
        for depth in 0..=max_depth {
            // ---- Intersection -------------------------------------------------------------
            let Some(hit) = self.accel.closest_hit(&ray, time) else {
                radiance += throughput * self.escaped(ray.dir, &prev, time);
                break;
            };
            // ---- Emission found by the ray ------------------------------------------------
            radiance += throughput * self.emitted(&hit, ray.dir, &prev, time);
            if depth == max_depth {
                break;
            }
            let wo = -ray.dir;
            // Mixes choose, bump and normal maps tilt the shading normal.
            let mut hit = hit;
            let material = crate::bsdf::mix::resolve(
                &scene.materials,
                &scene.tables,
                scene.geometry.surface(hit.prim).material,
                &mut hit,
                crate::bsdf::mix::Vertex {
                    key: samples.key(),
                    sample: samples.index(),
                    depth,
                },
                |hit| {
                    let prim = scene.geometry.prim(hit.prim);
                    crate::detail::tangents(&prim, &scene.motions, hit, time)
                },
            );
            let base = match material.kind() {
                material_kind::COATED_DIFFUSE | material_kind::COATED_CONDUCTOR => {
                    Some(&scene.materials[material.k[1] as usize])
                }
                _ => None,
            };
            let sp = ShadingPoint::with_base(&hit, material, base, &scene.tables, wo);
            let dims = first_dim + depth * self.layout.per_vertex;
            // ---- Next-event estimation (non-delta vertices) -------------------------------
            if !sp.bsdf.is_delta() {
                radiance += throughput * self.next_event(&sp, wo, samples, dims, time);
            }
            // ---- BSDF sampling of the continuation ----------------------------------------
            let u_dir = samples.sample_2d(dims + self.layout.direction);
            let u_lobe = self
                .layout
                .lobe
                .map_or(0.0, |d| samples.sample_1d(dims + d));
            let Some(bs) = sp.sample(wo, u_dir, u_lobe, self.settings.strategy) else {
                break;
            };
            throughput *= bs.weight;
            eta_scale *= bs.eta * bs.eta;
            if throughput.max_element() <= 0.0 {
                break;
            }
            // ---- Russian roulette (only when another scattering vertex can follow) --------
            if let Some(d) = self
                .layout
                .roulette
                .filter(|_| depth >= ROULETTE_START && depth + 1 < max_depth)
            {
                let q = (throughput.max_element() * eta_scale).clamp(MIN_SURVIVAL, MAX_SURVIVAL);
                if samples.sample_1d(dims + d) >= q {
                    break;
                }
                throughput /= q;
            }
            // The ray leaves from the offset origin, and emission it finds is weighed against
            // light sampling from there (`next_event` samples from the same point).
            let origin = crate::offset::spawn_origin(sp.p, sp.err, sp.ng, bs.wi);
            prev = PrevVertex {
                p: origin,
                pdf: bs.pdf,
                specular: bs.delta,
            };
            ray = Ray::new(origin, bs.wi, f32::INFINITY);
        }
        radiance
    }

    fn strategy(&self) -> Strategy {
        self.settings.strategy
    }

    /// Light `index` placed at shutter time `time`, with its prepared part.
    fn light(&self, index: u32, time: f32) -> (Light, light::Prepared<'a>) {
        let i = index as usize;
        let (stored, prepared) = (&self.scene.lights[i], &self.prepared[i]);
        if stored.motion == NONE {
            return (*stored, *prepared);
        }
        light::placed_prepared(stored, prepared, &self.scene.motions, time)
    }
}
