//! The render parameters uniform (`Params` in `shaders/scene.wgsl`): camera, sampler, strategy,
//! this batch's sample range, light and BVH counts.

use crate::shared::SURFACE_WORDS;
use crate::specialize::Specialization;
use bytemuck::{Pod, Zeroable};
use stratapt_film::twin::{TwinLayout, TWIN_KEY};
use stratapt_scene::records::{Camera, NONE};
use stratapt_scene::{FlatScene, RenderSettings};

/// Mirrors `struct Params` field for field. 336 bytes (asserted below).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Params {
    pub camera: Camera,
    pub sampler: u32,
    /// Samples per pixel of the whole render (sizes the stratified sampler's strata).
    pub spp: u32,
    pub seed: u32,
    pub strategy: u32,
    /// This batch renders samples `sample_base .. sample_base + split · batch_spp` of every
    /// pixel, in `split` slices of `batch_spp` samples, each slice in an invocation of its own.
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
    /// Film rows; virtual rows from here on are the twins (`stratapt_film::twin`), when
    /// `twin_count > 0`.
    pub film_rows: u32,
    /// The [`TwinLayout`]: block side, blocks per row, count (0: no twins), placement key.
    pub twin_block: u32,
    pub twin_blocks_x: u32,
    pub twin_count: u32,
    pub twin_key: u32,
    /// Where the texture coordinates start in the `normals` binding, in `f32`s (after the
    /// shading normals, three per point when there are any; `uv_base`).
    pub uv_base: u32,
    /// Slices each pixel's samples are split into, each with a tile of the accumulator (1: one
    /// invocation renders them all).
    pub split: u32,
    pub _pad: u32,
    /// The scene's specialization as data, for what the kernel decides at run time.
    pub kernel: KernelParams,
    /// Where each of the scene's arrays starts in the uniform scene, read where the kernel reads
    /// that copy (`UNIFORM_SCENE`).
    pub uniform_scene: UniformSceneOffsets,
}

const _: () = assert!(std::mem::size_of::<Params>() == 336);

/// Mirrors `struct UniformSceneOffsets`: where each of the scene's arrays starts in the uniform scene
/// (`uniform_scene` in `shaders/scene.wgsl`), in 16-byte words; the primitives start at 0, the
/// arrays follow in this order ([`UniformSceneOffsets::new`]). 48 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct UniformSceneOffsets {
    pub points: u32,
    pub normals: u32,
    pub surfaces: u32,
    pub materials: u32,
    pub lights: u32,
    pub light_table: u32,
    pub unhittable_table: u32,
    pub motions: u32,
    pub nodes: u32,
    pub _pad: [u32; 3],
}

const _: () = assert!(std::mem::size_of::<UniformSceneOffsets>() == 48);

impl UniformSceneOffsets {
    /// Where `scene`'s arrays start in its uniform scene; the BVH's nodes go last, so that no offset depends
    /// on the BVH layout.
    pub fn new(scene: &FlatScene) -> Self {
        fn words<T>(records: &[T]) -> usize {
            std::mem::size_of_val(records) / 16
        }
        let g = &scene.geometry;
        // Each array starts where the one before it ends (fields initialize in this order).
        let mut end = g.prims.len();
        let mut next = |len: usize| {
            let start = end as u32;
            end += len;
            start
        };
        Self {
            points: next(g.points.len()),
            normals: next(g.normals.len()),
            surfaces: next(g.surfaces.len() * SURFACE_WORDS),
            materials: next(words(&scene.materials)),
            lights: next(words(&scene.lights)),
            light_table: next(words(&scene.light_table)),
            unhittable_table: next(words(&scene.unhittable_table)),
            motions: next(words(&scene.motions)),
            nodes: next(0),
            _pad: [0; 3],
        }
    }
}

/// Mirrors `struct KernelParams`: the scene's [`Specialization`] as data, read by a kernel for what
/// it decides at run time (`RUNTIME_*`; all of it in the generic kernel). 64 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct KernelParams {
    /// [`crate::shared::effect_bit`]s.
    pub effects: u32,
    pub light_kinds: u32,
    pub material_kinds: u32,
    pub dim_pixel: u32,
    pub dim_lens: u32,
    pub dim_time: u32,
    pub dim_first_vertex: u32,
    pub dim_per_vertex: u32,
    pub dim_light_select: u32,
    pub dim_light_point: u32,
    pub dim_direction: u32,
    pub dim_lobe: u32,
    pub dim_roulette: u32,
    pub _pad: [u32; 3],
}

const _: () = assert!(std::mem::size_of::<KernelParams>() == 64);

impl KernelParams {
    /// `spec` as data: the same values its override constants hold.
    pub fn new(spec: &Specialization) -> Self {
        let l = &spec.layout;
        let dim = |d: Option<u32>| d.unwrap_or(NONE);
        Self {
            effects: spec.effect_bits(),
            light_kinds: spec.effects.light_kinds,
            material_kinds: spec.effects.material_kinds,
            dim_pixel: l.pixel,
            dim_lens: dim(l.lens),
            dim_time: dim(l.time),
            dim_first_vertex: l.first_vertex,
            dim_per_vertex: l.per_vertex,
            dim_light_select: dim(l.light_select),
            dim_light_point: dim(l.light_point),
            dim_direction: l.direction,
            dim_lobe: dim(l.lobe),
            dim_roulette: dim(l.roulette),
            _pad: [0; 3],
        }
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
        let spec = Specialization::of(scene, settings);
        Self::for_spec(scene, settings, &spec, sample_base, batch_spp)
    }

    /// [`Params::new`] with the scene's specialization already known (`Specialization::of`,
    /// which walks every primitive).
    pub fn for_spec(
        scene: &FlatScene,
        settings: &RenderSettings,
        spec: &Specialization,
        sample_base: u32,
        batch_spp: u32,
    ) -> Self {
        let twins = TwinLayout::new(scene.camera.width, scene.camera.height);
        Self {
            camera: scene.camera,
            sampler: settings.sampler.id(),
            spp: settings.pattern_spp.max(1),
            seed: settings.seed,
            strategy: settings.strategy.id(),
            sample_base,
            batch_spp,
            max_depth: settings.max_depth,
            light_count: scene.lights.len() as u32,
            env_first: scene.environment_lights().start as u32,
            light_table_len: scene.light_table.len() as u32,
            unhittable_table_len: scene.unhittable_table.len() as u32,
            node_count: scene.bvh.nodes.len() as u32,
            tile_origin: [0, 0],
            tile_size: [scene.camera.width, scene.camera.height],
            film_rows: scene.camera.height,
            twin_block: twins.block,
            twin_blocks_x: twins.blocks_x,
            twin_count: if settings.twins() { twins.count } else { 0 },
            twin_key: TWIN_KEY,
            uv_base: uv_base(scene),
            split: 1,
            _pad: 0,
            kernel: KernelParams::new(spec),
            uniform_scene: UniformSceneOffsets::new(scene),
        }
    }
}

/// Where the texture coordinates start in the `normals` binding (`crate::upload`), in `f32`s.
pub fn uv_base(scene: &FlatScene) -> u32 {
    3 * scene.geometry.normals.len() as u32
}

impl Params {
    /// Film rows plus the virtual rows of the twins: the rows a batch dispatches.
    pub fn rows_with_twins(&self) -> u32 {
        let width = self.camera.width.max(1);
        self.film_rows + self.twin_count.div_ceil(width)
    }

    /// These parameters for the band of `rows` (virtual) film rows from row `first_row`.
    pub fn rows(self, first_row: u32, rows: u32) -> Self {
        Self {
            tile_origin: [0, first_row],
            tile_size: [self.camera.width, rows],
            ..self
        }
    }
}
