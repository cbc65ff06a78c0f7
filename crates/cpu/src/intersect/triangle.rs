//! Watertight ray–triangle intersection: Woop, Benthin, Wald 2013, "Watertight Ray/Triangle
//! Intersection" (JCGT 2(1)), in f32 only.
//!
//! Edge functions that are exactly zero count as inside, so a ray through a shared edge or
//! vertex hits at least one of the triangles sharing it (the two triangles compute the same
//! edge function with opposite signs, bit for bit).

use crate::lanes::Lane;
use glam::{Vec3, Vec3Swizzles};
use stratapt_scene::shared::{GAMMA_2, GAMMA_3, GAMMA_5, GAMMA_7};

/// A triangle hit: distance along the ray and the barycentric weights of `(a, b, c)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    pub t: f32,
    pub bary: Vec3,
}

/// The per-ray part of the test: axis permutation and shear (computed once per ray).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shear {
    kx: usize,
    ky: usize,
    kz: usize,
    sx: f32,
    sy: f32,
    sz: f32,
}

impl Shear {
    /// Permute axes so that z is the ray's dominant axis (keeping the winding), and shear so that
    /// the ray points along +z.
    pub fn new(d: Vec3) -> Self {
        let kz = d.abs().max_position();
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let sz = 1.0 / d[kz];
        Self {
            kx,
            ky,
            kz,
            sx: d[kx] * sz,
            sy: d[ky] * sz,
            sz,
        }
    }

    /// The permuted axes `(kx, ky, kz)`: `kz` is the ray's dominant axis.
    #[inline]
    pub(crate) fn axes(&self) -> (usize, usize, usize) {
        (self.kx, self.ky, self.kz)
    }

    /// The shear factors `(sx, sy, sz)`.
    #[inline]
    pub(crate) fn factors(&self) -> (f32, f32, f32) {
        (self.sx, self.sy, self.sz)
    }
}

/// Intersect the ray `o + t·d`, `t ∈ (tmin, tmax)`, with triangle `(a, b, c)` (both sides).
pub fn intersect(
    a: Vec3,
    b: Vec3,
    c: Vec3,
    o: Vec3,
    d: Vec3,
    tmin: f32,
    tmax: f32,
) -> Option<TriangleHit> {
    intersect_sheared(a, b, c, o, &Shear::new(d), tmin, tmax)
}

/// [`intersect`] with the ray's [`Shear`] precomputed.
pub fn intersect_sheared(
    a: Vec3,
    b: Vec3,
    c: Vec3,
    o: Vec3,
    s: &Shear,
    tmin: f32,
    tmax: f32,
) -> Option<TriangleHit> {
    let (kx, ky, kz) = (s.kx, s.ky, s.kz);
    // Vertices relative to the origin, sheared.
    let (pa, pb, pc) = (a - o, b - o, c - o);
    let ax = pa[kx] - s.sx * pa[kz];
    let ay = pa[ky] - s.sy * pa[kz];
    let bx = pb[kx] - s.sx * pb[kz];
    let by = pb[ky] - s.sy * pb[kz];
    let cx = pc[kx] - s.sx * pc[kz];
    let cy = pc[ky] - s.sy * pc[kz];
    // Scaled barycentrics: 2D edge functions (zero counts as inside).
    let u = cx * by - cy * bx;
    let v = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    // Scaled distance, then the true one.
    let (az, bz, cz) = (s.sz * pa[kz], s.sz * pb[kz], s.sz * pc[kz]);
    let t_scaled = u * az + v * bz + w * cz;
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    if !(t > tmin && t < tmax) {
        return None;
    }
    // A distance within its own rounding error is a hit only when the ray measurably starts in
    // front of the triangle's plane and heads into it (a ray leaving the triangle, or a
    // coplanar neighbour, rounds to a tiny t of either sign; one leaving a concave corner meets
    // the other face of the corner at a tiny t for real).
    let max_z = max3(az.abs(), bz.abs(), cz.abs());
    let (max_x, max_y) = (
        max3(ax.abs(), bx.abs(), cx.abs()),
        max3(ay.abs(), by.abs(), cy.abs()),
    );
    let max_e = max3(u.abs(), v.abs(), w.abs());
    if t <= t_error_bound(max_x, max_y, max_z, max_e, inv_det) && !heads_into_plane(pa, pb, pc, s) {
        return None;
    }
    Some(TriangleHit {
        t,
        bary: Vec3::new(u * inv_det, v * inv_det, w * inv_det),
    })
}

/// Conservative bound on the rounding error of a triangle hit's `t`, from the largest sheared
/// vertex coordinates, the largest edge function and `1 / det` (pbrt-v4 `Triangle::Intersect`,
/// Pharr, Jakob & Humphreys ch. 6.8.7).
/// In any lanes: one ray and one triangle here, four triangles per ray in the BVH's leaf
/// packets, eight rays per triangle in the eight-lane traversal (the same bits each way).
pub(crate) fn t_error_bound<L: Lane>(max_x: L, max_y: L, max_z: L, max_e: L, inv_det: L) -> L {
    let g = L::splat;
    let delta_z = g(GAMMA_3) * max_z;
    let delta_x = g(GAMMA_5) * (max_x + max_z);
    let delta_y = g(GAMMA_5) * (max_y + max_z);
    let delta_e = g(2.0) * (g(GAMMA_2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    g(3.0) * (g(GAMMA_3) * max_e * max_z + delta_e * max_z + delta_z * max_e) * inv_det.abs()
}

/// Whether the ray (origin at 0, vertices `pa`, `pb`, `pc` relative to it, direction given by the
/// shear) starts in front of the triangle's plane by more than the rounding of that distance,
/// and heads into the plane. Its distance `n · (o − a)` is resolved far more finely than the t
/// bound near a concave corner: 10⁻⁶ of a 2-unit box's corner, where the t bound (9·10⁻⁶)
/// rejected the far face and the ray left the closed box.
fn heads_into_plane(pa: Vec3, pb: Vec3, pc: Vec3, s: &Shear) -> bool {
    let (e1, e2) = (pb - pa, pc - pa);
    let n = e1.yzx() * e2.zxy() - e1.zxy() * e2.yzx();
    let side = -(n.x * pa.x + n.y * pa.y + n.z * pa.z);
    // n · d up to the positive factor 1 / sz²: d = (sx, sy, 1) / sz in the permuted axes.
    let along = (n[s.kx] * s.sx + n[s.ky] * s.sy + n[s.kz]) * s.sz;
    // The cross product's rounding is within γ₃ of |e1|×|e2| (the products' magnitudes); the
    // dot product's within γ₃ of |n|·|pa|.
    let (a1, a2) = (e1.abs(), e2.abs());
    let magnitude = a1.yzx() * a2.zxy() + a1.zxy() * a2.yzx() + n.abs();
    let pa_abs = pa.abs();
    let slack =
        GAMMA_7 * (magnitude.x * pa_abs.x + magnitude.y * pa_abs.y + magnitude.z * pa_abs.z);
    side * along < 0.0 && side.abs() > slack
}

fn max3(a: f32, b: f32, c: f32) -> f32 {
    a.max(b).max(c)
}

/// Unnormalized geometric normal `(b − a) × (c − a)`: its side is the triangle's front.
pub fn normal(a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    (b - a).cross(c - a)
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: Vec3 = Vec3::new(0.0, 0.0, 0.0);
    const B: Vec3 = Vec3::new(1.0, 0.0, 0.0);
    const C: Vec3 = Vec3::new(0.0, 1.0, 0.0);

    #[test]
    fn hits_the_interior_with_correct_t_and_barycentrics() {
        let o = Vec3::new(0.25, 0.25, 2.0);
        let h = intersect(A, B, C, o, -Vec3::Z, 0.0, f32::INFINITY).unwrap();
        assert!((h.t - 2.0).abs() < 1e-6);
        assert!((h.bary - Vec3::new(0.5, 0.25, 0.25)).abs().max_element() < 1e-6);
        // Back side too.
        let h = intersect(A, B, C, Vec3::new(0.25, 0.25, -1.0), Vec3::Z, 0.0, 10.0).unwrap();
        assert!((h.t - 1.0).abs() < 1e-6);
    }

    #[test]
    fn misses_outside_parallel_and_out_of_range() {
        assert!(intersect(A, B, C, Vec3::new(0.8, 0.8, 1.0), -Vec3::Z, 0.0, 9.0).is_none());
        assert!(intersect(A, B, C, Vec3::new(0.2, 0.2, 0.0), Vec3::X, 0.0, 9.0).is_none());
        assert!(intersect(A, B, C, Vec3::new(0.2, 0.2, 1.0), -Vec3::Z, 0.0, 0.5).is_none());
        assert!(intersect(A, B, C, Vec3::new(0.2, 0.2, 1.0), Vec3::Z, 0.0, 9.0).is_none());
    }

    #[test]
    fn edges_and_vertices_count_as_inside() {
        for p in [A, B, C, (A + B) * 0.5, (B + C) * 0.5, (A + C) * 0.5] {
            let o = p + Vec3::Z;
            assert!(intersect(A, B, C, o, -Vec3::Z, 0.0, 9.0).is_some(), "{p}");
        }
    }

    #[test]
    fn grazing_ray_in_the_plane_misses() {
        // A ray in the triangle's plane has det = 0.
        let o = Vec3::new(-1.0, 0.25, 0.0);
        assert!(intersect(A, B, C, o, Vec3::X, 0.0, 9.0).is_none());
    }

    #[test]
    fn tiny_and_huge_scales() {
        for s in [1e-4f32, 1e-2, 1.0, 1e2, 1e5] {
            let o = Vec3::new(0.2, 0.3, 1.0) * s;
            let h = intersect(A * s, B * s, C * s, o, -Vec3::Z, 0.0, f32::INFINITY).unwrap();
            assert!((h.t / s - 1.0).abs() < 1e-5, "scale {s}: t {}", h.t);
            let tilted = Vec3::new(0.01, -0.02, -1.0).normalize();
            assert!(intersect(A * s, B * s, C * s, o, tilted, 0.0, f32::INFINITY).is_some());
        }
    }

    #[test]
    fn shared_edge_is_watertight() {
        // Quad split along its diagonal; rays exactly through the diagonal hit one of the two.
        let (p0, p1, p2, p3) = (Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y);
        for i in 0..=1000 {
            let s = i as f32 / 1000.0;
            let target = p0.lerp(p2, s);
            let o = Vec3::new(0.37, -0.61, 1.3);
            let d = target - o;
            let hit = intersect(p0, p1, p2, o, d, 0.0, f32::INFINITY).is_some()
                || intersect(p0, p2, p3, o, d, 0.0, f32::INFINITY).is_some();
            assert!(hit, "ray through diagonal at s = {s} leaked");
        }
    }
}
