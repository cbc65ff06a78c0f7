// needs: intersect bvh cwbvh
// Scene queries: the nearest surface along a ray for path rays, any blocker for shadow rays,
// over the BVH layout the host chose (`BVH_WIDE`): the BVH2 of `bvh.wgsl` or the compressed wide
// BVH of `cwbvh.wgsl` (same interface, same primitive tests and slab widening). Mirrors
// `crates/cpu/src/accel.rs` (`Accel::closest_hit`, `Accel::occluded`).
//
// Interface (other modules may call these):
//   fn accel_closest_hit(ray: Ray, time: f32, hit: ptr<function, Hit>) -> bool
//   fn accel_occluded(ray: Ray, time: f32) -> bool

// The nearest surface along `ray` at shutter time `time`; false (and `hit` untouched) on a miss.
fn accel_closest_hit(ray: Ray, time: f32, hit: ptr<function, Hit>) -> bool {
    var prim = NONE;
    var t: f32;
    if (BVH_WIDE) {
        t = cwbvh_traverse(ray, time, false, &prim);
    } else {
        t = bvh_traverse(ray, time, false, &prim);
    }
    if (prim == NONE) {
        return false;
    }
    *hit = intersect_surface(prim, ray, t, time);
    return true;
}

// Whether anything blocks `ray` within (tmin, tmax) at shutter time `time`.
fn accel_occluded(ray: Ray, time: f32) -> bool {
    var prim = NONE;
    if (BVH_WIDE) {
        cwbvh_traverse(ray, time, true, &prim);
    } else {
        bvh_traverse(ray, time, true, &prim);
    }
    return prim != NONE;
}
