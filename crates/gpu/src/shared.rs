//! What the host and the kernel share besides struct layouts: the bindings of group 0 by their
//! WGSL names, the sizes of the uniform scene, the traversal stack's depth, the workgroup side
//! and the effect bits. The composer writes the numbers into the kernel as WGSL constants
//! (`shader::shared_constants`); the bindings are declared in `shaders/scene.wgsl` and checked
//! against [`binding::ALL`] by name (`tests/layout.rs`).
//!
//! A leaf: it uses no other module of this crate, so that every module may use it and the
//! module graph stays one-way (`tests/modules.rs`).

/// The bindings of group 0, by the names `shaders/scene.wgsl` declares them with.
pub mod binding {
    /// The render parameters (`params`, a uniform).
    pub const PARAMS: u32 = 0;

    /// The scene's read-only storage arrays, bindings 1 ..= 13 in this order: their WGSL names,
    /// and what they hold (for messages). The primitives and the tables take two bindings each:
    /// as many as one binding holds, and the rest.
    pub const SCENE_ARRAYS: [(&str, &str); 13] = [
        ("prims", "primitives"),
        ("prims_more", "primitives beyond the first binding's"),
        ("surfaces", "surfaces"),
        ("points", "points"),
        ("normals", "shading normals and texture coordinates"),
        ("materials", "materials"),
        ("lights", "lights"),
        ("light_table", "light table"),
        ("unhittable_table", "unhittable light table"),
        ("motions", "motions"),
        ("nodes", "BVH nodes"),
        ("tables", "material, texture and environment-map tables"),
        ("tables_more", "tables beyond the first binding's"),
    ];

    /// The per-pixel accumulator (`accum`, read-write storage), after the scene's arrays.
    pub const ACCUM: u32 = SCENE_ARRAYS.len() as u32 + 1;

    /// The uniform scene (`uniform_scene`): the scene's arrays copied into one uniform buffer.
    pub const UNIFORM_SCENE: u32 = ACCUM + 1;

    /// The binding of the scene array the kernel calls `name` (one of [`SCENE_ARRAYS`]).
    pub fn scene_array(name: &str) -> u32 {
        let index = SCENE_ARRAYS
            .iter()
            .position(|(wgsl, _)| *wgsl == name)
            .unwrap_or_else(|| panic!("no scene array `{name}` in shaders/scene.wgsl"));
        index as u32 + 1
    }

    /// What the scene array the kernel calls `name` holds, in words.
    pub fn describe(name: &str) -> &'static str {
        SCENE_ARRAYS[scene_array(name) as usize - 1].1
    }

    /// Every binding of group 0: `(WGSL name, binding)`.
    pub fn all() -> Vec<(&'static str, u32)> {
        let mut all = vec![("params", PARAMS)];
        all.extend(
            SCENE_ARRAYS
                .iter()
                .map(|(name, _)| (*name, scene_array(name))),
        );
        all.extend([("accum", ACCUM), ("uniform_scene", UNIFORM_SCENE)]);
        all
    }
}

/// 16-byte words of the uniform scene on a device that binds 16 KiB of uniforms, the least any
/// adapter offers (WebGPU's downlevel limit). Every bundled scene fits it: the Cornell box takes
/// under 3 KiB, the mesh scene (182 smooth triangles) about 9 KiB, the largest (64-byte materials).
pub const MIN_UNIFORM_SCENE_WORDS: u32 = 1024;

/// 16-byte words of the largest uniform scene: 64 KiB, what lavapipe and most Vulkan drivers
/// bind (about 1300 triangles with their BVH).
pub const MAX_UNIFORM_SCENE_WORDS: u32 = 4096;

/// 16-byte words of the uniform scene on a device with `limits`: as many as one uniform binding
/// holds, between [`MIN_UNIFORM_SCENE_WORDS`] and [`MAX_UNIFORM_SCENE_WORDS`]. The kernel's
/// `uniform_scene` array is composed with this size (`UNIFORM_SCENE_WORDS`).
pub fn uniform_scene_words(limits: &wgpu::Limits) -> u32 {
    (limits.max_uniform_buffer_binding_size / 16).clamp(
        MIN_UNIFORM_SCENE_WORDS as u64,
        MAX_UNIFORM_SCENE_WORDS as u64,
    ) as u32
}

/// 16-byte words a surface takes in the uniform scene: its 20 bytes, padded. A point and a
/// shading normal take one word each (`xyz`); every other record is a whole number of words.
pub const SURFACE_WORDS: usize = 2;

/// Entries of the traversal stacks in `shaders/bvh.wgsl` and `shaders/cwbvh.wgsl`
/// (`BVH_STACK_SIZE`): the deepest BVH the host uploads.
pub const MAX_BVH_DEPTH: usize = 64;

/// Pixels per side of a workgroup (`@workgroup_size(WORKGROUP_SIDE, WORKGROUP_SIDE)` in
/// `shaders/integrator.wgsl`).
pub const WORKGROUP_SIDE: u32 = 8;

/// Bits of [`Runtime::effects`](crate::Runtime::effects) and of `KernelParams::effects` in
/// `shaders/scene.wgsl` (`EFFECT_*` there, generated from these).
pub mod effect_bit {
    pub const LENS: u32 = 1 << 0;
    pub const TIME: u32 = 1 << 1;
    pub const NEE: u32 = 1 << 2;
    pub const LOBE: u32 = 1 << 3;
    pub const ROULETTE: u32 = 1 << 4;
    /// Object motion ([`Specialization::motion`](crate::Specialization::motion)).
    pub const MOTION: u32 = 1 << 5;
    /// Texture lookups ([`Effects::textures`](stratapt_scene::Effects::textures)).
    pub const TEXTURES: u32 = 1 << 6;
    /// Alpha tests in traversal ([`Effects::alpha`](stratapt_scene::Effects::alpha)).
    pub const ALPHA: u32 = 1 << 7;
    /// Every bit, with its WGSL name.
    pub const ALL: [(&str, u32); 8] = [
        ("LENS", LENS),
        ("TIME", TIME),
        ("NEE", NEE),
        ("LOBE", LOBE),
        ("ROULETTE", ROULETTE),
        ("MOTION", MOTION),
        ("TEXTURES", TEXTURES),
        ("ALPHA", ALPHA),
    ];
}
