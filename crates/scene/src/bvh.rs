//! Bounds of primitives over the shutter, and the BVH2 over them (obvhs, PLOC build).
//!
//! A moving primitive's box must hold it at every instant of the shutter. When both poses share
//! the rotation, every point moves linearly (translation and scale are lerped), so the union of
//! the boxes at open and close holds it. Otherwise each object-space point `x` stays within
//! `max_scale · |x|` of the translation path, which is the segment between the two translations:
//! a conservative box (Hanika et al. would be tighter; this one is provably enough).

use crate::records::{prim_kind, Motion, Pose, NONE};
use crate::{Geometry, Prim};
use glam::{Vec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::bvh2::builder::build_bvh2;
use obvhs::bvh2::Bvh2;
use obvhs::BvhBuildParams;

/// Relative padding of moving primitives' boxes, covering `f32` rounding in `Motion::at`.
const MOTION_PAD: f32 = 1e-5;

/// World-space box of `prim` over the whole shutter.
pub fn prim_bounds(prim: &Prim, motions: &[Motion]) -> Aabb {
    let motion = (prim.motion != NONE)
        .then(|| motions.get(prim.motion as usize))
        .flatten();
    let Some(m) = motion else {
        return posed_bounds(prim, None);
    };
    let same_rotation = {
        let (a, b) = (m.open.rotation(), m.close.rotation());
        a == b || a == -b
    };
    let mut aabb = if same_rotation {
        let mut aabb = posed_bounds(prim, Some(&m.open));
        let close = posed_bounds(prim, Some(&m.close));
        aabb.extend(close.min).extend(close.max);
        aabb
    } else {
        rotating_bounds(prim, m)
    };
    let pad = MOTION_PAD
        * aabb
            .min
            .abs()
            .max(aabb.max.abs())
            .max_element()
            .max(aabb.diagonal().max_element());
    aabb.min -= pad;
    aabb.max += pad;
    aabb
}

/// Tight box of `prim` placed by `pose` (`None`: as stored).
fn posed_bounds(prim: &Prim, pose: Option<&Pose>) -> Aabb {
    let point = |p: [f32; 3]| pose.map_or(Vec3::from(p), |q| q.point_to_world(p.into()));
    let scale = pose.map_or(1.0, |q| q.scale().max_element());
    match prim.kind {
        prim_kind::SPHERE => {
            let (c, r) = (point(prim.a), prim.b[0] * scale);
            aabb(c - r, c + r)
        }
        prim_kind::DISK => {
            let c = point(prim.a);
            let n = pose.map_or(Vec3::from(prim.b), |q| q.normal_to_world(prim.b.into()));
            // Extent of a disk along axis i: r · sqrt(1 − nᵢ²).
            let e = prim.c[0] * scale * (Vec3::ONE - n * n).max(Vec3::ZERO).powf(0.5);
            aabb(c - e, c + e)
        }
        _ => {
            let [a, b, c] = [prim.a, prim.b, prim.c].map(point);
            aabb(a.min(b).min(c), a.max(b).max(c))
        }
    }
}

/// Conservative box for a primitive whose rotation changes during the shutter.
fn rotating_bounds(prim: &Prim, m: &Motion) -> Aabb {
    let max_scale = m.open.scale().max(m.close.scale()).max_element();
    let (t0, t1) = (m.open.translation(), m.close.translation());
    let path = aabb(t0.min(t1), t0.max(t1));
    // Object-space points and the radius about each that the prim reaches from it.
    let reach: Vec<(Vec3, f32)> = match prim.kind {
        prim_kind::SPHERE => vec![(prim.a.into(), prim.b[0])],
        prim_kind::DISK => vec![(prim.a.into(), prim.c[0])],
        _ => [prim.a, prim.b, prim.c]
            .map(|p| (Vec3::from(p), 0.0))
            .to_vec(),
    };
    let mut out = Aabb::empty();
    for (x, r) in reach {
        let d = max_scale * (x.length() + r);
        out.extend(path.min - d).extend(path.max + d);
    }
    out
}

fn aabb(min: Vec3, max: Vec3) -> Aabb {
    Aabb::new(Vec3A::from(min), Vec3A::from(max))
}

/// Primitives from which [`build`] takes obvhs's fast build rather than its medium one: a
/// narrower PLOC search and fewer reinsertions. From a million triangles on, a bumpy sphere
/// (`scripts/make-mesh-scene.py`) loads faster from the fast tree and renders as fast
/// (measured: docs/measurements/scaling.md#loading-4-m-triangles). Below this, building takes
/// well under a second either way, so the better tree is kept.
pub const FAST_BUILD_PRIMS: usize = 1_000_000;

/// The obvhs build parameters [`build`] uses for `prims` primitives.
pub fn build_params(prims: usize) -> BvhBuildParams {
    match prims >= FAST_BUILD_PRIMS {
        true => BvhBuildParams::fast_build(),
        false => BvhBuildParams::medium_build(),
    }
}

/// The BVH over the primitives of `geometry` and the world bounds over the shutter, built with
/// [`build_params`]. The primitives are reordered into BVH leaf order (their points stay) and
/// `primitive_indices` becomes the identity.
///
/// With no primitives the BVH has no nodes (obvhs traversal returns at once for an empty
/// `nodes`) and the bounds are the box `[-1, 1]³`.
pub fn build(geometry: &mut Geometry, motions: &[Motion]) -> (Bvh2, Vec3, Vec3) {
    build_with(geometry, motions, build_params(geometry.len()))
}

/// [`build`] with the given obvhs parameters.
pub fn build_with(
    geometry: &mut Geometry,
    motions: &[Motion],
    params: BvhBuildParams,
) -> (Bvh2, Vec3, Vec3) {
    if geometry.is_empty() {
        return (Bvh2::default(), Vec3::splat(-1.0), Vec3::splat(1.0));
    }
    let boxes: Vec<Aabb> = (0..geometry.len() as u32)
        .map(|id| match geometry.is_static_triangle(id) {
            true => {
                let [a, b, c] = geometry.vertices(id);
                aabb(a.min(b).min(c), a.max(b).max(c))
            }
            false => prim_bounds(&geometry.prim(id), motions),
        })
        .collect();
    let mut world = Aabb::empty();
    for b in &boxes {
        world.extend(b.min).extend(b.max);
    }
    let mut bvh = build_bvh2(&boxes, params, &mut Default::default());
    drop(boxes);

    // Reorder primitives into leaf order.
    let order = std::mem::take(&mut bvh.primitive_indices);
    geometry.reorder(&order);
    bvh.primitive_indices = (0..order.len() as u32).collect();
    if !bvh.primitives_to_nodes.is_empty() {
        let old = std::mem::take(&mut bvh.primitives_to_nodes);
        bvh.primitives_to_nodes = order.iter().map(|&i| old[i as usize]).collect();
    }
    (bvh, world.min.into(), world.max.into())
}
