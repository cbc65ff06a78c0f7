//! The records of a flattened scene, in the one layout both renderers read: the CPU reference
//! directly, the GPU kernel from the buffers `stratapt_gpu` uploads them into.
//!
//! Every struct here is `#[repr(C)]`, `Pod`, has explicit `_pad` fields, and is mirrored field for
//! field in `shaders/scene.wgsl` (issue 3). Sizes are stated in each doc comment and asserted at
//! compile time below. `vec3` fields are `[f32; 3]` followed by a 4-byte scalar so that each
//! 16-byte row matches WGSL's `vec3<f32>` + scalar packing.

use bytemuck::{Pod, Zeroable};

/// "No index" marker for optional `u32` references (light, motion, sky).
pub const NONE: u32 = u32::MAX;

/// Primitive kinds stored in [`Surface::kind`]. A primitive is three indices into
/// [`crate::Geometry::points`]; what the three points hold depends on the kind.
pub mod prim_kind {
    /// The three vertices.
    pub const TRIANGLE: u32 = 0;
    /// The centre, and a point whose `x` is the radius (the third is unused).
    pub const SPHERE: u32 = 1;
    /// The centre, the unit normal (the emitting / front side), and a point whose `x` is the
    /// radius.
    pub const DISK: u32 = 2;
}

/// Set in a primitive's surface word ([`crate::Geometry::prims`]) when it is a triangle that
/// does not move: ray traversal tests it without reading its surface.
pub const STATIC_TRIANGLE: u32 = 1 << 31;

/// What a primitive is and what it is made of. 24 bytes. Primitives that do not emit share
/// one surface per (kind, material, motion, shading); an emitting primitive has its own (its
/// light).
///
/// Static primitives' points are in world space. A primitive with `motion != NONE` has its
/// points in its object space and is placed at time `t` by [`Motion::at`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct Surface {
    /// One of [`prim_kind`].
    pub kind: u32,
    /// Index into [`crate::FlatScene::materials`].
    pub material: u32,
    /// Index into [`crate::FlatScene::lights`] when the surface emits, else [`NONE`].
    pub light: u32,
    /// Index into [`crate::FlatScene::motions`], or [`NONE`] for static primitives.
    pub motion: u32,
    /// [`surface_flag`]s: whether a triangle interpolates its vertices' shading normals and
    /// texture coordinates, whether it is cut out by an alpha.
    pub flags: u32,
    /// With [`surface_flag::ALPHA`]: the bits of the constant alpha (an `f32` in `[0, 1)`), or
    /// with [`surface_flag::ALPHA_TEXTURE`] too the index of its texture (read as one number).
    pub alpha: u32,
}

/// Flags stored in [`Surface::flags`].
pub mod surface_flag {
    /// Triangles: interpolate the shading normals [`crate::Geometry::normals`] of the vertices
    /// (same space as the vertices); without it the triangle is flat-shaded.
    pub const SHADING_NORMALS: u32 = 1 << 0;
    /// Triangles: interpolate the texture coordinates [`crate::Geometry::uvs`] of the vertices;
    /// without it a triangle's `(u, v)` are its barycentrics of the second and third vertex
    /// (Mitsuba 3's convention for meshes without texture coordinates).
    pub const UV: u32 = 1 << 1;
    /// The material reads a texture: hits compute their texture coordinates (only these, so
    /// that untextured surfaces of a textured scene pay nothing).
    pub const TEXTURED: u32 = 1 << 2;
    /// pbrt-v4's `alpha`: a ray meets the surface only with probability `alpha` at the hit
    /// ([`Surface::alpha`](super::Surface::alpha); [`alpha_passes`](super::alpha_passes)), camera,
    /// bounce and shadow rays alike. Such a
    /// triangle is never a [`STATIC_TRIANGLE`](super::STATIC_TRIANGLE): traversal reads its
    /// surface.
    pub const ALPHA: u32 = 1 << 3;
    /// With [`ALPHA`]: the alpha is a texture, and hits compute their texture coordinates.
    pub const ALPHA_TEXTURE: u32 = 1 << 4;
}

/// Whether a ray along `dir` from `origin` that hits, at a point whose alpha is `alpha`, the
/// primitive whose first point is `first` passes through it (pbrt-v4's stochastic alpha test):
/// never where `alpha ≥ 1`, always where `alpha ≤ 0`, else when a uniform number hashed from the
/// ray and the primitive is at least `alpha`. pbrt-v4 hashes the ray alone, which makes every
/// layer a ray crosses choose alike; the primitive's first point (the same bits on the CPU and
/// the GPU, unlike its index after the BVH build) makes each layer's choice its own, so `n`
/// layers of alpha `a` let `(1 − a)ⁿ` through, not `1 − a`.
pub fn alpha_passes(alpha: f32, origin: [f32; 3], dir: [f32; 3], first: [f32; 3]) -> bool {
    use stratapt_sampling::hash::hash_combine;
    if alpha >= 1.0 {
        return false;
    }
    if alpha <= 0.0 {
        return true;
    }
    let mut h = ALPHA_SALT;
    for v in origin.into_iter().chain(dir).chain(first) {
        h = hash_combine(h, v.to_bits());
    }
    (h >> 8) as f32 * (1.0 / (1u32 << 24) as f32) >= alpha
}

/// Separates [`alpha_passes`]' hashes from the others (`"alph"` in ASCII).
pub const ALPHA_SALT: u32 = 0x616c_7068;

/// Material kinds stored in [`Material::kind`].
pub mod material_kind {
    /// Lambertian; `color` is the albedo.
    pub const DIFFUSE: u32 = 0;
    /// GGX (Trowbridge–Reitz) microfacet conductor with Schlick's Fresnel: `color` is the
    /// normal-incidence reflectance F0, `alpha_u` / `alpha_v` the anisotropic GGX roughness.
    /// Both at most [`MIRROR_ALPHA`](super::MIRROR_ALPHA): a perfect mirror.
    pub const CONDUCTOR: u32 = 1;
    /// Smooth dielectric; `ior` is the index of refraction (inside / outside), `color` a
    /// transmission tint (1 = clear glass).
    pub const DIELECTRIC: u32 = 2;
    /// GGX microfacet conductor with the exact Fresnel reflectance of a complex index of
    /// refraction `eta + i k` (per RGB channel, relative to the outside medium), scaled by the
    /// tint `color`; roughness as [`CONDUCTOR`].
    pub const COMPLEX_CONDUCTOR: u32 = 3;
    /// Rough dielectric: GGX microfacet reflection and transmission; `ior`, `color` as
    /// [`DIELECTRIC`], `alpha_u` / `alpha_v` the GGX roughness (at least one above
    /// [`MIRROR_ALPHA`](super::MIRROR_ALPHA): smoother is the smooth [`DIELECTRIC`]).
    pub const ROUGH_DIELECTRIC: u32 = 4;
    /// Plastic as Mitsuba 3's `plastic`: a diffuse base (`color`) under a smooth dielectric
    /// coating of index `ior` (inside / outside); `eta` holds the coating's specular reflectance
    /// scale, `k[0]` the diffuse Fresnel reflectance of its inside
    /// ([`crate::coating::fresnel_diffuse_reflectance`] of 1/η) and `k[1]` the probability weight
    /// of sampling the coating (Mitsuba's `specular_sampling_weight`).
    pub const PLASTIC: u32 = 5;
    /// Rough plastic as Mitsuba 3's `roughplastic`: [`PLASTIC`] under a GGX coating of roughness
    /// `alpha_u` (= `alpha_v`: isotropic); `k[0]` is the coating's internal reflectance and
    /// `k[2]` the index in [`crate::FlatScene::tables`] of its transmittance table
    /// ([`crate::coating::RoughCoating`]).
    pub const ROUGH_PLASTIC: u32 = 6;
    /// A thin dielectric sheet as pbrt-v4's `thindielectric` and Mitsuba 3's `thindielectric`:
    /// two parallel smooth interfaces of index `ior` with the light's inter-reflections between
    /// them summed, so that light is either mirrored (reflectance `R + T²R / (1 − R²)`) or
    /// passes straight through, unbent; `color` tints the transmission.
    pub const THIN_DIELECTRIC: u32 = 7;
    /// Diffuse reflection and transmission as pbrt-v4's `diffusetransmission`: `color` is the
    /// reflectance (`color / π` on `wo`'s side), `eta` the transmittance (`eta / π` on the other
    /// side).
    pub const DIFFUSE_TRANSMISSION: u32 = 8;
    /// pbrt-v4's `mix`: at each shading point one of two materials, `k[0]` (indices into
    /// [`crate::FlatScene::materials`], as exact floats) or `k[1]`, the second with probability
    /// `alpha_u` (the amount; a texture's index with [`ALPHA_TEXTURE`](super::material_flag::ALPHA_TEXTURE)),
    /// chosen per path vertex by a hash of the path and the mix ([`mix_choice`](super::mix_choice)),
    /// so that both renderers choose alike. Mixes nest at most [`MAX_MIX_DEPTH`](super::MAX_MIX_DEPTH)
    /// deep.
    pub const MIX: u32 = 9;
    /// pbrt-v4's `coateddiffuse`: a dielectric coat over a diffuse base with a scattering slab
    /// between them, evaluated by pbrt's random walk. `ior` is the coat's relative index,
    /// `alpha_u` / `alpha_v` its GGX roughness (a texture with `ALPHA_TEXTURE`), `color` the
    /// slab's single-scattering albedo (`COLOR_TEXTURE`), `eta` = (thickness, Henyey–Greenstein
    /// g, events per walk), `k` = (walks per estimate, the index of the base's record, 0): a
    /// [`DIFFUSE`] record (its own textures).
    pub const COATED_DIFFUSE: u32 = 10;
    /// pbrt-v4's `coatedconductor`: as [`COATED_DIFFUSE`] over a conductor base, a
    /// [`CONDUCTOR`] or [`COMPLEX_CONDUCTOR`] record (whose η and k are relative to the coat, as
    /// pbrt divides them by the coat's index).
    pub const COATED_CONDUCTOR: u32 = 11;
    /// pbrt-v4's bump mapping (`displacement` on a material): the material `k[0]` (an index into
    /// [`crate::FlatScene::materials`], as an exact float), its shading normal first tilted as
    /// if the surface were displaced along it by the height `color[0]` (a texture's index with
    /// [`COLOR_TEXTURE`](super::material_flag::COLOR_TEXTURE), read as one number), by pbrt's
    /// finite differences of step [`BUMP_DELTA`](super::BUMP_DELTA) in `u` and `v`. `emission`
    /// is the material's. Resolved before shading, as [`MIX`] is
    /// ([`MAX_RESOLVE_STEPS`](super::MAX_RESOLVE_STEPS)).
    pub const BUMP: u32 = 12;
    /// pbrt-v4's `normalmap`: the material `k[0]` with its shading normal replaced by texture
    /// `color[0]` (always a texture, with `COLOR_TEXTURE`; its channels read as `2x − 1`), a
    /// direction in the tangent frame of the shading normal and `∂p/∂u`. As [`BUMP`] otherwise.
    pub const NORMAL_MAP: u32 = 13;
    /// The bits of [`Material::tag`](super::Material::tag) that hold the kind; the bits above
    /// are [`material_flag`](super::material_flag)s.
    pub const MASK: u32 = 0xff;
}

/// Flags stored above the kind in [`Material::tag`].
pub mod material_flag {
    /// GGX materials: Smith's separable masking-shadowing `G1(wo) G1(wi)` (Walter et al. 2007,
    /// and what Mitsuba 3 uses) instead of the height-correlated `1 / (1 + Λ(wo) + Λ(wi))`
    /// (Heitz 2014, pbrt-v4), which is exact for the Smith microsurface and the default.
    pub const SEPARABLE_MASKING: u32 = 1 << 8;
    /// Plastics: Mitsuba's `nonlinear`, the diffuse colour's own inter-reflections under the
    /// coating (`diffuse / (1 − diffuse · R_int)` rather than `diffuse / (1 − R_int)`), which
    /// saturates the colour as real plastics do.
    pub const NONLINEAR: u32 = 1 << 9;
    /// The colour (`color`) is a texture: `color[0]` holds its index in
    /// [`crate::FlatScene::tables`]' texture records ([`crate::texture`]), as an exact float.
    pub const COLOR_TEXTURE: u32 = 1 << 10;
    /// The GGX roughness is a texture: `alpha_u` and `alpha_v` hold the indices of the textures
    /// of αu and αv, as exact floats.
    pub const ALPHA_TEXTURE: u32 = 1 << 11;
    /// `eta` (a plastic's specular reflectance, a complex conductor's η) is a texture: `eta[0]`
    /// holds its index.
    pub const ETA_TEXTURE: u32 = 1 << 12;
    /// `k` (a complex conductor's absorption) is a texture: `k[0]` holds its index.
    pub const K_TEXTURE: u32 = 1 << 13;
    /// Every texture flag: a material with none of them reads no texture.
    pub const TEXTURES: u32 = COLOR_TEXTURE | ALPHA_TEXTURE | ETA_TEXTURE | K_TEXTURE;
}

/// The step in `u` and in `v` of [`material_kind::BUMP`]'s finite differences: pbrt-v4's when a
/// ray has no differentials (`du = .0005`); strata traces none.
pub const BUMP_DELTA: f32 = 0.0005;

/// How deep `mix` materials may nest (a mix of mixes of …): the loader refuses deeper ones, and
/// the renderers follow at most this many.
pub const MAX_MIX_DEPTH: u32 = 8;

/// How many records the renderers step through from a surface's material to the one they shade
/// with: each of at most [`MAX_MIX_DEPTH`] mixes and the material at the end may be wrapped in a
/// bump or normal map ([`material_kind::BUMP`]), which is a step of its own.
pub const MAX_RESOLVE_STEPS: u32 = 2 * MAX_MIX_DEPTH + 1;

/// The uniform number in `[0, 1)` that chooses between mix `index`'s two materials at the
/// vertex `depth` of sample `sample` of the pixel whose sampler key is `key`
/// ([`pixel_seed`](stratapt_sampling::hash::pixel_seed)): the four folded by
/// [`hash_combine`](stratapt_sampling::hash::hash_combine) after a salt, the top 24 bits scaled
/// by 2⁻²⁴.
///
/// pbrt-v4 hashes the shading point and the direction instead. Both choose the second material
/// with probability `amount`, independently of everything else the path draws, and keep the
/// choice for every estimate made at the vertex (next-event estimation, BSDF sampling and the
/// MIS weight of what that finds), so the expected image is the same. But the CPU's and the
/// GPU's hit points may differ in their last bits, and a hash of them flips the choice: on
/// `scenes/mix.toml` 64–69 % of the pixels were bit-close against 99 % for the plastics. The
/// path's identity is the same bits on both.
pub fn mix_choice(index: u32, key: u32, sample: u32, depth: u32) -> f32 {
    use stratapt_sampling::hash::hash_combine;
    let mut h = hash_combine(key, MIX_SALT);
    for v in [sample, depth, index] {
        h = hash_combine(h, v);
    }
    (h >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// Separates [`mix_choice`]'s hashes from the sampler's (`"mix"` in ASCII).
pub const MIX_SALT: u32 = 0x006d_6978;

/// Alpha at or below which a conductor is treated as a perfect mirror (delta BSDF): GGX with a
/// smaller alpha is numerically indistinguishable and its pdf overflows f32. An anisotropic
/// conductor is a mirror when both of its alphas are.
pub const MIRROR_ALPHA: f32 = 1.0e-3;

/// A surface material. 64 bytes.
///
/// Which fields a kind reads is listed at [`material_kind`]; the others are zero.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Material {
    /// Albedo (diffuse), F0 (Schlick conductor) or tint (dielectrics, complex conductor).
    pub color: [f32; 3],
    /// One of [`material_kind`] in the low byte ([`Material::kind`]), with
    /// [`material_flag`]s above.
    pub tag: u32,
    /// Emitted radiance from the front side (zero for non-emitters).
    pub emission: [f32; 3],
    /// Index of refraction of a dielectric, smooth or rough (inside / outside).
    pub ior: f32,
    /// Real part η of a complex conductor's index of refraction, per RGB channel; a plastic's
    /// specular reflectance.
    pub eta: [f32; 3],
    /// GGX α along the shading frame's first tangent (conductors, rough dielectrics).
    pub alpha_u: f32,
    /// Imaginary part k (absorption) of a complex conductor's index of refraction; a plastic's
    /// internal reflectance, sampling weight and table index ([`material_kind::PLASTIC`]).
    pub k: [f32; 3],
    /// GGX α along the shading frame's second tangent (conductors, rough dielectrics).
    pub alpha_v: f32,
}

impl Material {
    /// The [`material_kind`].
    pub fn kind(&self) -> u32 {
        self.tag & material_kind::MASK
    }

    /// Whether [`material_flag`] `flag` is set.
    pub fn has(&self, flag: u32) -> bool {
        self.tag & flag != 0
    }
}

/// Texture kinds, in the low byte of [`Texture::tag`].
pub mod texture_kind {
    /// An image, looked up bilinearly ([`crate::texture`]).
    pub const IMAGE: u32 = 0;
    /// A checkerboard of two colours, `value` and `other`, one period per unit of `(u, v)`.
    pub const CHECKERBOARD: u32 = 1;
}

/// How an image's texels are stored, in bits 8..16 of [`Texture::tag`].
pub mod texel_format {
    /// One word per texel: 8-bit red, green, blue (and an unused byte) from the lowest byte up,
    /// sRGB-encoded: decoded to linear per texel, before interpolation, by a table.
    pub const SRGB8: u32 = 0;
    /// As [`SRGB8`], the bytes linear (`x / 255`).
    pub const LINEAR8: u32 = 1;
    /// Three `f32` words per texel, linear RGB.
    pub const RGB32F: u32 = 2;
    /// One `f32` word per texel, linear grey.
    pub const GREY32F: u32 = 3;
}

/// What a lookup outside `[0, 1)` reads, per axis, in bits 16..20 (u) and 20..24 (v) of
/// [`Texture::tag`]: applied to each integer texel index of the bilinear footprint.
pub mod texture_wrap {
    /// Periodic: index `i mod n`.
    pub const REPEAT: u32 = 0;
    /// The edge texel: `clamp(i, 0, n − 1)`.
    pub const CLAMP: u32 = 1;
    /// Reflected copies: `0 1 … n−1 n−1 … 1 0`, repeated.
    pub const MIRROR: u32 = 2;
}

/// Flags of a [`Texture::tag`], from bit 24 up (below them: kind, texel format, wraps).
pub mod texture_flag {
    /// Each channel of the looked-up value (scaled, interpolated) is clamped to `[0, 1]`:
    /// pbrt-v4's `Clamp(texEval(reflectance), 0, 1)` of a diffuse reflectance, per lookup (not
    /// per texel: the interpolation of clamped texels is another function).
    pub const CLAMP: u32 = 1 << 24;
}

/// A texture, in [`crate::FlatScene::tables`] (texture `i` at word `TEXTURE_WORDS · i`). 80 bytes.
///
/// The lookup at `(u, v)` first maps `(u', v') = (u · uv_u.xy + uv_u.z, u · uv_v.xy + uv_v.z)`
/// (row by row: `u' = uv_u[0] u + uv_u[1] v + uv_u[2]`), then reads the image or the
/// checkerboard there; an image's value is multiplied by `value`; with [`texture_flag::CLAMP`]
/// the result is clamped to `[0, 1]`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Texture {
    /// [`texture_kind`] | [`texel_format`] `<< 8` | [`texture_wrap`] of u `<< 16` | of v `<< 20`
    /// | [`texture_flag`]s.
    pub tag: u32,
    /// Images: the word offset of texel `(0, 0)` (the top-left one) in `tables`.
    pub texels: u32,
    pub width: u32,
    pub height: u32,
    /// The first row of the uv transform.
    pub uv_u: [f32; 3],
    /// 8-bit images: the word offset in `tables` of the 256 entries that decode a byte.
    pub decode: u32,
    /// The second row of the uv transform.
    pub uv_v: [f32; 3],
    pub _pad0: u32,
    /// Images: the constant scale; checkerboards: the colour of the cells where
    /// `frac(u') > ½` and `frac(v') > ½` agree.
    pub value: [f32; 3],
    pub _pad1: u32,
    /// Checkerboards: the other cells' colour.
    pub other: [f32; 3],
    pub _pad2: u32,
}

/// Words of a [`Texture`] in [`crate::FlatScene::tables`].
pub const TEXTURE_WORDS: usize = std::mem::size_of::<Texture>() / 4;

/// Light kinds stored in [`Light::kind`].
pub mod light_kind {
    /// Emissive triangle: `p0, p1, p2` are the vertices; emits on the side of (p1-p0)×(p2-p0).
    pub const TRIANGLE: u32 = 0;
    /// Emissive rectangle: `p0` a corner, `p1` and `p2` the two edge vectors from it; emits on
    /// the side of p1×p2. Sampled by spherical-rectangle solid angle (Ureña et al. 2013).
    pub const RECTANGLE: u32 = 1;
    /// Emissive disk: `p0` centre, `p1` unit normal (emitting side), `p2[0]` radius.
    pub const DISK: u32 = 2;
    /// Emissive sphere: `p0` centre, `p2[0]` radius; emits from both sides of its surface
    /// (outwards, and inwards to a point inside).
    pub const SPHERE: u32 = 3;
    /// Line light from `p0` to `p1`: a thin diffuse tube. `radiance` is the radiant intensity per
    /// unit length perpendicular to the line (W·sr⁻¹·m⁻¹); at angle θ to the line an element dl
    /// emits `radiance · sin θ · dl`.
    pub const LINE: u32 = 4;
    /// Point light at `p0`; `radiance` is the radiant intensity (W·sr⁻¹).
    pub const POINT: u32 = 5;
    /// Distant (sun-like) light: `p0` the unit direction *towards* the light, `p2[0]` the cosine
    /// of the cone half-angle (1 = delta direction); `radiance` is the radiance inside the cone,
    /// or the irradiance when the cone is a delta direction.
    pub const DISTANT: u32 = 6;
    /// Sky: radiance `lerp(radiance, p1, 0.5 · (1 + ω·p0))`, with `p0` the unit up direction
    /// (radiance = bottom colour, p1 = top colour). Sampled uniformly over the sphere.
    pub const SKY: u32 = 7;
    /// Environment map ([`crate::environment`]): `p0`, `p1` the first two rows of the rotation
    /// from world to map directions (the third is their cross product), `p2` = (width, height,
    /// offset of its data in [`crate::FlatScene::tables`]); `radiance` its mean radiance over
    /// the sphere (for its power). Importance-sampled by luminance.
    pub const ENVIRONMENT: u32 = 8;
    /// Environment map in pbrt-v4's equal-area octahedral layout
    /// ([`crate::environment::octahedral`]): fields as [`ENVIRONMENT`]'s, width = height.
    pub const OCTAHEDRAL: u32 = 9;
    /// Spot light (pbrt-v4's): a point light at `p0` shining along the unit axis `p1`, its
    /// intensity `radiance` scaled by `smoothstep(p2[0], p2[1], cos θ)` at angle θ from the axis
    /// (`p2[0]` the cosine of the cone's edge, `p2[1]` of where the falloff starts; equal: a hard
    /// edge).
    pub const SPOT: u32 = 10;
}

/// Flags stored in [`Light::flags`].
pub mod light_flag {
    /// A triangle, rectangle or disk that emits from both sides (pbrt-v4's `twosided` area
    /// lights), its radiance the same on each.
    pub const TWO_SIDED: u32 = 1 << 0;
}

/// One light. 80 bytes. Geometry is in object space when `motion != NONE`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Light {
    pub p0: [f32; 3],
    /// One of [`light_kind`].
    pub kind: u32,
    pub p1: [f32; 3],
    /// Index into [`crate::FlatScene::motions`], or [`NONE`].
    pub motion: u32,
    pub p2: [f32; 3],
    /// Probability that [`crate::FlatScene::light_table`] selects this light (0 if it never does).
    pub select_pdf: f32,
    pub radiance: [f32; 3],
    /// Probability that [`crate::FlatScene::unhittable_table`] selects this light.
    pub unhittable_select_pdf: f32,
    /// [`light_flag`]s.
    pub flags: u32,
    pub _pad: [u32; 3],
}

impl Light {
    /// Whether [`light_flag`] `flag` is set.
    pub fn has(&self, flag: u32) -> bool {
        self.flags & flag != 0
    }
}

impl Light {
    /// Whether an escaping ray can see this light (the sky, or a sun with a cone).
    pub fn is_environment(&self) -> bool {
        self.kind == light_kind::SKY
            || self.kind == light_kind::ENVIRONMENT
            || self.kind == light_kind::OCTAHEDRAL
            || (self.kind == light_kind::DISTANT && self.p2[0] < 1.0)
    }
}

/// One entry of a Walker/Vose alias table. 16 bytes.
///
/// Selection: `i = min(floor(u · n), n - 1)`, `v = u · n - i`; choose `i` if `v < threshold`,
/// else `alias`. The selected entry's `pdf` is the probability of the *selected* index.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct AliasEntry {
    pub threshold: f32,
    pub alias: u32,
    /// Probability of selecting index `i` (this entry's own index).
    pub pdf: f32,
    pub _pad: u32,
}

/// A rigid-body pose: translation, rotation (unit quaternion xyzw) and per-axis scale.
/// Object-to-world is `T · R · S`. 48 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Pose {
    pub translation: [f32; 3],
    pub _pad0: u32,
    pub rotation: [f32; 4],
    pub scale: [f32; 3],
    pub _pad1: u32,
}

/// Object motion during the shutter: a pose at open (`t = 0`) and at close (`t = 1`),
/// interpolated by lerp (translation, scale) and slerp (rotation). 96 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Motion {
    pub open: Pose,
    pub close: Pose,
}

/// Pixel filter kinds stored in [`Camera::filter`]; every filter is importance-sampled exactly,
/// so each sample has weight 1.
pub mod filter_kind {
    /// Box of width `filter_param` pixels (default 1).
    pub const BOX: u32 = 0;
    /// Tent of radius `filter_param` pixels (default 1).
    pub const TENT: u32 = 1;
    /// Untruncated Gaussian of standard deviation `filter_param` pixels (default 0.5),
    /// sampled by Box–Muller.
    pub const GAUSSIAN: u32 = 2;
}

/// Camera and film. 128 bytes.
///
/// The pose at normalized shutter time `t` is `eye = lerp(eye0, eye1, t)`,
/// `target = lerp(target0, target1, t)`, `up = normalize(lerp(up0, up1, t))`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Camera {
    pub eye0: [f32; 3],
    /// `tan(fov_y / 2)`.
    pub tan_half_fov: f32,
    pub target0: [f32; 3],
    /// Thin-lens aperture radius in scene units; 0 is a pinhole.
    pub lens_radius: f32,
    pub up0: [f32; 3],
    /// Distance from the eye to the plane in focus.
    pub focus_distance: f32,
    pub eye1: [f32; 3],
    pub shutter_open: f32,
    pub target1: [f32; 3],
    pub shutter_close: f32,
    pub up1: [f32; 3],
    /// One of [`filter_kind`].
    pub filter: u32,
    pub width: u32,
    pub height: u32,
    pub filter_param: f32,
    pub _pad0: u32,
    pub _pad1: [u32; 4],
}

/// One BVH2 node as the shaders read it (obvhs's `Bvh2Node` repacked). 32 bytes.
///
/// `prim_count == 0`: an inner node whose children are nodes `first_index` and
/// `first_index + 1`. Otherwise a leaf holding primitives `first_index .. first_index +
/// prim_count` (indices of the primitives of [`crate::FlatScene::geometry`], which are in leaf order).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    pub min: [f32; 3],
    pub prim_count: u32,
    pub max: [f32; 3],
    pub first_index: u32,
}

impl BvhNode {
    /// The node's layout on the GPU.
    pub fn from_obvhs(node: &obvhs::bvh2::node::Bvh2Node) -> Self {
        Self {
            min: node.aabb.min.into(),
            prim_count: node.prim_count,
            max: node.aabb.max.into(),
            first_index: node.first_index,
        }
    }
}

/// Sky / environment seen by escaping rays is a [`light_kind::SKY`] light; this is the index of
/// it in `lights`, or [`NONE`] (black background).
pub type SkyIndex = u32;

const _: () = assert!(std::mem::size_of::<Surface>() == 24);
const _: () = assert!(std::mem::size_of::<Material>() == 64);
const _: () = assert!(std::mem::size_of::<Light>() == 80);
const _: () = assert!(std::mem::size_of::<Texture>() == 80);
const _: () = assert!(std::mem::size_of::<AliasEntry>() == 16);
const _: () = assert!(std::mem::size_of::<Pose>() == 48);
const _: () = assert!(std::mem::size_of::<Motion>() == 96);
const _: () = assert!(std::mem::size_of::<Camera>() == 128);
const _: () = assert!(std::mem::size_of::<BvhNode>() == 32);
