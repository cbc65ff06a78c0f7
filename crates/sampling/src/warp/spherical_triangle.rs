//! Uniform solid-angle sampling of a spherical triangle: Arvo 1995, "Stratified Sampling of
//! Spherical Triangles" (SIGGRAPH '95).
//!
//! Arvo's two steps, rewritten so that nothing cancels for tiny or huge triangles:
//! - the solid angle and the sub-triangle split use Van Oosterom–Strackee's `atan2` form with
//!   the triple product taken from the triangle's edges (not from differences of nearly equal
//!   unit vectors), so tiny triangles keep full relative precision, and Ω never comes from
//!   `α + β + γ − π`;
//! - step 1 (the point `C'` on arc `AC` cutting off area `u₀ Ω`) is solved in closed form for
//!   the half arc angle: with `w` the unit tangent from `A` towards `C`,
//!   `tan(t/2) = k sin(h) / (|D| cos(h) − m sin(h))`, `h = u₀ Ω / 2`, `k = 1 + A·B`,
//!   `m = B·w`, `D = det(A, B, w)` (from `tan(Ω'/2) = |det| / (1 + A·B + B·C' + C'·A)`);
//! - step 2 (`cos θ` uniform on arc `BC'`) uses `1 − B·C' = |C' − B|² / 2` with `C' − B` built
//!   from edge vectors.

use glam::{Vec2, Vec3};

use crate::atan::atan2;

/// Unit directions from `p` to the vertices plus the edge vectors, the common setup.
struct Setup {
    /// `a − p` and its length.
    pa: Vec3,
    la: f32,
    lb: f32,
    lc: f32,
    /// Edges `b − a`, `c − a`.
    e_ab: Vec3,
    e_ac: Vec3,
    /// Signed triple product of the unit directions, `det(â, b̂, ĉ)`.
    triple: f32,
    /// Solid angle.
    omega: f32,
}

impl Setup {
    fn new(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Self {
        let (pa, pb, pc) = (a - p, b - p, c - p);
        let (la, lb, lc) = (pa.length(), pb.length(), pc.length());
        let (e_ab, e_ac) = (b - a, c - a);
        let (va, vb, vc) = (pa / la, pb / lb, pc / lc);
        // det(a−p, b−p, c−p) = (a−p)·((b−a)×(c−a)), each factor scaled by its length.
        let triple = va.dot((e_ab / lb).cross(e_ac / lc));
        let denom = 1.0 + va.dot(vb) + vb.dot(vc) + vc.dot(va);
        let omega = 2.0 * atan2(triple.abs(), denom);
        Self {
            pa,
            la,
            lb,
            lc,
            e_ab,
            e_ac,
            triple,
            omega,
        }
    }

    fn is_degenerate(&self) -> bool {
        let finite = self.la > 0.0 && self.lb > 0.0 && self.lc > 0.0 && self.omega.is_finite();
        !(finite && self.triple != 0.0 && self.omega > 0.0 && (1.0 / self.omega).is_finite())
    }
}

/// Solid angle subtended by triangle `(a, b, c)` from point `p` (Van Oosterom & Strackee 1983).
///
/// `Ω = 2 atan2(|det(â, b̂, ĉ)|, 1 + â·b̂ + b̂·ĉ + ĉ·â)`, in `[0, 2π]`; 0 when `p` is a vertex.
pub fn solid_angle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let s = Setup::new(p, a, b, c);
    if s.omega.is_finite() {
        s.omega
    } else {
        0.0
    }
}
/// A unit direction from `p` uniformly distributed over the solid angle of `(a, b, c)`, with its
/// solid-angle pdf `1 / Ω`; `None` when the triangle is degenerate as seen from `p`.
///
/// Degenerate: `p` at a vertex or in the triangle's plane (Ω = 0, or the `2π` of a point on the
/// triangle itself), or Ω so small that `1/Ω` overflows.
pub fn sample(p: Vec3, a: Vec3, b: Vec3, c: Vec3, u: Vec2) -> Option<(Vec3, f32)> {
    let s = Setup::new(p, a, b, c);
    if s.is_degenerate() {
        return None;
    }
    let va = s.pa / s.la;
    let vb = (s.pa + s.e_ab) / s.lb;
    // Unit tangent at â towards ĉ: the part of c − a orthogonal to â.
    let w = (s.e_ac - s.e_ac.dot(va) * va).try_normalize()?;

    // Step 1: C' = cos t â + sin t w cuts off the sub-triangle (â, b̂, C') of area u₀ Ω.
    let m = s.e_ab.dot(w) / s.lb; // b̂·w (â·w = 0)
    let det = va.dot(s.e_ab.cross(w)).abs() / s.lb; // |det(â, b̂, w)|
    let k = 1.0 + va.dot(vb);
    let (sin_h, cos_h) = (0.5 * u.x * s.omega).sin_cos();
    let (x, y) = (det * cos_h - m * sin_h, k * sin_h); // ∝ (cos t/2, sin t/2)
    let r2 = x * x + y * y;
    if r2.is_nan() || r2 <= 0.0 {
        return None;
    }
    let (sin_t, one_minus_cos_t) = (2.0 * x * y / r2, 2.0 * y * y / r2);

    // Step 2: cos θ uniform between 1 and b̂·C' along the arc from b̂ to C'.
    // C' − b̂ = (C' − â) − (b̂ − â), both differences formed without cancellation.
    let d = sin_t * w - one_minus_cos_t * va - unit_difference(s.pa, s.la, s.e_ab, s.lb);
    let one_minus_cos_theta = u.y * 0.5 * d.length_squared();
    let sin_theta = (one_minus_cos_theta * (2.0 - one_minus_cos_theta))
        .max(0.0)
        .sqrt();
    let tangent = (d - d.dot(vb) * vb).normalize_or_zero();
    let dir = ((1.0 - one_minus_cos_theta) * vb + sin_theta * tangent).normalize_or(vb);
    Some((dir, 1.0 / s.omega))
}

/// `(pa + e)/|pa + e| − pa/|pa|` for `lb = |pa + e|`, without subtracting nearly equal unit
/// vectors: `(e − pa (2 pa·e + e·e) / (la (la + lb))) / lb`.
fn unit_difference(pa: Vec3, la: f32, e: Vec3, lb: f32) -> Vec3 {
    (e - pa * ((2.0 * pa.dot(e) + e.dot(e)) / (la * (la + lb)))) / lb
}
