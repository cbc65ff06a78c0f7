//! Four static triangles of a leaf, vertices by axis in SIMD lanes, tested against one ray at
//! once.
//!
//! Each lane runs the scalar watertight test
//! ([`crate::intersect::triangle::intersect_sheared`]) with the same f32 operations in the same
//! order (shear, edge functions, determinant, distance, the distance's error bound), so it
//! turns a triangle away exactly when the scalar test would, and a hit beyond its error bound
//! has the scalar test's distance and barycentrics, bit for bit. A hit within its error bound
//! (a ray leaving a surface, or meeting a concave corner) is left to the scalar test, whose
//! last step decides it from the triangle's plane.

use crate::intersect::triangle::{t_error_bound, Shear};
use glam::{Vec3, Vec4};
use stratapt_scene::Geometry;

/// Lanes per packet (and children per BVH node).
pub(super) const LANES: usize = 4;

/// Up to four triangles, `a`, `b`, `c` by axis (lane `i` is triangle `prim[i]`).
#[derive(Clone, Copy, Debug)]
pub(super) struct Packet {
    a: [Vec4; 3],
    b: [Vec4; 3],
    c: [Vec4; 3],
    pub prim: [u32; LANES],
    /// Lane `i` holds a triangle (bit `i`).
    pub(super) valid: u32,
}

impl Packet {
    /// The triangles `ids` (at most [`LANES`]) of `geometry`.
    pub fn new(ids: &[u32], geometry: &Geometry) -> Self {
        let mut v = [[[0.0f32; LANES]; 3]; 3];
        let mut prim = [0; LANES];
        for (lane, &id) in ids.iter().enumerate() {
            for (vertex, corner) in geometry.vertices(id).into_iter().enumerate() {
                for axis in 0..3 {
                    v[vertex][axis][lane] = corner[axis];
                }
            }
            prim[lane] = id;
        }
        let axes = |vertex: [[f32; LANES]; 3]| vertex.map(Vec4::from_array);
        Self {
            a: axes(v[0]),
            b: axes(v[1]),
            c: axes(v[2]),
            prim,
            valid: (1 << ids.len()) - 1,
        }
    }

    /// The vertices of the triangle in `lane`.
    pub fn triangle(&self, lane: usize) -> [Vec3; 3] {
        let at = |v: &[Vec4; 3]| Vec3::new(v[0][lane], v[1][lane], v[2][lane]);
        [at(&self.a), at(&self.b), at(&self.c)]
    }

    /// The ray against the four triangles: which lanes the scalar test might hit within
    /// `(tmin, tmax)` (every lane it does hit is among them), and which of those it hits for
    /// certain, with the distance and barycentrics it computes.
    #[inline]
    pub fn test(&self, origin: Vec3, shear: &Shear, tmin: f32, tmax: f32) -> Lanes {
        let o = [origin.x, origin.y, origin.z].map(Vec4::splat);
        let rel = |v: &[Vec4; 3]| [v[0] - o[0], v[1] - o[1], v[2] - o[2]];
        let (pa, pb, pc) = (rel(&self.a), rel(&self.b), rel(&self.c));
        let (kx, ky, kz) = shear.axes();
        let (sx, sy, sz) = shear.factors();
        let (sx, sy, sz) = (Vec4::splat(sx), Vec4::splat(sy), Vec4::splat(sz));
        // ---- Sheared vertices and the 2D edge functions (zero counts as inside) ------------
        let ax = pa[kx] - sx * pa[kz];
        let ay = pa[ky] - sy * pa[kz];
        let bx = pb[kx] - sx * pb[kz];
        let by = pb[ky] - sy * pb[kz];
        let cx = pc[kx] - sx * pc[kz];
        let cy = pc[ky] - sy * pc[kz];
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        let zero = Vec4::ZERO;
        let negative = u.cmplt(zero) | v.cmplt(zero) | w.cmplt(zero);
        let positive = u.cmpgt(zero) | v.cmpgt(zero) | w.cmpgt(zero);
        let det = u + v + w;
        // ---- Distance within the ray's interval -------------------------------------------
        let (az, bz, cz) = (sz * pa[kz], sz * pb[kz], sz * pc[kz]);
        let t_scaled = u * az + v * bz + w * cz;
        let inv_det = Vec4::ONE / det;
        let t = t_scaled * inv_det;
        let inside = !(negative & positive) & det.cmpne(zero);
        let in_range = t.cmpgt(Vec4::splat(tmin)) & t.cmplt(Vec4::splat(tmax));
        let candidates = (inside & in_range).bitmask() & self.valid;
        if candidates == 0 {
            // Most packets a ray meets hold nothing it hits: no bound, no barycentrics.
            return Lanes {
                candidates,
                sure: 0,
                t: [0.0; LANES],
                bary: [[0.0; LANES]; 3],
            };
        }
        // ---- Beyond its rounding error bound: a hit without the scalar test's last step ----
        // The bound's operations in the scalar order; a candidate's inputs are never NaN
        // (they would make t NaN), and with finite inputs lane and scalar maxima agree. A lane
        // whose bound is not finite is left to the scalar test.
        let max3 = |a: Vec4, b: Vec4, c: Vec4| a.abs().max(b.abs()).max(c.abs());
        let (max_x, max_y, max_z) = (max3(ax, bx, cx), max3(ay, by, cy), max3(az, bz, cz));
        let max_e = max3(u, v, w);
        let bound = t_error_bound(max_x, max_y, max_z, max_e, inv_det);
        let sure = t.cmpgt(bound) & bound.cmplt(Vec4::INFINITY);
        Lanes {
            candidates,
            sure: sure.bitmask() & candidates,
            t: t.to_array(),
            bary: [u * inv_det, v * inv_det, w * inv_det].map(|b| b.to_array()),
        }
    }
}

/// What [`Packet::test`] found, bit `i` for lane `i`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Lanes {
    /// Lanes the scalar test might hit.
    pub candidates: u32,
    /// Candidates it hits for certain, at `t` with barycentrics `bary`.
    pub sure: u32,
    pub t: [f32; LANES],
    bary: [[f32; LANES]; 3],
}

impl Lanes {
    /// Barycentric weights of `(a, b, c)` in `lane`.
    pub fn bary(&self, lane: usize) -> Vec3 {
        Vec3::new(self.bary[0][lane], self.bary[1][lane], self.bary[2][lane])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::intersect::triangle::intersect_sheared;
    use stratapt_sampling::testing::TestRng;
    use stratapt_scene::records::{prim_kind, NONE};
    use stratapt_scene::Prim;

    fn triangle(a: Vec3, b: Vec3, c: Vec3) -> Prim {
        Prim {
            a: a.into(),
            kind: prim_kind::TRIANGLE,
            b: b.into(),
            c: c.into(),
            light: NONE,
            motion: NONE,
            ..Default::default()
        }
    }

    /// The lanes never turn away a triangle the scalar test hits, what they keep the scalar test
    /// almost always hits too, and a hit they decide has the scalar test's bits:
    /// random triangles at scales 10⁻³…10³, rays aimed at their interiors, vertices and edges
    /// (where exact zeros decide), from random origins and from the triangles' own planes.
    #[test]
    fn candidates_are_exactly_the_scalar_tests_hits() {
        let mut rng = TestRng(0x9e37_79b9_7f4a_7c15);
        let (mut hits, mut kept, mut kept_missed, mut sure) = (0, 0, 0, 0);
        for round in 0..20_000 {
            let scale = [1e-3f32, 1.0, 1e3][round % 3];
            let centre = rng.point(scale);
            let prims: Vec<Prim> = (0..LANES)
                .map(|_| {
                    let a = centre + rng.point(scale);
                    triangle(a, a + rng.point(scale), a + rng.point(scale))
                })
                .collect();
            let count = 1 + round % LANES;
            let ids: Vec<u32> = (0..count as u32).collect();
            let packet = Packet::new(&ids, &Geometry::from_prims(&prims));
            let target_prim = &prims[round % count];
            let (a, b, c) = (
                target_prim.a.into(),
                target_prim.b.into(),
                target_prim.c.into(),
            );
            let target: Vec3 = match round % 4 {
                0 => (a + b + c) / 3.0,
                1 => [a, b, c][round % 3],
                2 => a.lerp(b, rng.f32()),
                _ => centre + rng.point(scale),
            };
            // Some rays leave the first triangle (hits within the error bound, left to the
            // scalar test).
            let on_first = (prims[0].a, prims[0].b, prims[0].c);
            let (ua, ub) = (rng.f32() * 0.5, rng.f32() * 0.5);
            let origin = if round % 7 == 6 {
                Vec3::from(on_first.0) * (1.0 - ua - ub)
                    + Vec3::from(on_first.1) * ua
                    + Vec3::from(on_first.2) * ub
            } else {
                centre + rng.point(3.0 * scale)
            };
            let dir = (target - origin).normalize();
            let (tmin, tmax) = (0.0, if round % 5 == 0 { scale } else { f32::INFINITY });
            let shear = Shear::new(dir);
            let found = packet.test(origin, &shear, tmin, tmax);
            let lanes = found.candidates;
            assert_eq!(lanes & !((1 << count) - 1), 0, "padding lanes kept");
            for (lane, p) in prims.iter().take(count).enumerate() {
                let (a, b, c) = (p.a.into(), p.b.into(), p.c.into());
                let scalar = intersect_sheared(a, b, c, origin, &shear, tmin, tmax);
                let hit = scalar.is_some();
                let candidate = lanes & (1 << lane) != 0;
                assert!(
                    candidate || !hit,
                    "round {round}: lane {lane} hit but filtered out"
                );
                if found.sure & (1 << lane) != 0 {
                    let h = scalar.expect("a sure lane is a scalar hit");
                    assert_eq!(h.t.to_bits(), found.t[lane].to_bits(), "round {round}: t");
                    let bary = found.bary(lane);
                    assert_eq!(
                        h.bary.to_array().map(f32::to_bits),
                        bary.to_array().map(f32::to_bits)
                    );
                    sure += 1;
                }
                hits += hit as u32;
                kept += candidate as u32;
                // Rays leaving a triangle meet it within the error bound, kept for the scalar test,
                // which turns them away; elsewhere a kept lane is a hit.
                if round % 7 != 6 {
                    kept_missed += (candidate && !hit) as u32;
                }
            }
        }
        assert!(hits > 5_000, "{hits} hits");
        assert!(
            sure * 10 >= hits * 9,
            "{sure} of {hits} hits decided in lanes"
        );
        println!(
            "{hits} hits; {kept} lanes kept, {kept_missed} missed by the scalar test (rays not leaving); \
             {sure} decided in lanes"
        );
        assert!(
            kept_missed * 1000 <= kept,
            "{kept_missed} of {kept} kept lanes missed"
        );
    }
}
