//! Uniform solid-angle sampling of a spherical rectangle
//! ([`stratapt_sampling::warp::spherical_rectangle`], Ureña et al. 2013) for eight shading
//! points at once: the one-lane routine's operations in the same order, its Cephes `atan2` in
//! the lanes, libm's `sin_cos` lane by lane, so every lane's point is the one-lane point.

use crate::lanes::{Mask, LANES, V3};
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};
use stratapt_sampling::warp::spherical_rectangle::Basis;
use stratapt_scene::shared::{MAX_SPHERICAL_SOLID_ANGLE, MIN_SPHERICAL_SOLID_ANGLE};
use wide::{f32x8, CmpEq, CmpGe, CmpGt, CmpLt};

/// A rectangle's frame, splatted: edge lengths and the unit axes (x along `ex`, z its normal).
pub struct Frame {
    exl: f32x8,
    eyl: f32x8,
    x: V3,
    y: V3,
    z: V3,
}

impl Frame {
    pub fn new(basis: &Basis) -> Self {
        let (exl, eyl, x, y, z) = basis.parts();
        Self {
            exl: f32x8::splat(exl),
            eyl: f32x8::splat(eyl),
            x: V3::splat(x),
            y: V3::splat(y),
            z: V3::splat(z),
        }
    }
}

/// The rectangle seen from eight points, `d` = corner − point.
pub struct Setup {
    x0: f32x8,
    x1: f32x8,
    y0: f32x8,
    y1: f32x8,
    exl: f32x8,
    eyl: f32x8,
    h: f32x8,
    delta0: f32x8,
    omega: f32x8,
}

impl Setup {
    /// The setup of every lane, and the lanes where the spherical method applies: a proper
    /// setup (`Setup::from_basis` succeeds) with a moderate solid angle (`use_spherical`).
    pub fn new(frame: &Frame, d: V3) -> (Self, Mask) {
        let h = d.dot(frame.z).abs();
        let (x0, y0) = (d.dot(frame.x), d.dot(frame.y));
        let mut s = Self {
            x0,
            x1: x0 + frame.exl,
            y0,
            y1: y0 + frame.eyl,
            exl: frame.exl,
            eyl: frame.eyl,
            h,
            delta0: f32x8::ZERO,
            omega: f32x8::ZERO,
        };
        s.delta0 = s.delta(s.x0);
        s.omega = s.delta(s.x1) - s.delta0;
        let finite = |v: f32x8| v.is_finite();
        let ok = h.cmp_gt(f32x8::ZERO)
            & s.omega.cmp_gt(f32x8::ZERO)
            & finite(s.omega)
            & finite(f32x8::ONE / s.omega)
            & s.omega.cmp_gt(f32x8::splat(MIN_SPHERICAL_SOLID_ANGLE))
            & s.omega.cmp_lt(f32x8::splat(MAX_SPHERICAL_SOLID_ANGLE));
        (s, ok)
    }

    pub fn solid_angle(&self) -> f32x8 {
        self.omega
    }

    /// `δ(x)`: the solid angle of the strip `[x0, x] × [y0, y1]` up to `δ(x0)`.
    fn delta(&self, x: f32x8) -> f32x8 {
        let (h, y0, y1) = (self.h, self.y0, self.y1);
        let d2 = x * x + h * h;
        let (r0, r1) = ((d2 + y0 * y0).sqrt(), (d2 + y1 * y1).sqrt());
        let same_side = (y0 * y1).cmp_gt(f32x8::ZERO);
        let n = same_side.blend(
            self.eyl * (y1 + y0) * d2 / (y1 * r0 + y0 * r1),
            y1 * r0 - y0 * r1,
        );
        atan2(x * h * n, h * h * r0 * r1 + x * x * y0 * y1)
    }

    /// Step 1: the x of the strip of solid angle `u · Ω`.
    fn invert_x(&self, u: f32x8) -> f32x8 {
        let (h, y0, y1) = (self.h, self.y0, self.y1);
        let tau = self.delta0 + u * self.omega;
        let half = f32x8::splat(0.5) * tau;
        let (mut sin_t, mut cos_t) = (half, half);
        for i in 0..LANES {
            (sin_t.as_array_mut()[i], cos_t.as_array_mut()[i]) = half.as_array_ref()[i].sin_cos();
        }
        let (st2, ct2) = (sin_t * sin_t, cos_t * cos_t);
        let (sa2, ca2) = half_angle_sq(h * self.eyl, h * h + y0 * y1);
        let (sb2, cb2) = half_angle_sq(h * (y1 + y0), h * h - y0 * y1);
        let pq = (sa2 * ct2 - ca2 * st2) * (cb2 * ct2 - sb2 * st2);
        let x = h * sin_t * cos_t / pq.max(f32x8::splat(f32::MIN_POSITIVE)).sqrt();
        x.max(self.x0).min(self.x1)
    }

    /// Step 2: the y at `v` of the strip at `x`.
    fn invert_y(&self, x: f32x8, v: f32x8) -> f32x8 {
        let (y0, y1) = (self.y0, self.y1);
        let d2 = x * x + self.h * self.h;
        let (m0, m1) = ((d2 + y0 * y0).sqrt(), (d2 + y1 * y1).sqrt());
        let s0 = y0 / m0;
        let same_side = (y0 * y1).cmp_gt(f32x8::ZERO);
        let ds = same_side.blend(
            self.eyl * (y1 + y0) * d2 / ((y1 * m0 + y0 * m1) * m0 * m1),
            y1 / m1 - s0,
        );
        let s = s0 + v * ds;
        let c2 = (f32x8::ONE - s) * (f32x8::ONE + s);
        let infinite = (s & f32x8::splat(-0.0)) | f32x8::splat(f32::INFINITY);
        let y = c2
            .cmp_gt(f32x8::ZERO)
            .blend(s * d2.sqrt() / c2.sqrt(), infinite);
        y.max(y0).min(y1)
    }

    /// The point `corner + s·ex + t·ey` of sample `u`, with `s, t` clamped to `[0, 1]`.
    pub fn sample(&self, corner: V3, ex: V3, ey: V3, u: (f32x8, f32x8)) -> V3 {
        let x = self.invert_x(u.0);
        let y = self.invert_y(x, u.1);
        let unit = |v: f32x8| v.max(f32x8::ZERO).min(f32x8::ONE);
        let fs = unit((x - self.x0) / self.exl);
        let ft = unit((y - self.y0) / self.eyl);
        corner + ex * fs + ey * ft
    }
}

/// Squared sine and cosine of half the angle of `(x, y)`, without trigonometry.
fn half_angle_sq(y: f32x8, x: f32x8) -> (f32x8, f32x8) {
    let r = (x * x + y * y).sqrt();
    let two = f32x8::splat(2.0);
    let right = x.cmp_ge(f32x8::ZERO);
    let c2 = (r + x) / (two * r);
    let s2 = (r - x) / (two * r);
    (
        right.blend(y * y / (two * r * (r + x)), s2),
        right.blend(c2, y * y / (two * r * (r - x))),
    )
}

/// [`stratapt_sampling::atan::atan2`] (Cephes `atanf`'s polynomial) per lane.
fn atan2(y: f32x8, x: f32x8) -> f32x8 {
    let (ax, ay) = (x.abs(), y.abs());
    let nan = ax.is_nan() | ay.is_nan();
    let big = ax.max(ay);
    let a = big.cmp_eq(f32x8::ZERO).blend(f32x8::ZERO, ax.min(ay) / big);
    let reduce = a.cmp_gt(f32x8::splat(0.414_213_57));
    let r0 = reduce & f32x8::splat(FRAC_PI_4);
    let a = reduce.blend((a - f32x8::ONE) / (a + f32x8::ONE), a);
    let z = a * a;
    let c = f32x8::splat;
    let poly = (((c(8.053_744_5e-2) * z - c(1.387_768_6e-1)) * z + c(1.997_771_1e-1)) * z
        - c(3.333_295e-1))
        * z
        * a
        + a;
    let mut r = r0 + poly;
    r = ay.cmp_gt(ax).blend(c(FRAC_PI_2) - r, r);
    let sign = f32x8::splat(-0.0);
    r = (x & sign).cmp_ne_zero().blend(c(PI) - r, r);
    r ^= y & sign;
    nan.blend(x + y, r)
}

/// The lanes whose sign bit is set, as a mask.
trait SignBit {
    fn cmp_ne_zero(self) -> Mask;
}

impl SignBit for f32x8 {
    fn cmp_ne_zero(self) -> Mask {
        let bits: wide::i32x8 = bytemuck::cast(self);
        bytemuck::cast(bits.cmp_lt(wide::i32x8::ZERO))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use stratapt_sampling::testing::TestRng;
    use stratapt_sampling::warp::spherical_rectangle;

    /// Every lane's atan2 is the one-lane atan2, bit for bit, signs and zeros included.
    #[test]
    fn atan2_is_the_reference() {
        let mut rng = TestRng(3);
        let special = [0.0, -0.0, 1.0, -1.0, f32::INFINITY, 1e-30, -3.5];
        for round in 0..4000 {
            let pick = |rng: &mut TestRng, k: usize| match round % 4 {
                0 => special[(k + round) % special.len()],
                _ => (rng.f32() - 0.5) * 10f32.powi((k % 5) as i32 - 2),
            };
            let y: [f32; LANES] = std::array::from_fn(|k| pick(&mut rng, k));
            let x: [f32; LANES] = std::array::from_fn(|k| pick(&mut rng, k + 3));
            let got = atan2(f32x8::from(y), f32x8::from(x));
            for i in 0..LANES {
                let want = stratapt_sampling::atan::atan2(y[i], x[i]);
                assert_eq!(
                    got.as_array_ref()[i].to_bits(),
                    want.to_bits(),
                    "atan2({}, {})",
                    y[i],
                    x[i]
                );
            }
        }
    }

    /// Every lane's solid angle and point are the one-lane setup's, bit for bit.
    #[test]
    fn lanes_sample_the_reference_points() {
        let mut rng = TestRng(5);
        let (ex, ey) = (Vec3::new(0.46, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.38));
        let corner = Vec3::new(-0.23, 0.99, -0.18);
        let basis = Basis::new(ex, ey).unwrap();
        let frame = Frame::new(&basis);
        let mut compared = 0;
        for _ in 0..2000 {
            let p: [Vec3; LANES] = std::array::from_fn(|_| {
                Vec3::new(
                    rng.f32() * 2.0 - 1.0,
                    rng.f32() * 2.0 - 1.0,
                    rng.f32() * 2.0 - 1.0,
                )
            });
            let u: [(f32, f32); LANES] = std::array::from_fn(|_| (rng.f32(), rng.f32()));
            let pc = V3::from_lanes(&p.map(|p| corner - p));
            let (setup, ok) = Setup::new(&frame, pc);
            let uu = (f32x8::from(u.map(|u| u.0)), f32x8::from(u.map(|u| u.1)));
            let v = setup.sample(pc, V3::splat(ex), V3::splat(ey), uu);
            for i in 0..LANES {
                let one =
                    spherical_rectangle::Setup::from_basis(&basis, p[i], corner).filter(|s| {
                        s.solid_angle() > MIN_SPHERICAL_SOLID_ANGLE
                            && s.solid_angle() < MAX_SPHERICAL_SOLID_ANGLE
                    });
                assert_eq!(one.is_some(), ok.move_mask() & (1 << i) != 0, "lane {i}");
                let Some(one) = one else { continue };
                assert_eq!(
                    one.solid_angle().to_bits(),
                    setup.solid_angle().as_array_ref()[i].to_bits()
                );
                let want = one.sample(corner - p[i], ex, ey, glam::Vec2::new(u[i].0, u[i].1));
                assert_eq!(
                    v.lane(i).to_array().map(f32::to_bits),
                    want.to_array().map(f32::to_bits)
                );
                compared += 1;
            }
        }
        assert!(compared > 1000, "{compared}");
    }
}
