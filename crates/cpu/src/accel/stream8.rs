//! A prototype for issue 28, measured and not used by the renderer: eight rays traversing the
//! 4-wide BVH together, one per lane of an AVX2 vector, in SoA form (each coordinate of the
//! eight origins in one `[f32; 8]`), as Mitsuba's LLVM backend traces eight paths per vector.
//!
//! The eight rays share one traversal stack. A node's children are tested against all eight
//! rays at once (one 8-lane slab test per child, the scalar test's operations in the same order
//! per lane, so a ray enters a box exactly when it would alone); a child is visited when any
//! still-active ray enters it, with the mask of those that do. A leaf's primitives are tested
//! ray by ray with the renderer's own leaf test ([`Accel::leaf`]: four triangles per ray at
//! once), so every ray finds the hit it finds alone (up to exact ties, which the visiting order
//! may resolve to the other primitive).
//!
//! `cargo bench -p stratapt-cpu --bench stream8` times it against the one-ray traversal on
//! camera rays, their bounces and shadow rays (`docs/measurements/speed.md`).

use super::bvh4::{Child, LEAF};
use super::{Accel, Found};
use crate::intersect::triangle::Shear;
use crate::intersect::Ray;

/// Rays per packet: one per 32-bit lane of an AVX2 vector.
pub const WIDTH: usize = 8;

type Lanes = [f32; WIDTH];

/// The nearest primitive and distance of a hit.
pub type PrimHit = Option<(u32, f32)>;

/// `a < b ? a : b` per lane (`minps`'s definition, as the one-ray test's `less_or`).
#[inline(always)]
fn less_or(a: Lanes, b: Lanes) -> Lanes {
    std::array::from_fn(|i| if a[i] < b[i] { a[i] } else { b[i] })
}

/// `a > b ? a : b` per lane.
#[inline(always)]
fn greater_or(a: Lanes, b: Lanes) -> Lanes {
    std::array::from_fn(|i| if a[i] > b[i] { a[i] } else { b[i] })
}

thread_local! {
    /// This thread's eight-ray traversal stack, kept between calls as the one-ray stack is.
    static STACK8: std::cell::RefCell<Vec<Entry>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// A stack entry: a child, the rays that entered it, and their entry distances.
#[derive(Clone, Copy)]
struct Entry {
    child: Child,
    mask: u8,
    t: Lanes,
}

impl Accel<'_> {
    /// The nearest primitive hit by the one-ray traversal, without the surface
    /// ([`Accel::closest_hit`] less its hit record): what [`Accel::closest8`] is compared with.
    #[doc(hidden)]
    pub fn closest_prim(&self, ray: &Ray, time: f32) -> PrimHit {
        self.traverse(ray, time, false).map(|f| (f.prim, f.t))
    }

    /// [`Accel::occluded`], without counting the ray.
    #[doc(hidden)]
    pub fn occluded_prim(&self, ray: &Ray, time: f32) -> bool {
        self.traverse(ray, time, true).is_some()
    }

    /// The nearest primitive hit by each of eight rays, traversed together.
    #[doc(hidden)]
    pub fn closest8(&self, rays: &[Ray; WIDTH], time: f32) -> [PrimHit; WIDTH] {
        self.traverse8(rays, time, false)
            .map(|found| found.map(|f| (f.prim, f.t)))
    }

    /// Whether anything blocks each of eight rays, traversed together.
    #[doc(hidden)]
    pub fn occluded8(&self, rays: &[Ray; WIDTH], time: f32) -> [bool; WIDTH] {
        self.traverse8(rays, time, true)
            .map(|found| found.is_some())
    }

    fn traverse8(&self, rays: &[Ray; WIDTH], time: f32, any: bool) -> [Option<Found>; WIDTH] {
        STACK8.with_borrow_mut(|stack| {
            stack.clear();
            self.traverse8_with(stack, rays, time, any)
        })
    }

    /// [`Accel::traverse8`] with an empty `stack`.
    fn traverse8_with(
        &self,
        stack: &mut Vec<Entry>,
        rays: &[Ray; WIDTH],
        time: f32,
        any: bool,
    ) -> [Option<Found>; WIDTH] {
        let mut best: [Option<Found>; WIDTH] = [None; WIDTH];
        let Some(root) = self.bvh.root else {
            return best;
        };
        let mut r = *rays;
        let shears = rays.map(|ray| Shear::new(ray.dir));
        let origin: [Lanes; 3] =
            std::array::from_fn(|a| std::array::from_fn(|i| rays[i].origin[a]));
        let inv_dir: [Lanes; 3] =
            std::array::from_fn(|a| std::array::from_fn(|i| 1.0 / rays[i].dir[a]));
        // Rays whose any-hit query is answered.
        let mut finished = 0u8;
        stack.push(Entry {
            child: root,
            mask: u8::MAX,
            t: rays.map(|ray| ray.tmin),
        });
        while let Some(entry) = stack.pop() {
            // The rays still after this child: a closer hit since it was pushed rules a ray out.
            let mut live = entry.mask & !finished;
            for (i, ray) in r.iter().enumerate() {
                if entry.t[i] > ray.tmax {
                    live &= !(1 << i);
                }
            }
            if live == 0 {
                continue;
            }
            if entry.child & LEAF != 0 {
                let mut lanes = live;
                while lanes != 0 {
                    let i = lanes.trailing_zeros() as usize;
                    lanes &= lanes - 1;
                    let leaf = entry.child & !LEAF;
                    if self.leaf(leaf, &mut r[i], &shears[i], time, any, &mut best[i]) && any {
                        finished |= 1 << i;
                    }
                }
                continue;
            }
            // ---- Each child against the eight rays, nearest (by its nearest ray) first --------
            let node = &self.bvh.nodes[entry.child as usize];
            let tmin: Lanes = r.map(|ray| ray.tmin);
            let tmax: Lanes = r.map(|ray| ray.tmax);
            let mut order = [(
                f32::INFINITY,
                Entry {
                    child: 0,
                    mask: 0,
                    t: [0.0; WIDTH],
                },
            ); 4];
            let mut n = 0;
            let mut children = node.valid;
            while children != 0 {
                let c = children.trailing_zeros() as usize;
                children &= children - 1;
                let (mut t0, mut t1) = (tmin, tmax);
                for axis in 0..3 {
                    let (lo, hi) = (node.min[axis][c], node.max[axis][c]);
                    let near: Lanes =
                        std::array::from_fn(|i| (lo - origin[axis][i]) * inv_dir[axis][i]);
                    let far: Lanes =
                        std::array::from_fn(|i| (hi - origin[axis][i]) * inv_dir[axis][i]);
                    let (near, far) = (less_or(far, near), greater_or(near, far));
                    let far = far.map(|f| f * stratapt_scene::shared::BVH_EXIT_SCALE);
                    t0 = greater_or(near, t0);
                    t1 = less_or(far, t1);
                }
                let mut mask = 0u8;
                for i in 0..WIDTH {
                    mask |= ((t0[i] <= t1[i]) as u8) << i;
                }
                mask &= live;
                if mask == 0 {
                    continue;
                }
                let mut key = f32::INFINITY;
                for (i, t) in t0.iter().enumerate() {
                    if mask & (1 << i) != 0 {
                        key = key.min(*t);
                    }
                }
                let item = (
                    key,
                    Entry {
                        child: node.child[c],
                        mask,
                        t: t0,
                    },
                );
                if any {
                    // Any hit ends a ray's search: the order does not matter.
                    stack.push(item.1);
                    continue;
                }
                // Farthest first on the stack, so that the nearest is popped first.
                let mut k = n;
                while k > 0 && order[k - 1].0.total_cmp(&item.0).is_lt() {
                    order[k] = order[k - 1];
                    k -= 1;
                }
                order[k] = item;
                n += 1;
            }
            for &(_, item) in &order[..n] {
                stack.push(item);
            }
        }
        best
    }
}
