//! Uniform solid-angle sampling of a rectangle: Ureña, Fajardo, King 2013, "An Area-Preserving
//! Parametrization for Spherical Rectangles" (EGSR).
//!
//! Ureña's two steps in a local frame where the rectangle is `[x0, x1] × [y0, y1]` at height
//! `−h` below `p` (the frame's z is flipped when `p` is on the other side, so either orientation
//! works), rewritten so that tiny (far) and huge (near) rectangles stay accurate:
//! - the solid angle of the strip `[x0, X] × [y0, y1]` is `δ(X) − δ(x0)` with
//!   `δ(X) = atan(X y1 / (h r1)) − atan(X y0 / (h r0))`, `r_i = √(X² + y_i² + h²)`, evaluated as
//!   one `atan2` whose numerator has its cancellation removed algebraically; Ω = `δ(x1) − δ(x0)`
//!   (Ureña's `Σγ − 2π` loses all precision for small Ω);
//! - step 1 inverts `δ(X) = τ` in closed form,
//!   `X = h sin τ / √(4 sin((Δω+τ)/2) sin((Δω−τ)/2) cos((Σω+τ)/2) cos((Σω−τ)/2))`,
//!   `ω_i = atan(y_i / h)`, `Δω = ω1 − ω0`, `Σω = ω1 + ω0`; with `t = τ/2`, `a = Δω/2`,
//!   `b = Σω/2` the products are `sin(a+t) sin(a−t) = sin²a cos²t − cos²a sin²t` and
//!   `cos(b+t) cos(b−t) = cos²b cos²t − sin²b sin²t`, so
//!   `X = h sin t cos t / √(P Q)` needs one `sin_cos(t)`: the squared half-angle sines and
//!   cosines of `Δω` and `Σω` come from the tangents `h·|ey| / (h² + y0 y1)` and
//!   `h (y0 + y1) / (h² − y0 y1)` without trigonometry (`half_angle_sq`);
//! - step 2 is Ureña's: `y / √(d² + y²)` uniform between its values at `y0` and `y1`.

use glam::{Vec2, Vec3};

use crate::atan::atan2;

/// The rectangle in the local frame of `p`: x along `ex`, y along `ey`, the plane at distance
/// `h` (mirrored to lie below `p`). Set up once per shading point, it gives the solid angle and
/// any number of samples.
pub struct Setup {
    x0: f32,
    x1: f32,
    y0: f32,
    y1: f32,
    /// Edge lengths `|ex|`, `|ey|` (`y1 − y0` without rounding).
    exl: f32,
    eyl: f32,
    /// Distance from `p` to the rectangle's plane.
    h: f32,
    /// `δ(x0)` and the solid angle `δ(x1) − δ(x0)`.
    delta0: f32,
    omega: f32,
}

/// The rectangle's own basis: edge lengths and the unit axes x (along `ex`), y and z (its
/// normal). It does not depend on the point the rectangle is seen from, so a renderer computes
/// it once per light; [`Setup::from_basis`] gives the same bits as [`Setup::new`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Basis {
    exl: f32,
    eyl: f32,
    x: Vec3,
    y: Vec3,
    z: Vec3,
}

impl Basis {
    /// The basis of edges `ex ⟂ ey`; `None` when they span no plane.
    pub fn new(ex: Vec3, ey: Vec3) -> Option<Self> {
        let (exl, eyl) = (ex.length(), ey.length());
        let x = ex / exl;
        let z = x.cross(ey).try_normalize()?;
        let y = z.cross(x);
        Some(Self { exl, eyl, x, y, z })
    }
}

impl Basis {
    /// `(|ex|, |ey|, x, y, z)`: the edge lengths and the frame (x along `ex`, z the normal),
    /// for a renderer that sets the rectangle up in its own vector lanes.
    pub fn parts(&self) -> (f32, f32, Vec3, Vec3, Vec3) {
        (self.exl, self.eyl, self.x, self.y, self.z)
    }
}

impl Setup {
    /// The rectangle `corner + s·ex + t·ey` seen from `p` (either side; `ex ⟂ ey`); `None`
    /// when `p` lies in its plane or the solid angle is degenerate.
    pub fn new(p: Vec3, corner: Vec3, ex: Vec3, ey: Vec3) -> Option<Self> {
        Self::from_basis(&Basis::new(ex, ey)?, p, corner)
    }

    /// [`Setup::new`] from the rectangle's [`Basis`].
    pub fn from_basis(basis: &Basis, p: Vec3, corner: Vec3) -> Option<Self> {
        let Basis { exl, eyl, x, y, z } = *basis;
        let d = corner - p;
        // Distance to the plane: orientation of the frame does not matter.
        let h = d.dot(z).abs();
        if !(h > 0.0 && exl.is_finite() && eyl.is_finite()) {
            return None;
        }
        let (x0, y0) = (d.dot(x), d.dot(y));
        let (x1, y1) = (x0 + exl, y0 + eyl);
        let mut s = Self {
            x0,
            x1,
            y0,
            y1,
            exl,
            eyl,
            h,
            delta0: 0.0,
            omega: 0.0,
        };
        s.delta0 = s.delta(x0);
        s.omega = s.delta(x1) - s.delta0;
        let ok = s.omega > 0.0 && s.omega.is_finite() && (1.0 / s.omega).is_finite();
        ok.then_some(s)
    }

    /// `δ(X)`: signed solid angle of the strip `[0, X] × [y0, y1]`.
    fn delta(&self, x: f32) -> f32 {
        let (h, y0, y1) = (self.h, self.y0, self.y1);
        let d2 = x * x + h * h;
        let (r0, r1) = ((d2 + y0 * y0).sqrt(), (d2 + y1 * y1).sqrt());
        // y1 r0 − y0 r1 = (y1² − y0²)(X² + h²) / (y1 r0 + y0 r1) when y0, y1 share a sign.
        let n = if y0 * y1 > 0.0 {
            self.eyl * (y1 + y0) * d2 / (y1 * r0 + y0 * r1)
        } else {
            y1 * r0 - y0 * r1
        };
        atan2(x * h * n, h * h * r0 * r1 + x * x * y0 * y1)
    }

    /// Step 1: the X whose strip `[x0, X]` holds the fraction `u` of the solid angle.
    fn invert_x(&self, u: f32) -> f32 {
        let (h, y0, y1) = (self.h, self.y0, self.y1);
        let tau = self.delta0 + u * self.omega;
        let (sin_t, cos_t) = (0.5 * tau).sin_cos();
        let (st2, ct2) = (sin_t * sin_t, cos_t * cos_t);
        // Half of Δω = atan2(h·|ey|, h² + y0 y1) and of Σω = atan2(h (y1 + y0), h² − y0 y1).
        let (sa2, ca2) = half_angle_sq(h * self.eyl, h * h + y0 * y1);
        let (sb2, cb2) = half_angle_sq(h * (y1 + y0), h * h - y0 * y1);
        let pq = (sa2 * ct2 - ca2 * st2) * (cb2 * ct2 - sb2 * st2);
        let x = h * sin_t * cos_t / pq.max(f32::MIN_POSITIVE).sqrt();
        x.clamp(self.x0, self.x1)
    }

    /// Step 2: the Y at column `x` whose `y/√(d² + y²)` is the fraction `v` between the ends.
    fn invert_y(&self, x: f32, v: f32) -> f32 {
        let (y0, y1) = (self.y0, self.y1);
        let d2 = x * x + self.h * self.h;
        let (m0, m1) = ((d2 + y0 * y0).sqrt(), (d2 + y1 * y1).sqrt());
        let s0 = y0 / m0;
        // s1 − s0 without cancellation when y0, y1 share a sign.
        let ds = if y0 * y1 > 0.0 {
            self.eyl * (y1 + y0) * d2 / ((y1 * m0 + y0 * m1) * m0 * m1)
        } else {
            y1 / m1 - s0
        };
        let s = s0 + v * ds;
        let c2 = (1.0 - s) * (1.0 + s);
        let y = if c2 > 0.0 {
            s * d2.sqrt() / c2.sqrt()
        } else {
            s.signum() * f32::INFINITY
        };
        y.clamp(y0, y1)
    }
}

/// `(sin²(θ/2), cos²(θ/2))` of `θ = atan2(y, x)`, `|θ| ≤ π`, without trigonometry:
/// `cos²(θ/2) = (r + x) / 2r` and `sin²(θ/2) = (r − x) / 2r`, `r = √(x² + y²)`, the one whose
/// numerator would cancel taken as `y² / (2r (r ± x))` instead (their product is `y² / 4r²`).
#[inline]
fn half_angle_sq(y: f32, x: f32) -> (f32, f32) {
    let r = (x * x + y * y).sqrt();
    if x >= 0.0 {
        let c2 = (r + x) / (2.0 * r);
        (y * y / (2.0 * r * (r + x)), c2)
    } else {
        let s2 = (r - x) / (2.0 * r);
        (s2, y * y / (2.0 * r * (r - x)))
    }
}

impl Setup {
    /// The solid angle the rectangle subtends (positive and finite).
    pub fn solid_angle(&self) -> f32 {
        self.omega
    }

    /// The point `corner + s·ex + t·ey` of sample `u` (see [`sample`]).
    pub fn sample(&self, corner: Vec3, ex: Vec3, ey: Vec3, u: Vec2) -> Vec3 {
        let x = self.invert_x(u.x);
        let y = self.invert_y(x, u.y);
        let fs = ((x - self.x0) / self.exl).clamp(0.0, 1.0);
        let ft = ((y - self.y0) / self.eyl).clamp(0.0, 1.0);
        corner + fs * ex + ft * ey
    }
}

/// Solid angle subtended by the rectangle `corner + s·ex + t·ey`, `s, t ∈ [0,1]`, from `p`.
///
/// `ex` and `ey` must be orthogonal. 0 when `p` lies in the rectangle's plane.
pub fn solid_angle(p: Vec3, corner: Vec3, ex: Vec3, ey: Vec3) -> f32 {
    Setup::new(p, corner, ex, ey).map_or(0.0, |s| s.omega)
}
/// A point on the rectangle whose direction from `p` is uniform over its solid angle, with the
/// solid-angle pdf `1 / Ω`; `None` when `p` lies in the rectangle's plane or Ω is degenerate.
///
/// `p` may be on either side; `ex` and `ey` must be orthogonal. The point is returned as
/// `corner + s·ex + t·ey` with `s, t` clamped to `[0, 1]`, so it always lies on the rectangle.
pub fn sample(p: Vec3, corner: Vec3, ex: Vec3, ey: Vec3, u: Vec2) -> Option<(Vec3, f32)> {
    let s = Setup::new(p, corner, ex, ey)?;
    Some((s.sample(corner, ex, ey, u), 1.0 / s.omega))
}
