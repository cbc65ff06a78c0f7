//! Numbers the CPU reference and the GPU kernel must agree on, each defined once, here. The
//! kernel gets every one as a WGSL `const` generated from these when it is composed
//! (`stratapt_gpu`'s shader composer writes them, with the kinds of [`crate::records`] and the
//! sampler and strategy ids, ahead of `shaders/scene.wgsl`).

/// Depth (vertex index, 0 = first hit) from which Russian roulette may end a path.
pub const ROULETTE_START: u32 = 3;
/// Bounds of the roulette's survival probability, the path's throughput (times η² of its
/// refractions). The upper bound is 1, as in pbrt-v4: a path of full throughput is never
/// ended. Ending one with probability 5 % (the bound was 0.95) and weighting the survivors
/// 1/0.95 each time adds variance and saves nothing, and along chains of lossless bounces (glass
/// and mirrors in a white furnace) it made the weights heavy-tailed, 1.05ᵏ after k vertices,
/// and a few samples then misjudged a pixel's error badly on `scenes/hard/glass-furnace`
/// (measured: docs/measurements/error-estimate.md#russian-roulettes-survival-bound).
pub const MIN_SURVIVAL: f32 = 0.05;
pub const MAX_SURVIVAL: f32 = 1.0;

/// Shadow rays towards a point on a light stop this fraction of the distance short of it.
pub const SHADOW_STOP_SHORT: f32 = 1e-4;

/// A shading point is in a planar light's plane (and receives nothing from it) only on a surface
/// whose geometric normal is parallel to the light's to this cosine (0.8°), besides lying in the
/// plane to within its error bound.
pub const IN_PLANE_COS: f32 = 1.0 - 1e-4;

/// Spherical sampling is used when a polygon's solid angle lies between these bounds, area
/// sampling otherwise (tiny: the spherical construction loses precision; near 2π: it is
/// ill-conditioned). The same values as pbrt-v4 (`TriangleLight`, `lights.h`).
pub const MIN_SPHERICAL_SOLID_ANGLE: f32 = 3e-4;
pub const MAX_SPHERICAL_SOLID_ANGLE: f32 = 6.22;
/// A rectangle or triangle light seen under a small angle is sampled by area, without the
/// spherical construction (a rectangle's costs two `atan2`, a `sin_cos` and eleven square roots
/// per sample): when its squared diameter (a rectangle's diagonal, a triangle's longest edge) is
/// under this fraction of the squared distance from the shading point to its centre, an angular
/// size under 0.5 rad. There the area pdf, in solid angle, changes little over the light, and
/// the spherical method's uniform density gains little: on Mitsuba's Cornell box, whose light
/// most of the room sees under less than that, the CPU reference gains more in time than it
/// loses in variance (measured: docs/measurements/speed.md#small-lights-sampled-by-area).
pub const AREA_SAMPLED_ANGULAR_SIZE_SQ: f32 = 0.25;

/// Points closer to a sphere light's centre than this (relative to r², on d²) are treated as
/// inside: a shading point on the sphere itself rounds to either side, and the cone of a point
/// on the surface degenerates to a hemisphere whose samples collapse onto the point.
pub const SPHERE_INSIDE: f32 = 1.0 + 1e-3;
/// A point within this many times a sphere hit point's error bound (γ₅ of the centre's largest
/// coordinate plus the radius, on each axis) of a sphere light's surface samples it as from
/// inside: far from the origin, where the bound exceeds `SPHERE_INSIDE`'s margin, points of
/// the inside surface round outwards. (The bound's length is √3 of it; twice that, for moving
/// spheres, whose placement adds its own rounding.)
pub const SPHERE_ON_ERROR: f32 = 4.0;
/// Below this sin²θmax (sin² of 1.5°), a sphere light's 1 − cos θmax is computed by its series
/// to avoid cancellation.
pub const SPHERE_SMALL_SIN2: f32 = 0.000_685_23;

/// Ray origins: after moving a hit point off its surface by the bound on its rounding error,
/// each coordinate the normal moves is stepped this many ULPs times the normal's component, at
/// least one, further (integer arithmetic on the bits as Wächter & Binder 2019, who step 256
/// ULPs with no error bound), which covers the rounding of that move as pbrt-v4's one-ULP
/// `NextFloatUp` does, with margin. No absolute term: the offset scales with the primitive, from
/// 10⁻³⁰ to 10³⁰. (256 ULPs 10⁵ from the origin are 2 units: a room there leaked light,
/// measured: docs/measurements/far-from-the-origin.md#ray-origin-offsets-without-an-absolute-step.)
pub const OFFSET_INT_SCALE: f32 = 4.0;

/// Ray origins: the smallest barycentric weight of the point a ray leaves a triangle from. A hit
/// within rounding of an edge left the next ray's origin as close to the plane of the face across
/// a concave edge (a box's inside corner), where that face's hit fell within its own error bound
/// and was dropped: the ray left the closed box (4 rays in 16 million in a rotated box,
/// `crates/cpu/tests/closed_box.rs`; found by the differential check against Mitsuba 3,
/// docs/measurements/mitsuba-diff.md). Moved this far inside (10⁻⁵ of the triangle's heights,
/// 20 times the side test's resolution), the origin is measurably in front of the other face.
pub const EDGE_BARY: f32 = 1e-5;

/// `γₙ = nε / (1 − nε)`, `ε = 2⁻²⁴`: the bound on the relative error of `n` rounded f32
/// operations (Higham; pbrt-v4 `gamma`).
pub const fn gamma(n: u32) -> f32 {
    let e = n as f32 * (f32::EPSILON * 0.5);
    e / (1.0 - e)
}
/// The `γₙ` the intersection error bounds use (pbrt-v4 `Triangle::Intersect`, `Sphere`,
/// `Transform`).
pub const GAMMA_2: f32 = gamma(2);
pub const GAMMA_3: f32 = gamma(3);
pub const GAMMA_5: f32 = gamma(5);
pub const GAMMA_6: f32 = gamma(6);
pub const GAMMA_7: f32 = gamma(7);
pub const GAMMA_8: f32 = gamma(8);
pub const GAMMA_16: f32 = gamma(16);

/// `1 + 2γ₃` with `γₙ = nε / (1 − nε)`, `ε = 2⁻²⁴`: widening of a slab's exit distance that
/// covers the rounding of `(bound − origin) · (1 / dir)` (pbrt-v4 `Bounds3::IntersectP`).
pub const BVH_EXIT_SCALE: f32 = 1.0 + 2.0 * GAMMA_3;
