//! Ray–sphere intersection with the numerically careful quadratic of Haines, Günther,
//! Akenine-Möller 2019, "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems,
//! ch. 7): the discriminant from the distance of the centre to the ray (no cancellation of
//! b² − ac), the roots from the citardauq / classic pair (no cancellation of −b ± √Δ).

use glam::Vec3;

/// Nearest `t ∈ (tmin, tmax)` where `o + t·d` meets the sphere `(center, radius)`; `d` need not
/// be unit length.
pub fn intersect(center: Vec3, radius: f32, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Option<f32> {
    let f = o - center;
    let a = d.dot(d);
    // Half of the linear coefficient: the quadratic is a t² + 2 b t + c.
    let b = -f.dot(d);
    let c = f.dot(f) - radius * radius;
    // Δ / a = r² − |f + (b/a) d|² (the centre's squared distance to the line).
    let l = f + (b / a) * d;
    let delta = a * (radius * radius - l.dot(l));
    if delta < 0.0 {
        return None;
    }
    let q = b + delta.sqrt().copysign(b);
    let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (c / q, q / a) };
    let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
    if near > tmin && near < tmax {
        Some(near)
    } else if far > tmin && far < tmax {
        Some(far)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn front_and_back_roots() {
        let o = Vec3::new(0.0, 0.0, -5.0);
        assert!((intersect(Vec3::ZERO, 1.0, o, Vec3::Z, 0.0, 99.0).unwrap() - 4.0).abs() < 1e-6);
        // From inside: the far root.
        let t = intersect(Vec3::ZERO, 1.0, Vec3::ZERO, Vec3::Z, 0.0, 99.0).unwrap();
        assert!((t - 1.0).abs() < 1e-6);
        // Behind the ray.
        assert!(intersect(Vec3::ZERO, 1.0, o, -Vec3::Z, 0.0, 99.0).is_none());
    }

    #[test]
    fn grazing_and_missing() {
        let o = Vec3::new(0.0, 1.0 + 1e-3, -5.0);
        assert!(intersect(Vec3::ZERO, 1.0, o, Vec3::Z, 0.0, 99.0).is_none());
        let o = Vec3::new(0.0, 1.0 - 1e-3, -5.0);
        let t = intersect(Vec3::ZERO, 1.0, o, Vec3::Z, 0.0, 99.0).unwrap();
        assert!((t - (5.0 - (1.0f32 - (1.0 - 1e-3f32).powi(2)).sqrt())).abs() < 1e-4);
    }

    #[test]
    fn origin_on_the_surface() {
        // Leaving outwards: no hit beyond a small tmin; going inwards: the far side.
        let o = Vec3::new(0.0, 0.0, -1.0);
        assert!(intersect(Vec3::ZERO, 1.0, o, -Vec3::Z, 1e-4, 99.0).is_none());
        let t = intersect(Vec3::ZERO, 1.0, o, Vec3::Z, 1e-4, 99.0).unwrap();
        assert!((t - 2.0).abs() < 1e-5);
    }

    #[test]
    fn small_sphere_far_away_and_huge_sphere() {
        for (r, dist) in [(1e-4f32, 1e5f32), (1e-4, 1.0), (1e5, 3e5), (1.0, 1e5)] {
            let o = Vec3::new(0.0, 0.0, -dist);
            let t = intersect(Vec3::ZERO, r, o, Vec3::Z, 0.0, f32::INFINITY).unwrap();
            assert!(
                ((t - (dist - r)) / dist).abs() < 1e-6,
                "r {r} dist {dist}: t {t}"
            );
            // Offset by half a radius sideways still hits.
            let o2 = o + Vec3::X * (0.5 * r);
            assert!(
                intersect(Vec3::ZERO, r, o2, Vec3::Z, 0.0, f32::INFINITY).is_some(),
                "r {r}"
            );
        }
    }

    #[test]
    fn unnormalized_direction_keeps_t() {
        let o = Vec3::new(0.0, 0.0, -5.0);
        let t = intersect(Vec3::ZERO, 1.0, o, Vec3::Z * 2.0, 0.0, 99.0).unwrap();
        assert!((t - 2.0).abs() < 1e-6);
    }
}
