//! Clarberg's equal-area map between the unit square and the unit sphere ("Fast equal-area
//! mapping of the (hemi)sphere using SIMD", 2008), as pbrt-v4 lays out its octahedral
//! environment maps (`EqualAreaSquareToSphere`, `EqualAreaSphereToSquare`).
//!
//! With `(u, v) = 2p − 1` in `[−1, 1]²`: the inner diamond `|u| + |v| < 1` is the `z > 0`
//! hemisphere (the square's centre is `+z`), its edge the equator, the four corner triangles
//! `z < 0` (the corners are `−z`); `x` takes the sign of `u` and `y` the sign of `v`, so the right
//! edge's midpoint is `+x` and the bottom edge's (`p.y = 1`) is `+y`. Equal areas of the square
//! go to equal solid angles: a uniform point of the square is a uniform direction, density
//! `1 / 4π` ([`pdf`]).
//!
//! Both directions use only `+ − × ÷ √`, and `sin`/`cos` in [`square_to_sphere`]; the angle of
//! [`sphere_to_square`] is pbrt-v4's polynomial for `2/π · atan`, evaluated by plain multiplies
//! and adds in the same order as `warp_equal_area_sphere_to_square` in `shaders/warp.wgsl`, so
//! the kernel finds the same texel for the same direction. Signs are taken by comparison
//! (`x < 0`), not from the sign bit, alike in both.

use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_PI_4;

/// The direction at `p ∈ [0, 1]²` (unit).
pub fn square_to_sphere(p: Vec2) -> Vec3 {
    let (u, v) = (2.0 * p.x - 1.0, 2.0 * p.y - 1.0);
    let (up, vp) = (u.abs(), v.abs());
    // Signed distance from the diagonal |u| + |v| = 1, and the radius of the square ring.
    let sd = 1.0 - (up + vp);
    let r = 1.0 - sd.abs();
    let phi = if r == 0.0 { 1.0 } else { (vp - up) / r + 1.0 } * FRAC_PI_4;
    let z = if sd < 0.0 {
        -(1.0 - r * r)
    } else {
        1.0 - r * r
    };
    let (sin_phi, cos_phi) = phi.sin_cos();
    let s = r * (2.0 - r * r).max(0.0).sqrt();
    Vec3::new(
        if u < 0.0 { -cos_phi } else { cos_phi } * s,
        if v < 0.0 { -sin_phi } else { sin_phi } * s,
        z,
    )
}

/// The point of `[0, 1]²` of direction `d` (unit; pbrt-v4 asks the same).
pub fn sphere_to_square(d: Vec3) -> Vec2 {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    let r = (1.0 - z).max(0.0).sqrt();
    let a = x.max(y);
    let b = if a == 0.0 { 0.0 } else { x.min(y) / a };
    // 2/π · atan(b) on [0, 1] (pbrt-v4's minimax polynomial, error below 10⁻⁵ of a quadrant).
    let phi = 4.067_586e-6
        + b * (0.636_226_5
            + b * (0.615_720_2e-2
                + b * (-0.247_333_73
                    + b * (0.881_770_7e-1 + b * (0.419_038_8e-1 + b * -0.251_390_97e-1)))));
    // The angle from the nearer axis: v = φ r, u = r − v, with φ measured from x (pbrt-v4's
    // `1 − φ` when x < y, here by swapping u and v, which a driver cannot reassociate).
    let near = phi * r;
    let (mut u, mut v) = if x < y {
        (near, r - near)
    } else {
        (r - near, near)
    };
    if d.z < 0.0 {
        // The lower hemisphere: fold the triangles outwards.
        (u, v) = (1.0 - v, 1.0 - u);
    }
    if d.x < 0.0 {
        u = -u;
    }
    if d.y < 0.0 {
        v = -v;
    }
    Vec2::new(0.5 * (u + 1.0), 0.5 * (v + 1.0))
}

/// Solid-angle density of [`square_to_sphere`] of a uniform point: `1 / 4π`.
pub fn pdf() -> f32 {
    std::f32::consts::FRAC_1_PI * 0.25
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-5
    }

    /// pbrt-v4's orientation: the centre `+z`, the corners `−z`, the right edge `+x`, the bottom
    /// edge (`p.y = 1`) `+y`, and `(¾, ¾)` on the equator between `+x` and `+y`.
    #[test]
    fn orientation_is_pbrts() {
        assert!(close(square_to_sphere(Vec2::splat(0.5)), Vec3::Z));
        for corner in [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE] {
            assert!(close(square_to_sphere(corner), -Vec3::Z), "{corner}");
        }
        assert!(close(square_to_sphere(Vec2::new(1.0, 0.5)), Vec3::X));
        assert!(close(square_to_sphere(Vec2::new(0.0, 0.5)), -Vec3::X));
        assert!(close(square_to_sphere(Vec2::new(0.5, 1.0)), Vec3::Y));
        assert!(close(square_to_sphere(Vec2::new(0.5, 0.0)), -Vec3::Y));
        let h = std::f32::consts::FRAC_1_SQRT_2;
        assert!(close(
            square_to_sphere(Vec2::splat(0.75)),
            Vec3::new(h, h, 0.0)
        ));
        assert!(close(
            square_to_sphere(Vec2::new(0.75, 0.5)),
            Vec3::new(0.661_437_8, 0.0, 0.75)
        ));
    }

    /// Unit directions, and the inverse recovers the point to about 10⁻⁵ (the polynomial's
    /// error) everywhere but on the square's edge, where two points are one direction.
    #[test]
    fn round_trip() {
        let n = 301;
        for j in 0..n {
            for i in 0..n {
                let p = Vec2::new(i as f32 / (n - 1) as f32, j as f32 / (n - 1) as f32);
                let d = square_to_sphere(p);
                assert!((d.length() - 1.0).abs() < 2e-6, "{p} → {d}");
                let back = sphere_to_square(d);
                let edge = p.x == 0.0 || p.x == 1.0 || p.y == 0.0 || p.y == 1.0;
                assert!(
                    (back - p).abs().max_element() < 2e-5
                        || (edge && close(square_to_sphere(back), d)),
                    "{p} → {d} → {back}"
                );
            }
        }
    }

    /// The polynomial is `2/π · atan` to within 10⁻⁵ on [0, 1].
    #[test]
    fn polynomial_is_the_angle() {
        for i in 0..=1000 {
            let b = i as f32 / 1000.0;
            let d = Vec3::new(1.0, b, 0.0).normalize();
            let p = sphere_to_square(d);
            // On the equator in the first quadrant: v − ½ = ½ φ.
            let phi = 2.0 * (p.y - 0.5);
            let exact = (f64::from(b).atan() * 2.0 / std::f64::consts::PI) as f32;
            assert!((phi - exact).abs() < 1.2e-5, "{b}: {phi} vs {exact}");
        }
    }
}
