//! Ray–disk intersection: the plane of the disk, then the radius test.

use glam::Vec3;

/// `t ∈ (tmin, tmax)` where `o + t·d` meets the disk `(center, unit normal, radius)` (both sides).
pub fn intersect(
    center: Vec3,
    normal: Vec3,
    radius: f32,
    o: Vec3,
    d: Vec3,
    tmin: f32,
    tmax: f32,
) -> Option<f32> {
    let denom = normal.dot(d);
    if denom == 0.0 {
        return None;
    }
    let t = (center - o).dot(normal) / denom;
    if !(t > tmin && t < tmax) {
        return None;
    }
    let p = o + t * d;
    // Distance to the centre measured within the plane.
    let r = p - center;
    let r = r - normal * r.dot(normal);
    (r.length_squared() <= radius * radius).then_some(t)
}

/// The point of the disk's plane nearest to `p` (removes the along-normal error of `o + t·d`).
pub fn project(center: Vec3, normal: Vec3, p: Vec3) -> Vec3 {
    p - normal * (p - center).dot(normal)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hit_inside_miss_outside_and_parallel() {
        let c = Vec3::new(1.0, 2.0, 3.0);
        let n = Vec3::Z;
        let t = intersect(c, n, 0.5, c + Vec3::new(0.3, 0.0, 2.0), -Vec3::Z, 0.0, 9.0).unwrap();
        assert!((t - 2.0).abs() < 1e-6);
        assert!(intersect(c, n, 0.5, c + Vec3::new(0.6, 0.0, 2.0), -Vec3::Z, 0.0, 9.0).is_none());
        assert!(intersect(c, n, 0.5, c + Vec3::new(0.1, 0.0, 0.0), Vec3::X, 0.0, 9.0).is_none());
        // From below as well.
        assert!(intersect(c, n, 0.5, c - Vec3::Z, Vec3::Z, 0.0, 9.0).is_some());
    }

    #[test]
    fn grazing_and_scales() {
        for s in [1e-4f32, 1.0, 1e5] {
            let c = Vec3::new(0.3, -0.2, 0.1) * s;
            let n = Vec3::new(1.0, 1.0, 1.0).normalize();
            let o = c + n * s + Vec3::new(0.1, -0.1, 0.0) * s;
            let t = intersect(c, n, s, o, -n, 0.0, f32::INFINITY).unwrap();
            assert!((t / s - 1.0).abs() < 1e-4, "scale {s}: t {t}");
            // A nearly grazing ray that starts on the plane's front and crosses it inside.
            let d = (c - (c + n * (1e-3 * s) + Vec3::X * (0.5 * s))).normalize();
            assert!(intersect(
                c,
                n,
                s,
                c + n * (1e-3 * s) + Vec3::X * (0.5 * s),
                d,
                0.0,
                f32::INFINITY
            )
            .is_some());
        }
    }

    #[test]
    fn origin_on_the_surface_does_not_self_hit_beyond_tmin() {
        let c = Vec3::ZERO;
        let o = Vec3::new(0.1, 0.1, 0.0);
        assert!(intersect(c, Vec3::Z, 1.0, o, Vec3::new(0.0, 0.6, 0.8), 1e-6, 9.0).is_none());
    }
}
