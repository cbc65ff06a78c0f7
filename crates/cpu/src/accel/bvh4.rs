//! The CPU's 4-wide BVH: the scene crate's BVH2 collapsed so that every node holds up to four
//! children, whose boxes are tested at once in SIMD lanes (glam's `Vec4`: SSE on x86-64, NEON
//! on AArch64, scalar elsewhere). The boxes are the BVH2's own, not re-fitted or quantized, and
//! each lane runs the scalar slab test's operations in the same order, so a box is entered
//! exactly when the BVH2 traversal entered it.
//!
//! Collapsing: a node's two children are expanded, largest surface area first, until it has four
//! children or only leaves (Wald, Benthin & Boulos 2008, "Getting Rid of Packets"). Leaves keep
//! their BVH2 primitive ranges; their static triangles go into 4-wide [`Packet`]s.

use super::packet::{Packet, LANES};
use glam::{BVec4A, Vec3, Vec4};
use obvhs::bvh2::node::Bvh2Node;
use stratapt_scene::shared::BVH_EXIT_SCALE as EXIT_SCALE;
use stratapt_scene::Geometry;

/// A child reference: a node index, or (with [`LEAF`] set) a leaf index.
pub(super) type Child = u32;
/// Marks a [`Child`] as a leaf.
pub(super) const LEAF: u32 = 1 << 31;

/// Up to four children's boxes, one per lane, by axis.
#[derive(Clone, Copy, Debug)]
pub(super) struct Node4 {
    pub min: [Vec4; 3],
    pub max: [Vec4; 3],
    pub child: [Child; LANES],
    /// Lane `i` holds a child (bit `i`).
    pub valid: u32,
}

/// A leaf's primitives: whole packets of static triangles, then the primitives tested one by
/// one (spheres, disks, moving triangles), as ranges into [`Bvh4::packets`] and
/// [`Bvh4::singles`].
#[derive(Clone, Copy, Debug)]
pub(super) struct Leaf {
    pub packets: [u32; 2],
    pub singles: [u32; 2],
}

/// The collapsed BVH. `root` is the BVH2 root's child reference: the top node, or a lone leaf
/// for a scene whose BVH2 is one leaf; empty scenes have no root. (Its box is not kept: every
/// child's box lies inside it, so traversal starts at the top node's four.)
#[derive(Debug, Default)]
pub(super) struct Bvh4 {
    pub nodes: Vec<Node4>,
    pub leaves: Vec<Leaf>,
    pub packets: Vec<Packet>,
    pub singles: Vec<u32>,
    pub root: Option<Child>,
}

impl Bvh4 {
    /// Collapse `nodes` (obvhs BVH2, root at 0, primitives in leaf order) over `geometry`.
    ///
    /// Iterative (a work list, not recursion), so a degenerate, very deep BVH2 cannot overflow
    /// the thread's stack.
    pub fn new(nodes: &[Bvh2Node], geometry: &Geometry) -> Self {
        let mut out = Self::default();
        if nodes.is_empty() {
            return out;
        }
        // (BVH2 node, where its child reference goes: a lane of a Node4, or the root).
        let mut work: Vec<(u32, Option<(usize, usize)>)> = vec![(0, None)];
        while let Some((index, parent)) = work.pop() {
            let child = out.child(nodes, index, geometry, &mut work);
            match parent {
                Some((slot, lane)) => out.nodes[slot].child[lane] = child,
                None => out.root = Some(child),
            }
        }
        out
    }

    /// The child reference for BVH2 node `index`: a leaf, or a new node whose children are
    /// queued on `work`.
    fn child(
        &mut self,
        nodes: &[Bvh2Node],
        index: u32,
        geometry: &Geometry,
        work: &mut Vec<(u32, Option<(usize, usize)>)>,
    ) -> Child {
        let node = &nodes[index as usize];
        if node.is_leaf() {
            return LEAF
                | self.leaf(
                    node.first_index..node.first_index + node.prim_count,
                    geometry,
                );
        }
        // ---- Expand the largest inner child until there are four ---------------------------
        let mut kids = vec![node.first_index, node.first_index + 1];
        while kids.len() < LANES {
            let widest = kids
                .iter()
                .enumerate()
                .filter(|(_, &k)| !nodes[k as usize].is_leaf())
                .max_by(|(_, &a), (_, &b)| {
                    let area = |k: u32| nodes[k as usize].aabb().half_area();
                    area(a).total_cmp(&area(b))
                })
                .map(|(i, _)| i);
            let Some(i) = widest else { break };
            let first = nodes[kids[i] as usize].first_index;
            kids.splice(i..=i, [first, first + 1]);
        }
        // ---- The node's boxes; its children are filled in as the work list reaches them ----
        let (mut min, mut max) = ([[0.0f32; LANES]; 3], [[0.0f32; LANES]; 3]);
        let slot = self.nodes.len();
        for (lane, &k) in kids.iter().enumerate() {
            let aabb = nodes[k as usize].aabb();
            for axis in 0..3 {
                min[axis][lane] = aabb.min[axis];
                max[axis][lane] = aabb.max[axis];
            }
            work.push((k, Some((slot, lane))));
        }
        self.nodes.push(Node4 {
            min: min.map(Vec4::from_array),
            max: max.map(Vec4::from_array),
            child: [0; LANES],
            valid: (1 << kids.len()) - 1,
        });
        slot as u32
    }

    /// A leaf over `range` of the primitives: static triangles in packets, the rest one by one.
    fn leaf(&mut self, range: std::ops::Range<u32>, geometry: &Geometry) -> u32 {
        let packed = |id: &u32| geometry.is_static_triangle(*id);
        let triangles: Vec<u32> = range.clone().filter(packed).collect();
        let first_packet = self.packets.len() as u32;
        self.packets.extend(
            triangles
                .chunks(LANES)
                .map(|ids| Packet::new(ids, geometry)),
        );
        let first_single = self.singles.len() as u32;
        self.singles.extend(range.filter(|id| !packed(id)));
        self.leaves.push(Leaf {
            packets: [first_packet, self.packets.len() as u32],
            singles: [first_single, self.singles.len() as u32],
        });
        (self.leaves.len() - 1) as u32
    }
}

/// A ray's origin and exact reciprocal direction, splat across lanes.
#[derive(Clone, Copy, Debug)]
pub(super) struct RayLanes {
    pub origin: [Vec4; 3],
    pub inv_dir: [Vec4; 3],
}

impl RayLanes {
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        let inv = Vec3::ONE / dir;
        Self {
            origin: [origin.x, origin.y, origin.z].map(Vec4::splat),
            inv_dir: [inv.x, inv.y, inv.z].map(Vec4::splat),
        }
    }
}

/// `a < b ? a : b` per lane: `b` where either is NaN (the scalar slab test's comparisons).
/// One `minps` on x86-64, whose definition this is; elsewhere a compare and select (NEON's
/// minimum would return the NaN).
#[inline]
fn less_or(a: Vec4, b: Vec4) -> Vec4 {
    #[cfg(target_arch = "x86_64")]
    {
        a.min(b)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        Vec4::select(a.cmplt(b), a, b)
    }
}

/// `a > b ? a : b` per lane: `b` where either is NaN (see [`less_or`]).
#[inline]
fn greater_or(a: Vec4, b: Vec4) -> Vec4 {
    #[cfg(target_arch = "x86_64")]
    {
        a.max(b)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        Vec4::select(a.cmpgt(b), a, b)
    }
}

impl Node4 {
    /// Entry distances of the ray into the four children, and which of them overlap
    /// `[tmin, tmax]` (bit per lane).
    ///
    /// Per lane, the scalar slab test (Ize 2013): each exit distance widened by `1 + 2γ₃`, and
    /// a NaN slab distance (an origin on a slab plane with a zero direction component, `0 · ∞`)
    /// leaves the interval unchanged, since `NaN > t0` and `NaN < t1` are false.
    #[inline]
    pub fn enter(&self, ray: &RayLanes, tmin: f32, tmax: f32) -> (Vec4, u32) {
        let (mut t0, mut t1) = (Vec4::splat(tmin), Vec4::splat(tmax));
        for axis in 0..3 {
            let near = (self.min[axis] - ray.origin[axis]) * ray.inv_dir[axis];
            let far = (self.max[axis] - ray.origin[axis]) * ray.inv_dir[axis];
            // Ordered (`if near > far { swap }`), the exit widened, the interval narrowed.
            let (near, far) = (less_or(far, near), greater_or(near, far) * EXIT_SCALE);
            t0 = greater_or(near, t0);
            t1 = less_or(far, t1);
        }
        let overlap: BVec4A = t0.cmple(t1);
        (t0, overlap.bitmask() & self.valid)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stratapt_scene::bvh;
    use stratapt_scene::records::{prim_kind, Motion, Pose, NONE};
    use stratapt_scene::Prim;

    fn prim(kind: u32, a: [f32; 3], b: [f32; 3], c: [f32; 3], motion: u32) -> Prim {
        Prim {
            a,
            kind,
            b,
            c,
            light: NONE,
            motion,
            ..Default::default()
        }
    }

    /// The lane minimum and maximum keep the scalar comparisons' answer for NaN, infinities
    /// and signed zeros, bit for bit, in either operand.
    #[test]
    fn lane_min_and_max_are_the_scalar_comparisons() {
        let values = [
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            0.0,
            -0.0,
            1.0,
            -1.0,
            f32::MIN_POSITIVE,
            3.0e38,
        ];
        for &a in &values {
            for &b in &values {
                let less = less_or(Vec4::splat(a), Vec4::splat(b)).x;
                let greater = greater_or(Vec4::splat(a), Vec4::splat(b)).x;
                let (want_less, want_greater) =
                    (if a < b { a } else { b }, if a > b { a } else { b });
                assert_eq!(less.to_bits(), want_less.to_bits(), "{a} < {b}");
                assert_eq!(greater.to_bits(), want_greater.to_bits(), "{a} > {b}");
            }
        }
    }

    /// Every primitive lands in exactly one leaf (static triangles in a packet, the rest
    /// alone), every node and leaf is reached once, and nodes hold two to four children.
    #[test]
    fn collapsing_keeps_every_primitive_once() {
        for n in [1usize, 2, 3, 5, 17, 300, 2000] {
            let prims: Vec<Prim> = (0..n)
                .map(|i| {
                    let x = (i as f32 * 0.618_034).fract() * 40.0;
                    let y = (i as f32 * 0.414_214).fract() * 40.0;
                    match i % 7 {
                        0 => prim(
                            prim_kind::SPHERE,
                            [x, y, 0.0],
                            [0.3, 0.0, 0.0],
                            [0.0; 3],
                            NONE,
                        ),
                        // Moving triangles are tested one by one (motion 0 is the one motion).
                        1 => prim(
                            prim_kind::TRIANGLE,
                            [x, y, 0.0],
                            [x + 1.0, y, 0.0],
                            [x, y + 1.0, 1.0],
                            0,
                        ),
                        _ => prim(
                            prim_kind::TRIANGLE,
                            [x, y, 0.0],
                            [x + 1.0, y, 0.0],
                            [x, y + 1.0, 1.0],
                            NONE,
                        ),
                    }
                })
                .collect();
            let still = Pose::new(Vec3::ZERO, glam::Quat::IDENTITY, Vec3::ONE);
            let motions = vec![Motion {
                open: still,
                close: still,
            }];
            let mut geometry = stratapt_scene::Geometry::from_prims(&prims);
            let (bvh2, _, _) = bvh::build(&mut geometry, &motions);
            let wide = Bvh4::new(&bvh2.nodes, &geometry);
            let mut seen = vec![0u32; n];
            let (mut nodes, mut leaves) = (0, 0);
            let root = wide.root.expect("non-empty scene has a root");
            let mut work = vec![root];
            while let Some(child) = work.pop() {
                if child & LEAF != 0 {
                    leaves += 1;
                    let leaf = wide.leaves[(child & !LEAF) as usize];
                    for packet in &wide.packets[leaf.packets[0] as usize..leaf.packets[1] as usize]
                    {
                        for lane in 0..packet.valid.count_ones() as usize {
                            let id = packet.prim[lane] as usize;
                            let p = geometry.prim(id as u32);
                            assert_eq!(p.motion, NONE);
                            assert_eq!(p.kind, prim_kind::TRIANGLE);
                            seen[id] += 1;
                        }
                    }
                    for &id in &wide.singles[leaf.singles[0] as usize..leaf.singles[1] as usize] {
                        seen[id as usize] += 1;
                    }
                    continue;
                }
                nodes += 1;
                let node = &wide.nodes[child as usize];
                let children = node.valid.count_ones() as usize;
                assert!((2..=LANES).contains(&children) && node.valid == (1 << children) - 1);
                work.extend(&node.child[..children]);
            }
            assert!(seen.iter().all(|&k| k == 1), "{n} prims: {seen:?}");
            assert_eq!(
                (nodes, leaves),
                (wide.nodes.len(), wide.leaves.len()),
                "{n} prims"
            );
        }
    }
}
