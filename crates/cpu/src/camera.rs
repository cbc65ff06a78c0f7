//! Primary rays: the camera pose at the sample's shutter time, the pixel filter offset, and the
//! thin lens (Kolb et al. 1995; pbrt-v4 `PerspectiveCamera`).

use glam::{Vec2, Vec3};
use stratapt_sampling::warp::{self, filter};
use stratapt_scene::records::{filter_kind, Camera};

/// Origin and unit direction of the camera ray through `pixel`, for the pixel-domain sample
/// `u_pixel`, the lens-domain sample `u_lens` (when the camera has an aperture) and normalized
/// shutter time `time`.
pub fn generate_ray(
    camera: &Camera,
    pixel: [u32; 2],
    u_pixel: Vec2,
    u_lens: Option<Vec2>,
    time: f32,
) -> (Vec3, Vec3) {
    let v = Vec3::from_array;
    // Pose at time t.
    let eye = v(camera.eye0).lerp(v(camera.eye1), time);
    let target = v(camera.target0).lerp(v(camera.target1), time);
    let up = v(camera.up0).lerp(v(camera.up1), time).normalize();
    let forward = (target - eye).normalize();
    let right = forward.cross(up).normalize();
    let true_up = right.cross(forward);
    // Film point: pixel centre plus the filter offset, in pixels.
    let offset = filter_offset(camera, u_pixel);
    let (w, h) = (camera.width as f32, camera.height as f32);
    let aspect = w / h;
    let sx = (2.0 * (pixel[0] as f32 + 0.5 + offset.x) / w - 1.0) * camera.tan_half_fov * aspect;
    let sy = (1.0 - 2.0 * (pixel[1] as f32 + 0.5 + offset.y) / h) * camera.tan_half_fov;
    let dir = (forward + sx * right + sy * true_up).normalize();
    let Some(u_lens) = u_lens.filter(|_| camera.lens_radius > 0.0) else {
        return (eye, dir);
    };
    // Thin lens: every ray through the lens meets the pinhole ray on the plane in focus.
    let l = warp::concentric_disk(u_lens) * camera.lens_radius;
    let origin = eye + l.x * right + l.y * true_up;
    let focus = eye + dir * (camera.focus_distance / dir.dot(forward));
    (origin, (focus - origin).normalize())
}

/// Offset from the pixel centre, distributed as the pixel filter (weight 1).
fn filter_offset(camera: &Camera, u: Vec2) -> Vec2 {
    match camera.filter {
        filter_kind::TENT => filter::tent(u, camera.filter_param),
        filter_kind::GAUSSIAN => filter::gaussian(u, camera.filter_param),
        _ => filter::box_filter(u, camera.filter_param),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            eye0: [0.0, 0.0, 0.0],
            target0: [0.0, 0.0, -1.0],
            up0: [0.0, 1.0, 0.0],
            eye1: [0.0, 0.0, 0.0],
            target1: [0.0, 0.0, -1.0],
            up1: [0.0, 1.0, 0.0],
            tan_half_fov: 1.0,
            width: 2,
            height: 2,
            filter: filter_kind::BOX,
            filter_param: 1.0,
            focus_distance: 2.0,
            ..Default::default()
        }
    }

    #[test]
    fn corners_of_the_film_span_the_field_of_view() {
        let c = camera();
        // Top-left pixel, offset to its top-left corner: direction (−1, 1, −1).
        let (_, d) = generate_ray(&c, [0, 0], Vec2::ZERO, None, 0.0);
        assert!(
            (d - Vec3::new(-1.0, 1.0, -1.0).normalize()).length() < 1e-6,
            "{d}"
        );
        let (_, d) = generate_ray(&c, [1, 1], Vec2::splat(0.5), None, 0.0);
        assert!(
            (d - Vec3::new(0.5, -0.5, -1.0).normalize()).length() < 1e-6,
            "{d}"
        );
    }

    #[test]
    fn thin_lens_rays_meet_on_the_focus_plane() {
        let mut c = camera();
        c.lens_radius = 0.1;
        let (o0, d0) = generate_ray(&c, [0, 1], Vec2::splat(0.3), None, 0.0);
        for u in [Vec2::new(0.1, 0.9), Vec2::new(0.7, 0.2)] {
            let (o, d) = generate_ray(&c, [0, 1], Vec2::splat(0.3), Some(u), 0.0);
            assert!(o != o0);
            // Both rays reach z = −2 at the same point.
            let p = o + d * ((-2.0 - o.z) / d.z);
            let p0 = o0 + d0 * ((-2.0 - o0.z) / d0.z);
            assert!((p - p0).length() < 1e-5, "{p} vs {p0}");
        }
    }

    #[test]
    fn pose_moves_with_time() {
        let mut c = camera();
        c.eye1 = [1.0, 0.0, 0.0];
        c.target1 = [1.0, 0.0, -1.0];
        let (o, _) = generate_ray(&c, [0, 0], Vec2::splat(0.5), None, 0.5);
        assert!((o - Vec3::new(0.5, 0.0, 0.0)).length() < 1e-6);
    }
}
