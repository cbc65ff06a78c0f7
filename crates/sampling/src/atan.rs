//! `atan2` to about 2 ulp from Cephes' `atanf` polynomial (Moshier 1989), the same operations
//! in the same order as `frame_atan2` in `shaders/frame.wgsl`.
//!
//! The warps take their solid angles from it instead of `f32::atan2`, so that the CPU reference
//! and the GPU kernel evaluate one formula (Vulkan's built-in `atan2` may be 4096 ulp off), and
//! because it is inlined: libm's `atan2f` showed in profiles of a Cornell-box render, its call
//! and its special cases more than its polynomial (measured:
//! docs/measurements/cpu-reference.md#the-4-wide-bvh-and-what-each-change-gave).

use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// `atan2(y, x)` in `[−π, π]`: NaN in, NaN out; `atan2(±0, x < 0) = ±π` and
/// `atan2(±0, −0) = ±π` as in Rust; `atan2(±∞, ±∞)` is NaN (the ratio ∞/∞), where Rust gives
/// `±π/4` or `±3π/4`.
#[inline]
pub fn atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    if ax.is_nan() || ay.is_nan() {
        return x + y;
    }
    let big = ax.max(ay);
    // Ratio in [0, 1]; 0/0 stays 0.
    let mut a = if big == 0.0 { 0.0 } else { ax.min(ay) / big };
    // Reduce to |a| ≤ tan(π/8): atan(a) = π/4 + atan((a − 1)/(a + 1)).
    let mut r = 0.0;
    if a > 0.414_213_57 {
        r = FRAC_PI_4;
        a = (a - 1.0) / (a + 1.0);
    }
    let z = a * a;
    r += (((8.053_744_5e-2 * z - 1.387_768_6e-1) * z + 1.997_771_1e-1) * z - 3.333_295e-1) * z * a
        + a;
    // Back to the octant, the half plane and the sign of y.
    if ay > ax {
        r = FRAC_PI_2 - r;
    }
    if x.is_sign_negative() {
        r = PI - r;
    }
    if y.is_sign_negative() {
        -r
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Within 3 ulp of the f64 `atan2` over every octant, tiny and huge ratios, and the signed
    /// zeros; the special values as documented.
    #[test]
    fn matches_f64_atan2() {
        let mut worst = 0.0f64;
        let mut state = 0x1234_5678u32;
        let mut next = || {
            state = crate::hash::lowbias32(state);
            state
        };
        for _ in 0..200_000 {
            let y = f32::from_bits(next() & 0xbfff_ffff);
            let x = f32::from_bits(next() & 0xbfff_ffff);
            if !(x.is_finite() && y.is_finite()) || (x == 0.0 && y == 0.0) {
                continue;
            }
            let exact = (y as f64).atan2(x as f64);
            let got = atan2(y, x) as f64;
            let ulp = (exact.abs() as f32).max(f32::MIN_POSITIVE);
            let ulp = (f32::from_bits(ulp.to_bits() + 1) - ulp) as f64;
            worst = worst.max((got - exact).abs() / ulp);
        }
        assert!(worst <= 3.0, "worst error {worst} ulp");
        for (y, x, want) in [
            (0.0, 1.0, 0.0),
            (-0.0, 1.0, -0.0),
            (0.0, -1.0, PI),
            (-0.0, -1.0, -PI),
            (0.0, -0.0, PI),
            (-0.0, -0.0, -PI),
            (1.0, 0.0, FRAC_PI_2),
            (-1.0, 0.0, -FRAC_PI_2),
            (1.0, f32::INFINITY, 0.0),
            (f32::INFINITY, 1.0, FRAC_PI_2),
        ] {
            let got = atan2(y, x);
            assert_eq!(
                got.to_bits(),
                want.to_bits(),
                "atan2({y}, {x}) = {got}, want {want}"
            );
        }
        assert!(atan2(f32::NAN, 1.0).is_nan() && atan2(1.0, f32::NAN).is_nan());
    }
}
