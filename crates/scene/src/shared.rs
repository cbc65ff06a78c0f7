//! Numbers the CPU reference and the GPU kernel must agree on, each defined once, here. The
//! kernel gets every one as a WGSL `const` generated from these when it is composed
//! (`stratapt_gpu`'s shader composer writes them, with the kinds of [`crate::gpu`] and the
//! sampler and strategy ids, ahead of `shaders/scene.wgsl`).

/// Depth (vertex index, 0 = first hit) from which Russian roulette may end a path.
pub const ROULETTE_START: u32 = 3;
/// Bounds of the roulette's survival probability.
pub const MIN_SURVIVAL: f32 = 0.05;
pub const MAX_SURVIVAL: f32 = 0.95;

/// Shadow rays towards a point on a light stop this fraction of the distance short of it.
pub const SHADOW_STOP_SHORT: f32 = 1e-4;

/// Spherical sampling is used when a polygon's solid angle lies between these bounds, area
/// sampling otherwise (tiny: the spherical construction loses precision; near 2π: it is
/// ill-conditioned). The same values as pbrt-v4 (`TriangleLight`, `lights.h`).
pub const MIN_SPHERICAL_SOLID_ANGLE: f32 = 3e-4;
pub const MAX_SPHERICAL_SOLID_ANGLE: f32 = 6.22;

/// Points closer to a sphere light's centre than this (relative to r², on d²) are treated as
/// inside: a shading point on the sphere itself rounds to either side, and the cone of a point
/// on the surface degenerates to a hemisphere whose samples collapse onto the point.
pub const SPHERE_INSIDE: f32 = 1.0 + 1e-3;
/// Below this sin²θmax (sin² of 1.5°), a sphere light's 1 − cos θmax is computed by its series
/// to avoid cancellation.
pub const SPHERE_SMALL_SIN2: f32 = 0.000_685_23;

/// Ray origins (Wächter & Binder 2019): below this magnitude a coordinate is offset by an
/// absolute distance instead of ULPs.
pub const OFFSET_ORIGIN: f32 = 1.0 / 32.0;
/// Absolute offset (times the normal) for coordinates near the origin.
pub const OFFSET_FLOAT_SCALE: f32 = 1.0 / 65536.0;
/// ULPs (times the normal) for coordinates away from the origin.
pub const OFFSET_INT_SCALE: f32 = 256.0;

/// `1 + 2γ₃` with `γₙ = nε / (1 − nε)`, `ε = 2⁻²⁴`: widening of a slab's exit distance that
/// covers the rounding of `(bound − origin) · (1 / dir)` (pbrt-v4 `Bounds3::IntersectP`).
pub const BVH_EXIT_SCALE: f32 =
    1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);
