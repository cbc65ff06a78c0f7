// needs: intersect
// Scene queries over the BVH2 (obvhs layout repacked as `BvhNode`): closest hit for path rays,
// any hit for shadow rays. Mirrors `crates/cpu/src/accel.rs`: same visiting order (nearer child
// first, ties to the first child), same pruning, same conservative slab test, so the same
// primitive wins even at exact ties.
//
// Slab test: exact reciprocals, and each exit distance widened by `1 + 2γ₃` (Ize 2013, "Robust
// BVH Ray Traversal", JCGT 2(2)); NaN slab distances (origin on a slab plane with a zero
// direction component) leave the interval unchanged, as in pbrt.
//
// Stack: `BVH_STACK_SIZE` entries of private memory (12 bytes each). With the farther child
// pushed and the nearer one visited at once, at most one entry per tree level is pending, so a
// tree of depth d (root at depth 0) never needs more than d entries. The CPU spills beyond 64
// entries to the heap; here a push onto a full stack is dropped (that subtree is not visited),
// so the host must keep the BVH depth at most `BVH_STACK_SIZE`, which obvhs PLOC trees of
// millions of triangles stay within (measured: docs/measurements/scaling.md#bvh-depths).
//
// Interface (other modules may call these):
//   fn bvh_traverse(ray: Ray, time: f32, any_hit: bool, prim: ptr<function, u32>) -> f32
//          (+inf and `prim` untouched when nothing is hit)

// Generated from the Rust side: BVH_EXIT_SCALE (`1 + 2γ₃`, widening a slab's exit distance
// over the rounding of `(bound − origin) · (1 / dir)`; pbrt-v4 `Bounds3::IntersectP`) and
// BVH_STACK_SIZE (pending subtrees one traversal holds, `MAX_BVH_DEPTH`).

// The traversal stack: pending subtrees `(first_index, prim_count)` and their entry distances.
// Module-scope `private` so it is zero-initialized once per invocation, not at every call: WGSL
// zero-fills a function's local arrays on entry, which lavapipe does element by element and lane
// by lane (64 × 3 masked stores per lane per ray), the kernel's largest single cost (measured:
// docs/measurements/lavapipe.md#on-mesa-223).
// Every traversal writes an entry before it reads it, so what earlier rays left is never seen.
var<private> bvh_stack_node: array<vec2u, BVH_STACK_SIZE>;
var<private> bvh_stack_entry: array<f32, BVH_STACK_SIZE>;

// Node `i` of the BVH2 (two entries of the raw node array).
fn bvh_node(i: u32) -> BvhNode {
    let lo = node_word(2u * i);
    let hi = node_word(2u * i + 1u);
    return BvhNode(bitcast<vec3f>(lo.xyz), lo.w, bitcast<vec3f>(hi.xyz), hi.w);
}

// The ray's span `(t0, t1)` inside the box `[lo, hi]`, clipped to `[tmin, tmax]`; the box is hit
// when `t0 <= t1` (never NaN), and `t0` is the entry distance.
fn bvh_slab(lo: vec3f, hi: vec3f, origin: vec3f, inv_dir: vec3f, tmin: f32, tmax: f32) -> vec2f {
    let a = (lo - origin) * inv_dir;
    let b = (hi - origin) * inv_dir;
    // Order each axis's pair (a NaN pair stays as is), widen the exit.
    let swap = a > b;
    let near = select(a, b, swap);
    let far = select(b, a, swap) * BVH_EXIT_SCALE;
    // Intersect the intervals axis by axis; NaN comparisons leave the bound unchanged.
    var t0 = tmin;
    var t1 = tmax;
    t0 = select(t0, near.x, near.x > t0);
    t1 = select(t1, far.x, far.x < t1);
    t0 = select(t0, near.y, near.y > t0);
    t1 = select(t1, far.y, far.y < t1);
    t0 = select(t0, near.z, near.z > t0);
    t1 = select(t1, far.z, far.z < t1);
    return vec2f(t0, t1);
}

// Closest (or, with `any_hit`, the first found) primitive hit along `ray`: its distance, and its
// index in `*prim`. The stack holds the far children still to visit as `(first_index,
// prim_count)` with their entry distance, so no node is read twice.
fn bvh_traverse(ray: Ray, time: f32, any_hit: bool, prim: ptr<function, u32>) -> f32 {
    var tmax = ray.tmax;
    if (params.node_count == 0u) {
        return f32_infinity();
    }
    let inv_dir = 1.0 / ray.dir;
    let shear = intersect_shear_new(ray.dir);
    let root = bvh_node(0u);
    let root_span = bvh_slab(root.min, root.max, ray.origin, inv_dir, ray.tmin, tmax);
    if (!(root_span.x <= root_span.y)) {
        return f32_infinity();
    }
    var sp = 0u;
    var found = false;
    // The node being visited: (first_index, prim_count).
    var cur = vec2u(root.first_index, root.prim_count);
    loop {
        if (cur.y != 0u) {
            // Leaf: test its primitives, shrinking the ray to each closer hit.
            var r = Ray(ray.origin, ray.dir, ray.tmin, tmax);
            let end = cur.x + cur.y;
            for (var id = cur.x; id < end; id++) {
                let t = intersect_prim_sheared(prim_at(id), r, shear, time);
                if (t < r.tmax) {
                    *prim = id;
                    found = true;
                    if (any_hit) {
                        return t;
                    }
                    r.tmax = t;
                }
            }
            tmax = r.tmax;
        } else {
            // Inner node: test both children; visit the nearer now, push the farther.
            let a = bvh_node(cur.x);
            let b = bvh_node(cur.x + 1u);
            let sa = bvh_slab(a.min, a.max, ray.origin, inv_dir, ray.tmin, tmax);
            let sb = bvh_slab(b.min, b.max, ray.origin, inv_dir, ray.tmin, tmax);
            let hit_a = sa.x <= sa.y;
            let hit_b = sb.x <= sb.y;
            let node_a = vec2u(a.first_index, a.prim_count);
            let node_b = vec2u(b.first_index, b.prim_count);
            if (hit_a && hit_b) {
                let a_first = sa.x <= sb.x;
                if (sp < BVH_STACK_SIZE) {
                    bvh_stack_node[sp] = select(node_a, node_b, a_first);
                    bvh_stack_entry[sp] = select(sa.x, sb.x, a_first);
                    sp += 1u;
                }
                cur = select(node_b, node_a, a_first);
                continue;
            }
            if (hit_a) {
                cur = node_a;
                continue;
            }
            if (hit_b) {
                cur = node_b;
                continue;
            }
        }
        // Pop the next pending subtree; a closer hit found since it was pushed may rule it out.
        var next = false;
        while (sp > 0u) {
            sp -= 1u;
            if (!(bvh_stack_entry[sp] > tmax)) {
                cur = bvh_stack_node[sp];
                next = true;
                break;
            }
        }
        if (!next) {
            break;
        }
    }
    if (!found) {
        return f32_infinity();
    }
    return tmax;
}
