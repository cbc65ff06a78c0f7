// needs: intersect bvh
// Scene queries over the compressed wide BVH (CWBVH; Ylitie, Karras & Laine 2017, "Efficient
// Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs"), which the host builds from the
// BVH2 (`crates/gpu/src/cwbvh.rs`). `accel_closest_hit` and `accel_occluded` (accel.wgsl) call
// this traversal instead of `bvh_traverse` when `BVH_WIDE` is set; same primitive tests, same result
// up to exact ties (children are visited in octant order, not nearest first, so of two primitives
// hit at exactly the same distance the other one may win).
//
// Loop: obvhs's `traverse!` (src/cwbvh/traverse_macro.rs). A node group is `(first child node,
// hit bits << 24 | imask)`; entering a node tests its (up to) eight children at once and yields
// the inner children hit (bit `24 + (slot ^ octant)`, highest first: octant order) and the
// primitive slots of the leaf children hit (bits 0..23).
//
// Child boxes: a child's planes are `p + q · step` in f32 (`q · step` is exact: `q` has 8 bits
// and `step` is a power of two, so this is one rounding however it is compiled), and the host
// quantizes them so that these f32 planes hold every BVH2 leaf box beneath (it evaluates them the
// same way). The slab test is bvh.wgsl's `bvh_slab` (exact reciprocals, exits widened by
// `BVH_EXIT_SCALE`), which is monotone in the box, rounding included: a ray that enters a BVH2
// leaf box enters every grid box holding it, so no primitive the BVH2 traversal would test is
// skipped. (Planes relative to the ray, `q · step / dir + (p − o) / dir`, would save a few
// operations but round relative to the node's size rather than to the distance of the plane,
// which admits boxes a ray only leaves: rays spawned from a surface then test that surface.)
//
// Stack: `BVH_STACK_SIZE` node groups of private memory (8 bytes each), at module scope for the
// reason given in bvh.wgsl. A group is pushed only when one of its children is entered and others
// remain, so at most one per level above the deepest inner node; the host refuses deeper trees.
//
// Interface:
//   fn cwbvh_traverse(ray: Ray, time: f32, any_hit: bool, prim: ptr<function, u32>) -> f32
//          (as `bvh_traverse`: +inf and `prim` untouched when nothing is hit)

// Pending node groups `(first child node, hit bits << 24 | imask)`.
var<private> cwbvh_stack: array<vec2u, BVH_STACK_SIZE>;

// Node `i` (five entries of the raw node array).
fn cwbvh_node(i: u32) -> CwbvhNode {
    let b = 5u * i;
    let a = node_word(b);
    let m = node_word(b + 1u);
    let x = node_word(b + 2u);
    let y = node_word(b + 3u);
    let z = node_word(b + 4u);
    return CwbvhNode(bitcast<vec3f>(a.xyz), a.w, m.x, m.y, m.zw, x.xy, x.zw, y.xy, y.zw, z.xy, z.zw);
}

// Byte `child` of eight packed in a `vec2u`.
fn cwbvh_byte(bytes: vec2u, child: u32) -> u32 {
    return extractBits(bytes[child >> 2u], (child & 3u) * 8u, 8u);
}

// The children of `node` that the ray enters within `[tmin, tmax]`: bit `24 + (slot ^ octant)`
// for an inner child, the bits of its primitive slots for a leaf child.
fn cwbvh_intersect(node: CwbvhNode, origin: vec3f, inv_dir: vec3f, octant: u32, tmin: f32, tmax: f32) -> u32 {
    // Grid step per axis: a power of two, from its exponent byte.
    let e = (vec3u(node.e_imask) >> vec3u(0u, 8u, 16u)) & vec3u(0xffu);
    let step = bitcast<vec3f>(e << vec3u(23u));
    var hits = 0u;
    for (var c = 0u; c < 8u; c++) {
        // The child's box: its grid cells' planes.
        let q_lo = vec3f(f32(cwbvh_byte(node.child_min_x, c)), f32(cwbvh_byte(node.child_min_y, c)), f32(cwbvh_byte(node.child_min_z, c)));
        let q_hi = vec3f(f32(cwbvh_byte(node.child_max_x, c)), f32(cwbvh_byte(node.child_max_y, c)), f32(cwbvh_byte(node.child_max_z, c)));
        let span = bvh_slab(node.p + q_lo * step, node.p + q_hi * step, origin, inv_dir, tmin, tmax);
        if (span.x <= span.y) {
            // Inner children carry 24 + slot in the low five bits (bits 3 and 4 both set), leaves
            // their first slot; the top three bits are 1 (inner) or the leaf's slots, unary.
            let info = cwbvh_byte(node.child_meta, c);
            let inner = (info & (info << 1u) & 0x10u) != 0u;
            hits |= (info >> 5u) << (select(info, info ^ octant, inner) & 31u);
        }
    }
    return hits;
}

// Closest (or, with `any_hit`, the first found) primitive hit along `ray`: its distance, and its
// index in `*prim`.
fn cwbvh_traverse(ray: Ray, time: f32, any_hit: bool, prim: ptr<function, u32>) -> f32 {
    // `node_count` counts the BVH2's nodes: zero exactly when the scene is empty.
    if (params.node_count == 0u) {
        return f32_infinity();
    }
    let inv_dir = 1.0 / ray.dir;
    let shear = intersect_shear_new(ray.dir);
    // The ray's octant, inverted (a bit per axis the direction does not point down).
    let neg = inv_dir < vec3f(0.0);
    let octant = select(4u, 0u, neg.x) | select(2u, 0u, neg.y) | select(1u, 0u, neg.z);
    var r = Ray(ray.origin, ray.dir, ray.tmin, ray.tmax);
    var found = false;
    var sp = 0u;
    // The root, as the only hit inner child of a group whose slot maps to node 0.
    var group = vec2u(0u, 0x80000000u);
    loop {
        // Primitive slots to test: (word offset of the node's first slot, hit slots).
        var slots = vec2u(0u);
        if (group.y > 0x00ffffffu) {
            // Enter the group's next hit child; keep the rest of the group for later.
            let bit = firstLeadingBit(group.y);
            let imask = group.y;
            group.y &= ~(1u << bit);
            if (group.y > 0x00ffffffu && sp < BVH_STACK_SIZE) {
                cwbvh_stack[sp] = group;
                sp += 1u;
            }
            // Its node: the inner children are stored in slot order after `child_base`.
            let slot = (bit - 24u) ^ octant;
            let index = group.x + countOneBits(imask & ~(0xffffffffu << slot));
            let node = cwbvh_node(index);
            let hits = cwbvh_intersect(node, r.origin, inv_dir, octant, r.tmin, r.tmax);
            group = vec2u(node.child_base, (hits & 0xff000000u) | (node.e_imask >> 24u));
            slots = vec2u(node.prim_base, hits & 0x00ffffffu);
        }
        // Test the primitives of the leaves hit, shrinking the ray to each closer hit.
        while (slots.y != 0u) {
            let bit = firstLeadingBit(slots.y);
            slots.y &= ~(1u << bit);
            let word = slots.x + bit;
            let id = node_word(word >> 2u)[word & 3u];
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
        // No inner child of this group left: resume the last pending group.
        if (group.y <= 0x00ffffffu) {
            if (sp == 0u) {
                break;
            }
            sp -= 1u;
            group = cwbvh_stack[sp];
        }
    }
    if (!found) {
        return f32_infinity();
    }
    return r.tmax;
}
