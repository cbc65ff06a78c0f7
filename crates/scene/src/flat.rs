//! The flattened scene: GPU-layout arrays in BVH order, shared by both renderers.

use crate::records::{AliasEntry, Camera, Light, Material, Motion};
use crate::Geometry;
use crate::RenderSettings;
use glam::Vec3;
use std::path::PathBuf;

/// A loaded, validated, flattened scene.
#[derive(Clone)]
pub struct FlatScene {
    /// The scene file it came from (or a name for scenes built in code).
    pub path: PathBuf,
    pub camera: Camera,
    /// Primitives in BVH order (`bvh.primitive_indices[i] == i`), their points and surfaces.
    pub geometry: Geometry,
    pub materials: Vec<Material>,
    /// Material names, parallel to `materials` (for messages and `strata info`).
    pub material_names: Vec<String>,
    /// What materials and lights look values up in, each from the offset in its record: the
    /// texture records ([`crate::texture`], first), a rough plastic's coating transmittance
    /// ([`crate::coating::TRANSMITTANCE_RES`] entries), an environment map's texels and
    /// distribution ([`crate::environment`]), the textures' texels (last).
    pub tables: Vec<f32>,
    /// Textures ([`crate::texture`]): their records are the first words of `tables`.
    pub textures: u32,
    /// Bytes of `tables` the textures take (records, texels, decode tables).
    pub texture_bytes: u64,
    pub lights: Vec<Light>,
    /// Alias table over all lights, proportional to power (next-event estimation of every light).
    pub light_table: Vec<AliasEntry>,
    /// Alias table over the lights no direction can hit (point, line, delta distant),
    /// proportional to power; empty if there are none.
    pub unhittable_table: Vec<AliasEntry>,
    pub motions: Vec<Motion>,
    /// Index of the sky light in `lights`, or [`crate::records::NONE`].
    pub sky: u32,
    /// BVH2 over `prims` (leaf bounds sweep the whole shutter for moving primitives).
    pub bvh: obvhs::bvh2::Bvh2,
    /// World-space bounds of everything, over the whole shutter.
    pub bounds_min: Vec3,
    pub bounds_max: Vec3,
    /// Render settings from the scene's `[render]` table (defaults where absent).
    pub settings: RenderSettings,
    /// Every pixel's exact value, when the scene states a closed form (`[render] exact`).
    pub exact: Option<[f64; 3]>,
    /// For a scene imported from pbrt-v4: what the import did instead of what the file asked
    /// (warnings), and what it flattened.
    pub import: Option<crate::report::Report>,
}

impl FlatScene {
    /// The lights an escaping ray can see (sun cones, the sky; [`Light::is_environment`]), as
    /// indices into `lights`: the load order puts them last, so both renderers loop over this
    /// range and nothing else decides it.
    pub fn environment_lights(&self) -> std::ops::Range<usize> {
        let first = self
            .lights
            .iter()
            .rposition(|l| !l.is_environment())
            .map_or(0, |i| i + 1);
        first..self.lights.len()
    }

    /// A hash of everything the renderers read (camera and film size, geometry, materials,
    /// lights, motions, sky): equal for the same scene loaded anywhere, different when any of
    /// it changes. Render parts carry it so that parts of different scenes are never merged.
    pub fn content_hash(&self) -> u64 {
        use crate::content_hash::fnv1a_extend;
        use bytemuck::cast_slice;
        let mut h = crate::content_hash::fnv1a(bytemuck::bytes_of(&self.camera));
        let g = &self.geometry;
        h = fnv1a_extend(h, cast_slice(&g.points));
        h = fnv1a_extend(h, cast_slice(&g.normals));
        h = fnv1a_extend(h, cast_slice(&g.prims));
        h = fnv1a_extend(h, cast_slice(&g.surfaces));
        h = fnv1a_extend(h, cast_slice(&self.materials));
        h = fnv1a_extend(h, cast_slice(&self.tables));
        h = fnv1a_extend(h, cast_slice(&self.lights));
        h = fnv1a_extend(h, cast_slice(&self.light_table));
        h = fnv1a_extend(h, cast_slice(&self.unhittable_table));
        h = fnv1a_extend(h, cast_slice(&self.motions));
        fnv1a_extend(h, &self.sky.to_le_bytes())
    }
}
