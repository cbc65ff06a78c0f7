// needs: frame
// Poses and their interpolation over the shutter: mirrors `crates/scene/src/motion.rs`, with the
// quaternion arithmetic of glam 0.34 (SSE2 path, the one the CPU reference runs) written out so
// the GPU rounds the same way: `Quat * Vec3`, `Quat::slerp` with `acos_approx` and the
// DirectXMath minimax sine, `Quat::normalize` (divide by the length), `Vec3::normalize` (multiply
// by the reciprocal length), `Vec3::lerp` (`a·(1 − s) + b·s`).
//
// Interface (other modules may call these):
//   fn motion_pose_identity() -> Pose
//   fn motion_pose_point_to_world(pose: Pose, p: vec3f) -> vec3f
//   fn motion_pose_point_to_object(pose: Pose, p: vec3f) -> vec3f
//   fn motion_pose_vector_to_world(pose: Pose, v: vec3f) -> vec3f
//   fn motion_pose_vector_to_object(pose: Pose, v: vec3f) -> vec3f   (keeps ray parameters t)
//   fn motion_pose_normal_to_world(pose: Pose, n: vec3f) -> vec3f    (inverse transpose, normalized)
//   fn motion_at(motion_index: u32, time: f32) -> Pose        (reads `motions`; time in [0, 1])
//   fn motion_quat_rotate(q: vec4f, v: vec3f) -> vec3f        (q = (x, y, z, w), unit)
//   fn motion_quat_slerp(a: vec4f, b: vec4f, s: f32) -> vec4f
//   fn motion_normalize(v: vec3f) -> vec3f                    (glam `Vec3::normalize`)
// No `Option` here: a static primitive or light (`motion == NONE`) simply does not call these.

// `1 − f32::EPSILON`: above this |cos θ| slerp falls back to a normalized lerp (glam).
const MOTION_DOT_THRESHOLD: f32 = 1.0 - F32_EPSILON;

// ---- Pose ------------------------------------------------------------------------------------

fn motion_pose_identity() -> Pose {
    return Pose(vec3f(0.0), 0u, vec4f(0.0, 0.0, 0.0, 1.0), vec3f(1.0), 0u);
}

// `Pose::new`: the rotation is renormalized.
fn motion_pose_new(translation: vec3f, rotation: vec4f, scale: vec3f) -> Pose {
    return Pose(translation, 0u, motion_quat_normalize(rotation), scale, 0u);
}

// Object-space point to world: R (S p) + T.
fn motion_pose_point_to_world(pose: Pose, p: vec3f) -> vec3f {
    return motion_quat_rotate(pose.rotation, pose.scale * p) + pose.translation;
}

// World-space point to object: R⁻¹ (p − T) / S.
fn motion_pose_point_to_object(pose: Pose, p: vec3f) -> vec3f {
    let q = motion_quat_conjugate(pose.rotation);
    return motion_quat_rotate(q, p - pose.translation) / pose.scale;
}

// Object-space direction (not normalized) to world: R (S v).
fn motion_pose_vector_to_world(pose: Pose, v: vec3f) -> vec3f {
    return motion_quat_rotate(pose.rotation, pose.scale * v);
}

// World-space direction to object: R⁻¹ v / S (lengths change with scale, so t is preserved).
fn motion_pose_vector_to_object(pose: Pose, v: vec3f) -> vec3f {
    return motion_quat_rotate(motion_quat_conjugate(pose.rotation), v) / pose.scale;
}

// Object-space normal to world by the inverse transpose R S⁻¹, normalized.
fn motion_pose_normal_to_world(pose: Pose, n: vec3f) -> vec3f {
    return motion_normalize(motion_quat_rotate(pose.rotation, n / pose.scale));
}

// ---- Motion ----------------------------------------------------------------------------------

// `Motion::at`: the pose at normalized shutter time `time`: lerp of translation and scale,
// slerp (shortest arc) of the rotation.
fn motion_at(motion_index: u32, time: f32) -> Pose {
    let m = motion_of(motion_index);
    let a = m.open;
    let b = m.close;
    return motion_pose_new(
        frame_lerp3(a.translation, b.translation, time),
        motion_quat_slerp(a.rotation, b.rotation, time),
        frame_lerp3(a.scale, b.scale, time),
    );
}

// ---- glam arithmetic -------------------------------------------------------------------------

// `Vec3::normalize`: times the reciprocal of the length.
fn motion_normalize(v: vec3f) -> vec3f {
    return v * (1.0 / length(v));
}

// `Quat::normalize`: divided by the length.
fn motion_quat_normalize(q: vec4f) -> vec4f {
    return q / length(q);
}

// `Quat::inverse` of a unit quaternion.
fn motion_quat_conjugate(q: vec4f) -> vec4f {
    return vec4f(-q.xyz, q.w);
}

// `Quat * Vec3` (glam SSE2): v (w² − b·b) + b (2 v·b) + (b × v)(2 w).
fn motion_quat_rotate(q: vec4f, v: vec3f) -> vec3f {
    let b = q.xyz;
    let w = q.w;
    return v * (w * w - dot(b, b)) + b * (dot(v, b) * 2.0) + cross(b, v) * (w * 2.0);
}

// `Quat::slerp` (glam): flip to the shorter arc, normalized lerp when nearly parallel, else
// sin-weighted blend (Shoemake 1985).
fn motion_quat_slerp(a: vec4f, b_in: vec4f, s: f32) -> vec4f {
    var b = b_in;
    var d = dot(a, b);
    // The shorter of the two arcs between ±b.
    if (d < 0.0) {
        b = -b;
        d = -d;
    }
    // Nearly equal rotations: normalized lerp avoids dividing by sin θ ≈ 0.
    if (d > MOTION_DOT_THRESHOLD) {
        return motion_quat_normalize(a * (1.0 - s) + b * s);
    }
    let theta = motion_acos_approx(d);
    let scale1 = motion_sin(theta * (1.0 - s));
    let scale2 = motion_sin(theta * s);
    let theta_sin = motion_sin(theta * 1.0);
    return (b * scale2 + a * scale1) / theta_sin;
}

// glam `acos_approx` (DirectXMath `XMScalarAcos`): clamped, 7-degree minimax polynomial.
fn motion_acos_approx(v: f32) -> f32 {
    let nonnegative = v >= 0.0;
    let x = abs(v);
    let root = sqrt(max(1.0 - x, 0.0));
    var result = ((((((-0.0012624911 * x + 0.00667009) * x - 0.017088126) * x + 0.03089188) * x
        - 0.050174303) * x + 0.08897899) * x - 0.2145988) * x + 1.5707963;
    result *= root;
    // acos(x) = π − acos(−x) for x < 0.
    if (nonnegative) {
        return result;
    }
    return PI - result;
}

// glam `m128_sin` (DirectXMath `XMVectorSin`): reduce to [−π, π], reflect into [−π/2, π/2],
// then an 11-degree minimax polynomial.
fn motion_sin(v: f32) -> f32 {
    // Modulo 2π (round half to even, as `m128_round_ties_even`).
    var x = v - TAU * round(v * 0.15915494);
    // sin(x) = sin(±π − x) folds |x| > π/2 into [−π/2, π/2].
    let negative = (bitcast<u32>(x) & 0x80000000u) != 0u;
    let c = select(PI, -PI, negative);
    if (!(abs(x) <= FRAC_PI_2)) {
        x = c - x;
    }
    let x2 = x * x;
    var r = -2.3889859e-8 * x2 + 2.7525562e-6;
    r = r * x2 - 0.00019840874;
    r = r * x2 + 0.008333331;
    r = r * x2 - 0.16666667;
    r = r * x2 + 1.0;
    return r * x;
}
