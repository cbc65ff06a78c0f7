// needs: frame motion intersect texture
// Surface detail: pbrt-v4's bump maps and normal maps, which tilt a hit's shading normal before
// its material is placed there (MATERIAL_BUMP, MATERIAL_NORMAL_MAP). Mirrors
// `crates/cpu/src/detail.rs`: same formulas, same branches, same order of operations.
//
// Interface (other modules may call these):
//   struct DetailTangents { dpdu: vec3f, dpdv: vec3f, dndu: vec3f, dndv: vec3f }
//   fn detail_tangents(hit: Hit, time: f32) -> DetailTangents
//   fn detail_bump(m: Material, t: DetailTangents, ns: vec3f, uv: vec2f) -> vec3f
//   fn detail_normal_map(m: Material, t: DetailTangents, ns: vec3f, uv: vec2f) -> vec3f

// The shading geometry's partial derivatives at a hit, in world space (detail.rs `Tangents`).
struct DetailTangents {
    dpdu: vec3f,
    dpdv: vec3f,
    dndu: vec3f,
    dndv: vec3f,
}

// The tangents of `hit` (its primitive placed at shutter time `time` if it moves).
fn detail_tangents(hit: Hit, time: f32) -> DetailTangents {
    let prim = prim_at(hit.prim);
    let moving = has_motion() && prim.motion != NONE;
    var pose = motion_pose_identity();
    var p = hit.p;
    var ns = hit.ns;
    if (moving) {
        // Normals go back by the transpose of the world map's inverse transpose: S R⁻¹.
        pose = motion_at(prim.motion, time);
        p = motion_pose_point_to_object(pose, hit.p);
        let back = motion_quat_rotate(motion_quat_conjugate(pose.rotation), hit.ns);
        ns = frame_normalize_or(pose.scale * back, hit.ns);
    }
    var local: DetailTangents;
    if (prim.kind == PRIM_TRIANGLE) {
        local = detail_triangle(prim, ns);
    } else if (prim.kind == PRIM_SPHERE) {
        local = detail_sphere(prim.a, prim.b.x, p);
    } else {
        local = detail_disk(prim.a, prim.b, prim.c.x, p);
    }
    if (!moving) {
        return local;
    }
    // Tangents by R S, the normal's derivatives as normals (R S⁻¹).
    return DetailTangents(
        motion_pose_vector_to_world(pose, local.dpdu),
        motion_pose_vector_to_world(pose, local.dpdv),
        motion_quat_rotate(pose.rotation, local.dndu / pose.scale),
        motion_quat_rotate(pose.rotation, local.dndv / pose.scale),
    );
}

// A triangle's tangents (pbrt-v4's), `ns` its shading normal at the hit (detail.rs `triangle`).
fn detail_triangle(prim: Prim, ns: vec3f) -> DetailTangents {
    let flags = surface_flags(prim.surface);
    var uv0 = vec2f(0.0, 0.0);
    var uv1 = vec2f(1.0, 0.0);
    var uv2 = vec2f(0.0, 1.0);
    if ((flags & SURFACE_UV) != 0u) {
        uv0 = uv_at(prim.points.x);
        uv1 = uv_at(prim.points.y);
        uv2 = uv_at(prim.points.z);
    }
    let duv02 = uv0 - uv2;
    let duv12 = uv1 - uv2;
    let dp02 = prim.a - prim.c;
    let dp12 = prim.b - prim.c;
    let det = duv02.x * duv12.y - duv02.y * duv12.x;
    let inv = 1.0 / det;
    var dpdu = (dp02 * duv12.y - dp12 * duv02.y) * inv;
    var dpdv = (dp12 * duv02.x - dp02 * duv12.x) * inv;
    let across = cross(dpdu, dpdv);
    let degenerate = abs(det) < 1e-9 || dot(across, across) == 0.0;
    if (degenerate) {
        let f = frame_from_normal(frame_normalize_or(cross(dp12, dp02), vec3f(0.0, 0.0, 1.0)));
        dpdu = f.s;
        dpdv = f.t;
    }
    if ((flags & SURFACE_SHADING_NORMALS) == 0u) {
        return DetailTangents(dpdu, dpdv, vec3f(0.0), vec3f(0.0));
    }
    // pbrt's shading tangents: ∂p/∂u without its component along ns, and ns × ∂p/∂u.
    var ts = cross(ns, dpdu);
    var ss: vec3f;
    if (dot(ts, ts) > 0.0) {
        ss = cross(ts, ns);
    } else {
        let f = frame_from_normal(ns);
        ts = f.t;
        ss = f.s;
    }
    // The vertex normals' derivatives (zero where the coordinates are degenerate).
    var dndu = vec3f(0.0);
    var dndv = vec3f(0.0);
    if (!degenerate) {
        let n0 = normal_at(prim.points.x);
        let n1 = normal_at(prim.points.y);
        let n2 = normal_at(prim.points.z);
        let dn1 = n0 - n2;
        let dn2 = n1 - n2;
        dndu = (dn1 * duv12.y - dn2 * duv02.y) * inv;
        dndv = (dn2 * duv02.x - dn1 * duv12.x) * inv;
    }
    return DetailTangents(ss, ts, dndu, dndv);
}

// A sphere's tangents at `p` (u = φ/2π, v = θ/π; detail.rs `sphere`).
fn detail_sphere(center: vec3f, radius: f32, p: vec3f) -> DetailTangents {
    let n = (p - center) / radius;
    let sin_theta = sqrt(n.x * n.x + n.y * n.y);
    var dndu: vec3f;
    var dndv: vec3f;
    if (sin_theta > 1e-6) {
        let cos_phi = n.x / sin_theta;
        let sin_phi = n.y / sin_theta;
        dndu = vec3f(-n.y, n.x, 0.0) * TAU;
        dndv = vec3f(n.z * cos_phi, n.z * sin_phi, -sin_theta) * PI;
    } else {
        let f = frame_from_normal(n);
        dndu = f.s;
        dndv = f.t;
    }
    return DetailTangents(dndu * radius, dndv * radius, dndu, dndv);
}

// A disk's tangents at `p` (u = distance over the radius, v = φ/2π; detail.rs `disk`).
fn detail_disk(center: vec3f, normal: vec3f, radius: f32, p: vec3f) -> DetailTangents {
    let d = p - center;
    let f = frame_from_normal(normal);
    let len = length(d);
    var dpdu = f.s * radius;
    var dpdv = f.t;
    if (len > 0.0) {
        dpdu = d * (radius / len);
        dpdv = cross(normal, d) * TAU;
    }
    return DetailTangents(dpdu, dpdv, vec3f(0.0), vec3f(0.0));
}

// A bump map's height at `uv`: its texture's number, or its constant (detail.rs `bump`).
fn detail_height(m: Material, uv: vec2f) -> f32 {
    if (has_textures() && (m.tag & MATERIAL_COLOR_TEXTURE) != 0u) {
        return texture_eval_scalar(u32(m.color.x), uv);
    }
    return m.color.x;
}

// The shading normal bump map `m` gives a point of shading normal `ns` (pbrt-v4's `BumpMap`,
// finite differences of step DETAIL_BUMP_DELTA; detail.rs `bump`).
fn detail_bump(m: Material, t: DetailTangents, ns: vec3f, uv: vec2f) -> vec3f {
    let d = detail_height(m, uv);
    let du = (detail_height(m, uv + vec2f(DETAIL_BUMP_DELTA, 0.0)) - d) / DETAIL_BUMP_DELTA;
    let dv = (detail_height(m, uv + vec2f(0.0, DETAIL_BUMP_DELTA)) - d) / DETAIL_BUMP_DELTA;
    let dpdu = t.dpdu + ns * du + t.dndu * d;
    let dpdv = t.dpdv + ns * dv + t.dndv * d;
    return detail_facing(cross(dpdu, dpdv), ns);
}

// The shading normal normal map `m` gives a point of shading normal `ns` (pbrt-v4's
// `NormalMap`; detail.rs `normal_map`).
fn detail_normal_map(m: Material, t: DetailTangents, ns: vec3f, uv: vec2f) -> vec3f {
    var c = vec3f(0.5, 0.5, 1.0);
    if (has_textures()) {
        c = texture_eval(u32(m.color.x), uv);
    }
    let local = frame_normalize_or(c * 2.0 - vec3f(1.0), vec3f(0.0));
    let s = frame_normalize_or(t.dpdu - ns * dot(ns, t.dpdu), vec3f(0.0));
    if (all(local == vec3f(0.0)) || all(s == vec3f(0.0))) {
        return ns;
    }
    let frame = Frame(s, cross(ns, s), ns);
    return detail_facing(frame_to_world(frame, local), ns);
}

// `n` normalized and turned to the side of `ns`; `ns` if `n` has no direction.
fn detail_facing(n: vec3f, ns: vec3f) -> vec3f {
    let u = frame_normalize_or(n, vec3f(0.0));
    if (all(u == vec3f(0.0))) {
        return ns;
    }
    return select(u, -u, dot(u, ns) < 0.0);
}
