// Scene data as the shaders see it: the structs of `crates/scene/src/gpu.rs`, field for field,
// the render parameters, the specialization constants, and the bindings of group 0.
//
// The host (`crates/gpu/src/shader.rs`) concatenates this module with the others in `shaders/`
// into one WGSL source; every module may use what is declared here.

const NONE: u32 = 0xffffffffu;
const PI: f32 = 3.14159265358979323846;
const INV_PI: f32 = 0.31830988618379067154;

// ---- Kinds (mirrors `prim_kind`, `material_kind`, `light_kind`, `filter_kind`) -------------
const PRIM_TRIANGLE: u32 = 0u;
const PRIM_SPHERE: u32 = 1u;
const PRIM_DISK: u32 = 2u;

const MATERIAL_DIFFUSE: u32 = 0u;
const MATERIAL_CONDUCTOR: u32 = 1u;
const MATERIAL_DIELECTRIC: u32 = 2u;
const MIRROR_ALPHA: f32 = 1.0e-3;

const LIGHT_TRIANGLE: u32 = 0u;
const LIGHT_RECTANGLE: u32 = 1u;
const LIGHT_DISK: u32 = 2u;
const LIGHT_SPHERE: u32 = 3u;
const LIGHT_LINE: u32 = 4u;
const LIGHT_POINT: u32 = 5u;
const LIGHT_DISTANT: u32 = 6u;
const LIGHT_SKY: u32 = 7u;

const FILTER_BOX: u32 = 0u;
const FILTER_TENT: u32 = 1u;
const FILTER_GAUSSIAN: u32 = 2u;

// Sampler kinds (`SamplerKind as u32`) and strategies (`Strategy as u32`).
const SAMPLER_INDEPENDENT: u32 = 0u;
const SAMPLER_STRATIFIED: u32 = 1u;
const SAMPLER_SOBOL: u32 = 2u;

const STRATEGY_UNIFORM: u32 = 0u;
const STRATEGY_COSINE: u32 = 1u;
const STRATEGY_BSDF: u32 = 2u;
const STRATEGY_LIGHT: u32 = 3u;
const STRATEGY_MIS: u32 = 4u;

// ---- Scene structs (sizes asserted on the host) --------------------------------------------

// 64 bytes.
struct Prim {
    a: vec3f,
    kind: u32,
    b: vec3f,
    material: u32,
    c: vec3f,
    light: u32,
    motion: u32,
    normals: u32,
    _pad0: u32,
    _pad1: u32,
}

// 32 bytes.
struct Material {
    color: vec3f,
    kind: u32,
    emission: vec3f,
    param: f32,
}

// 64 bytes.
struct Light {
    p0: vec3f,
    kind: u32,
    p1: vec3f,
    motion: u32,
    p2: vec3f,
    select_pdf: f32,
    radiance: vec3f,
    unhittable_select_pdf: f32,
}

// 16 bytes.
struct AliasEntry {
    threshold: f32,
    alias_index: u32, // `alias` in gpu.rs (a WGSL keyword)
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
    filter_kind: u32, // `filter` in gpu.rs (a WGSL keyword)
    width: u32,
    height: u32,
    filter_param: f32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
    _pad3: u32,
    _pad4: u32,
}

// Render parameters, one uniform per batch (`crates/gpu/src/params.rs`). 224 bytes.
struct Params {
    camera: Camera,
    // Sampler: kind, samples per pixel of the whole render (the stratification), seed.
    sampler: u32,
    spp: u32,
    seed: u32,
    strategy: u32,
    // This batch: samples `sample_base .. sample_base + batch_spp` of every pixel.
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
    // accumulator holds the tile's pixels row by row.
    tile_origin: vec2u,
    tile_size: vec2u,
    // Film rows; virtual rows from here on are twin pixels (twin.wgsl), when twin_count > 0.
    film_rows: u32,
    // Twin layout: block side, blocks per row, count (0: none), placement key.
    twin_block: u32,
    twin_blocks_x: u32,
    twin_count: u32,
    twin_key: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

// ---- Specialization: effects the scene calls for (`Effects`) and the dimension layout ------
// (`DimLayout`). Set by the host per scene; the defaults enable everything (used by tests).

override HAS_LENS: bool = true;
override HAS_TIME: bool = true;
override HAS_NEE: bool = true;
override HAS_LOBE: bool = true;
override HAS_ROULETTE: bool = true;
override HAS_MOTION: bool = true;
override HAS_SKY: bool = true;
// Bit `1 << kind` for every light kind / material kind present.
override LIGHT_KINDS: u32 = 0xffu;
override MATERIAL_KINDS: u32 = 0x7u;
// The BVH layout in `nodes`: false for the BVH2 (`bvh.wgsl`), true for the compressed wide BVH
// (`cwbvh.wgsl`). Not an effect: the host picks it per adapter.
override BVH_WIDE: bool = true;

override DIM_PIXEL: u32 = 0u;
override DIM_LENS: u32 = 2u;
override DIM_TIME: u32 = 4u;
override DIM_FIRST_VERTEX: u32 = 5u;
override DIM_PER_VERTEX: u32 = 8u;
override DIM_LIGHT_SELECT: u32 = 0u;
override DIM_LIGHT_POINT: u32 = 1u;
override DIM_DIRECTION: u32 = 3u;
override DIM_LOBE: u32 = 5u;
override DIM_ROULETTE: u32 = 6u;

fn has_light_kind(kind: u32) -> bool {
    return (LIGHT_KINDS & (1u << kind)) != 0u;
}

fn has_material_kind(kind: u32) -> bool {
    return (MATERIAL_KINDS & (1u << kind)) != 0u;
}

// ---- Bindings --------------------------------------------------------------------------------

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> prims: array<Prim>;
// Shading normals, 4 floats each (xyz + pad), three per smooth triangle.
@group(0) @binding(2) var<storage, read> normals: array<vec4f>;
@group(0) @binding(3) var<storage, read> materials: array<Material>;
@group(0) @binding(4) var<storage, read> lights: array<Light>;
@group(0) @binding(5) var<storage, read> light_table: array<AliasEntry>;
@group(0) @binding(6) var<storage, read> unhittable_table: array<AliasEntry>;
@group(0) @binding(7) var<storage, read> motions: array<Motion>;
// The BVH, raw: `BvhNode`s, or (`BVH_WIDE`) `CwbvhNode`s followed by their primitive slots.
@group(0) @binding(8) var<storage, read> nodes: array<vec4u>;
// Per pixel, two entries: this batch's sum of samples (rgb) and rays traced (w); its sum of
// squares (rgb) and non-finite samples replaced by zero (w).
@group(0) @binding(9) var<storage, read_write> accum: array<vec4f>;

// +inf, built from bits (WGSL has no infinity literal and constant-folds overflow as an error).
fn f32_infinity() -> f32 {
    return bitcast<f32>(0x7f800000u);
}
