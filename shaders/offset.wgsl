// Robust ray origins: Wächter & Binder 2019, "A Fast and Robust Method for Avoiding
// Self-Intersection" (Ray Tracing Gems, ch. 6). Mirrors `crates/cpu/src/offset.rs`.
//
// A hit point is pushed off its surface along the geometric normal by a fixed number of units in
// the last place of each coordinate (integer arithmetic on the float bits), or by a small
// absolute distance near the origin where ULPs are tiny.
//
// Interface (other modules may call these):
//   fn offset_ray_origin(p: vec3f, n: vec3f) -> vec3f     (n: unit normal towards the new ray)
//   fn spawn_origin(p: vec3f, ng: vec3f, dir: vec3f) -> vec3f

// Generated from `stratapt_scene::shared`: below OFFSET_ORIGIN a coordinate is offset by
// OFFSET_FLOAT_SCALE (times the normal) instead of OFFSET_INT_SCALE ULPs.

// `p` moved off the surface to the side of `n` (a unit normal already flipped towards where the
// new ray goes); all three axes at once.
fn offset_ray_origin(p: vec3f, n: vec3f) -> vec3f {
    // Offset in ULPs (truncated towards zero, as Rust's `as i32`); moving the bits of a negative
    // float up moves it further from zero, so negate there. i32 addition wraps like the CPU's.
    let of_i = vec3i(OFFSET_INT_SCALE * n);
    let p_i = bitcast<vec3f>(bitcast<vec3i>(p) + select(of_i, -of_i, p < vec3f(0.0)));
    // Absolute offset near the origin.
    let p_f = p + OFFSET_FLOAT_SCALE * n;
    return select(p_i, p_f, abs(p) < vec3f(OFFSET_ORIGIN));
}

// Origin for a ray leaving the surface point `p` with geometric normal `ng` in direction `dir`:
// offset to the side of `ng` that `dir` points to.
fn spawn_origin(p: vec3f, ng: vec3f, dir: vec3f) -> vec3f {
    let n = select(ng, -ng, dot(ng, dir) < 0.0);
    return offset_ray_origin(p, n);
}
