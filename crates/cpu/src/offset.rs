//! Robust ray origins: Wächter & Binder 2019, "A Fast and Robust Method for Avoiding
//! Self-Intersection" (Ray Tracing Gems, ch. 6).
//!
//! A hit point is pushed off its surface along the geometric normal by a fixed number of units
//! in the last place of each coordinate (integer arithmetic on the float bits, `bitcast` in
//! WGSL), or by a small absolute distance near the origin where ULPs are tiny.

use glam::Vec3;
use stratapt_scene::shared::{
    OFFSET_FLOAT_SCALE as FLOAT_SCALE, OFFSET_INT_SCALE as INT_SCALE, OFFSET_ORIGIN as ORIGIN,
};

/// `p` moved off the surface to the side of `n` (a unit normal already flipped towards where
/// the new ray goes).
pub fn offset_ray_origin(p: Vec3, n: Vec3) -> Vec3 {
    Vec3::new(
        offset_axis(p.x, n.x),
        offset_axis(p.y, n.y),
        offset_axis(p.z, n.z),
    )
}

/// Origin for a ray leaving the surface point `p` with geometric normal `ng` in direction `dir`:
/// offset to the side of `ng` that `dir` points to.
pub fn spawn_origin(p: Vec3, ng: Vec3, dir: Vec3) -> Vec3 {
    let n = if ng.dot(dir) < 0.0 { -ng } else { ng };
    offset_ray_origin(p, n)
}

/// One coordinate: integer ULP offset away from the origin, absolute offset near it.
fn offset_axis(p: f32, n: f32) -> f32 {
    if p.abs() < ORIGIN {
        return p + FLOAT_SCALE * n;
    }
    // Offset in ULPs; moving the bits of a negative float up moves it further from zero.
    let of_i = (INT_SCALE * n) as i32;
    let of_i = if p < 0.0 { -of_i } else { of_i };
    f32::from_bits((p.to_bits() as i32).wrapping_add(of_i) as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator for test inputs.
    fn lcg(state: &mut u64) -> f32 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*state >> 40) as f32) / (1u64 << 24) as f32
    }

    fn random_unit(state: &mut u64) -> Vec3 {
        loop {
            let v = Vec3::new(lcg(state), lcg(state), lcg(state)) * 2.0 - 1.0;
            let l2 = v.length_squared();
            if l2 > 1e-4 && l2 <= 1.0 {
                return v / l2.sqrt();
            }
        }
    }

    #[test]
    fn moves_strictly_to_the_side_of_the_normal_at_all_scales() {
        let mut s = 7;
        for exp in -6..=6 {
            let scale = 10f32.powi(exp);
            for _ in 0..2000 {
                let p = random_unit(&mut s) * scale * (0.1 + lcg(&mut s));
                let n = random_unit(&mut s);
                let q = offset_ray_origin(p, n);
                // Compare in f64 so the check itself does not round the offset away.
                let d = (q.as_dvec3() - p.as_dvec3()).dot(n.as_dvec3());
                assert!(d > 0.0, "p {p} n {n} q {q} scale {scale}: moved {d}");
                assert!(q.is_finite());
                // Each coordinate moves in the direction of the normal's component (or not at all).
                for c in 0..3 {
                    let delta = q[c] as f64 - p[c] as f64;
                    assert!(delta * n[c] as f64 >= 0.0, "axis {c}: p {p} n {n} q {q}");
                }
            }
        }
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
                let q = offset_ray_origin(p, n);
                assert!((q - p).dot(n) > 0.0, "p {p} n {n} q {q}");
            }
        }
    }

    #[test]
    fn spawn_origin_goes_to_the_side_of_the_direction() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        let ng = Vec3::Z;
        assert!(spawn_origin(p, ng, Vec3::new(0.3, 0.0, 1.0)).z > p.z);
        assert!(spawn_origin(p, ng, Vec3::new(0.3, 0.0, -1.0)).z < p.z);
    }
}
