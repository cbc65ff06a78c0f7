// needs: nothing
// Robust ray origins: a hit point is moved off its surface by the bound on its own rounding error
// (pbrt-v4 `OffsetRayOrigin`), then each coordinate is stepped OFFSET_INT_SCALE · |n| units in the
// last place (at least one) further in integer arithmetic on the float bits (Wächter & Binder
// 2019, "A Fast and Robust Method for Avoiding Self-Intersection", Ray Tracing Gems ch. 6). No
// absolute term: the error bound scales with the primitive. Mirrors `crates/cpu/src/offset.rs`.
//
// Interface (other modules may call these):
//   fn offset_ray_origin(p: vec3f, err: vec3f, n: vec3f) -> vec3f
//          (err: bound on p's rounding error per axis; n: unit normal towards the new ray)
//   fn offset_spawn_origin(p: vec3f, err: vec3f, ng: vec3f, dir: vec3f) -> vec3f

// `p`, within `err` of its surface, moved off it to the side of `n`; all three axes at once.
fn offset_ray_origin(p: vec3f, err: vec3f, n: vec3f) -> vec3f {
    // The distance widened by its own rounding (offset.rs).
    let q = p + n * (dot(abs(n), err) * (1.0 + GAMMA_5));
    // Steps (truncated towards zero, as Rust's `as i32`; at least one on every axis the normal
    // moves) along the number line: the float as its ordered integer (±0 → 0, negative floats
    // below it), plus the steps, and back.
    let count = max(vec3i(OFFSET_INT_SCALE * abs(n)), vec3i(1));
    let steps = select(select(vec3i(0), -count, n < vec3f(0.0)), count, n > vec3f(0.0));
    let bits = bitcast<vec3i>(q);
    let ordered = select(bits, -(bits & vec3i(0x7fffffff)), bits < vec3i(0));
    let moved = ordered + steps;
    let out = select(vec3u(moved), vec3u(-moved) | vec3u(0x80000000u), moved < vec3i(0));
    // No step keeps the value exactly (a negative zero stays one).
    return select(bitcast<vec3f>(out), q, steps == vec3i(0));
}

// Origin for a ray leaving the surface point `p` (error bound `err`, geometric normal `ng`) in
// direction `dir`: offset to the side of `ng` that `dir` points to.
fn offset_spawn_origin(p: vec3f, err: vec3f, ng: vec3f, dir: vec3f) -> vec3f {
    let n = select(ng, -ng, dot(ng, dir) < 0.0);
    return offset_ray_origin(p, err, n);
}
