//! Robust ray origins: a hit point is moved off its surface by the bound on its own rounding
//! error (pbrt-v4 `OffsetRayOrigin`, the bounds of Pharr, Jakob & Humphreys, ch. 6.8), then
//! each coordinate is stepped a few units in the last place further (at least one), in integer
//! arithmetic on the float bits (Wächter & Binder 2019, "A Fast and Robust Method for Avoiding
//! Self-Intersection", Ray Tracing Gems ch. 6; `bitcast` in WGSL).
//!
//! Wächter & Binder replace the ULP step near the origin by an absolute 2⁻¹⁶, where a
//! coordinate's ULPs are far smaller than the error of a point computed from vertices a unit
//! away; in a room 10⁻³ across that absolute term moved ray origins by 1.5 % of the room. Here
//! the error bound plays that part instead: it scales with the primitive's coordinates (the
//! vertices, a sphere's centre), so the offset holds from 10⁻³⁰ to 10³⁰.

use glam::{IVec3, Vec3};
use stratapt_scene::shared::{GAMMA_5, OFFSET_INT_SCALE as INT_SCALE};

/// `p`, whose coordinates are within `err` of the surface's, moved off the surface to the side
/// of `n` (a unit normal already flipped towards where the new ray goes).
pub fn offset_ray_origin(p: Vec3, err: Vec3, n: Vec3) -> Vec3 {
    // The distance to move, widened by the rounding of its own dot product (γ₃) and of the
    // product and sum below: near the origin that rounding exceeds the ULPs of `p` that the
    // steps add.
    let q = p + n * (n.abs().dot(err) * (1.0 + GAMMA_5));
    // `step` on every axis at once, in integer lanes (as the WGSL mirror): the per-axis
    // branches on signs mispredicted (measured:
    // docs/measurements/cpu-reference.md#the-4-wide-bvh-and-what-each-change-gave).
    let count = (n.abs() * INT_SCALE).as_ivec3().max(IVec3::ONE);
    let steps = IVec3::select(
        n.cmpgt(Vec3::ZERO),
        count,
        IVec3::select(n.cmplt(Vec3::ZERO), -count, IVec3::ZERO),
    );
    let bits = IVec3::from_array(q.to_array().map(|x| x.to_bits() as i32));
    let ordered = IVec3::select(bits.cmplt(IVec3::ZERO), -(bits & i32::MAX), bits);
    let moved = ordered + steps;
    let out = IVec3::select(moved.cmplt(IVec3::ZERO), -moved | i32::MIN, moved);
    let out = Vec3::from_array(out.to_array().map(|b| f32::from_bits(b as u32)));
    // No step keeps the value exactly (a negative zero stays one).
    Vec3::select(steps.cmpeq(IVec3::ZERO), q, out)
}

/// Origin for a ray leaving the surface point `p` (error bound `err`, geometric normal `ng`) in
/// direction `dir`: offset to the side of `ng` that `dir` points to.
pub fn spawn_origin(p: Vec3, err: Vec3, ng: Vec3, dir: Vec3) -> Vec3 {
    let n = if ng.dot(dir) < 0.0 { -ng } else { ng };
    offset_ray_origin(p, err, n)
}

/// `x` moved `INT_SCALE · n` (truncated, at least one when `n` is not 0) representable floats
/// along the number line: the float as its ordered integer (±0 → 0, negative floats below it),
/// plus the steps, and back. Unlike adding to the raw bits, this crosses zero in either
/// direction. [`offset_ray_origin`] does this in integer lanes; this scalar form is the
/// specification its test holds it to.
#[cfg(test)]
fn step(x: f32, n: f32) -> f32 {
    let steps = ((INT_SCALE * n.abs()) as i32).max(1);
    let steps = if n > 0.0 {
        steps
    } else if n < 0.0 {
        -steps
    } else {
        0
    };
    let bits = x.to_bits() as i32;
    let ordered = if bits < 0 { -(bits & i32::MAX) } else { bits };
    let moved = ordered + steps;
    let out = if moved < 0 {
        (-moved) as u32 | 0x8000_0000
    } else {
        moved as u32
    };
    // No step keeps the value exactly (a negative zero stays one).
    if steps == 0 {
        x
    } else {
        f32::from_bits(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stratapt_sampling::testing::TestRng;

    /// Points on surfaces of size `scale` (coordinates up to `scale`, some near zero) with the
    /// error bound of a triangle of that size: the offset origin is beyond the error bound on the
    /// side of the normal, and moves by a small fraction of the scale (no absolute term).
    #[test]
    fn moves_beyond_the_error_bound_and_no_further_than_the_scale_allows_from_1e_minus_30_to_1e30()
    {
        use stratapt_scene::shared::GAMMA_7;
        let mut rng = TestRng(7);
        let mut worst = 0.0f64;
        for exp in -30..=30 {
            let scale = 10f32.powi(exp);
            for k in 0..2000 {
                // Every fourth point close to the origin relative to the primitive's size.
                let near = if k % 4 == 0 { 1e-6 } else { 1.0 };
                let p = rng.unit() * scale * near * (0.1 + rng.f32());
                let err = Vec3::splat(GAMMA_7 * scale * 3.0);
                let n = rng.unit();
                let q = offset_ray_origin(p, err, n);
                assert!(q.is_finite(), "p {p} n {n} q {q}");
                // Compare in f64 so the check itself does not round the offset away.
                let (pd, qd, nd) = (p.as_dvec3(), q.as_dvec3(), n.as_dvec3());
                let moved = (qd - pd).dot(nd);
                let bound = nd.abs().dot(err.as_dvec3());
                assert!(
                    moved > bound,
                    "scale {scale}: p {p} n {n} q {q}: moved {moved} ≤ {bound}"
                );
                // Each coordinate moves in the direction of the normal's component (or not at all).
                for c in 0..3 {
                    assert!(
                        (qd[c] - pd[c]) * nd[c] >= 0.0,
                        "axis {c}: p {p} n {n} q {q}"
                    );
                }
                let relative = (qd - pd).length() / scale as f64;
                worst = worst.max(relative);
                assert!(
                    relative < 1e-4,
                    "scale {scale}: p {p} moved {relative} of the scale"
                );
            }
        }
        println!("largest move: {worst:e} of the scale");
    }

    #[test]
    fn handles_zero_and_axis_aligned_coordinates() {
        for n in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z] {
            for p in [
                Vec3::ZERO,
                Vec3::splat(-0.0),
                Vec3::new(1e6, -1e6, 0.0),
                Vec3::splat(-3.0),
            ] {
                for err in [Vec3::ZERO, Vec3::splat(1e-7)] {
                    let q = offset_ray_origin(p, err, n);
                    assert!(q.is_finite() && (q - p).dot(n) > 0.0, "p {p} n {n} q {q}");
                }
            }
        }
    }

    /// The lanes compute the scalar [`step`] on every axis, bit for bit, across signs, zeros,
    /// tiny, huge and infinite coordinates.
    #[test]
    fn lanes_are_the_scalar_steps() {
        let mut rng = TestRng(7);
        let specials = [
            0.0,
            -0.0,
            1e-40,
            -1e-40,
            1.0,
            -1.0,
            3e38,
            -3e38,
            f32::INFINITY,
        ];
        let pick = |rng: &mut TestRng| {
            let u = rng.f32();
            if u < 0.2 {
                specials[(rng.f32() * specials.len() as f32) as usize % specials.len()]
            } else {
                (rng.f32() * 2.0 - 1.0) * 10f32.powf(rng.f32() * 60.0 - 30.0)
            }
        };
        for _ in 0..100_000 {
            let p = Vec3::new(pick(&mut rng), pick(&mut rng), pick(&mut rng));
            // Unit normals (the contract), some with zero and negative-zero components.
            let n = match rng.f32() {
                u if u < 0.1 => Vec3::new(0.0, -0.0, 1.0),
                u if u < 0.2 => Vec3::new(-0.0, -1.0, 0.0),
                _ => rng.unit(),
            };
            let err = Vec3::splat(rng.f32() * 1e-6);
            let q = p + n * (n.abs().dot(err) * (1.0 + GAMMA_5));
            let want = [step(q.x, n.x), step(q.y, n.y), step(q.z, n.z)].map(f32::to_bits);
            let got = offset_ray_origin(p, err, n).to_array().map(f32::to_bits);
            assert_eq!(got, want, "p {p} n {n} err {err}");
        }
    }

    #[test]
    fn steps_cross_zero_along_the_number_line() {
        let tiny = f32::from_bits(1);
        let k = INT_SCALE as u32;
        assert_eq!(step(0.0, 1.0), tiny * k as f32);
        assert_eq!(step(-0.0, -1.0), -tiny * k as f32);
        assert_eq!(step(tiny, -1.0), -tiny * (k - 1) as f32);
        assert_eq!(step(-tiny, 1.0), tiny * (k - 1) as f32);
        assert_eq!(step(1.0, 1.0), f32::from_bits(1.0f32.to_bits() + k));
        assert_eq!(step(-1.0, 1.0), f32::from_bits((-1.0f32).to_bits() - k));
        // A small component still steps once; a zero one not at all (−0 stays −0).
        assert_eq!(step(-2.5, 1e-3).to_bits(), (-2.5f32).to_bits() - 1);
        assert_eq!(step(-0.0, 0.0).to_bits(), (-0.0f32).to_bits());
    }

    #[test]
    fn spawn_origin_goes_to_the_side_of_the_direction() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        let ng = Vec3::Z;
        let err = Vec3::splat(1e-6);
        assert!(spawn_origin(p, err, ng, Vec3::new(0.3, 0.0, 1.0)).z > p.z + 1e-6);
        assert!(spawn_origin(p, err, ng, Vec3::new(0.3, 0.0, -1.0)).z < p.z - 1e-6);
    }
}
