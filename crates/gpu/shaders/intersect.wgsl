// needs: frame motion sampler texture
// Ray–primitive intersection and the surface geometry at a hit. Mirrors
// `crates/cpu/src/intersect.rs` and `intersect/{triangle,sphere,disk}.rs`, same formulas, same
// branches, same order of operations.
//
// Static primitives are tested in world space. A moving primitive (`Prim::motion != NONE`) is
// stored in object space: the ray is taken there by the pose at the ray's time (ray parameters
// `t` are preserved because directions are not renormalized), and the hit geometry is brought
// back to world space (points by the pose, normals by its inverse transpose).
//
// `Option<f32>` distances become an `f32` that is +inf on a miss (callers test `t < tmax`);
// `Option<TriangleHit>` becomes `IntersectTriangleHit` with a `valid` flag.
//
// Interface (other modules may call these):
//   struct Ray { origin: vec3f, dir: vec3f, tmin: f32, tmax: f32 }
//   struct Hit { t: f32, prim: u32, p: vec3f, err: vec3f, ng: vec3f, ns: vec3f, uv: vec2f }
//   fn ray_new(origin: vec3f, dir: vec3f, tmax: f32) -> Ray              (tmin = 0)
//   fn intersect_ray_to_object(ray: Ray, pose: Pose) -> Ray
//   fn intersect_shear_new(d: vec3f) -> IntersectShear
//   fn intersect_prim(prim: Prim, ray: Ray, time: f32) -> f32            (+inf on a miss)
//   fn intersect_prim_sheared(prim: Prim, ray: Ray, shear: IntersectShear, time: f32) -> f32
//   fn intersect_surface(prim_index: u32, ray: Ray, t: f32, time: f32) -> Hit
//   fn intersect_triangle(a, b, c, o: vec3f, s: IntersectShear, tmin, tmax: f32)
//          -> IntersectTriangleHit
//   fn intersect_sphere(center: vec3f, radius: f32, o, d: vec3f, tmin, tmax: f32) -> f32
//   fn intersect_disk(center, normal: vec3f, radius: f32, o, d: vec3f, tmin, tmax: f32) -> f32
//   fn intersect_disk_project(center, normal, p: vec3f) -> vec3f

// A ray segment `origin + t·dir`, `t ∈ (tmin, tmax)`; `dir` is unit length for world rays.
struct Ray {
    origin: vec3f,
    dir: vec3f,
    tmin: f32,
    tmax: f32,
}

// Surface geometry at a ray hit, in world space: distance along the ray, primitive index,
// the point recomputed from the surface, the bound on its coordinates' rounding error (how far
// `offset_spawn_origin` moves off the surface), the unit geometric normal on the primitive's front side
// and the unit shading normal (neither flipped towards the ray), and the texture coordinates
// (computed only on SURFACE_TEXTURED surfaces of a scene with textures, else zero).
struct Hit {
    t: f32,
    prim: u32,
    p: vec3f,
    err: vec3f,
    ng: vec3f,
    ns: vec3f,
    uv: vec2f,
}

// The per-ray part of the triangle test: axis permutation and shear.
struct IntersectShear {
    kx: u32,
    ky: u32,
    kz: u32,
    sx: f32,
    sy: f32,
    sz: f32,
}

// A triangle hit: distance and the barycentric weights of (a, b, c).
struct IntersectTriangleHit {
    valid: bool,
    t: f32,
    bary: vec3f,
}

fn ray_new(origin: vec3f, dir: vec3f, tmax: f32) -> Ray {
    return Ray(origin, dir, 0.0, tmax);
}

// The same ray in the object space of `pose` (t unchanged).
fn intersect_ray_to_object(ray: Ray, pose: Pose) -> Ray {
    let origin = motion_pose_point_to_object(pose, ray.origin);
    return Ray(origin, motion_pose_vector_to_object(pose, ray.dir), ray.tmin, ray.tmax);
}

// ---- Primitives ------------------------------------------------------------------------------

// Distance to `prim` along `ray` within (tmin, tmax), or +inf on a miss.
fn intersect_prim(prim: Prim, ray: Ray, time: f32) -> f32 {
    return intersect_prim_sheared(prim, ray, intersect_shear_new(ray.dir), time);
}

// `intersect_prim` with the world ray's shear precomputed (a moving primitive computes its own
// in object space); +inf also where the primitive's alpha lets the ray through
// (`intersect_alpha_passes`).
fn intersect_prim_sheared(prim: Prim, ray: Ray, shear: IntersectShear, time: f32) -> f32 {
    var local = ray;
    var h: IntersectTriangleHit;
    if (has_motion() && prim.motion != NONE) {
        local = intersect_ray_to_object(ray, motion_at(prim.motion, time));
        h = intersect_local(prim, local, intersect_shear_new(local.dir));
    } else {
        h = intersect_local(prim, ray, shear);
    }
    if (!h.valid) {
        return f32_infinity();
    }
    if (has_alpha()) {
        let surface = surface_at(prim.surface);
        if ((surface.flags & SURFACE_ALPHA) != 0u) {
            var alpha = bitcast<f32>(surface.alpha);
            if ((surface.flags & SURFACE_ALPHA_TEXTURE) != 0u) {
                alpha = texture_eval_scalar(surface.alpha, intersect_hit_uv(prim, local, h));
            }
            if (intersect_alpha_passes(alpha, ray.origin, ray.dir, prim.a)) {
                return f32_infinity();
            }
        }
    }
    return h.t;
}

// Intersection in the primitive's own space: the distance and a triangle's barycentrics.
fn intersect_local(prim: Prim, r: Ray, shear: IntersectShear) -> IntersectTriangleHit {
    if (prim.kind == PRIM_TRIANGLE) {
        return intersect_triangle(prim.a, prim.b, prim.c, r.origin, shear, r.tmin, r.tmax);
    }
    var t = f32_infinity();
    if (prim.kind == PRIM_SPHERE) {
        t = intersect_sphere(prim.a, prim.b.x, r.origin, r.dir, r.tmin, r.tmax);
    } else if (prim.kind == PRIM_DISK) {
        t = intersect_disk(prim.a, prim.b, prim.c.x, r.origin, r.dir, r.tmin, r.tmax);
    }
    return IntersectTriangleHit(t < f32_infinity(), t, vec3f(0.0));
}

// The texture coordinates of hit `h` along the object-space ray `r`, as `intersect_surface`
// computes them (intersect.rs `hit_uv`).
fn intersect_hit_uv(prim: Prim, r: Ray, h: IntersectTriangleHit) -> vec2f {
    if (prim.kind == PRIM_TRIANGLE) {
        return intersect_triangle_uv(prim, h.bary);
    }
    if (prim.kind == PRIM_SPHERE) {
        return intersect_sphere_uv(motion_normalize(r.origin + h.t * r.dir - prim.a));
    }
    let p = intersect_disk_project(prim.a, prim.b, r.origin + h.t * r.dir);
    return intersect_disk_uv(prim.a, prim.b, prim.c.x, p);
}

// Whether a ray (origin, dir) through a point of alpha `alpha` of the primitive whose first
// point is `first` passes through it (records.rs `alpha_passes`).
fn intersect_alpha_passes(alpha: f32, origin: vec3f, dir: vec3f, first: vec3f) -> bool {
    if (alpha >= 1.0) {
        return false;
    }
    if (alpha <= 0.0) {
        return true;
    }
    var h = INTERSECT_ALPHA_SALT;
    for (var k = 0u; k < 3u; k++) {
        h = sampler_hash_combine(h, bitcast<u32>(origin[k]));
    }
    for (var k = 0u; k < 3u; k++) {
        h = sampler_hash_combine(h, bitcast<u32>(dir[k]));
    }
    for (var k = 0u; k < 3u; k++) {
        h = sampler_hash_combine(h, bitcast<u32>(first[k]));
    }
    return f32(h >> 8u) * (1.0 / 16777216.0) >= alpha;
}

// Full surface geometry for a hit on primitive `prim_index` at distance `t` along `ray` (as found
// by `intersect_prim`).
fn intersect_surface(prim_index: u32, ray: Ray, t: f32, time: f32) -> Hit {
    let prim = prim_at(prim_index);
    let moving = has_motion() && prim.motion != NONE;
    var pose = motion_pose_identity();
    var r = ray;
    if (moving) {
        pose = motion_at(prim.motion, time);
        r = intersect_ray_to_object(ray, pose);
    }
    let a = prim.a;
    let b = prim.b;
    let c = prim.c;
    // Object-space point, its error bound and normals.
    var p: vec3f;
    var err: vec3f;
    var ng: vec3f;
    var ns: vec3f;
    var uv = vec2f(0.0);
    // Texture coordinates only on textured surfaces of a textured scene.
    let textured = has_textures() && (surface_flags(prim.surface) & SURFACE_TEXTURED) != 0u;
    if (prim.kind == PRIM_TRIANGLE) {
        // Barycentrics of the hit (the centroid if the unbounded re-test misses).
        let shear = intersect_shear_new(r.dir);
        let h = intersect_triangle(a, b, c, r.origin, shear, -F32_MAX, F32_MAX);
        let bary = select(vec3f(1.0 / 3.0), h.bary, h.valid);
        // The point, moved off the edges by EDGE_BARY (rays leave from it: shared.rs).
        let w0 = max(bary, vec3f(EDGE_BARY));
        let w = w0 / (w0.x + w0.y + w0.z);
        p = a * w.x + b * w.y + c * w.z;
        // Interpolation rounds by at most γ₇ Σ|bᵢ pᵢ| off the plane (pbrt-v4).
        // On every axis at its largest (intersect.rs: an exact axis would offset by denormals).
        err = vec3f(GAMMA_7 * intersect_max3(abs(a * w.x) + abs(b * w.y) + abs(c * w.z)));
        // A sliver hit edge-on has no normal: face the ray.
        ng = frame_normalize_or(intersect_triangle_normal(a, b, c), -motion_normalize(r.dir));
        ns = intersect_shading_normal(prim, bary, ng);
        if (textured) {
            uv = intersect_triangle_uv(prim, bary);
        }
    } else if (prim.kind == PRIM_SPHERE) {
        // Reproject onto the sphere.
        let n = motion_normalize(r.origin + t * r.dir - a);
        let rn = b.x * n;
        p = a + rn;
        err = vec3f(GAMMA_5 * intersect_max3(abs(a) + abs(rn)));
        ng = n;
        ns = n;
        if (textured) {
            uv = intersect_sphere_uv(n);
        }
    } else {
        let q = r.origin + t * r.dir;
        p = intersect_disk_project(a, b, q);
        let m = abs(a) + abs(q);
        err = vec3f(GAMMA_7 * max(max(m.x, m.y), m.z));
        ng = b;
        ns = b;
        if (textured) {
            uv = intersect_disk_uv(a, b, c.x, p);
        }
    }
    if (moving) {
        let p_world = motion_pose_point_to_world(pose, p);
        let ng_world = motion_pose_normal_to_world(pose, ng);
        let err_world = intersect_pose_error(pose, p, err);
        let ns_world = motion_pose_normal_to_world(pose, ns);
        return Hit(t, prim_index, p_world, err_world, ng_world, ns_world, uv);
    }
    return Hit(t, prim_index, p, err, ng, ns, uv);
}

// A triangle's texture coordinates at `bary`: its vertices' interpolated (SURFACE_UV), else the
// barycentrics of b and c (intersect.rs).
fn intersect_triangle_uv(prim: Prim, bary: vec3f) -> vec2f {
    if ((surface_flags(prim.surface) & SURFACE_UV) == 0u) {
        return bary.yz;
    }
    let v = prim.points;
    return uv_at(v.x) * bary.x + uv_at(v.y) * bary.y + uv_at(v.z) * bary.z;
}

// A sphere's (u, v) at unit offset `n` from its centre (intersect.rs `sphere_uv`).
fn intersect_sphere_uv(n: vec3f) -> vec2f {
    var u = frame_atan2(n.y, n.x) * (0.5 / PI);
    u = select(u, u + 1.0, u < 0.0);
    let v = frame_atan2(sqrt(n.x * n.x + n.y * n.y), n.z) * (1.0 / PI);
    return vec2f(u, v);
}

// A disk's (u, v) at its point `p` (intersect.rs `disk_uv`).
fn intersect_disk_uv(center: vec3f, normal: vec3f, radius: f32, p: vec3f) -> vec2f {
    let f = frame_from_normal(normal);
    let d = p - center;
    let x = dot(d, f.s);
    let y = dot(d, f.t);
    var v = frame_atan2(y, x) * (0.5 / PI);
    v = select(v, v + 1.0, v < 0.0);
    return vec2f(sqrt(x * x + y * y) / radius, v);
}

// Error bound of `motion_pose_point_to_world(pose, p)` for an object-space point with error bound `err`
// (the scaled error rotated, the transform's own rounding, and the way back to object space).
fn intersect_pose_error(pose: Pose, p: vec3f, err: vec3f) -> vec3f {
    let scaled = length(pose.scale * p);
    let moved = length(pose.translation);
    let rotated = length(abs(pose.scale) * err) * (1.0 + GAMMA_3) + GAMMA_8 * scaled;
    return vec3f(rotated + GAMMA_8 * (scaled + moved) + GAMMA_3 * rotated);
}

// Interpolated vertex normal, or `ng` for flat shading (or a degenerate interpolation).
fn intersect_shading_normal(prim: Prim, bary: vec3f, ng: vec3f) -> vec3f {
    if ((surface_flags(prim.surface) & SURFACE_SHADING_NORMALS) == 0u) {
        return ng;
    }
    let v = prim.points;
    let n = normal_at(v.x) * bary.x + normal_at(v.y) * bary.y + normal_at(v.z) * bary.z;
    let ns = frame_normalize_or(n, vec3f(0.0));
    if (all(ns == vec3f(0.0))) {
        return ng;
    }
    return ns;
}

// ---- Triangle: Woop, Benthin, Wald 2013, "Watertight Ray/Triangle Intersection" (JCGT 2(1)) --

// Permute axes so that z is the ray's dominant axis (keeping the winding), and shear so that the
// ray points along +z.
fn intersect_shear_new(d: vec3f) -> IntersectShear {
    // Index of the largest |d| component (first one on ties, as glam `max_position`).
    let ad = abs(d);
    var kz = 0u;
    var m = ad.x;
    if (ad.y > m) {
        kz = 1u;
        m = ad.y;
    }
    if (ad.z > m) {
        kz = 2u;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kx + 1u) % 3u;
    // A negative dominant component swaps x and y to keep the winding.
    if (d[kz] < 0.0) {
        let k = kx;
        kx = ky;
        ky = k;
    }
    let sz = 1.0 / d[kz];
    return IntersectShear(kx, ky, kz, d[kx] * sz, d[ky] * sz, sz);
}

// Intersect the ray `o + t·d` (its shear `s`), `t ∈ (tmin, tmax)`, with triangle (a, b, c), both
// sides. Edge functions exactly zero count as inside (watertight across shared edges).
fn intersect_triangle(
    a: vec3f, b: vec3f, c: vec3f, o: vec3f, s: IntersectShear, tmin: f32, tmax: f32,
) -> IntersectTriangleHit {
    let miss = IntersectTriangleHit(false, f32_infinity(), vec3f(0.0));
    // Vertices relative to the origin, permuted.
    let pa = a - o;
    let pb = b - o;
    let pc = c - o;
    let az = pa[s.kz];
    let bz = pb[s.kz];
    let cz = pc[s.kz];
    // Sheared into the ray's frame.
    let ax = pa[s.kx] - s.sx * az;
    let ay = pa[s.ky] - s.sy * az;
    let bx = pb[s.kx] - s.sx * bz;
    let by = pb[s.ky] - s.sy * bz;
    let cx = pc[s.kx] - s.sx * cz;
    let cy = pc[s.ky] - s.sy * cz;
    // Scaled barycentrics: 2D edge functions; mixed signs miss (zero counts as inside).
    let uvw = vec3f(cx * by - cy * bx, ax * cy - ay * cx, bx * ay - by * ax);
    if (any(uvw < vec3f(0.0)) && any(uvw > vec3f(0.0))) {
        return miss;
    }
    let det = uvw.x + uvw.y + uvw.z;
    if (det == 0.0) {
        return miss;
    }
    // Scaled distance, then the true one.
    let zs = s.sz * vec3f(az, bz, cz);
    let t_scaled = uvw.x * zs.x + uvw.y * zs.y + uvw.z * zs.z;
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    if (!(t > tmin && t < tmax)) {
        return miss;
    }
    // A distance within its own rounding error is a hit only when the ray measurably starts in
    // front of the plane and heads into it (triangle.rs).
    let max_x = intersect_max3(abs(vec3f(ax, bx, cx)));
    let max_y = intersect_max3(abs(vec3f(ay, by, cy)));
    let max_z = intersect_max3(abs(zs));
    if (t <= intersect_t_error_bound(max_x, max_y, max_z, intersect_max3(abs(uvw)), inv_det)
        && !intersect_heads_into_plane(pa, pb, pc, s)) {
        return miss;
    }
    return IntersectTriangleHit(true, t, uvw * inv_det);
}

// Conservative bound on the rounding error of a triangle hit's t (pbrt-v4 `Triangle::Intersect`).
fn intersect_t_error_bound(max_x: f32, max_y: f32, max_z: f32, max_e: f32, inv_det: f32) -> f32 {
    let delta_z = GAMMA_3 * max_z;
    let delta_x = GAMMA_5 * (max_x + max_z);
    let delta_y = GAMMA_5 * (max_y + max_z);
    let delta_e = 2.0 * (GAMMA_2 * max_x * max_y + delta_y * max_x + delta_x * max_y);
    return 3.0 * (GAMMA_3 * max_e * max_z + delta_e * max_z + delta_z * max_e) * abs(inv_det);
}

// Whether the ray (origin at 0, vertices relative to it) starts in front of the triangle's plane
// by more than the rounding of that distance, and heads into it (triangle.rs `heads_into_plane`).
fn intersect_heads_into_plane(pa: vec3f, pb: vec3f, pc: vec3f, s: IntersectShear) -> bool {
    let e1 = pb - pa;
    let e2 = pc - pa;
    let n = e1.yzx * e2.zxy - e1.zxy * e2.yzx;
    let side = -(n.x * pa.x + n.y * pa.y + n.z * pa.z);
    let along = (n[s.kx] * s.sx + n[s.ky] * s.sy + n[s.kz]) * s.sz;
    let a1 = abs(e1);
    let a2 = abs(e2);
    let magnitude = a1.yzx * a2.zxy + a1.zxy * a2.yzx + abs(n);
    let pa_abs = abs(pa);
    let slack = GAMMA_7 * (magnitude.x * pa_abs.x + magnitude.y * pa_abs.y + magnitude.z * pa_abs.z);
    return side * along < 0.0 && abs(side) > slack;
}

fn intersect_max3(v: vec3f) -> f32 {
    return max(max(v.x, v.y), v.z);
}

// Unnormalized geometric normal (b − a) × (c − a): its side is the triangle's front.
fn intersect_triangle_normal(a: vec3f, b: vec3f, c: vec3f) -> vec3f {
    return cross(b - a, c - a);
}

// ---- Sphere: Haines, Günther, Akenine-Möller 2019, "Precision Improvements for Ray/Sphere
// Intersection" (Ray Tracing Gems, ch. 7) ----------------------------------------------------

// Nearest t ∈ (tmin, tmax) where `o + t·d` meets the sphere; `d` need not be unit length.
fn intersect_sphere(center: vec3f, radius: f32, o: vec3f, d: vec3f, tmin: f32, tmax: f32) -> f32 {
    let f = o - center;
    let a = dot(d, d);
    // Half of the linear coefficient: the quadratic is a t² + 2 b t + c.
    let b = -dot(f, d);
    let c = dot(f, f) - radius * radius;
    // Δ / a = r² − |f + (b/a) d|² (the centre's squared distance to the line).
    let l = f + (b / a) * d;
    let delta = a * (radius * radius - dot(l, l));
    if (delta < 0.0) {
        return f32_infinity();
    }
    // q = b + copysign(√Δ, b): no cancellation.
    let root = sqrt(delta);
    let q = b + select(root, -root, (bitcast<u32>(b) & 0x80000000u) != 0u);
    var t0 = 0.0;
    var t1 = 0.0;
    if (q != 0.0) {
        t0 = c / q;
        t1 = q / a;
    }
    let near = select(t1, t0, t0 <= t1);
    let far = select(t0, t1, t0 <= t1);
    if (near > tmin && near < tmax) {
        return near;
    }
    if (far > tmin && far < tmax) {
        return far;
    }
    return f32_infinity();
}

// ---- Disk: the plane of the disk, then the radius test ----------------------------------------

// t ∈ (tmin, tmax) where `o + t·d` meets the disk (centre, unit normal, radius), both sides.
fn intersect_disk(
    center: vec3f, normal: vec3f, radius: f32, o: vec3f, d: vec3f, tmin: f32, tmax: f32,
) -> f32 {
    let denom = dot(normal, d);
    if (denom == 0.0) {
        return f32_infinity();
    }
    let t = dot(center - o, normal) / denom;
    if (!(t > tmin && t < tmax)) {
        return f32_infinity();
    }
    let p = o + t * d;
    // Distance to the centre measured within the plane.
    let r0 = p - center;
    let r = r0 - normal * dot(r0, normal);
    if (dot(r, r) <= radius * radius) {
        return t;
    }
    return f32_infinity();
}

// The point of the disk's plane nearest to `p` (removes the along-normal error of o + t·d).
fn intersect_disk_project(center: vec3f, normal: vec3f, p: vec3f) -> vec3f {
    return p - normal * dot(p - center, normal);
}
