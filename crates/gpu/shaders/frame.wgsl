// needs: nothing
// Orthonormal frame and the float helpers the warps, BSDFs and lights share. Mirrors
// `crates/sampling/src/frame.rs` for the frame, and glam / `f32` methods for the helpers (WGSL
// has no `is_finite` or `normalize_or`, and its `atan2` is coarse under Vulkan).
//
// Interface (other modules may call):
//   fn frame_is_finite(x: f32) -> bool                 (f32::is_finite via the bits)
//   fn frame_is_finite3(v: vec3f) -> bool
//   fn frame_normalize_or(v: vec3f, fallback: vec3f) -> vec3f   (glam normalize_or)
//   fn frame_lerp3(a: vec3f, b: vec3f, t: f32) -> vec3f          (glam lerp)
//   fn frame_atan2(y: f32, x: f32) -> f32                 (accurate; prefer it to atan2)
//   struct Frame { s: vec3f, t: vec3f, n: vec3f }   (frame.rs; local z is n)
//   fn frame_from_normal(n: vec3f) -> Frame
//   fn frame_to_local(f: Frame, v: vec3f) -> vec3f   fn frame_to_world(f: Frame, v: vec3f) -> vec3f

// ---- Float helpers ---------------------------------------------------------------------------

fn frame_is_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn frame_is_finite3(v: vec3f) -> bool {
    return frame_is_finite(v.x) && frame_is_finite(v.y) && frame_is_finite(v.z);
}

// `v / |v|`, or `fallback` when the reciprocal length is not finite and positive (glam).
fn frame_normalize_or(v: vec3f, fallback: vec3f) -> vec3f {
    let rcp = 1.0 / sqrt(dot(v, v));
    if (frame_is_finite(rcp) && rcp > 0.0) {
        return v * rcp;
    }
    return fallback;
}

// glam's `Vec3::lerp`: a (1 - t) + b t.
fn frame_lerp3(a: vec3f, b: vec3f, t: f32) -> vec3f {
    return a * (1.0 - t) + b * t;
}

// atan2 to ~2 ulp (Cephes `atanf` polynomial, Moshier 1989): the built-in may be off by 4096
// ulp under Vulkan (measured on lavapipe: docs/measurements/lavapipe.md#the-built-in-atan2s-error),
// and the solid angles of `warp.wgsl` subtract atan2s. NaN in, NaN out; atan2(±0, x < 0) = ±π
// as in Rust.
fn frame_atan2(y: f32, x: f32) -> f32 {
    let ax = abs(x);
    let ay = abs(y);
    if (!(ax == ax && ay == ay)) {
        return x + y;
    }
    let big = max(ax, ay);
    // Ratio in [0, 1]; 0/0 stays 0.
    var a = select(min(ax, ay) / big, 0.0, big == 0.0);
    // Reduce to |a| ≤ tan(π/8): atan(a) = π/4 + atan((a − 1)/(a + 1)).
    var r = 0.0;
    if (a > 0.41421356237309504880) {
        r = FRAC_PI_4;
        a = (a - 1.0) / (a + 1.0);
    }
    let z = a * a;
    r += (((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z
        - 3.33329491539e-1) * z * a + a;
    // Back to the octant, the half plane and the sign of y.
    if (ay > ax) {
        r = FRAC_PI_2 - r;
    }
    if (x < 0.0 || (x == 0.0 && bitcast<u32>(x) != 0u)) {
        r = PI - r;
    }
    return select(r, -r, bitcast<u32>(y) >= 0x80000000u);
}

// ---- Orthonormal frame (`crates/sampling/src/frame.rs`) -----------------------------------
struct Frame {
    s: vec3f,
    t: vec3f,
    n: vec3f,
}

// Branchless basis: Duff et al. 2017, "Building an Orthonormal Basis, Revisited" (JCGT 6(1)).
fn frame_from_normal(n: vec3f) -> Frame {
    // Sign of n.z with -0.0 counted as positive (as the CPU does).
    let sign = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let s = vec3f(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let t = vec3f(b, sign + n.y * n.y * a, -n.y);
    return Frame(s, t, n);
}

// World → local coordinates.
fn frame_to_local(f: Frame, v: vec3f) -> vec3f {
    return vec3f(dot(v, f.s), dot(v, f.t), dot(v, f.n));
}

// Local → world coordinates.
fn frame_to_world(f: Frame, v: vec3f) -> vec3f {
    return f.s * v.x + f.t * v.y + f.n * v.z;
}
