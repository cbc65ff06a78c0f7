//! pbrt-v4's perspective camera as strata's: where it stands and looks, the vertical field of
//! view, the thin lens, and the handedness.
//!
//! pbrt's camera space is left-handed: it looks along +z with +y up and +x towards the image's
//! right. strata's camera is right-handed (its image's right is `forward × up`). From a proper
//! camera transform (a plain `LookAt`, determinant > 0) pbrt's image right is `up × forward`:
//! the mirror of strata's image of the same numbers. Scenes written for right-handed renderers
//! add `Scale -1 1 1` before `LookAt` (determinant < 0), and then the two agree. So where the
//! camera's transform is proper, the importer mirrors the whole world across the plane through
//! the eye spanned by the view direction and up ([`Camera::world`]): strata's image of the
//! mirrored world is pbrt's image, and nothing in the image moves.

use super::include::Parsed;
use super::params::Params;
use super::settings::Located;
use super::state::Warning;
use glam::{DMat3, DMat4, DVec3};
use stratapt_scene::error::SceneError;

/// strata's camera for a pbrt-v4 perspective camera.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub eye: DVec3,
    pub look_at: DVec3,
    pub up: DVec3,
    /// Vertical field of view, degrees.
    pub fov_y: f64,
    /// Lens radius (0: pinhole).
    pub aperture: f64,
    pub focus_distance: f64,
    /// Applied to every point and direction of the world before strata sees it: the identity,
    /// or the mirror that makes strata's right-handed image pbrt's (see the module's docs).
    pub world: DMat4,
}

/// The camera of `camera_from_world` (the CTM at `Camera`) with pbrt's `fov` (degrees, on the
/// shorter image axis), `lensradius` and `focaldistance`, for a `width × height` film. `Err`
/// says why there is none (a degenerate transform, a field of view outside (0, 180)).
pub fn camera(
    camera_from_world: DMat4,
    fov: f64,
    lens_radius: f64,
    focal_distance: f64,
    width: u32,
    height: u32,
) -> Result<Camera, String> {
    if !(fov > 0.0 && fov < 180.0) {
        return Err(format!(
            "fov {fov}: a field of view is between 0 and 180 degrees"
        ));
    }
    let world_from_camera = camera_from_world.inverse();
    let m3 = DMat3::from_mat4(world_from_camera);
    let det = m3.determinant();
    if !(det.is_finite() && det.abs() > 1e-300) {
        return Err("the camera's transform is singular".into());
    }
    let eye = world_from_camera.transform_point3(DVec3::ZERO);
    let forward = world_from_camera.transform_vector3(DVec3::Z).normalize();
    let up = world_from_camera.transform_vector3(DVec3::Y).normalize();
    // pbrt's fov spans the shorter side; strata's the height.
    let fov_y = if height > width {
        let t = (fov.to_radians() / 2.0).tan() * height as f64 / width as f64;
        2.0 * t.atan().to_degrees()
    } else {
        fov
    };
    let world = if det > 0.0 {
        // Mirror across the plane through the eye spanned by forward and up: its normal is
        // their cross product (orthogonalized).
        let n = forward.cross(up).normalize();
        let reflect =
            DMat4::from_mat3(DMat3::IDENTITY - 2.0 * DMat3::from_cols(n * n.x, n * n.y, n * n.z));
        DMat4::from_translation(eye) * reflect * DMat4::from_translation(-eye)
    } else {
        DMat4::IDENTITY
    };
    let focus_distance = if focal_distance > 0.0 {
        focal_distance
    } else {
        1e6
    };
    Ok(Camera {
        eye,
        look_at: eye + forward * focus_distance.min(1.0),
        up,
        fov_y,
        aperture: lens_radius.max(0.0),
        focus_distance,
        world,
    })
}

/// The scene's `Camera` directive (`None`: pbrt's default, a perspective camera of fov 90 at
/// the origin looking along +z) with the CTM it was given, for a `width × height` film, and the
/// warnings for what strata draws differently. Only `"perspective"` is a camera strata has.
pub fn camera_of(
    parsed: &Parsed,
    directive: Option<Located>,
    camera_from_world: DMat4,
    width: u32,
    height: u32,
) -> Result<(Camera, Vec<Warning>), SceneError> {
    let Some((source, d)) = directive else {
        let c = camera(camera_from_world, 90.0, 0.0, 0.0, width, height)
            .expect("pbrt's default camera is valid");
        return Ok((c, Vec::new()));
    };
    let p = Params::new(parsed, source, d);
    if p.kind() != "perspective" {
        return Err(p.directive_err(format!(
            "Camera \"{}\": strata has a perspective camera only (a thin lens)",
            p.kind()
        )));
    }
    let fov = p.float("fov", 90.0)?;
    let lens_radius = p.float("lensradius", 0.0)?;
    let focal_distance = p.float("focaldistance", 1e6)?;
    let c = camera(
        camera_from_world,
        fov,
        lens_radius,
        focal_distance,
        width,
        height,
    )
    .map_err(|reason| p.directive_err(format!("Camera \"perspective\": {reason}")))?;
    let mut warnings = p.unused();
    if lens_radius < 0.0 {
        warnings.push(p.warning(format!("lensradius {lens_radius} drawn as a pinhole")));
    }
    Ok((c, warnings))
}

#[cfg(test)]
mod tests {
    use super::super::state::look_at;
    use super::*;

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-9
    }

    /// Where a world point lands in strata's image: its right and up coordinates.
    fn strata_image(c: &Camera, p: DVec3) -> (f64, f64) {
        let p = c.world.transform_point3(p);
        let forward = (c.look_at - c.eye).normalize();
        let right = forward.cross(c.up).normalize();
        let up = right.cross(forward);
        let d = p - c.eye;
        (d.dot(right) / d.dot(forward), d.dot(up) / d.dot(forward))
    }

    /// Where pbrt puts it: camera space x is the image's right, y its top.
    fn pbrt_image(camera_from_world: DMat4, p: DVec3) -> (f64, f64) {
        let q = camera_from_world.transform_point3(p);
        (q.x / q.z, q.y / q.z)
    }

    /// An asymmetric set of points lands where pbrt's camera puts it, with and without the
    /// `Scale -1 1 1` that right-handed scenes add, and from an oblique camera.
    #[test]
    fn the_image_is_pbrts_whatever_the_handedness() {
        let points = [
            DVec3::new(1.0, 0.2, 5.0),
            DVec3::new(-0.3, 1.1, 7.0),
            DVec3::new(0.5, -0.4, 3.0),
        ];
        let plain = look_at(DVec3::ZERO, DVec3::Z, DVec3::Y).unwrap();
        let mirrored = DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0)) * plain;
        let oblique = look_at(
            DVec3::new(2.0, 1.0, -3.0),
            DVec3::new(0.0, 0.5, 4.0),
            DVec3::new(0.1, 1.0, 0.0),
        )
        .unwrap();
        for (name, m, mirrors) in [
            ("plain", plain, true),
            ("Scale -1 1 1", mirrored, false),
            ("oblique", oblique, true),
        ] {
            let c = camera(m, 45.0, 0.0, 0.0, 64, 64).unwrap();
            assert_eq!(c.world != DMat4::IDENTITY, mirrors, "{name}");
            for p in points {
                let (a, b) = (strata_image(&c, p), pbrt_image(m, p));
                assert!(
                    (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9,
                    "{name} {p}: {a:?} vs {b:?}"
                );
            }
            // The mirror keeps the camera where it is.
            assert!(close(c.world.transform_point3(c.eye), c.eye), "{name}");
        }
        // Without the mirror the plain camera's image would be flipped left to right.
        let c = camera(plain, 45.0, 0.0, 0.0, 64, 64).unwrap();
        let unmirrored = Camera {
            world: DMat4::IDENTITY,
            ..c
        };
        let p = points[0];
        assert!((strata_image(&unmirrored, p).0 + pbrt_image(plain, p).0).abs() < 1e-9);
    }

    /// pbrt's fov is the shorter side's: the same vertical fov for a landscape film, the
    /// horizontal one for a portrait film.
    #[test]
    fn fov_spans_the_shorter_side() {
        let m = look_at(DVec3::ZERO, DVec3::Z, DVec3::Y).unwrap();
        assert_eq!(camera(m, 40.0, 0.0, 0.0, 400, 300).unwrap().fov_y, 40.0);
        let portrait = camera(m, 40.0, 0.0, 0.0, 300, 400).unwrap().fov_y;
        let expected = 2.0 * ((20f64).to_radians().tan() * 4.0 / 3.0).atan().to_degrees();
        assert!((portrait - expected).abs() < 1e-12, "{portrait}");
        let lens = camera(m, 40.0, 0.05, 3.0, 400, 300).unwrap();
        assert_eq!((lens.aperture, lens.focus_distance), (0.05, 3.0));
        for bad in [0.0, 180.0, f64::NAN] {
            assert!(camera(m, bad, 0.0, 0.0, 4, 4).is_err(), "{bad}");
        }
        assert!(camera(DMat4::ZERO, 40.0, 0.0, 0.0, 4, 4).is_err());
    }

    /// The directive: its parameters read, the rest warned about, other cameras refused.
    #[test]
    fn the_camera_directive() {
        let run = |text: &str| {
            let parsed = Parsed::from_text(text, std::path::Path::new("s.pbrt")).unwrap();
            let d = parsed.last("Camera");
            let m = look_at(DVec3::ZERO, DVec3::Z, DVec3::Y).unwrap();
            camera_of(&parsed, d, m, 400, 300).map(|(c, w)| {
                let w: Vec<String> = w
                    .iter()
                    .map(|w| format!("{}: {}", w.at, w.message))
                    .collect();
                (c, w)
            })
        };
        let (c, w) = run(
            "Camera \"perspective\" \"float fov\" 30 \"float lensradius\" 0.1 \
             \"float focaldistance\" 4 \"float screenwindow\" [-1 1 -1 1]",
        )
        .unwrap();
        assert_eq!((c.fov_y, c.aperture, c.focus_distance), (30.0, 0.1, 4.0));
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].starts_with("s.pbrt:1:"), "{w:?}");
        assert!(
            w[0].contains("parameter \"float screenwindow\" ignored"),
            "{w:?}"
        );
        let (c, w) = run("WorldBegin").unwrap();
        assert_eq!((c.fov_y, w.len()), (90.0, 0));
        let e = run("Camera \"orthographic\"").unwrap_err().to_string();
        assert!(
            e.starts_with("s.pbrt:1:1:") && e.contains("perspective camera only"),
            "{e}"
        );
        let e = run("Camera \"perspective\" \"float fov\" 200")
            .unwrap_err()
            .to_string();
        assert!(e.contains("fov 200"), "{e}");
    }
}
