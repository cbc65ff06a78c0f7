//! pbrt-v4's `thindielectric`, `diffusetransmission`, `mix`, `coateddiffuse` and
//! `coatedconductor` import as strata's thin dielectric, diffuse transmission, mix and coated
//! materials, with the parameters pbrt reads, and without a warning; a mix that names itself, or
//! not two materials, is an error at its directive.

use std::path::Path;
use stratapt_import::scene_file::load;
use stratapt_scene::records::{material_flag, material_kind, Material};
use stratapt_scene::FlatScene;

const HEAD: &str = "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n\
                    PixelFilter \"box\"\nWorldBegin\n";

const QUAD: &str =
    "Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0] \"integer indices\" [0 1 2]\n";

/// `body` after a camera, written as `dir/s.pbrt` and loaded: the scene, or the error's text.
fn load_body(dir: &Path, body: &str) -> Result<FlatScene, String> {
    let path = dir.join("s.pbrt");
    std::fs::write(&path, format!("{HEAD}{body}")).unwrap();
    load(&path).map_err(|e| e.to_string())
}

fn warnings(scene: &FlatScene) -> Vec<String> {
    let report = scene.import.as_ref().expect("a pbrt import");
    report.warnings.iter().map(|w| w.message.clone()).collect()
}

/// The material of the scene's first primitive.
fn drawn(scene: &FlatScene) -> Material {
    scene.materials[scene.geometry.surfaces[0].material as usize]
}

#[test]
fn a_thin_dielectric_is_a_thin_sheet() {
    let dir = tempfile::tempdir().unwrap();
    let scene = load_body(
        dir.path(),
        &format!("Material \"thindielectric\" \"float eta\" 1.33\n{QUAD}"),
    )
    .unwrap();
    assert_eq!(warnings(&scene), Vec::<String>::new());
    let m = drawn(&scene);
    assert_eq!(m.kind(), material_kind::THIN_DIELECTRIC);
    assert_eq!(m.ior, 1.33);
}

#[test]
fn diffuse_transmission_scales_then_clamps_as_pbrt() {
    let dir = tempfile::tempdir().unwrap();
    let scene = load_body(
        dir.path(),
        &format!(
            "Material \"diffusetransmission\" \"rgb reflectance\" [0.3 0.25 0.2] \
             \"rgb transmittance\" [0.3 1.5 0.2] \"float scale\" 0.5\n{QUAD}"
        ),
    )
    .unwrap();
    assert_eq!(warnings(&scene), Vec::<String>::new());
    let m = drawn(&scene);
    assert_eq!(m.kind(), material_kind::DIFFUSE_TRANSMISSION);
    assert_eq!(m.color, [0.15, 0.125, 0.1]);
    assert_eq!(m.eta, [0.15, 0.75, 0.1]);
    // 2.5 × 0.5 is clamped to 1, as pbrt clamps each lookup; with the reflectance that is more
    // than 1, which pbrt would draw and strata scales down, warned.
    let gaining = load_body(
        dir.path(),
        &format!(
            "Material \"diffusetransmission\" \"rgb reflectance\" [0.3 0.25 0.2] \
             \"rgb transmittance\" [0.3 2.5 0.2] \"float scale\" 0.5\n{QUAD}"
        ),
    )
    .unwrap();
    let w = warnings(&gaining);
    assert!(w.len() == 1 && w[0].contains("1.125"), "{w:?}");
    let m = drawn(&gaining);
    assert!(
        (m.color[1] + m.eta[1] - 1.0).abs() < 1e-6 && m.eta[1] > 0.88,
        "{m:?}"
    );
    // pbrt's defaults: 0.25 each.
    let plain = load_body(
        dir.path(),
        &format!("Material \"diffusetransmission\"\n{QUAD}"),
    )
    .unwrap();
    assert_eq!(drawn(&plain).color, [0.25; 3]);
    assert_eq!(drawn(&plain).eta, [0.25; 3]);
}

#[test]
fn a_mix_chooses_between_its_two_materials() {
    let dir = tempfile::tempdir().unwrap();
    let named = "MakeNamedMaterial \"red\" \"string type\" \"diffuse\" \
                 \"rgb reflectance\" [0.8 0.1 0.1]\n\
                 MakeNamedMaterial \"glass\" \"string type\" \"dielectric\"\n";
    let scene = load_body(
        dir.path(),
        &format!(
            "{named}MakeNamedMaterial \"both\" \"string type\" \"mix\" \
             \"string materials\" [\"red\" \"glass\"] \"float amount\" 0.3\n\
             NamedMaterial \"both\"\n{QUAD}"
        ),
    )
    .unwrap();
    assert_eq!(warnings(&scene), Vec::<String>::new());
    let m = drawn(&scene);
    assert_eq!(m.kind(), material_kind::MIX);
    assert_eq!(m.alpha_u, 0.3);
    let [a, b] = [m.k[0], m.k[1]].map(|i| scene.materials[i as usize]);
    assert_eq!(
        (a.kind(), b.kind()),
        (material_kind::DIFFUSE, material_kind::DIELECTRIC)
    );
    assert_eq!(a.color, [0.8, 0.1, 0.1]);

    // A float texture as the amount: the mix reads it, and its surfaces compute uv.
    let textured = load_body(
        dir.path(),
        &format!(
            "{named}Texture \"checks\" \"float\" \"checkerboard\" \"float tex1\" 0 \
             \"float tex2\" 1\n\
             MakeNamedMaterial \"both\" \"string type\" \"mix\" \
             \"string materials\" [\"red\" \"glass\"] \"texture amount\" \"checks\"\n\
             NamedMaterial \"both\"\n{QUAD}"
        ),
    )
    .unwrap();
    assert_eq!(warnings(&textured), Vec::<String>::new());
    assert!(drawn(&textured).has(material_flag::ALPHA_TEXTURE));
}

#[test]
fn mixes_that_name_themselves_or_not_two_materials_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let looping = load_body(
        dir.path(),
        &format!(
            "MakeNamedMaterial \"a\" \"string type\" \"mix\" \"string materials\" [\"b\" \"b\"]\n\
             MakeNamedMaterial \"b\" \"string type\" \"mix\" \"string materials\" [\"a\" \"a\"]\n\
             NamedMaterial \"a\"\n{QUAD}"
        ),
    )
    .err()
    .expect("a mix that names itself loads");
    assert!(
        looping.contains("s.pbrt:") && looping.contains("16 mixes"),
        "{looping}"
    );
    let one = load_body(
        dir.path(),
        &format!(
            "MakeNamedMaterial \"a\" \"string type\" \"mix\" \"string materials\" [\"b\"]\n\
             NamedMaterial \"a\"\n{QUAD}"
        ),
    )
    .err()
    .expect("a mix of one material loads");
    assert!(one.contains("two materials"), "{one}");
}

#[test]
fn coated_materials_keep_pbrts_layers() {
    let dir = tempfile::tempdir().unwrap();
    let scene = load_body(
        dir.path(),
        &format!(
            "Material \"coateddiffuse\" \"rgb reflectance\" [0.6 0.1 0.1] \"float eta\" 1.4 \
             \"float roughness\" 0.04 \"float thickness\" 0.2 \"rgb albedo\" [0.5 0.5 0.5] \
             \"float g\" 0.3 \"integer maxdepth\" 20 \"integer nsamples\" 2\n{QUAD}"
        ),
    )
    .unwrap();
    assert_eq!(warnings(&scene), Vec::<String>::new());
    let m = drawn(&scene);
    assert_eq!(m.kind(), material_kind::COATED_DIFFUSE);
    assert_eq!(m.ior, 1.4);
    // Remapped as pbrt's RoughnessToAlpha: √0.04.
    assert!((m.alpha_u - 0.2).abs() < 1e-6 && m.alpha_u == m.alpha_v);
    assert_eq!(m.color, [0.5; 3]);
    assert_eq!(m.eta, [0.2, 0.3, 20.0]);
    assert_eq!(m.k[0], 2.0);
    let base = scene.materials[m.k[1] as usize];
    assert_eq!(base.kind(), material_kind::DIFFUSE);
    assert_eq!(base.color, [0.6, 0.1, 0.1]);

    let conductor = load_body(
        dir.path(),
        &format!(
            "Material \"coatedconductor\" \"float interface.eta\" 1.6 \
             \"float conductor.roughness\" 0.09 \"rgb conductor.eta\" [0.2 0.9 1.1] \
             \"rgb conductor.k\" [3.9 2.4 2.1]\n{QUAD}"
        ),
    )
    .unwrap();
    assert_eq!(warnings(&conductor), Vec::<String>::new());
    let m = drawn(&conductor);
    assert_eq!(m.kind(), material_kind::COATED_CONDUCTOR);
    assert_eq!((m.ior, m.alpha_u), (1.6, 0.0));
    // pbrt's defaults: thickness 0.01, a clear slab, 10 events, 1 walk.
    assert_eq!((m.eta, m.k[0]), ([0.01, 0.0, 10.0], 1.0));
    let base = conductor.materials[m.k[1] as usize];
    assert_eq!(base.kind(), material_kind::COMPLEX_CONDUCTOR);
    assert_eq!((base.eta, base.k), ([0.2, 0.9, 1.1], [3.9, 2.4, 2.1]));
    assert!((base.alpha_u - 0.3).abs() < 1e-6);
}
