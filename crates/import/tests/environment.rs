//! Environment maps: the image formats read (OpenEXR, Radiance HDR, PFM) give the same texels,
//! bad images are refused with the reason, and `scenes/environment.toml` loads as an
//! environment light with its map in the scene's tables.

use glam::Vec3;
use std::path::{Path, PathBuf};
use stratapt_import::load::load_str;
use stratapt_scene::environment::{self, pfm_bytes, read_image};
use stratapt_scene::records::light_kind;

/// A 5 × 3 map with distinct texels (row r, column c).
fn texels() -> Vec<f32> {
    (0..3)
        .flat_map(|r| {
            (0..5).flat_map(move |c| [0.5 + r as f32, 0.25 * c as f32, 2.0 + (r * c) as f32])
        })
        .collect()
}

#[test]
fn exr_hdr_and_pfm_read_alike() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (5, 3);
    let t = texels();
    let pfm = dir.path().join("m.pfm");
    std::fs::write(&pfm, pfm_bytes(&t, w, h)).unwrap();
    assert_eq!(read_image(&pfm).unwrap(), (t.clone(), w, h));
    let exr = dir.path().join("m.exr");
    exr::prelude::write_rgb_file(&exr, w, h, |x, y| {
        let i = 3 * (y * w + x);
        (t[i], t[i + 1], t[i + 2])
    })
    .unwrap();
    assert_eq!(read_image(&exr).unwrap(), (t.clone(), w, h));
    // Radiance HDR stores 8-bit mantissas with a shared exponent: within 1 % of the texels.
    let hdr = dir.path().join("m.hdr");
    let pixels: Vec<image::Rgb<f32>> = t
        .chunks(3)
        .map(|c| image::Rgb([c[0], c[1], c[2]]))
        .collect();
    let file = std::fs::File::create(&hdr).unwrap();
    image::codecs::hdr::HdrEncoder::new(file)
        .encode(&pixels, w, h)
        .unwrap();
    let (read, rw, rh) = read_image(&hdr).unwrap();
    assert_eq!((rw, rh), (w, h));
    for (a, b) in read.iter().zip(&t) {
        assert!((a - b).abs() <= 0.01 * b.max(0.1), "{a} vs {b}");
    }
}

#[test]
fn bad_images_are_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, bytes: &[u8]| {
        let p = dir.path().join(name);
        std::fs::write(&p, bytes).unwrap();
        p
    };
    let mut negative = texels();
    negative[7] = -1.0;
    let cases: Vec<(PathBuf, &str)> = vec![
        (write("short.pfm", b"PF\n4 4\n-1.0\n\0\0"), "need"),
        (write("text.pfm", b"P3\n1 1\n255\n"), "not a PFM"),
        (write("tiny.pfm", &pfm_bytes(&[1.0; 3], 1, 1)), "at least 2"),
        (
            write("negative.pfm", &pfm_bytes(&negative, 5, 3)),
            "texel (2, 0)",
        ),
        (
            write("nan.pfm", &pfm_bytes(&[f32::NAN; 12], 2, 2)),
            "finite",
        ),
        (write("broken.exr", b"not an exr"), ""),
        (dir.path().join("absent.hdr"), ""),
    ];
    for (path, reason) in cases {
        let e = read_image(&path).expect_err(&path.display().to_string());
        assert!(e.contains(reason), "{}: {e}", path.display());
    }
}

#[test]
fn the_bundled_environment_scene_loads_its_map() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let scene = stratapt_import::scene_file::load(&root.join("environment.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    let l = scene.lights.last().unwrap();
    assert_eq!(l.kind, light_kind::ENVIRONMENT);
    assert!(l.is_environment());
    assert_eq!(&scene.lights[scene.environment_lights()], &[*l]);
    let [w, h, offset] = l.p2.map(|x| x as usize);
    assert_eq!((w, h), (128, 64));
    assert_eq!(offset + environment::data_len(w, h), scene.tables.len());
    // Rotated 30° about y: the map's -z (its centre column) is the world's direction there.
    let (r0, r1) = (Vec3::from_array(l.p0), Vec3::from_array(l.p1));
    let r2 = r0.cross(r1);
    // Map → world is the transpose of world → map (rows r0, r1, r2): map −z goes to −r2.
    let world_of_map_minus_z = -r2;
    let expected = glam::Quat::from_rotation_y(30f32.to_radians()) * Vec3::NEG_Z;
    assert!(
        (world_of_map_minus_z - expected).length() < 1e-5,
        "{world_of_map_minus_z}"
    );
    // Its mean radiance is positive and far below the sun's 4000.
    assert!(
        l.radiance.iter().all(|&x| x > 0.1 && x < 100.0),
        "{:?}",
        l.radiance
    );
}

#[test]
fn a_map_is_read_relative_to_the_scene_and_scaled() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("maps")).unwrap();
    std::fs::write(dir.path().join("maps/m.pfm"), pfm_bytes(&texels(), 5, 3)).unwrap();
    let base = "[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov = 40\n";
    let scene = |sky: &str| load_str(&format!("{base}{sky}"), &dir.path().join("s.toml"));
    let plain = scene("[sky]\nmap = \"maps/m.pfm\"\n").unwrap();
    let scaled = scene("[sky]\nmap = \"maps/m.pfm\"\nscale = [2, 1, 0.5]\n").unwrap();
    for (a, b) in plain.tables[..45]
        .chunks(3)
        .zip(scaled.tables[..45].chunks(3))
    {
        assert_eq!([a[0] * 2.0, a[1], a[2] * 0.5], [b[0], b[1], b[2]]);
    }
    // All black: no light at all.
    std::fs::write(
        dir.path().join("maps/black.pfm"),
        pfm_bytes(&[0.0; 12], 2, 2),
    )
    .unwrap();
    let black = scene("[sky]\nmap = \"maps/black.pfm\"\n").unwrap();
    assert!(black.lights.is_empty());
}

/// `mapping = "octahedral"`: pbrt-v4's equal-area square, `z` up in the map's frame; the light
/// holds the same fields, its mean radiance is the texels' mean (every texel the same solid
/// angle); a map that is not square, an unknown layout and a layout without a map are refused.
#[test]
fn an_octahedral_map_is_square_and_its_mean_is_the_texels() {
    let dir = tempfile::tempdir().unwrap();
    let square: Vec<f32> = (0..16).flat_map(|i| [i as f32, 1.0, 0.5]).collect();
    std::fs::write(dir.path().join("square.pfm"), pfm_bytes(&square, 4, 4)).unwrap();
    std::fs::write(dir.path().join("wide.pfm"), pfm_bytes(&texels(), 5, 3)).unwrap();
    let base = "[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov = 40\n";
    let scene = |sky: &str| load_str(&format!("{base}{sky}"), &dir.path().join("s.toml"));
    let s = scene("[sky]\nmap = \"square.pfm\"\nmapping = \"octahedral\"\n").unwrap();
    let l = s.lights[0];
    assert_eq!(l.kind, light_kind::OCTAHEDRAL);
    assert!(l.is_environment());
    assert_eq!(l.p2[..2], [4.0, 4.0]);
    assert_eq!(l.radiance, [7.5, 1.0, 0.5]);
    let latlong = scene("[sky]\nmap = \"square.pfm\"\nmapping = \"equirectangular\"\n").unwrap();
    assert_eq!(latlong.lights[0].kind, light_kind::ENVIRONMENT);
    for (sky, words) in [
        (
            "[sky]\nmap = \"wide.pfm\"\nmapping = \"octahedral\"\n",
            &["wide.pfm", "5×3", "square", ":7:"][..],
        ),
        (
            "[sky]\nmap = \"square.pfm\"\nmapping = \"cube\"\n",
            &[
                "unknown mapping `cube`",
                "equirectangular, octahedral",
                ":7:",
            ],
        ),
        (
            "[sky]\ncolor = 1\nmapping = \"octahedral\"\n",
            &["`mapping` applies to an environment `map`", ":7:"],
        ),
    ] {
        let e = scene(sky).err().expect(sky).to_string();
        for w in words {
            assert!(e.contains(w), "`{w}` not in: {e}");
        }
    }
}

#[test]
fn the_bundled_octahedral_scene_loads_its_map_z_up() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let scene = stratapt_import::scene_file::load(&root.join("environment-octahedral.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    let l = scene.lights.last().unwrap();
    assert_eq!(l.kind, light_kind::OCTAHEDRAL);
    assert_eq!(l.p2[..2], [128.0, 128.0]);
    // rotate = [-90, 30, 0]: the map's +z (the image's centre) is the world's up.
    let (r0, r1) = (Vec3::from_array(l.p0), Vec3::from_array(l.p1));
    let world_of_map_z = r0.cross(r1);
    assert!(
        (world_of_map_z - Vec3::Y).length() < 1e-6,
        "{world_of_map_z}"
    );
}
