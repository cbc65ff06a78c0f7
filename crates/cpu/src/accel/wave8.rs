//! Eight rays through the 4-wide BVH together, for the eight-lane renderer
//! ([`crate::eight`]): one ray per lane of an AVX2 vector, as `stream8` traverses them, and
//! each triangle of a leaf tested against the eight rays at once (the one-ray watertight test's
//! operations per lane, so a lane turns a triangle away exactly when the one-ray test does; a
//! hit within its rounding-error bound goes to the one-ray test, which decides it).
//!
//! A path tracer's eight rays diverge after the first bounce; what the shared traversal costs
//! and gains against eight one-ray traversals is measured in `docs/measurements/eight-lanes.md`.

use super::bvh4::{Child, LEAF};
use super::{finish, Accel, Found};
use crate::intersect::triangle::{intersect_sheared, t_error_bound, Shear};
use crate::intersect::{intersect_prim_sheared, Hit, Ray};
use crate::lanes::{bits, mask_of, Mask, LANES, V3};
use glam::Vec3;
use stratapt_scene::records::surface_flag::{SHADING_NORMALS, UV};
use stratapt_scene::shared::{BVH_EXIT_SCALE, EDGE_BARY, GAMMA_7};
use wide::{f32x8, CmpGt, CmpLe, CmpLt, CmpNe};

/// Eight rays over `(0, tmax)` in SoA form, with each ray's triangle-test shear
/// ([`Shear::new`]'s values, computed in the lanes).
pub(crate) struct Rays8 {
    origin: V3,
    dir: V3,
    inv_dir: V3,
    tmax: f32x8,
    /// Lanes whose permuted axis `kx` (`ky`, `kz`) is x, and those where it is y.
    k: [[Mask; 2]; 3],
    s: [f32x8; 3],
}

impl Rays8 {
    /// The rays `origin + t·dir`, `t ∈ (0, tmax)`, lane by lane (unit directions).
    pub fn new(origin: V3, dir: V3, tmax: f32x8) -> Self {
        // ---- The dominant axis kz (the first largest |d|), then kx, ky after it, swapped
        // where d[kz] < 0 to keep the winding ------------------------------------------------
        let (ax, ay, az) = (dir.x.abs(), dir.y.abs(), dir.z.abs());
        let y_wins = ay.cmp_gt(ax);
        let z_wins = az.cmp_gt(y_wins.blend(ay, ax));
        let (kz_z, kz_y) = (z_wins, y_wins & !z_wins);
        let kz_x = !(kz_z | kz_y);
        let dz = kz_x.blend(dir.x, kz_y.blend(dir.y, dir.z));
        let neg = dz.cmp_lt(f32x8::ZERO);
        let k = [
            [(kz_z & !neg) | (kz_y & neg), (kz_x & !neg) | (kz_z & neg)],
            [(kz_y & !neg) | (kz_z & neg), (kz_z & !neg) | (kz_x & neg)],
            [kz_x, kz_y],
        ];
        let one = f32x8::ONE;
        let mut rays = Self {
            origin,
            dir,
            inv_dir: V3 {
                x: one / dir.x,
                y: one / dir.y,
                z: one / dir.z,
            },
            tmax,
            k,
            s: [f32x8::ZERO; 3],
        };
        let sz = one / dz;
        rays.s = [rays.permuted(&dir, 0) * sz, rays.permuted(&dir, 1) * sz, sz];
        rays
    }

    /// Ray `i` on its own.
    fn ray(&self, i: usize) -> Ray {
        Ray::new(
            self.origin.lane(i),
            self.dir.lane(i),
            self.tmax.as_array_ref()[i],
        )
    }

    /// Coordinate `k` of the permuted axes (`kx`, `ky`, `kz`) of `v`, per lane.
    #[inline(always)]
    fn permuted(&self, v: &V3, k: usize) -> f32x8 {
        let [is_x, is_y] = self.k[k];
        is_x.blend(v.x, is_y.blend(v.y, v.z))
    }
}

thread_local! {
    /// This thread's stack of `(child, rays that entered it, their entry distances)`.
    static STACK: std::cell::RefCell<Vec<(Child, u32, f32x8)>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// A leaf triangle's test against eight rays: the lanes that might hit it, those that surely
/// do (beyond the rounding-error bound), and the distances and barycentrics.
struct Lanes8 {
    candidates: u32,
    sure: u32,
    t: f32x8,
    bary: V3,
}

impl Accel<'_> {
    /// The nearest surface along each live ray of `rays` (`live`: bit per lane); every ray
    /// finds the hit it finds alone (up to exact ties).
    pub(crate) fn closest_hits8(&self, rays: &Rays8, live: u32) -> [Option<Hit>; LANES] {
        super::count_rays(live.count_ones() as u64);
        let found = self.traverse_wave8(rays, live, false);
        self.surfaces8(rays, &found)
    }

    /// The surface geometry of the hits `found` along `rays`: [`finish`]'s, computed in the
    /// lanes for static triangles without shading normals or texture coordinates (the same
    /// operations, the same bits), lane by lane for the others.
    fn surfaces8(&self, rays: &Rays8, found: &[Option<Found>; LANES]) -> [Option<Hit>; LANES] {
        let scene = self.scene;
        let mut hits = [None; LANES];
        let (mut a, mut b, mut c, mut w) = (
            [Vec3::ZERO; LANES],
            [Vec3::ZERO; LANES],
            [Vec3::ZERO; LANES],
            [Vec3::ONE; LANES],
        );
        let mut lanes = 0u32;
        for (i, found) in found.iter().enumerate() {
            let Some(f) = found else { continue };
            let plain = scene.geometry.surface(f.prim).flags & (SHADING_NORMALS | UV) == 0;
            match f.bary {
                Some(bary) if plain && scene.geometry.is_static_triangle(f.prim) => {
                    [a[i], b[i], c[i]] = scene.geometry.vertices(f.prim);
                    w[i] = bary;
                    lanes |= 1 << i;
                }
                _ => hits[i] = Some(finish(scene, &rays.ray(i), f, 0.0)),
            }
        }
        if lanes == 0 {
            return hits;
        }
        let (a, b, c) = (V3::from_lanes(&a), V3::from_lanes(&b), V3::from_lanes(&c));
        // The point, moved off the edges by `EDGE_BARY`, and its error bound on every axis.
        let edge = f32x8::splat(EDGE_BARY);
        let w = V3::from_lanes(&w);
        let w = V3 {
            x: w.x.max(edge),
            y: w.y.max(edge),
            z: w.z.max(edge),
        };
        let w = w.div(w.x + w.y + w.z);
        let (aw, bw, cw) = (a * w.x, b * w.y, c * w.z);
        let p = aw + bw + cw;
        let err = f32x8::splat(GAMMA_7) * (aw.abs() + bw.abs() + cw.abs()).max_element();
        // The unit normal; a sliver hit edge-on faces the ray.
        let n = (b - a).cross(c - a);
        let rcp = f32x8::ONE / n.length();
        let ok = rcp.is_finite() & rcp.cmp_gt(f32x8::ZERO);
        let ng = V3::select(ok, n * rcp, -rays.dir.normalize());
        for i in (0..LANES).filter(|i| lanes & (1 << i) != 0) {
            let f = found[i].expect("a lane with a hit");
            hits[i] = Some(Hit {
                t: f.t,
                prim: f.prim,
                p: p.lane(i),
                err: Vec3::splat(err.as_array_ref()[i]),
                ng: ng.lane(i),
                ns: ng.lane(i),
                uv: glam::Vec2::ZERO,
            });
        }
        hits
    }

    /// The live rays of `rays` that something blocks, as bits.
    pub(crate) fn occluded_wave8(&self, rays: &Rays8, live: u32) -> u32 {
        super::count_rays(live.count_ones() as u64);
        let found = self.traverse_wave8(rays, live, true);
        (0..LANES).fold(0, |m, i| m | (found[i].is_some() as u32) << i)
    }

    fn traverse_wave8(&self, rays: &Rays8, live: u32, any: bool) -> [Option<Found>; LANES] {
        STACK.with_borrow_mut(|stack| {
            stack.clear();
            self.traverse_wave8_with(stack, rays, live, any)
        })
    }

    fn traverse_wave8_with(
        &self,
        stack: &mut Vec<(Child, u32, f32x8)>,
        rays: &Rays8,
        live: u32,
        any: bool,
    ) -> [Option<Found>; LANES] {
        let mut best: [Option<Found>; LANES] = [None; LANES];
        let Some(root) = self.bvh.root else {
            return best;
        };
        let mut tmax = rays.tmax;
        let mut finished = 0u32;
        stack.push((root, live, f32x8::ZERO));
        while let Some((child, mask, entry)) = stack.pop() {
            // A closer hit found since this child was pushed may rule rays out.
            let mask = mask & !finished & !bits(entry.cmp_gt(tmax));
            if mask == 0 {
                continue;
            }
            if child & LEAF != 0 {
                finished |= self.leaf8(child & !LEAF, rays, mask, &mut tmax, any, &mut best);
                continue;
            }
            // ---- Each child against the eight rays; nearest (by its nearest ray) popped first
            let node = &self.bvh.nodes[child as usize];
            let live = mask_of(mask);
            let mut order = [(f32::INFINITY, 0 as Child, 0u32, f32x8::ZERO); 4];
            let mut n = 0;
            let mut children = node.valid;
            while children != 0 {
                let c = children.trailing_zeros() as usize;
                children &= children - 1;
                let (mut t0, mut t1) = (f32x8::ZERO, tmax);
                for axis in 0..3 {
                    let (o, inv) = match axis {
                        0 => (rays.origin.x, rays.inv_dir.x),
                        1 => (rays.origin.y, rays.inv_dir.y),
                        _ => (rays.origin.z, rays.inv_dir.z),
                    };
                    let near = (f32x8::splat(node.min[axis][c]) - o) * inv;
                    let far = (f32x8::splat(node.max[axis][c]) - o) * inv;
                    let (near, far) = (less_or(far, near), greater_or(near, far));
                    let far = far * f32x8::splat(BVH_EXIT_SCALE);
                    t0 = greater_or(near, t0);
                    t1 = less_or(far, t1);
                }
                let inside = t0.cmp_le(t1) & live;
                let entered = bits(inside);
                if entered == 0 {
                    continue;
                }
                let item = (0.0, node.child[c], entered, t0);
                if any {
                    stack.push((item.1, item.2, item.3));
                    continue;
                }
                // The nearest entry of the rays that enter.
                let near = inside.blend(t0, f32x8::splat(f32::INFINITY));
                let key = near
                    .as_array_ref()
                    .iter()
                    .fold(f32::INFINITY, |k, &t| k.min(t));
                let item = (key, item.1, item.2, item.3);
                // Farthest first on the stack.
                let mut k = n;
                while k > 0 && order[k - 1].0.total_cmp(&key).is_lt() {
                    order[k] = order[k - 1];
                    k -= 1;
                }
                order[k] = item;
                n += 1;
            }
            for &(_, c, m, t) in &order[..n] {
                stack.push((c, m, t));
            }
        }
        best
    }

    /// Test leaf `index`'s primitives against the rays `mask`, shortening `tmax` to each
    /// closer hit and recording it in `best`; returns the rays whose any-hit query (`any`) is
    /// answered.
    fn leaf8(
        &self,
        index: u32,
        rays: &Rays8,
        mask: u32,
        tmax: &mut f32x8,
        any: bool,
        best: &mut [Option<Found>; LANES],
    ) -> u32 {
        let (bvh, scene) = (&self.bvh, self.scene);
        let leaf = bvh.leaves[index as usize];
        let mut answered = 0u32;
        let mut mask = mask;
        for packet in &bvh.packets[leaf.packets[0] as usize..leaf.packets[1] as usize] {
            let mut triangles = packet.valid;
            while triangles != 0 && mask != 0 {
                let lane = triangles.trailing_zeros() as usize;
                triangles &= triangles - 1;
                let [a, b, c] = packet.triangle(lane);
                let id = packet.prim[lane];
                let lanes = test8(a, b, c, rays, *tmax);
                let mut candidates = lanes.candidates & mask;
                while candidates != 0 {
                    let i = candidates.trailing_zeros() as usize;
                    candidates &= candidates - 1;
                    let limit = tmax.as_array_ref()[i];
                    let hit = if lanes.sure & (1 << i) != 0 {
                        let t = lanes.t.as_array_ref()[i];
                        (t < limit).then(|| (t, lanes.bary.lane(i)))
                    } else {
                        let o = rays.origin.lane(i);
                        let shear = Shear::new(rays.dir.lane(i));
                        intersect_sheared(a, b, c, o, &shear, 0.0, limit).map(|h| (h.t, h.bary))
                    };
                    if let Some((t, bary)) = hit {
                        best[i] = Some(Found {
                            prim: id,
                            t,
                            bary: Some(bary),
                        });
                        tmax.as_array_mut()[i] = t;
                        if any {
                            answered |= 1 << i;
                            mask &= !(1 << i);
                        }
                    }
                }
            }
        }
        // ---- Spheres, disks and moving triangles, ray by ray --------------------------------
        for &id in &bvh.singles[leaf.singles[0] as usize..leaf.singles[1] as usize] {
            let prim = scene.geometry.prim(id);
            for (i, best) in best.iter_mut().enumerate() {
                if mask & (1 << i) == 0 {
                    continue;
                }
                let mut r = rays.ray(i);
                r.tmax = tmax.as_array_ref()[i];
                let shear = Shear::new(r.dir);
                let t =
                    intersect_prim_sheared(&prim, &scene.motions, &scene.tables, &r, &shear, 0.0);
                if t < r.tmax {
                    *best = Some(Found {
                        prim: id,
                        t,
                        bary: None,
                    });
                    tmax.as_array_mut()[i] = t;
                    if any {
                        answered |= 1 << i;
                        mask &= !(1 << i);
                    }
                }
            }
        }
        answered
    }
}

/// Triangle `(a, b, c)` against eight rays within `(0, tmax)`: [`super::packet::Packet::test`]
/// with rays in the lanes instead of triangles.
#[inline]
fn test8(a: Vec3, b: Vec3, c: Vec3, rays: &Rays8, tmax: f32x8) -> Lanes8 {
    let o = &rays.origin;
    let rel = |v: Vec3| V3 {
        x: f32x8::splat(v.x) - o.x,
        y: f32x8::splat(v.y) - o.y,
        z: f32x8::splat(v.z) - o.z,
    };
    let (pa, pb, pc) = (rel(a), rel(b), rel(c));
    let [sx, sy, sz] = rays.s;
    let k = |v: &V3| {
        (
            rays.permuted(v, 0),
            rays.permuted(v, 1),
            rays.permuted(v, 2),
        )
    };
    let ((pax, pay, paz), (pbx, pby, pbz), (pcx, pcy, pcz)) = (k(&pa), k(&pb), k(&pc));
    // ---- Sheared vertices and the 2D edge functions (zero counts as inside) ----------------
    let ax = pax - sx * paz;
    let ay = pay - sy * paz;
    let bx = pbx - sx * pbz;
    let by = pby - sy * pbz;
    let cx = pcx - sx * pcz;
    let cy = pcy - sy * pcz;
    let u = cx * by - cy * bx;
    let v = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    let zero = f32x8::ZERO;
    let negative = u.cmp_lt(zero) | v.cmp_lt(zero) | w.cmp_lt(zero);
    let positive = u.cmp_gt(zero) | v.cmp_gt(zero) | w.cmp_gt(zero);
    let det = u + v + w;
    // ---- Distance within the ray's interval -----------------------------------------------
    let (az, bz, cz) = (sz * paz, sz * pbz, sz * pcz);
    let t_scaled = u * az + v * bz + w * cz;
    let inv_det = f32x8::ONE / det;
    let t = t_scaled * inv_det;
    let inside = !(negative & positive) & det.cmp_ne(zero);
    let in_range = t.cmp_gt(zero) & t.cmp_lt(tmax);
    let candidates = bits(inside & in_range);
    if candidates == 0 {
        return Lanes8 {
            candidates,
            sure: 0,
            t,
            bary: V3::default(),
        };
    }
    // ---- Beyond its rounding error bound: a hit without the one-ray test's last step -------
    let max3 = |a: f32x8, b: f32x8, c: f32x8| a.abs().max(b.abs()).max(c.abs());
    let (max_x, max_y, max_z) = (max3(ax, bx, cx), max3(ay, by, cy), max3(az, bz, cz));
    let max_e = max3(u, v, w);
    let bound = t_error_bound(max_x, max_y, max_z, max_e, inv_det);
    let sure = t.cmp_gt(bound) & bound.cmp_lt(f32x8::splat(f32::INFINITY));
    Lanes8 {
        candidates,
        sure: bits(sure) & candidates,
        t,
        bary: V3 {
            x: u * inv_det,
            y: v * inv_det,
            z: w * inv_det,
        },
    }
}

/// `a < b ? a : b` per lane (`minps`'s definition, the one-ray slab test's).
#[inline(always)]
fn less_or(a: f32x8, b: f32x8) -> f32x8 {
    a.cmp_lt(b).blend(a, b)
}

/// `a > b ? a : b` per lane.
#[inline(always)]
fn greater_or(a: f32x8, b: f32x8) -> f32x8 {
    a.cmp_gt(b).blend(a, b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::V3;

    /// Eight rays traced together find what each finds alone: the same distance (an exact tie
    /// may name the other primitive), and on the same primitive the same surface, bit for bit;
    /// eight shadow segments are blocked exactly when each is alone.
    #[test]
    fn eight_rays_together_find_what_each_finds_alone() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        for name in ["mitsuba/cornell-box.toml", "cornell-box.toml", "mesh.toml"] {
            let scene = stratapt_import::scene_file::load(&root.join(name)).unwrap();
            let accel = Accel::new(&scene);
            let bounds = scene.bvh.nodes[0].aabb();
            let (lo, hi) = (Vec3::from(bounds.min), Vec3::from(bounds.max));
            let mut rng = stratapt_sampling::testing::TestRng(11);
            let mut point = || lo + (hi - lo) * Vec3::new(rng.f32(), rng.f32(), rng.f32());
            let (mut same_prim, mut hits, mut blocked) = (0, 0, 0);
            for round in 0..400 {
                let ends: [(Vec3, Vec3); LANES] = std::array::from_fn(|_| (point(), point()));
                let origin = V3::from_lanes(&ends.map(|(a, _)| a));
                let dir = V3::from_lanes(&ends.map(|(a, b)| (b - a).normalize()));
                let length = f32x8::from(ends.map(|(a, b)| (b - a).length()));
                let live = [0xff, 0b1011_0110][round % 2];
                let rays = Rays8::new(origin, dir, f32x8::splat(f32::INFINITY));
                let found = accel.closest_hits8(&rays, live);
                let segments = Rays8::new(origin, dir, length);
                let occluded = accel.occluded_wave8(&segments, live);
                for (i, found) in found.iter().enumerate() {
                    if live & (1 << i) == 0 {
                        assert!(found.is_none() && occluded & (1 << i) == 0);
                        continue;
                    }
                    let alone = accel.closest_hit(&rays.ray(i), 0.0);
                    let bits = |h: &Option<Hit>| h.map(|h| h.t.to_bits());
                    assert_eq!(bits(&alone), bits(found), "{name}: {:?}", rays.ray(i));
                    if let (Some(a), Some(b)) = (alone, *found) {
                        hits += 1;
                        if a.prim == b.prim {
                            same_prim += 1;
                            let v = |h: &Hit| {
                                [h.p, h.err, h.ng, h.ns].map(|v| v.to_array().map(f32::to_bits))
                            };
                            assert_eq!(v(&a), v(&b), "{name}: prim {}", a.prim);
                        }
                    }
                    let ray = segments.ray(i);
                    assert_eq!(
                        accel.occluded(&ray, 0.0),
                        occluded & (1 << i) != 0,
                        "{name}: {ray:?}"
                    );
                    blocked += (occluded & (1 << i) != 0) as usize;
                }
            }
            assert!(hits > 400, "{name}: {hits} hits");
            assert!(
                same_prim * 100 >= hits * 99,
                "{name}: {same_prim} of {hits} on the same primitive"
            );
            assert!(blocked > 0 && blocked < hits, "{name}: {blocked} blocked");
        }
    }
}
