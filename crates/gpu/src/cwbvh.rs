//! The compressed wide BVH (CWBVH; Ylitie, Karras & Laine 2017, "Efficient Incoherent Ray
//! Traversal on GPUs Through Compressed Wide BVHs") the GPU may traverse instead of the BVH2.
//!
//! Built from the scene's BVH2 by obvhs (`bvh2_to_cwbvh`: SAH-optimal collapse into 8-wide
//! nodes, children ordered by ray octant), then re-quantized here so that every child's grid
//! box, its planes evaluated in `f32` as the shader does (`p + q · step`, one rounding: `q · step`
//! is exact), contains the BVH2 leaf boxes of all primitives beneath it. Those boxes already
//! sweep the whole shutter, and the shader runs the BVH2's slab test on these planes; the test
//! is monotone in the box, rounding included, so the CWBVH traversal tests every primitive the
//! BVH2 traversal would (and, within a grid cell of the leaf boxes, a few more).
//!
//! Primitives stay where [`stratapt_scene::FlatScene::geometry`] has them (BVH2 leaf order); each node's primitive slots
//! map to them through `Cwbvh::prim_indices`.

use bytemuck::{Pod, Zeroable};
use obvhs::aabb::Aabb;
use obvhs::bvh2::node::Bvh2Node;
use obvhs::bvh2::Bvh2;
use obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh;
use obvhs::cwbvh::node::CwBvhNode;

/// One node of the compressed wide BVH (CWBVH; Ylitie, Karras & Laine 2017) as the shaders read
/// it: obvhs's `CwBvhNode`, field for field, built by [`Cwbvh::build`]. 80 bytes.
///
/// Up to eight children, each boxed on the node's grid: child `i` spans
/// `p + q · 2^(e − 127)` for `q` from `child_min_*[i]` to `child_max_*[i]` on each axis (these
/// planes, evaluated in `f32`, hold the BVH2 leaf boxes of every primitive beneath). `child_meta[i]`: 0 for an empty slot;
/// an inner child is `0b001_11iii` (`24 + i`, its node is `child_base` plus the number of inner
/// children in slots below `i`); a leaf child holds 1 to 3 primitive slots, unary in the top
/// three bits, starting at slot `child_meta[i] & 31` of this node.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct CwbvhNode {
    /// Origin of the child grid (the node box's min corner).
    pub p: [f32; 3],
    /// Grid step per axis as a biased `f32` exponent: `f32::from_bits((e as u32) << 23)`.
    pub e: [u8; 3],
    /// Bit `i` set: child `i` is an inner node.
    pub imask: u8,
    /// Index of the first inner child node (the inner children are consecutive).
    pub child_base: u32,
    /// This node's first primitive slot, an index into
    /// `Cwbvh::prim_indices`; in the uploaded node buffer (the slots
    /// follow the nodes, see [`Cwbvh::words`]) its word offset. Each slot
    /// holds an index into the primitives of [`stratapt_scene::FlatScene::geometry`].
    pub prim_base: u32,
    pub child_meta: [u8; 8],
    pub child_min_x: [u8; 8],
    pub child_max_x: [u8; 8],
    pub child_min_y: [u8; 8],
    pub child_max_y: [u8; 8],
    pub child_min_z: [u8; 8],
    pub child_max_z: [u8; 8],
}

const _: () = assert!(std::mem::size_of::<CwbvhNode>() == 80);

/// Most primitives in one leaf child (the CWBVH node format's limit).
const MAX_LEAF_PRIMS: u32 = 3;
/// Smallest grid step exponent: a flat axis gets a step of 2⁻¹⁰⁰ (still a normal `f32` once
/// scaled by a reciprocal direction component).
const MIN_STEP_EXP: i32 = -100;

/// A CWBVH over a scene's primitives.
#[derive(Clone, Debug, Default)]
pub struct Cwbvh {
    /// Nodes, root first. `prim_base` is an index into `prim_indices` here;
    /// [`Cwbvh::words`] turns it into a word offset.
    pub nodes: Vec<CwbvhNode>,
    /// Primitive slots: indices into the primitives of [`stratapt_scene::FlatScene::geometry`].
    pub prim_indices: Vec<u32>,
    /// Levels below the root of the deepest inner node (the traversal stack holds at most one
    /// pending group per level above it).
    pub depth: usize,
}

impl Cwbvh {
    /// The CWBVH of `bvh`, a BVH2 whose `primitive_indices` index the primitives (leaves of any
    /// size). Empty for an empty BVH.
    pub fn build(bvh: &Bvh2) -> Self {
        if bvh.nodes.is_empty() {
            return Self::default();
        }
        // obvhs converts BVH2s with one primitive per leaf: split the larger leaves, every new
        // node keeping the leaf's box.
        let mut single = Bvh2 {
            nodes: vec![Bvh2Node::default()],
            ..Default::default()
        };
        let mut leaf_box = vec![Aabb::empty(); bvh.primitive_indices.len()];
        split_leaves(bvh, 0, &mut single, 0, &mut leaf_box);
        let cw = bvh2_to_cwbvh(&single, MAX_LEAF_PRIMS, true, false);
        let mut out = Self {
            nodes: vec![CwbvhNode::default(); cw.nodes.len()],
            prim_indices: cw.primitive_indices.clone(),
            depth: 0,
        };
        let boxes = Boxes {
            cw: &cw.nodes,
            prims: &cw.primitive_indices,
            leaf_box: &leaf_box,
        };
        boxes.quantize(0, 0, &mut out);
        out
    }

    /// The node buffer the shaders read: the nodes, then the primitive slots (padded to 16
    /// bytes), each node's `prim_base` made a word offset into it.
    pub fn words(&self) -> Vec<u32> {
        let slots = (self.nodes.len() * std::mem::size_of::<CwbvhNode>() / 4) as u32;
        let mut words: Vec<u32> = Vec::with_capacity(slots as usize + self.prim_indices.len() + 3);
        for node in &self.nodes {
            let node = CwbvhNode {
                prim_base: node.prim_base + slots,
                ..*node
            };
            words.extend_from_slice(&bytemuck::cast::<CwbvhNode, [u32; 20]>(node));
        }
        words.extend_from_slice(&self.prim_indices);
        words.resize(words.len().next_multiple_of(4), 0);
        words
    }
}

/// Copy BVH2 node `src` of `bvh` into node `dst` of `out`, splitting leaves into single-primitive
/// leaves with the same box; record each primitive's leaf box.
fn split_leaves(bvh: &Bvh2, src: usize, out: &mut Bvh2, dst: usize, leaf_box: &mut [Aabb]) {
    let node = bvh.nodes[src];
    if node.is_leaf() {
        let first = node.first_index as usize;
        let prims = &bvh.primitive_indices[first..first + node.prim_count as usize];
        for &p in prims {
            leaf_box[p as usize] = *node.aabb();
        }
        split_range(prims, *node.aabb(), out, dst);
        return;
    }
    let children = out.nodes.len();
    out.nodes.resize(children + 2, Bvh2Node::default());
    out.nodes[dst] = Bvh2Node::new(*node.aabb(), 0, children as u32);
    split_leaves(bvh, node.first_index as usize, out, children, leaf_box);
    split_leaves(
        bvh,
        node.first_index as usize + 1,
        out,
        children + 1,
        leaf_box,
    );
}

/// A balanced subtree over `prims` at node `dst`, every node with box `aabb`.
fn split_range(prims: &[u32], aabb: Aabb, out: &mut Bvh2, dst: usize) {
    if let [p] = prims {
        out.nodes[dst] = Bvh2Node::new(aabb, 1, out.primitive_indices.len() as u32);
        out.primitive_indices.push(*p);
        return;
    }
    let children = out.nodes.len();
    out.nodes.resize(children + 2, Bvh2Node::default());
    out.nodes[dst] = Bvh2Node::new(aabb, 0, children as u32);
    let (a, b) = prims.split_at(prims.len() / 2);
    split_range(a, aabb, out, children);
    split_range(b, aabb, out, children + 1);
}

/// What re-quantization reads: obvhs's nodes and slots, and each primitive's BVH2 leaf box.
struct Boxes<'a> {
    cw: &'a [CwBvhNode],
    prims: &'a [u32],
    leaf_box: &'a [Aabb],
}

impl Boxes<'_> {
    /// Fill `out.nodes[index]` from obvhs's node with grid boxes that contain the exact boxes
    /// beneath; returns the node's exact box (the union of its children's).
    fn quantize(&self, index: usize, depth: usize, out: &mut Cwbvh) -> Aabb {
        let node = &self.cw[index];
        let mut child_boxes = [None; 8];
        for (ch, slot) in child_boxes.iter_mut().enumerate() {
            if node.is_child_empty(ch) {
                continue;
            }
            *slot = Some(if node.is_leaf(ch) {
                let (first, count) = node.child_primitives(ch);
                let mut b = Aabb::empty();
                for s in first..first + count {
                    let leaf = &self.leaf_box[self.prims[s as usize] as usize];
                    b.extend(leaf.min).extend(leaf.max);
                }
                b
            } else {
                out.depth = out.depth.max(depth + 1);
                self.quantize(node.child_node_index(ch) as usize, depth + 1, out)
            });
        }
        let mut total = Aabb::empty();
        for b in child_boxes.iter().flatten() {
            total.extend(b.min).extend(b.max);
        }
        let mut q = CwbvhNode {
            p: total.min.into(),
            imask: node.imask,
            child_base: node.child_base_idx,
            prim_base: node.primitive_base_idx,
            child_meta: node.child_meta,
            ..Default::default()
        };
        for axis in 0..3 {
            let (lo, hi) = (total.min[axis], total.max[axis]);
            let exp = step_exponent(hi as f64 - lo as f64);
            q.e[axis] = (exp + 127) as u8;
            let step = f32::from_bits(((exp + 127) as u32) << 23);
            let (mins, maxs) = match axis {
                0 => (&mut q.child_min_x, &mut q.child_max_x),
                1 => (&mut q.child_min_y, &mut q.child_max_y),
                _ => (&mut q.child_min_z, &mut q.child_max_z),
            };
            for (ch, b) in child_boxes.iter().enumerate() {
                if let Some(b) = b {
                    (mins[ch], maxs[ch]) = grid_span(lo, step, b.min[axis], b.max[axis]);
                }
            }
        }
        out.nodes[index] = q;
        total
    }
}

/// Exponent of the smallest power-of-two grid step whose 255 steps cover `extent`.
fn step_exponent(extent: f64) -> i32 {
    let mut exp = (extent / 255.0).log2().ceil().max(MIN_STEP_EXP as f64) as i32;
    while 255.0 * (exp as f64).exp2() < extent {
        exp += 1;
    }
    while exp > MIN_STEP_EXP && 255.0 * ((exp - 1) as f64).exp2() >= extent {
        exp -= 1;
    }
    exp
}

/// A grid plane as the shader computes it: `origin + q · step` in `f32` (`q · step` is exact, so
/// with or without a fused multiply-add this is one rounding of the exact value).
fn grid_plane(origin: f32, step: f32, q: u32) -> f32 {
    origin + q as f32 * step
}

/// Grid cells `(qlo, qhi)` whose planes satisfy `plane(qlo) <= lo` and `plane(qhi) >= hi`, for
/// `lo..hi` inside `origin .. origin + extent` with `255 · step >= extent`: `plane(0)` is
/// `origin`, and `plane(255)` rounds a value at least the box's max, itself an `f32`.
fn grid_span(origin: f32, step: f32, lo: f32, hi: f32) -> (u8, u8) {
    let cell = |x: f32| (x as f64 - origin as f64) / step as f64;
    let mut qlo = cell(lo).floor().clamp(0.0, 255.0) as u32;
    while qlo > 0 && grid_plane(origin, step, qlo) > lo {
        qlo -= 1;
    }
    let mut qhi = cell(hi).ceil().clamp(0.0, 255.0) as u32;
    while qhi < 255 && grid_plane(origin, step, qhi) < hi {
        qhi += 1;
    }
    debug_assert!(grid_plane(origin, step, qlo) <= lo && grid_plane(origin, step, qhi) >= hi);
    (qlo as u8, qhi as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every primitive once; every child's grid box holds the leaf boxes beneath it.
    fn check(bvh: &Bvh2, cw: &Cwbvh) {
        let mut seen = vec![0; bvh.primitive_indices.len()];
        let mut leaf_box = vec![Aabb::empty(); seen.len()];
        for n in bvh.nodes.iter().filter(|n| n.is_leaf()) {
            let first = n.first_index as usize;
            for &p in &bvh.primitive_indices[first..first + n.prim_count as usize] {
                leaf_box[p as usize] = *n.aabb();
            }
        }
        // (node, the intersection of its ancestors' grid boxes, as the shader's f32 planes).
        let mut todo = vec![(0usize, [[f64::MIN; 3], [f64::MAX; 3]])];
        while let Some((i, parent)) = todo.pop() {
            let n = &cw.nodes[i];
            for ch in 0..8 {
                let meta = n.child_meta[ch];
                if meta == 0 {
                    continue;
                }
                let q = [
                    [n.child_min_x[ch], n.child_min_y[ch], n.child_min_z[ch]],
                    [n.child_max_x[ch], n.child_max_y[ch], n.child_max_z[ch]],
                ];
                let mut grid = parent;
                for a in 0..3 {
                    let step = f32::from_bits((n.e[a] as u32) << 23);
                    let plane = |q: u8| grid_plane(n.p[a], step, q as u32) as f64;
                    grid[0][a] = grid[0][a].max(plane(q[0][a]));
                    grid[1][a] = grid[1][a].min(plane(q[1][a]));
                }
                if n.imask & (1 << ch) != 0 {
                    let slot = (meta & 31) as u32 - 24;
                    let rel = (n.imask as u32 & !(u32::MAX << slot)).count_ones();
                    todo.push(((n.child_base + rel) as usize, grid));
                    continue;
                }
                let first = n.prim_base + (meta & 31) as u32;
                for s in first..first + (meta >> 5).count_ones() {
                    let p = cw.prim_indices[s as usize] as usize;
                    seen[p] += 1;
                    let b = leaf_box[p];
                    assert!(
                        (0..3).all(|a| grid[0][a] <= b.min[a] as f64 && grid[1][a] >= b.max[a] as f64),
                        "prim {p}: leaf box {b:?} outside grid box {grid:?}"
                    );
                }
            }
        }
        assert!(seen.iter().all(|&c| c == 1), "primitives seen {seen:?}");
    }

    #[test]
    fn every_scene_cwbvh_holds_each_primitive_once_in_conservative_boxes() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        let mut n = 0;
        for path in stratapt_import::load::scene_files(&dir).unwrap() {
            let scene = stratapt_import::scene_file::load(&path).unwrap_or_else(|e| panic!("{e}"));
            let cw = Cwbvh::build(&scene.bvh);
            check(&scene.bvh, &cw);
            let words = cw.words();
            assert_eq!(words.len() % 4, 0);
            assert_eq!(
                words.len(),
                (cw.nodes.len() * 20 + cw.prim_indices.len()).next_multiple_of(4)
            );
            println!(
                "{}: {} BVH2 nodes, {} CWBVH nodes, depth {}",
                path.display(),
                scene.bvh.nodes.len(),
                cw.nodes.len(),
                cw.depth
            );
            n += 1;
        }
        assert!(n >= 10);
    }

    #[test]
    fn grid_spans_are_conservative_at_awkward_values() {
        let cases = [
            (0.1f32, 0.3f32),
            (-1e-7, 1e-7),
            (1000.001, 1000.002),
            (5.0, 5.0),
            (-548.8, 1e-3),
            (3.0e7, 3.0000002e7),
        ];
        for (lo, hi) in cases {
            let exp = step_exponent(hi as f64 - lo as f64);
            let step = f32::from_bits(((exp + 127) as u32) << 23);
            assert!(255.0 * step as f64 >= (hi as f64 - lo as f64));
            let (a, b) = grid_span(lo, step, lo, hi);
            assert_eq!(a, 0);
            assert!(grid_plane(lo, step, b as u32) >= hi);
            // Any box inside gets planes outside it.
            let (x0, x1) = (lo + (hi - lo) * 0.3, lo + (hi - lo) * 0.7);
            let (a, b) = grid_span(lo, step, x0, x1);
            assert!(grid_plane(lo, step, a as u32) <= x0 && grid_plane(lo, step, b as u32) >= x1);
        }
    }

    #[test]
    fn empty_bvh_has_no_nodes() {
        let cw = Cwbvh::build(&Bvh2::default());
        assert!(cw.nodes.is_empty() && cw.words().is_empty());
    }
}
