//! Scene queries over the BVH2 built by the scene crate (obvhs layout): closest hit for path
//! rays, any hit for shadow rays. Primitives are stored in BVH order, so a leaf's primitive
//! range indexes `FlatScene::prims` directly. Brute-force versions are kept for the tests.
//!
//! The traversal is our own rather than obvhs's `ray_traverse`: its ray–box test is not
//! conservative (an approximate reciprocal for near-zero direction components, and no rounding
//! margin), so a ray through a vertex or edge lying on the faces of the leaf boxes — every shared
//! vertex of a flat, axis-aligned face — can miss both boxes and leak through a closed mesh.
//! Here the slab test uses exact reciprocals and widens each exit distance by `1 + 2γ₃`
//! (Ize 2013, "Robust BVH Ray Traversal", JCGT 2(2)); the same test is meant for `bvh.wgsl`.

use crate::intersect::triangle::Shear;
use crate::intersect::{intersect_prim, intersect_prim_sheared, surface, Hit, Ray};
use glam::Vec3;
use obvhs::bvh2::node::Bvh2Node;
use stratapt_scene::FlatScene;

/// The nearest surface along `ray` at shutter time `time`.
pub fn closest_hit(scene: &FlatScene, ray: &Ray, time: f32) -> Option<Hit> {
    count_ray();
    traverse(scene, ray, time, false).map(|(prim, t)| finish(scene, ray, prim, t, time))
}

/// Whether anything blocks `ray` within `(tmin, tmax)` at shutter time `time`.
pub fn occluded(scene: &FlatScene, ray: &Ray, time: f32) -> bool {
    count_ray();
    traverse(scene, ray, time, true).is_some()
}

thread_local! {
    /// Rays this thread has traced through [`closest_hit`] and [`occluded`].
    static RAYS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

fn count_ray() {
    RAYS.with(|r| r.set(r.get() + 1));
}

/// Rays (path and shadow) the calling thread has traced so far; differences of two readings
/// on one thread count the rays of the work in between (for rays-per-second figures).
pub fn rays_traced() -> u64 {
    RAYS.with(|r| r.get())
}

/// [`closest_hit`] by testing every primitive (reference for tests).
pub fn closest_hit_brute_force(scene: &FlatScene, ray: &Ray, time: f32) -> Option<Hit> {
    let mut best = None;
    let mut r = *ray;
    for (id, prim) in scene.prims.iter().enumerate() {
        let t = intersect_prim(prim, &scene.motions, &r, time);
        if t < r.tmax {
            best = Some((id as u32, t));
            r.tmax = t;
        }
    }
    best.map(|(prim, t)| finish(scene, ray, prim, t, time))
}

/// [`occluded`] by testing every primitive (reference for tests).
pub fn occluded_brute_force(scene: &FlatScene, ray: &Ray, time: f32) -> bool {
    scene
        .prims
        .iter()
        .any(|prim| intersect_prim(prim, &scene.motions, ray, time) < ray.tmax)
}

fn finish(scene: &FlatScene, ray: &Ray, prim: u32, t: f32, time: f32) -> Hit {
    let p = &scene.prims[prim as usize];
    surface(prim, p, &scene.normals, &scene.motions, ray, t, time)
}

// ---------------------------------------------------------------------------------------------
// Traversal
// ---------------------------------------------------------------------------------------------

use stratapt_scene::shared::BVH_EXIT_SCALE as EXIT_SCALE;

/// Stack depth kept inline; deeper trees spill to the heap.
const INLINE_STACK: usize = 64;

/// Closest (or, with `any`, the first found) primitive hit along `ray`: `(prim, t)`.
fn traverse(scene: &FlatScene, ray: &Ray, time: f32, any: bool) -> Option<(u32, f32)> {
    let nodes = &scene.bvh.nodes;
    if nodes.is_empty() {
        return None;
    }
    let inv_dir = Vec3::ONE / ray.dir;
    let shear = Shear::new(ray.dir);
    let mut r = *ray;
    let mut best = None;
    let mut stack = Stack::new();
    if let Some(t) = slab_entry(&nodes[0], r.origin, inv_dir, r.tmin, r.tmax) {
        stack.push(0, t);
    }
    while let Some((index, entry)) = stack.pop() {
        // A closer hit found since this node was pushed may rule it out.
        if entry > r.tmax {
            continue;
        }
        let node = &nodes[index as usize];
        if node.is_leaf() {
            for id in node.first_index..node.first_index + node.prim_count {
                let t = intersect_prim_sheared(
                    &scene.prims[id as usize],
                    &scene.motions,
                    &r,
                    &shear,
                    time,
                );
                if t < r.tmax {
                    best = Some((id, t));
                    if any {
                        return best;
                    }
                    r.tmax = t;
                }
            }
            continue;
        }
        // Children: push the farther one first so the nearer one is visited first.
        let (a, b) = (node.first_index, node.first_index + 1);
        let ta = slab_entry(&nodes[a as usize], r.origin, inv_dir, r.tmin, r.tmax);
        let tb = slab_entry(&nodes[b as usize], r.origin, inv_dir, r.tmin, r.tmax);
        match (ta, tb) {
            (Some(ta), Some(tb)) if ta <= tb => {
                stack.push(b, tb);
                stack.push(a, ta);
            }
            (Some(ta), Some(tb)) => {
                stack.push(a, ta);
                stack.push(b, tb);
            }
            (Some(ta), None) => stack.push(a, ta),
            (None, Some(tb)) => stack.push(b, tb),
            (None, None) => {}
        }
    }
    best
}

/// Entry distance of the ray into `node`'s box if the box overlaps `[tmin, tmax]`.
///
/// Comparisons are written so that a NaN slab distance (origin on a slab plane with a zero
/// direction component: `0 · ∞`) leaves the interval unchanged, as in pbrt.
#[inline]
fn slab_entry(node: &Bvh2Node, origin: Vec3, inv_dir: Vec3, tmin: f32, tmax: f32) -> Option<f32> {
    let aabb = node.aabb();
    let (min, max): (Vec3, Vec3) = (aabb.min.into(), aabb.max.into());
    let (mut t0, mut t1) = (tmin, tmax);
    for axis in 0..3 {
        let near = (min[axis] - origin[axis]) * inv_dir[axis];
        let far = (max[axis] - origin[axis]) * inv_dir[axis];
        let (near, far) = if near > far { (far, near) } else { (near, far) };
        let far = far * EXIT_SCALE;
        if near > t0 {
            t0 = near;
        }
        if far < t1 {
            t1 = far;
        }
        if t0 > t1 {
            return None;
        }
    }
    Some(t0)
}

/// Traversal stack of `(node, entry distance)`, inline up to [`INLINE_STACK`] entries.
struct Stack {
    inline: [(u32, f32); INLINE_STACK],
    len: usize,
    spill: Vec<(u32, f32)>,
}

impl Stack {
    fn new() -> Self {
        Self {
            inline: [(0, 0.0); INLINE_STACK],
            len: 0,
            spill: Vec::new(),
        }
    }

    #[inline]
    fn push(&mut self, node: u32, t: f32) {
        if self.len < INLINE_STACK {
            self.inline[self.len] = (node, t);
            self.len += 1;
        } else {
            self.spill.push((node, t));
        }
    }

    #[inline]
    fn pop(&mut self) -> Option<(u32, f32)> {
        if let Some(top) = self.spill.pop() {
            return Some(top);
        }
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        Some(self.inline[self.len])
    }
}
