//! pbrt-v4 scenes imported and rendered: what the importer makes of handedness, of the side a
//! surface emits from, of instances and of an environment map's orientation, checked on small
//! images whose answer is known from pbrt-v4's conventions (not from strata's own code).

use glam::{Vec2, Vec3};
use std::path::{Path, PathBuf};
use stratapt::film::Film;
use stratapt::import::scene_file;
use stratapt::scene::{FlatScene, RenderSettings};

/// Write `text` as `dir/scene.pbrt`.
fn write(dir: &Path, text: &str) -> PathBuf {
    let path = dir.join("scene.pbrt");
    std::fs::write(&path, text).unwrap();
    path
}

fn import(dir: &Path, text: &str) -> FlatScene {
    scene_file::load(&write(dir, text)).unwrap_or_else(|e| panic!("{e}"))
}

fn render(scene: &FlatScene, spp: u32) -> Film {
    let settings = RenderSettings {
        pattern_spp: spp,
        ..scene.settings
    };
    stratapt::cpu::render(scene, &settings, &|_| {}, None).0
}

/// The mean red of the left and right halves of the image.
fn halves(film: &Film) -> (f64, f64) {
    let (w, h) = (film.width as usize, film.height as usize);
    let (mut left, mut right) = (0.0, 0.0);
    for y in 0..h {
        for x in 0..w {
            let r = film.mean(y * w + x)[0];
            if x < w / 2 {
                left += r;
            } else {
                right += r;
            }
        }
    }
    (left, right)
}

/// A camera at the origin looking along +z with +y up (pbrt's default pose), and an emitting
/// sphere at world +x: pbrt's image shows it on the right, unless the camera's transform has
/// `Scale -1 1 1`, which mirrors pbrt's image.
fn sphere_at_plus_x(camera_prefix: &str) -> String {
    format!(
        r#"{camera_prefix}
LookAt 0 0 0  0 0 1  0 1 0
Camera "perspective" "float fov" 60
Film "rgb" "integer xresolution" 24 "integer yresolution" 12
Integrator "path" "integer maxdepth" 1
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 0 0]
  Translate 1.5 0 4
  Shape "sphere" "float radius" 0.5
AttributeEnd
"#
    )
}

#[test]
fn handedness_follows_pbrts_camera() {
    let dir = tempfile::tempdir().unwrap();
    let (l, r) = halves(&render(&import(dir.path(), &sphere_at_plus_x("")), 4));
    assert!(
        r > 0.0 && l == 0.0,
        "plain LookAt: pbrt shows +x on the right ({l}, {r})"
    );
    let (l, r) = halves(&render(
        &import(dir.path(), &sphere_at_plus_x("Scale -1 1 1")),
        4,
    ));
    assert!(
        l > 0.0 && r == 0.0,
        "Scale -1 1 1: pbrt shows +x on the left ({l}, {r})"
    );
}

/// One emitting triangle at z = 2 in front of the camera, `extra` directives before it, its
/// vertices in `order`, with normals `normals` if given.
fn triangle(extra: &str, order: &str, normals: &str) -> String {
    facing_emitter(&format!(
        "{extra}\n  Shape \"trianglemesh\" \"point3 P\" [-3 -3 2  3 -3 2  0 3 2] \
         \"integer indices\" [{order}] {normals}"
    ))
}

/// A camera at the origin looking along +z (8 × 8 pixels, 90°, direct light only) and one
/// white area light made of `shape` (with whatever directives precede it in its block).
fn facing_emitter(shape: &str) -> String {
    format!(
        r#"LookAt 0 0 0  0 0 1  0 1 0
Camera "perspective" "float fov" 90
Film "rgb" "integer xresolution" 8 "integer yresolution" 8
Integrator "path" "integer maxdepth" 1
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 1 1]
  {shape}
AttributeEnd
"#
    )
}

/// Whether the camera sees the triangle emit.
fn emits_towards_camera(dir: &Path, text: &str) -> bool {
    let film = render(&import(dir, text), 1);
    let (l, r) = halves(&film);
    l + r > 0.0
}

#[test]
fn area_lights_emit_from_pbrts_front_side() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // pbrt-v4's front is (p0 − p2) × (p1 − p2), the same as (p1 − p0) × (p2 − p0): for the
    // vertices in order 0 1 2 that is +z, away from the camera; in order 0 2 1, towards it.
    assert!(!emits_towards_camera(d, &triangle("", "0 1 2", "")));
    assert!(emits_towards_camera(d, &triangle("", "0 2 1", "")));
    assert!(emits_towards_camera(
        d,
        &triangle("ReverseOrientation", "0 1 2", "")
    ));
    assert!(!emits_towards_camera(
        d,
        &triangle("ReverseOrientation", "0 2 1", "")
    ));
    // A transform that swaps handedness turns the front with it: mirrored in z about the
    // triangle's plane (z = 2), the front of 0 2 1 faces +z, away from the camera.
    assert!(!emits_towards_camera(
        d,
        &triangle("Translate 0 0 2 Scale 1 1 -1 Translate 0 0 -2", "0 2 1", "")
    ));
    // Normals decide where the mesh has them, whatever the winding...
    let towards = r#""normal N" [0 0 -1  0 0 -1  0 0 -1]"#;
    let away = r#""normal N" [0 0 1  0 0 1  0 0 1]"#;
    assert!(emits_towards_camera(d, &triangle("", "0 1 2", towards)));
    assert!(!emits_towards_camera(d, &triangle("", "0 2 1", away)));
    // ...and ReverseOrientation flips the normals.
    assert!(!emits_towards_camera(
        d,
        &triangle("ReverseOrientation", "0 1 2", towards)
    ));
}

#[test]
fn instances_are_flattened_copies() {
    let dir = tempfile::tempdir().unwrap();
    let scene = import(
        dir.path(),
        r#"LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective"
WorldBegin
ObjectBegin "pair"
  Shape "sphere" "float radius" 0.25
  Translate 1 0 0
  Shape "trianglemesh" "point3 P" [0 0 0  1 0 0  0 1 0] "integer indices" [0 1 2]
ObjectEnd
AttributeBegin
  Translate -2 0 0
  ObjectInstance "pair"
AttributeEnd
Scale 2 2 2
ObjectInstance "pair"
"#,
    );
    let report = scene.import.as_ref().unwrap();
    assert_eq!((report.instances, report.instanced_shapes), (2, 4));
    assert_eq!(report.shapes, 0, "every shape is an instance's");
    assert_eq!(scene.geometry.len(), 4, "two spheres and two triangles");
    let mut spheres: Vec<(f32, f32)> = (0..4)
        .map(|i| scene.geometry.prim(i))
        .filter(|p| p.kind == stratapt::scene::records::prim_kind::SPHERE)
        .map(|p| (p.a[0], p.b[0]))
        .collect();
    spheres.sort_by(|a, b| a.partial_cmp(b).unwrap());
    // The first instance at x = −2 (radius 0.25), the second scaled by 2 (radius 0.5); the
    // camera's plain LookAt mirrors x about the eye's plane x = 0.
    assert_eq!(spheres, vec![(0.0, 0.5), (2.0, 0.25)]);
}

/// An equal-area octahedral map, `side` texels square, bright (1) where pbrt-v4 looks up a
/// direction with x > 0.6 in the light's space and dark elsewhere, as a PFM (rows bottom to
/// top). pbrt-v4 reads texel (x, y) (y from the top) for the directions of the square's
/// `((x + ½) / side, (y + ½) / side)`.
fn plus_x_map(path: &Path, side: usize) {
    let mut rows = Vec::new();
    for y in 0..side {
        let mut row = Vec::new();
        for x in 0..side {
            let uv = Vec2::new(
                (x as f32 + 0.5) / side as f32,
                (y as f32 + 0.5) / side as f32,
            );
            let d: Vec3 = stratapt::sampling::warp::equal_area::square_to_sphere(uv);
            let v = if d.x > 0.6 { 1.0f32 } else { 0.0 };
            row.extend([v, v, v]);
        }
        rows.push(row);
    }
    let mut bytes = format!("PF\n{side} {side}\n-1.0\n").into_bytes();
    for row in rows.iter().rev() {
        for v in row {
            bytes.extend(v.to_le_bytes());
        }
    }
    std::fs::write(path, bytes).unwrap();
}

/// Looking along +z from the origin with a 120° view, the +x part of the sky is on pbrt's
/// right with a plain LookAt; turned by `light_transform`, it is where that puts it.
fn sky_scene(camera_prefix: &str, light_transform: &str) -> String {
    format!(
        r#"{camera_prefix}
LookAt 0 0 0  0 0 1  0 1 0
Camera "perspective" "float fov" 120
Film "rgb" "integer xresolution" 24 "integer yresolution" 8
Integrator "path" "integer maxdepth" 1
WorldBegin
AttributeBegin
  {light_transform}
  LightSource "infinite" "string filename" "sky.pfm"
AttributeEnd
"#
    )
}

#[test]
fn environment_maps_keep_pbrts_orientation() {
    let dir = tempfile::tempdir().unwrap();
    plus_x_map(&dir.path().join("sky.pfm"), 64);
    let cases = [
        ("", "", "right"),
        ("Scale -1 1 1", "", "left"),
        // The light's +x turned to world −x.
        ("", "Rotate 180 0 1 0", "left"),
        ("Scale -1 1 1", "Rotate 180 0 1 0", "right"),
        // The light's +x turned to world +y, up, out of this view's sides: both halves alike.
        ("", "Rotate 90 0 0 1", "both"),
    ];
    for (camera, light, side) in cases {
        let film = render(&import(dir.path(), &sky_scene(camera, light)), 4);
        let (l, r) = halves(&film);
        let got = match (l > 2.0 * r, r > 2.0 * l) {
            (true, _) => "left",
            (_, true) => "right",
            _ => "both",
        };
        assert_eq!(
            got, side,
            "camera `{camera}`, light `{light}`: halves {l}, {r}"
        );
    }
}

#[test]
fn spot_lights_keep_pbrts_cone_and_aim() {
    let dir = tempfile::tempdir().unwrap();
    let scene = import(
        dir.path(),
        r#"Scale -1 1 1
LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective"
WorldBegin
AttributeBegin
  Translate 0 2 0
  LightSource "spot" "point3 from" [0 0 0] "point3 to" [1 -1 0] "rgb I" [2 3 4]
    "float coneangle" 40 "float conedeltaangle" 10 "float scale" 0.5
AttributeEnd
"#,
    );
    let spot = scene.lights[0];
    assert_eq!(spot.kind, stratapt::scene::records::light_kind::SPOT);
    assert_eq!(spot.p0, [0.0, 2.0, 0.0]);
    let axis = Vec3::from_array(spot.p1);
    assert!(
        (axis - Vec3::new(1.0, -1.0, 0.0).normalize()).length() < 1e-6,
        "{axis}"
    );
    let cos = |deg: f64| deg.to_radians().cos() as f32;
    assert!((spot.p2[0] - cos(40.0)).abs() < 1e-6 && (spot.p2[1] - cos(30.0)).abs() < 1e-6);
    assert_eq!(spot.radiance, [1.0, 1.5, 2.0]);
}

/// `"spectrum eta" "file.spd"` reads wavelength–value pairs from the file (with `#` comments),
/// as the same pairs written inline.
#[test]
fn spectrum_files_read_as_inline_spectra() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("cu.eta.spd"),
        "# wavelength eta\n400 1.1\n500 0.9 # a comment\n600 0.3\n700 0.2\n",
    )
    .unwrap();
    let scene = |eta: &str| {
        import(
            dir.path(),
            &format!(
                "PixelFilter \"box\"\nWorldBegin\nMaterial \"conductor\" \"spectrum eta\" {eta} \"rgb k\" [3 2 1]\n\
                 Shape \"sphere\"\n"
            ),
        )
    };
    let from_file = scene("\"cu.eta.spd\"");
    let inline = scene("[400 1.1 500 0.9 600 0.3 700 0.2]");
    assert_eq!(from_file.materials, inline.materials);
    assert!(from_file.import.unwrap().warnings.is_empty());
}

/// One scene with what the other tests do not cover: a PLY mesh (binary, with normals and
/// texture coordinates) placed by `Transform` and `ConcatTransform`, a gzip-compressed
/// `Include`, checkerboard, `scale` and `constant` textures, a named glass, `interface`, a
/// subdivision surface, `CoordinateSystem`/`CoordSysTransform`, distant and constant infinite
/// lights, `TransformBegin`/`TransformEnd`; and what each becomes, read back from the TOML text
/// its description is written as.
#[test]
fn every_directive_imports() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mesh = stratapt::import::load::MeshData {
        positions: vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0],
        normals: Some([0.0, 0.0, -1.0].repeat(4)),
        uvs: Some(vec![0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0]),
        indices: vec![0, 1, 2, 0, 2, 3],
    };
    stratapt::import::load::write_ply(&d.join("quad.ply"), &mesh).unwrap();
    let mut gz = flate2_writer(&d.join("lights.pbrt.gz"));
    gz.write_all(
        b"LightSource \"distant\" \"point3 from\" [0 10 0] \"point3 to\" [0 0 0] \"blackbody L\" 5500\n\
          LightSource \"infinite\" \"rgb L\" [0.1 0.2 0.3]\n",
    )
    .unwrap();
    gz.finish().unwrap();
    let text = r#"
Scale -1 1 1
LookAt 0 2 -6  0 0 0  0 1 0
Camera "perspective" "float fov" 40
PixelFilter "triangle" "float xradius" 1.5 "float yradius" 1.5
Sampler "stratified" "integer xsamples" 2 "integer ysamples" 3
WorldBegin
CoordinateSystem "origin"
Texture "checks" "spectrum" "checkerboard" "float uscale" 4 "float vscale" 2
  "rgb tex1" [0.9 0.9 0.9] "rgb tex2" [0.1 0.1 0.1]
Texture "grey" "float" "constant" "float value" 0.25
Texture "half" "spectrum" "scale" "texture tex" "checks" "float scale" 1
MakeNamedMaterial "floor" "string type" "diffuse" "texture reflectance" "half"
MakeNamedMaterial "glass" "string type" "dielectric" "spectrum eta" "glass-BK7"
MakeNamedMaterial "rough" "string type" "conductor" "texture roughness" "grey"
  "bool remaproughness" false "rgb eta" [0.2 0.9 1.1] "rgb k" [3.9 2.4 2.1]
MakeNamedMaterial "boundary" "string type" "interface"
AttributeBegin
  NamedMaterial "floor"
  Transform [1 0 0 0  0 1 0 0  0 0 1 0  -0.5 0 0 1]
  ConcatTransform [2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1]
  Shape "plymesh" "string filename" "quad.ply"
AttributeEnd
TransformBegin
  Translate 0 1 0
  NamedMaterial "glass"
  Shape "sphere" "float radius" 0.5
TransformEnd
NamedMaterial "boundary"
Shape "sphere" "float radius" 3
NamedMaterial "rough"
CoordSysTransform "origin"
Shape "loopsubdiv" "integer levels" 0 "point3 P" [0 0 1  1 0 1  0 1 1] "integer indices" [0 1 2]
Include "lights.pbrt.gz"
"#;
    let path = write(d, text);
    let imported = stratapt::import::pbrt::import::import(&path, "scene-meshes").unwrap();
    let report = imported.import.as_ref().unwrap();
    // The one warning: the glass's dispersion.
    assert_eq!(report.warnings.len(), 1, "{:?}", report.warnings);
    assert!(report.warnings[0].message.contains("dispersive"));
    assert_eq!(
        (report.shapes, report.ply_files),
        (3, 1),
        "the interface sphere is no shape"
    );
    let toml = stratapt::import::desc::write::to_toml(&imported, d).unwrap();
    for expected in [
        "filter = \"tent\"\nfilter_width = 1.5",
        "max_depth = 5\nsampler = \"stratified\"\nspp = 6",
        // pbrt's squares are one unit wide, strata's checkerboard two; strata's v is 1 − pbrt's.
        "type = \"checkerboard\"\ncolor0 = 0.9\ncolor1 = 0.1\nuv_transform = [[2.0, 0.0, 0.0], [0.0, -1.0, 1.0]]",
        "[materials.\"floor\"]\ntype = \"diffuse\"\nalbedo = \"checks\"",
        "[materials.\"glass\"]\ntype = \"dielectric\"\nior = 1.518",
        "[materials.\"rough\"]\ntype = \"conductor\"\neta = [0.2, 0.9, 1.1]\nk = [3.9, 2.4, 2.1]\nroughness = 0.25",
        "type = \"sphere\"\ncenter = [0.0, 1.0, 0.0]\nmaterial = \"glass\"\nradius = 0.5",
        "[[lights]]\ntype = \"distant\"\ndirection = [0.0, 1.0, 0.0]",
        "[sky]\ncolor = [0.1, 0.2, 0.3]",
    ] {
        assert!(toml.contains(expected), "`{expected}` not in\n{toml}");
    }
    // The PLY quad, scaled by 2 and moved by −0.5 in x, its uv flipped to strata's (v → 1 − v).
    let quad = &imported.meshes["scene-meshes/00000.ply"];
    assert_eq!(quad.positions[..6], [-0.5, 0.0, 0.0, 1.5, 0.0, 0.0]);
    assert_eq!(quad.uvs.as_ref().unwrap()[..4], [0.0, 1.0, 1.0, 1.0]);
    // And the whole scene loads and renders.
    let scene = scene_file::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.geometry.len(), 2 + 1 + 1);
    let film = render(&scene, 1);
    assert!(!film.has_non_finite());
}

/// A gzip writer to `path`.
fn flate2_writer(path: &Path) -> flate2::write::GzEncoder<std::fs::File> {
    flate2::write::GzEncoder::new(
        std::fs::File::create(path).unwrap(),
        flate2::Compression::default(),
    )
}

/// pbrt-v4's disks face as its quadrics do: the object's +z, flipped by `ReverseOrientation`
/// and by a CTM that swaps handedness (unlike a triangle, whose object-space front survives
/// such a CTM: `area_lights_emit_from_pbrts_front_side`).
#[test]
fn disks_face_as_pbrts_quadrics() {
    let dir = tempfile::tempdir().unwrap();
    let disk = |extra: &str| {
        facing_emitter(&format!(
            "Translate 0 0 2\n  {extra}\n  Shape \"disk\" \"float radius\" 3"
        ))
    };
    // +z faces away from the camera.
    assert!(!emits_towards_camera(dir.path(), &disk("")));
    assert!(emits_towards_camera(
        dir.path(),
        &disk("ReverseOrientation")
    ));
    assert!(!emits_towards_camera(dir.path(), &disk("Scale 1 1 -1")));
    assert!(emits_towards_camera(
        dir.path(),
        &disk("Scale 1 1 -1 ReverseOrientation")
    ));
}

/// A light of zero radiance is no light: its shapes share their material with unlit ones.
#[test]
fn zero_radiance_area_lights_are_no_lights() {
    let dir = tempfile::tempdir().unwrap();
    let scene = import(
        dir.path(),
        r#"WorldBegin
MakeNamedMaterial "m" "string type" "diffuse"
NamedMaterial "m"
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [0 0 0]
  Shape "sphere"
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "float scale" 0
  Translate 3 0 0
  Shape "sphere"
AttributeEnd
Translate -3 0 0
Shape "sphere"
"#,
    );
    assert_eq!(scene.geometry.len(), 3);
    assert!(scene.lights.is_empty());
}
