// needs: intersect
// Scene queries through the adapter's ray queries (wgpu's `wgpu_ray_query`): the kernel's
// `accel.wgsl` replaced, in the ray-query kernel only, by the same interface over the
// acceleration structure the host builds from the scene's triangles (`crates/gpu/src/rays.rs`;
// primitive `i` of it is the scene's primitive `i`). The hit's surface is the software
// traversal's (`intersect_surface` from the primitive and the distance); the distance itself is
// the driver's, which differs from the watertight test's in its last bits.
//
// Interface (other modules may call these):
//   fn accel_closest_hit(ray: Ray, time: f32, hit: ptr<function, Hit>) -> bool
//   fn accel_occluded(ray: Ray, time: f32) -> bool

@group(1) @binding(0) var accel_structure: acceleration_structure;

// The ray as a query asks for it: tmax finite (infinite rays reach the largest float).
fn accel_ray_desc(ray: Ray, flags: u32) -> RayDesc {
    return RayDesc(flags, 0xffu, ray.tmin, min(ray.tmax, 3.4028235e38), ray.origin, ray.dir);
}

// The nearest surface along `ray`; false (and `hit` untouched) on a miss. The scene is static.
fn accel_closest_hit(ray: Ray, time: f32, hit: ptr<function, Hit>) -> bool {
    var query: ray_query;
    rayQueryInitialize(&query, accel_structure, accel_ray_desc(ray, RAY_FLAG_FORCE_OPAQUE));
    rayQueryProceed(&query);
    let found = rayQueryGetCommittedIntersection(&query);
    if (found.kind == RAY_QUERY_INTERSECTION_NONE) {
        return false;
    }
    *hit = intersect_surface(found.primitive_index, ray, found.t, time);
    return true;
}

// Whether anything blocks `ray` within (tmin, tmax).
fn accel_occluded(ray: Ray, time: f32) -> bool {
    if (!(ray.tmax > ray.tmin)) {
        return false;
    }
    var query: ray_query;
    let flags = RAY_FLAG_FORCE_OPAQUE | RAY_FLAG_TERMINATE_ON_FIRST_HIT;
    rayQueryInitialize(&query, accel_structure, accel_ray_desc(ray, flags));
    rayQueryProceed(&query);
    return rayQueryGetCommittedIntersection(&query).kind != RAY_QUERY_INTERSECTION_NONE;
}
