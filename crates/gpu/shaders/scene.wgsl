// needs: nothing
// Scene data as the shaders see it: the structs of `crates/scene/src/records.rs`, field for field,
// the render parameters, the specialization constants, and the bindings of group 0.
//
// The host (`crates/gpu/src/shader.rs`) concatenates this module with the others in `shaders/`
// into one WGSL source; every module may use what is declared here.

// Kinds (`prim_kind`, `material_kind`, `light_kind`, `filter_kind` as PRIM_*, MATERIAL_*,
// LIGHT_*, FILTER_*), sampler and strategy ids (SAMPLER_*, STRATEGY_*), effect bits (EFFECT_*),
// NONE, PI, and every numeric constant shared with the CPU reference are generated from their
// Rust definitions ahead of this module (`shared_constants` in `crates/gpu/src/shader.rs`).

// ---- Scene structs (sizes asserted on the host) --------------------------------------------

// 20 bytes.
struct Surface {
    kind: u32,
    material: u32,
    light: u32,
    motion: u32,
    flags: u32, // SURFACE_SHADING_NORMALS | SURFACE_UV | SURFACE_TEXTURED | SURFACE_ALPHA…
    alpha: u32, // a constant alpha's bits, or its texture's index (SURFACE_ALPHA_TEXTURE)
}

// What intersecting a primitive needs, gathered (`Geometry::prim`): not stored.
struct Prim {
    a: vec3f,
    b: vec3f,
    c: vec3f,
    kind: u32,
    motion: u32,
    // The indices of `a`, `b`, `c` in `points` (and `normals`).
    points: vec3u,
    // Index into `surfaces`.
    surface: u32,
}

// 64 bytes. Which fields a kind reads: `stratapt_scene::records::material_kind`.
struct Material {
    color: vec3f,
    tag: u32,
    emission: vec3f,
    ior: f32,
    eta: vec3f,
    alpha_u: f32,
    k: vec3f,
    alpha_v: f32,
}

// 80 bytes.
struct Light {
    p0: vec3f,
    kind: u32,
    p1: vec3f,
    motion: u32,
    p2: vec3f,
    select_pdf: f32,
    radiance: vec3f,
    unhittable_select_pdf: f32,
    // LIGHT_FLAG_* bits.
    flags: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

// 16 bytes.
struct AliasEntry {
    threshold: f32,
    alias_index: u32, // `alias` in records.rs (a WGSL keyword)
    pdf: f32,
    _pad: u32,
}

// 48 bytes. Object to world is T · R · S; `rotation` is a unit quaternion (x, y, z, w).
struct Pose {
    translation: vec3f,
    _pad0: u32,
    rotation: vec4f,
    scale: vec3f,
    _pad1: u32,
}

// 96 bytes.
struct Motion {
    open: Pose,
    close: Pose,
}

// 32 bytes (two entries of `nodes`, decoded by `bvh_node`).
struct BvhNode {
    min: vec3f,
    prim_count: u32,
    max: vec3f,
    first_index: u32,
}

// 80 bytes (five entries of `nodes`, decoded by `cwbvh_node`). `e_imask`: the grid step
// exponents `e` in bytes 0..2, `imask` in byte 3. Each `vec2u` holds 8 bytes, one per child.
struct CwbvhNode {
    p: vec3f,
    e_imask: u32,
    child_base: u32,
    prim_base: u32,
    child_meta: vec2u,
    child_min_x: vec2u,
    child_max_x: vec2u,
    child_min_y: vec2u,
    child_max_y: vec2u,
    child_min_z: vec2u,
    child_max_z: vec2u,
}

// 128 bytes.
struct Camera {
    eye0: vec3f,
    tan_half_fov: f32,
    target0: vec3f,
    lens_radius: f32,
    up0: vec3f,
    focus_distance: f32,
    eye1: vec3f,
    shutter_open: f32,
    target1: vec3f,
    shutter_close: f32,
    up1: vec3f,
    filter_kind: u32, // `filter` in records.rs (a WGSL keyword)
    width: u32,
    height: u32,
    filter_param: f32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
    _pad3: u32,
    _pad4: u32,
}

// Render parameters, one uniform per batch (`crates/gpu/src/params.rs`). 336 bytes.
struct Params {
    camera: Camera,
    // Sampler: kind, samples per pixel of the whole render (the stratification), seed.
    sampler: u32,
    spp: u32,
    seed: u32,
    strategy: u32,
    // This batch: samples `sample_base .. sample_base + split * batch_spp` of every pixel, in
    // `split` slices of `batch_spp` samples, one invocation each (`id.z`).
    sample_base: u32,
    batch_spp: u32,
    max_depth: u32,
    // Lights: count, first environment light (sky, sun cones: `env_first .. light_count`),
    // entries of the light table and of the unhittable table.
    light_count: u32,
    env_first: u32,
    light_table_len: u32,
    unhittable_table_len: u32,
    node_count: u32,
    // Tile of the film this dispatch covers: its first pixel and its size (width, rows); the
    // accumulator holds the tile's pixels row by row, one tile per slice (`split`).
    tile_origin: vec2u,
    tile_size: vec2u,
    // Film rows; virtual rows from here on are twin pixels (twin.wgsl), when twin_count > 0.
    film_rows: u32,
    // Twin layout: block side, blocks per row, count (0: none), placement key.
    twin_block: u32,
    twin_blocks_x: u32,
    twin_count: u32,
    twin_key: u32,
    // Where the texture coordinates start in `normals`, in f32s (after the shading normals).
    uv_base: u32,
    // Slices each pixel's samples are split into (1: one invocation renders them all).
    split: u32,
    _pad: u32,
    // The specialization as data, for what the kernel decides at run time (`RUNTIME_*`).
    kernel: KernelParams,
    // Where each array starts in `uniform_scene`, when the kernel reads it (`UNIFORM_SCENE`).
    uniform_scene: UniformSceneOffsets,
}

// Where the scene's arrays start in `uniform_scene`, in 16-byte words (the primitives at 0; then
// in this order; `crates/gpu/src/upload.rs`). A point, shading normal or alias entry takes a
// word, a surface two, a material or light four, a motion six. 48 bytes.
struct UniformSceneOffsets {
    points: u32,
    normals: u32,
    surfaces: u32,
    materials: u32,
    lights: u32,
    light_table: u32,
    unhittable_table: u32,
    motions: u32,
    nodes: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

// The scene's effects and dimension layout as data (`crates/gpu/src/params.rs`). 64 bytes.
struct KernelParams {
    effects: u32, // EFFECT_* bits
    light_kinds: u32,
    material_kinds: u32,
    dim_pixel: u32,
    dim_lens: u32,
    dim_time: u32,
    dim_first_vertex: u32,
    dim_per_vertex: u32,
    dim_light_select: u32,
    dim_light_point: u32,
    dim_direction: u32,
    dim_lobe: u32,
    dim_roulette: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

// ---- Specialization: effects the scene calls for (`Effects`) and the dimension layout ------
// (`DimLayout`). Set by the host per scene, by name (`Specialization::constants` in
// `crates/gpu/src/specialize.rs`); the defaults are `Specialization::everything()`, every effect
// compiled in (what probes composed without a specialization get; `crates/gpu/tests/layout.rs`
// holds each default to it). Modules ask through `has_*()` and `dim_*()` below, never the
// constants themselves.

override HAS_LENS: bool = true;
override HAS_TIME: bool = true;
override HAS_NEE: bool = true;
override HAS_LOBE: bool = true;
override HAS_ROULETTE: bool = true;
override HAS_MOTION: bool = true;
override HAS_TEXTURES: bool = true;
override HAS_ALPHA: bool = true;
// Bit `1 << kind` for every light kind / material kind present.
override LIGHT_KINDS: u32 = 0x7ffu;
override MATERIAL_KINDS: u32 = 0x3fffu;
// The BVH layout in `nodes`: false for the BVH2 (`bvh.wgsl`), true for the compressed wide BVH
// (`cwbvh.wgsl`). Not an effect: the host picks it per adapter.
override BVH_WIDE: bool = true;
// The first primitive in `prims_more`, or 0 when `prims` holds them all.
override PRIMS_SPLIT: u32 = 0u;
// The first word of the tables in `tables_more`, or 0 when `tables` holds them all.
override TABLES_SPLIT: u32 = 0u;
// Read the scene's arrays from their copy in `uniform_scene`, not from their storage buffers: set
// where the scene fits the copy (16–64 KiB, as the device binds) on software Vulkan, which
// loads a uniform buffer's elements with one gather but a storage buffer's lane by lane. Not an
// effect: the host picks it per adapter and scene (`SceneBinding` in
// `crates/gpu/src/specialize.rs`). Modules read the arrays through the accessors after the
// bindings (`prim_word`, `point_at`, `surface_at`, `motion_of`, `node_word`, …), never the
// bindings themselves.
override UNIFORM_SCENE: bool = false;

override DIM_PIXEL: u32 = 0u;
override DIM_LENS: u32 = 2u;
override DIM_TIME: u32 = 4u;
override DIM_FIRST_VERTEX: u32 = 5u;
override DIM_PER_VERTEX: u32 = 7u;
override DIM_LIGHT_SELECT: u32 = 0u;
override DIM_LIGHT_POINT: u32 = 1u;
override DIM_DIRECTION: u32 = 3u;
override DIM_LOBE: u32 = 5u;
override DIM_ROULETTE: u32 = 6u;

// Decided at run time instead: an effect (`EFFECT_*` bit), light kind or material kind whose
// bit is set here is compiled in and read from `params.kernel` per dispatch, whatever the
// constants above say; `RUNTIME_DIMS` reads the dimension layout from there too. All zero (the
// default): the specialized kernel. All set: the generic kernel (`Kernel::Generic`). One bit:
// the specialized kernel carrying one unused effect (what `strata bench --kernel effects`
// measures).
override RUNTIME_EFFECTS: u32 = 0u;
override RUNTIME_LIGHT_KINDS: u32 = 0u;
override RUNTIME_MATERIAL_KINDS: u32 = 0u;
override RUNTIME_DIMS: bool = false;

fn kernel_effect(bit: u32, specialized: bool) -> bool {
    if ((RUNTIME_EFFECTS & bit) != 0u) {
        return (params.kernel.effects & bit) != 0u;
    }
    return specialized;
}

fn has_lens() -> bool {
    return kernel_effect(EFFECT_LENS, HAS_LENS);
}

fn has_time() -> bool {
    return kernel_effect(EFFECT_TIME, HAS_TIME);
}

fn has_nee() -> bool {
    return kernel_effect(EFFECT_NEE, HAS_NEE);
}

fn has_lobe() -> bool {
    return kernel_effect(EFFECT_LOBE, HAS_LOBE);
}

fn has_roulette() -> bool {
    return kernel_effect(EFFECT_ROULETTE, HAS_ROULETTE);
}

fn has_motion() -> bool {
    return kernel_effect(EFFECT_MOTION, HAS_MOTION);
}

fn has_textures() -> bool {
    return kernel_effect(EFFECT_TEXTURES, HAS_TEXTURES);
}

fn has_alpha() -> bool {
    return kernel_effect(EFFECT_ALPHA, HAS_ALPHA);
}

fn has_light_kind(kind: u32) -> bool {
    let bit = 1u << kind;
    if ((RUNTIME_LIGHT_KINDS & bit) != 0u) {
        return (params.kernel.light_kinds & bit) != 0u;
    }
    return (LIGHT_KINDS & bit) != 0u;
}

fn has_material_kind(kind: u32) -> bool {
    let bit = 1u << kind;
    if ((RUNTIME_MATERIAL_KINDS & bit) != 0u) {
        return (params.kernel.material_kinds & bit) != 0u;
    }
    return (MATERIAL_KINDS & bit) != 0u;
}

fn kernel_dim(runtime: u32, specialized: u32) -> u32 {
    if (RUNTIME_DIMS) {
        return runtime;
    }
    return specialized;
}

fn dim_pixel() -> u32 {
    return kernel_dim(params.kernel.dim_pixel, DIM_PIXEL);
}

fn dim_lens() -> u32 {
    return kernel_dim(params.kernel.dim_lens, DIM_LENS);
}

fn dim_time() -> u32 {
    return kernel_dim(params.kernel.dim_time, DIM_TIME);
}

fn dim_first_vertex() -> u32 {
    return kernel_dim(params.kernel.dim_first_vertex, DIM_FIRST_VERTEX);
}

fn dim_per_vertex() -> u32 {
    return kernel_dim(params.kernel.dim_per_vertex, DIM_PER_VERTEX);
}

fn dim_light_select() -> u32 {
    return kernel_dim(params.kernel.dim_light_select, DIM_LIGHT_SELECT);
}

fn dim_light_point() -> u32 {
    return kernel_dim(params.kernel.dim_light_point, DIM_LIGHT_POINT);
}

fn dim_direction() -> u32 {
    return kernel_dim(params.kernel.dim_direction, DIM_DIRECTION);
}

fn dim_lobe() -> u32 {
    return kernel_dim(params.kernel.dim_lobe, DIM_LOBE);
}

fn dim_roulette() -> u32 {
    return kernel_dim(params.kernel.dim_roulette, DIM_ROULETTE);
}

// ---- Bindings --------------------------------------------------------------------------------
// The host binds each of these by its name (`binding` in `crates/gpu/src/shared.rs`;
// `crates/gpu/tests/layout.rs` checks every number against it).

@group(0) @binding(0) var<uniform> params: Params;
// The geometry (`crates/scene/src/geometry.rs`), laid out so that ten million triangles fit
// 128 MiB bindings: per primitive three indices into `points` and its surface word (the
// primitives a binding cannot hold continue in `prims_more`); the points (`xyz`); a shading
// normal per point (packed), then texture coordinates per point from `params.uv_base` (each a
// dummy when no surface has any).
@group(0) @binding(1) var<storage, read> prims: array<vec4u>;
@group(0) @binding(2) var<storage, read> prims_more: array<vec4u>;
@group(0) @binding(3) var<storage, read> surfaces: array<Surface>;
@group(0) @binding(4) var<storage, read> points: array<vec4f>;
@group(0) @binding(5) var<storage, read> normals: array<f32>;
@group(0) @binding(6) var<storage, read> materials: array<Material>;
@group(0) @binding(7) var<storage, read> lights: array<Light>;
@group(0) @binding(8) var<storage, read> light_table: array<AliasEntry>;
@group(0) @binding(9) var<storage, read> unhittable_table: array<AliasEntry>;
@group(0) @binding(10) var<storage, read> motions: array<Motion>;
// The BVH, raw: `BvhNode`s, or (`BVH_WIDE`) `CwbvhNode`s followed by their primitive slots.
@group(0) @binding(11) var<storage, read> nodes: array<vec4u>;
// What materials and lights look values up in (`FlatScene::tables`), each from the offset in
// its record: the texture records (first), a rough plastic's coating transmittance
// (TRANSMITTANCE_RES entries from `k.z`), an environment map's texels and distribution (from
// `p2.z`), the textures' texels; as words (`table_f32`, `table_u32`), those a binding cannot
// hold continuing in `tables_more`. Read from here only, never from the uniform scene.
@group(0) @binding(12) var<storage, read> tables: array<u32>;
@group(0) @binding(13) var<storage, read> tables_more: array<u32>;
// Per pixel, two entries: this batch's sum of samples (rgb) and rays traced (w); its sum of
// squares (rgb) and non-finite samples replaced by zero (w).
@group(0) @binding(14) var<storage, read_write> accum: array<vec4f>;
// The scene's read-only arrays above, copied word for word (`crates/gpu/src/upload.rs`), each
// from `params.uniform_scene`'s offset; zeros when the kernel reads the storage buffers instead
// (`UNIFORM_SCENE`). Its size is the device's (`uniform_scene_words`, generated).
@group(0) @binding(15) var<uniform> uniform_scene: array<vec4u, UNIFORM_SCENE_WORDS>;

// Word `i` of `uniform_scene`'s array that starts at `base`.
fn uniform_scene_word(base: u32, i: u32) -> vec4u {
    return uniform_scene[base + i];
}

// Point `i` of the geometry.
fn point_at(i: u32) -> vec3f {
    if (UNIFORM_SCENE) {
        return bitcast<vec3f>(uniform_scene_word(params.uniform_scene.points, i).xyz);
    }
    return points[i].xyz;
}

// The shading normal of point `i` (only for primitives with `shading_normals`).
fn normal_at(i: u32) -> vec3f {
    if (UNIFORM_SCENE) {
        return bitcast<vec3f>(uniform_scene_word(params.uniform_scene.normals, i).xyz);
    }
    return vec3f(normals[3u * i], normals[3u * i + 1u], normals[3u * i + 2u]);
}

// The texture coordinates of point `i` (only for primitives with SURFACE_UV).
fn uv_at(i: u32) -> vec2f {
    let at = params.uv_base + 2u * i;
    return vec2f(normals[at], normals[at + 1u]);
}

// Word `i` of the tables.
fn table_u32(i: u32) -> u32 {
    if (TABLES_SPLIT == 0u || i < TABLES_SPLIT) {
        return tables[i];
    }
    return tables_more[i - TABLES_SPLIT];
}

// Word `i` of the tables, as the number it holds.
fn table_f32(i: u32) -> f32 {
    return bitcast<f32>(table_u32(i));
}

// Primitive `id`'s point indices and surface word.
fn prim_word(id: u32) -> vec4u {
    if (UNIFORM_SCENE) {
        return uniform_scene_word(0u, id);
    }
    if (PRIMS_SPLIT == 0u || id < PRIMS_SPLIT) {
        return prims[id];
    }
    return prims_more[id - PRIMS_SPLIT];
}

// Surface `i`.
fn surface_at(i: u32) -> Surface {
    if (UNIFORM_SCENE) {
        let a = uniform_scene_word(params.uniform_scene.surfaces, 2u * i);
        let b = uniform_scene_word(params.uniform_scene.surfaces, 2u * i + 1u);
        return Surface(a.x, a.y, a.z, a.w, b.x, b.y);
    }
    return surfaces[i];
}

// Material `i`.
fn material_at(i: u32) -> Material {
    if (UNIFORM_SCENE) {
        let a = uniform_scene_word(params.uniform_scene.materials, 4u * i);
        let b = uniform_scene_word(params.uniform_scene.materials, 4u * i + 1u);
        let c = uniform_scene_word(params.uniform_scene.materials, 4u * i + 2u);
        let d = uniform_scene_word(params.uniform_scene.materials, 4u * i + 3u);
        return Material(
            bitcast<vec3f>(a.xyz),
            a.w,
            bitcast<vec3f>(b.xyz),
            bitcast<f32>(b.w),
            bitcast<vec3f>(c.xyz),
            bitcast<f32>(c.w),
            bitcast<vec3f>(d.xyz),
            bitcast<f32>(d.w),
        );
    }
    return materials[i];
}

// Light `i` (at the shutter's opening; `light_placed` moves it).
fn light_at(i: u32) -> Light {
    if (UNIFORM_SCENE) {
        let a = uniform_scene_word(params.uniform_scene.lights, 5u * i);
        let b = uniform_scene_word(params.uniform_scene.lights, 5u * i + 1u);
        let c = uniform_scene_word(params.uniform_scene.lights, 5u * i + 2u);
        let d = uniform_scene_word(params.uniform_scene.lights, 5u * i + 3u);
        let e = uniform_scene_word(params.uniform_scene.lights, 5u * i + 4u);
        return Light(
            bitcast<vec3f>(a.xyz),
            a.w,
            bitcast<vec3f>(b.xyz),
            b.w,
            bitcast<vec3f>(c.xyz),
            bitcast<f32>(c.w),
            bitcast<vec3f>(d.xyz),
            bitcast<f32>(d.w),
            e.x,
            e.y,
            e.z,
            e.w,
        );
    }
    return lights[i];
}

// Light `i`'s probability of being chosen from the table over every light (`Light::select_pdf`
// alone: a storage buffer loads just that word).
fn light_select_pdf(i: u32) -> f32 {
    if (UNIFORM_SCENE) {
        return bitcast<f32>(uniform_scene_word(params.uniform_scene.lights, 5u * i + 2u).w);
    }
    return lights[i].select_pdf;
}

// Material `i`'s emitted radiance alone.
fn material_emission(i: u32) -> vec3f {
    if (UNIFORM_SCENE) {
        return bitcast<vec3f>(uniform_scene_word(params.uniform_scene.materials, 4u * i + 1u).xyz);
    }
    return materials[i].emission;
}

// Surface `i`'s flags alone (SURFACE_SHADING_NORMALS, SURFACE_UV).
fn surface_flags(i: u32) -> u32 {
    if (UNIFORM_SCENE) {
        return uniform_scene_word(params.uniform_scene.surfaces, 2u * i + 1u).x;
    }
    return surfaces[i].flags;
}

// An alias entry from its word.
fn alias_entry(w: vec4u) -> AliasEntry {
    return AliasEntry(bitcast<f32>(w.x), w.y, bitcast<f32>(w.z), w.w);
}

// Entry `i` of the alias table over every light.
fn light_table_at(i: u32) -> AliasEntry {
    if (UNIFORM_SCENE) {
        return alias_entry(uniform_scene_word(params.uniform_scene.light_table, i));
    }
    return light_table[i];
}

// Entry `i` of the alias table over the lights a ray cannot hit.
fn unhittable_table_at(i: u32) -> AliasEntry {
    if (UNIFORM_SCENE) {
        return alias_entry(uniform_scene_word(params.uniform_scene.unhittable_table, i));
    }
    return unhittable_table[i];
}

// Pose `k` of the motions in `uniform_scene` (three words each, two per motion).
fn uniform_scene_pose(k: u32) -> Pose {
    let a = uniform_scene_word(params.uniform_scene.motions, 3u * k);
    let b = uniform_scene_word(params.uniform_scene.motions, 3u * k + 1u);
    let c = uniform_scene_word(params.uniform_scene.motions, 3u * k + 2u);
    return Pose(bitcast<vec3f>(a.xyz), a.w, bitcast<vec4f>(b), bitcast<vec3f>(c.xyz), c.w);
}

// Motion `i`.
fn motion_of(i: u32) -> Motion {
    if (UNIFORM_SCENE) {
        return Motion(uniform_scene_pose(2u * i), uniform_scene_pose(2u * i + 1u));
    }
    return motions[i];
}

// Word `i` of the BVH's raw `nodes`.
fn node_word(i: u32) -> vec4u {
    if (UNIFORM_SCENE) {
        return uniform_scene_word(params.uniform_scene.nodes, i);
    }
    return nodes[i];
}

// The surface of primitive `id`.
fn surface_of(id: u32) -> Surface {
    return surface_at(prim_word(id).w & ~STATIC_TRIANGLE);
}

// Primitive `id`, gathered; a static triangle without reading its surface.
fn prim_at(id: u32) -> Prim {
    let w = prim_word(id);
    let surface = w.w & ~STATIC_TRIANGLE;
    var kind = PRIM_TRIANGLE;
    var motion = NONE;
    if ((w.w & STATIC_TRIANGLE) == 0u) {
        let s = surface_at(surface);
        kind = s.kind;
        motion = s.motion;
    }
    return Prim(point_at(w.x), point_at(w.y), point_at(w.z), kind, motion, w.xyz, surface);
}

// +inf, built from bits (WGSL has no infinity literal and constant-folds overflow as an error).
fn f32_infinity() -> f32 {
    return bitcast<f32>(0x7f800000u);
}
