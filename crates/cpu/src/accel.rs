//! Scene queries: closest hit for path rays, any hit for shadow rays, over a 4-wide BVH
//! (`bvh4`) collapsed from the scene crate's BVH2 (obvhs), with the static triangles of each
//! leaf tested four at a time (`packet`). Brute-force versions are kept for the tests.
//!
//! The traversal is our own rather than obvhs's: its ray–box test is not conservative (an
//! approximate reciprocal for near-zero direction components, and no rounding margin), so a
//! ray through a vertex or edge lying on the faces of the leaf boxes — every shared vertex of a
//! flat, axis-aligned face — can miss both boxes and leak through a closed mesh. Here the slab
//! test uses exact reciprocals and widens each exit distance by `1 + 2γ₃` (Ize 2013, "Robust
//! BVH Ray Traversal", JCGT 2(2)); the same test is in `bvh.wgsl`.
//!
//! The wide layout changes how fast a ray finds its hit, not which: every box is entered
//! exactly when the BVH2's scalar slab test entered it, and every hit is the scalar triangle
//! test's. Only exact ties (two primitives at the same distance) may resolve to the other one,
//! as they do between the GPU's two layouts.

mod bvh4;
mod packet;
#[doc(hidden)]
pub mod stream8;
mod wave8;
pub(crate) use wave8::Rays8;

use crate::intersect::triangle::{intersect_sheared, Shear};
use crate::intersect::{intersect_prim, intersect_prim_sheared, surface, Hit, Ray};
use bvh4::{Bvh4, Child, RayLanes, LEAF};
use glam::Vec3;
use packet::LANES;
use stratapt_scene::FlatScene;

/// A scene ready for ray queries on the CPU: the scene and its 4-wide BVH. Build it once per
/// render (linear in the primitives) and share it between threads.
pub struct Accel<'a> {
    scene: &'a FlatScene,
    bvh: Bvh4,
}

impl<'a> Accel<'a> {
    pub fn new(scene: &'a FlatScene) -> Self {
        Self {
            scene,
            bvh: Bvh4::new(&scene.bvh.nodes, &scene.geometry),
        }
    }

    pub fn scene(&self) -> &'a FlatScene {
        self.scene
    }

    /// The nearest surface along `ray` at shutter time `time`.
    pub fn closest_hit(&self, ray: &Ray, time: f32) -> Option<Hit> {
        count_ray();
        let found = self.traverse(ray, time, false)?;
        Some(finish(self.scene, ray, &found, time))
    }

    /// Whether anything blocks `ray` within `(tmin, tmax)` at shutter time `time`.
    pub fn occluded(&self, ray: &Ray, time: f32) -> bool {
        count_ray();
        self.traverse(ray, time, true).is_some()
    }
}

thread_local! {
    /// Rays this thread has traced through [`Accel::closest_hit`] and [`Accel::occluded`].
    static RAYS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

fn count_ray() {
    count_rays(1);
}

fn count_rays(n: u64) {
    RAYS.with(|r| r.set(r.get() + n));
}

/// Rays (path and shadow) the calling thread has traced so far; differences of two readings
/// on one thread count the rays of the work in between (for rays-per-second figures).
pub fn rays_traced() -> u64 {
    RAYS.with(|r| r.get())
}

/// [`Accel::closest_hit`] by testing every primitive (reference for tests).
pub fn closest_hit_brute_force(scene: &FlatScene, ray: &Ray, time: f32) -> Option<Hit> {
    let mut best = None;
    let mut r = *ray;
    for (id, prim) in scene.geometry.iter().enumerate() {
        let t = intersect_prim(&prim, &scene.motions, &scene.tables, &r, time);
        if t < r.tmax {
            best = Some((id as u32, t));
            r.tmax = t;
        }
    }
    best.map(|(prim, t)| {
        finish(
            scene,
            ray,
            &Found {
                prim,
                t,
                bary: None,
            },
            time,
        )
    })
}

/// [`Accel::occluded`] by testing every primitive (reference for tests).
pub fn occluded_brute_force(scene: &FlatScene, ray: &Ray, time: f32) -> bool {
    scene
        .geometry
        .iter()
        .any(|prim| intersect_prim(&prim, &scene.motions, &scene.tables, ray, time) < ray.tmax)
}

/// The surface geometry of a hit `found` along `ray`.
fn finish(scene: &FlatScene, ray: &Ray, found: &Found, time: f32) -> Hit {
    let p = scene.geometry.prim(found.prim);
    surface(
        found.prim,
        &p,
        &scene.motions,
        ray,
        found.t,
        time,
        found.bary,
    )
}

/// A primitive hit during traversal: its index, distance, and a static triangle's barycentrics
/// as its triangle test found them.
#[derive(Clone, Copy, Debug)]
struct Found {
    prim: u32,
    t: f32,
    bary: Option<Vec3>,
}

// ---------------------------------------------------------------------------------------------
// Traversal
// ---------------------------------------------------------------------------------------------

thread_local! {
    /// This thread's traversal stack of `(child, entry distance)`, kept between rays: a fresh
    /// inline array per ray was zero-filled every time, a cost that showed in profiles as
    /// `memset` (docs/measurements/cpu-reference.md#the-4-wide-bvh-and-what-each-change-gave).
    static STACK: std::cell::RefCell<Vec<(Child, f32)>> = const { std::cell::RefCell::new(Vec::new()) };
}

impl Accel<'_> {
    /// Closest (or, with `any`, the first found) primitive hit along `ray`.
    fn traverse(&self, ray: &Ray, time: f32, any: bool) -> Option<Found> {
        STACK.with_borrow_mut(|stack| {
            stack.clear();
            self.traverse_with(stack, ray, time, any)
        })
    }

    /// [`Accel::traverse`] with an empty `stack`.
    fn traverse_with(
        &self,
        stack: &mut Vec<(Child, f32)>,
        ray: &Ray,
        time: f32,
        any: bool,
    ) -> Option<Found> {
        let root = self.bvh.root?;
        let lanes = RayLanes::new(ray.origin, ray.dir);
        let shear = Shear::new(ray.dir);
        let mut r = *ray;
        let mut best = None;
        // No test of the root's own box: it holds every child's, so it would only repeat their
        // test (a ray that misses the scene misses the top node's four boxes at the same cost).
        stack.push((root, r.tmin));
        while let Some((child, entry)) = stack.pop() {
            // A closer hit found since this child was pushed may rule it out.
            if entry > r.tmax {
                continue;
            }
            if child & LEAF != 0 {
                if self.leaf(child & !LEAF, &mut r, &shear, time, any, &mut best) && any {
                    return best;
                }
                continue;
            }
            // ---- The children the ray enters, nearest visited first -----------------------
            let node = &self.bvh.nodes[child as usize];
            let (entries, mut hits) = node.enter(&lanes, r.tmin, r.tmax);
            let entries = entries.to_array();
            let mut order = [(0 as Child, 0.0f32); LANES];
            let mut n = 0;
            while hits != 0 {
                let lane = hits.trailing_zeros() as usize;
                hits &= hits - 1;
                let item = (node.child[lane], entries[lane]);
                if any {
                    // Any hit ends the search: the order does not matter.
                    stack.push(item);
                    continue;
                }
                // Insertion by entry distance, farthest first, so the nearest is popped first
                // (equal distances keep lane order, as a stable sort would).
                let mut k = n;
                while k > 0 && order[k - 1].1.total_cmp(&item.1).is_lt() {
                    order[k] = order[k - 1];
                    k -= 1;
                }
                order[k] = item;
                n += 1;
            }
            // One by one: a copy of a run-time length calls `memmove`, which showed in profiles
            // (docs/measurements/speed.md#where-the-cpu-references-time-goes-now).
            for &item in &order[..n] {
                stack.push(item);
            }
        }
        best
    }

    /// Test leaf `index`'s primitives against `r`, shortening `r.tmax` to each closer hit and
    /// recording it in `best`; whether anything was hit.
    fn leaf(
        &self,
        index: u32,
        r: &mut Ray,
        shear: &Shear,
        time: f32,
        any: bool,
        best: &mut Option<Found>,
    ) -> bool {
        let (bvh, scene) = (&self.bvh, self.scene);
        let leaf = bvh.leaves[index as usize];
        let mut found = false;
        // ---- Static triangles, four at a time ----------------------------------------------
        for packet in &bvh.packets[leaf.packets[0] as usize..leaf.packets[1] as usize] {
            let lanes = packet.test(r.origin, shear, r.tmin, r.tmax);
            let mut candidates = lanes.candidates;
            while candidates != 0 {
                let lane = candidates.trailing_zeros() as usize;
                candidates &= candidates - 1;
                let id = packet.prim[lane];
                // Decided in the lane, or (within its error bound) by the scalar test.
                let hit = if lanes.sure & (1 << lane) != 0 {
                    (lanes.t[lane] < r.tmax).then(|| (lanes.t[lane], lanes.bary(lane)))
                } else {
                    let [a, b, c] = scene.geometry.vertices(id);
                    intersect_sheared(a, b, c, r.origin, shear, r.tmin, r.tmax)
                        .map(|h| (h.t, h.bary))
                };
                if let Some((t, bary)) = hit {
                    *best = Some(Found {
                        prim: id,
                        t,
                        bary: Some(bary),
                    });
                    r.tmax = t;
                    found = true;
                    if any {
                        return true;
                    }
                }
            }
        }
        // ---- Spheres, disks and moving triangles, one by one --------------------------------
        for &id in &bvh.singles[leaf.singles[0] as usize..leaf.singles[1] as usize] {
            let prim = scene.geometry.prim(id);
            let t = intersect_prim_sheared(&prim, &scene.motions, &scene.tables, r, shear, time);
            if t < r.tmax {
                *best = Some(Found {
                    prim: id,
                    t,
                    bary: None,
                });
                r.tmax = t;
                found = true;
                if any {
                    return true;
                }
            }
        }
        found
    }
}
