// needs: frame filter warp
// Primary rays, mirroring `crates/cpu/src/camera.rs`: the camera pose at the sample's shutter
// time, the pixel-filter offset, and the thin lens (Kolb et al. 1995; pbrt-v4
// `PerspectiveCamera`). Reads `params.camera`.
//
// Interface (other modules may call):
//   struct CameraRay { origin: vec3f, dir: vec3f }              // dir is unit length
//   fn camera_generate_ray(pixel: vec2u, u_pixel: vec2f, u_lens: vec2f, time: f32) -> CameraRay
//   fn camera_filter_offset(u: vec2f) -> vec2f                  // pixel-filter offset, pixels
// Option: the CPU's `u_lens: Option<Vec2>` is `Some` exactly when the scene has a lens domain
// (`Effects::lens`, i.e. lens_radius > 0), which is `has_lens()`; so the lens is used
// when has_lens() && lens_radius > 0, and `u_lens` is ignored otherwise (pass anything, e.g. 0).
// The CPU passes time 0 when there is no time domain: do the same.

struct CameraRay {
    origin: vec3f,
    dir: vec3f,
}

// Offset from the pixel centre, distributed as the pixel filter (weight 1).
fn camera_filter_offset(u: vec2f) -> vec2f {
    let c = params.camera;
    switch c.filter_kind {
        case FILTER_TENT: {
            return filter_tent(u, c.filter_param);
        }
        case FILTER_GAUSSIAN: {
            return filter_gaussian(u, c.filter_param);
        }
        default: {
            return filter_box_filter(u, c.filter_param);
        }
    }
}

// Origin and unit direction of the camera ray through `pixel` for the pixel-domain sample
// `u_pixel`, the lens-domain sample `u_lens` and the normalized shutter time `time`.
fn camera_generate_ray(pixel: vec2u, u_pixel: vec2f, u_lens: vec2f, time: f32) -> CameraRay {
    let c = params.camera;
    // Pose at time t.
    let eye = frame_lerp3(c.eye0, c.eye1, time);
    let look_at = frame_lerp3(c.target0, c.target1, time);
    let up = normalize(frame_lerp3(c.up0, c.up1, time));
    let forward = normalize(look_at - eye);
    let right = normalize(cross(forward, up));
    let true_up = cross(right, forward);
    // Film point: pixel centre plus the filter offset, in pixels.
    let offset = camera_filter_offset(u_pixel);
    let w = f32(c.width);
    let h = f32(c.height);
    let aspect = w / h;
    let sx = (2.0 * (f32(pixel.x) + 0.5 + offset.x) / w - 1.0) * c.tan_half_fov * aspect;
    let sy = (1.0 - 2.0 * (f32(pixel.y) + 0.5 + offset.y) / h) * c.tan_half_fov;
    let dir = normalize(forward + sx * right + sy * true_up);
    // Pinhole: no lens domain, or no aperture.
    if (!has_lens() || !(c.lens_radius > 0.0)) {
        return CameraRay(eye, dir);
    }
    // Thin lens: every ray through the lens meets the pinhole ray on the plane in focus.
    let l = warp_concentric_disk(u_lens) * c.lens_radius;
    let origin = eye + l.x * right + l.y * true_up;
    let focus = eye + dir * (c.focus_distance / dot(dir, forward));
    return CameraRay(origin, normalize(focus - origin));
}
