//! The render parameters uniform (`Params` in `shaders/scene.wgsl`): camera, sampler, strategy,
//! this batch's sample range, light and BVH counts.

use bytemuck::{Pod, Zeroable};
use stratapt_scene::gpu::Camera;
use stratapt_scene::{FlatScene, RenderSettings, SamplerKind, Strategy};

/// Mirrors `struct Params` field for field. 208 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Params {
    pub camera: Camera,
    pub sampler: u32,
    /// Samples per pixel of the whole render (sizes the stratified sampler's strata).
    pub spp: u32,
    pub seed: u32,
    pub strategy: u32,
    /// This batch renders samples `sample_base .. sample_base + batch_spp` of every pixel.
    pub sample_base: u32,
    pub batch_spp: u32,
    pub max_depth: u32,
    pub light_count: u32,
    /// First environment light (sun cones, sky): environment lights are `env_first ..
    /// light_count` (the scene orders lights so).
    pub env_first: u32,
    pub light_table_len: u32,
    pub unhittable_table_len: u32,
    pub node_count: u32,
    /// Pixel of the film at the dispatch's (0, 0).
    pub tile_origin: [u32; 2],
    /// Pixels the dispatch covers (width, rows) from `tile_origin`; its accumulator holds them
    /// row by row.
    pub tile_size: [u32; 2],
    /// Independent randomizations the samples are split into (`stratapt_sampling::replica`);
    /// the accumulator holds one sum per replica.
    pub replicas: u32,
    pub _pad: [u32; 3],
}

const _: () = assert!(std::mem::size_of::<Params>() == 208);

/// WGSL value of a sampler kind (`SAMPLER_*`).
pub fn sampler_code(kind: SamplerKind) -> u32 {
    match kind {
        SamplerKind::Independent => 0,
        SamplerKind::Stratified => 1,
        SamplerKind::Sobol => 2,
    }
}

/// WGSL value of a strategy (`STRATEGY_*`).
pub fn strategy_code(strategy: Strategy) -> u32 {
    match strategy {
        Strategy::Uniform => 0,
        Strategy::Cosine => 1,
        Strategy::Bsdf => 2,
        Strategy::Light => 3,
        Strategy::Mis => 4,
    }
}

impl Params {
    /// Parameters of the batch `sample_base .. sample_base + batch_spp` over the whole film.
    pub fn new(
        scene: &FlatScene,
        settings: &RenderSettings,
        sample_base: u32,
        batch_spp: u32,
    ) -> Self {
        Self {
            camera: scene.camera,
            sampler: sampler_code(settings.sampler),
            spp: settings.spp.max(1),
            seed: settings.seed,
            strategy: strategy_code(settings.strategy),
            sample_base,
            batch_spp,
            max_depth: settings.max_depth,
            light_count: scene.lights.len() as u32,
            env_first: env_first(scene),
            light_table_len: scene.light_table.len() as u32,
            unhittable_table_len: scene.unhittable_table.len() as u32,
            node_count: scene.bvh.nodes.len() as u32,
            tile_origin: [0, 0],
            tile_size: [scene.camera.width, scene.camera.height],
            replicas: settings.replicas.max(1),
            _pad: [0; 3],
        }
    }
}

/// Index of the first environment light: lights after it are all sun cones or the sky.
fn env_first(scene: &FlatScene) -> u32 {
    use stratapt_scene::gpu::light_kind::{DISTANT, SKY};
    let is_env =
        |l: &stratapt_scene::gpu::Light| l.kind == SKY || (l.kind == DISTANT && l.p2[0] < 1.0);
    let mut first = scene.lights.len();
    while first > 0 && is_env(&scene.lights[first - 1]) {
        first -= 1;
    }
    first as u32
}

impl Params {
    /// These parameters for the band of `rows` film rows from row `first_row`.
    pub fn rows(self, first_row: u32, rows: u32) -> Self {
        Self {
            tile_origin: [0, first_row],
            tile_size: [self.camera.width, rows],
            ..self
        }
    }
}
