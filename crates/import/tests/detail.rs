//! Bump and normal maps in scene files: `displacement` (a number or a texture) and `normal_map`
//! (a raw image texture) on any material become a map record over the material, which mixes
//! and shapes reach through its name; every misuse is refused with its line; pbrt-v4's
//! `displacement` and `normalmap` import as them without a warning.

use std::path::Path;
use stratapt_import::scene_file::load;
use stratapt_scene::records::{material_flag, material_kind, surface_flag, Material};
use stratapt_scene::{Effects, FlatScene, RenderSettings};

const CAMERA: &str = "[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov = 40\n\n";

const TEXTURES: &str = "[textures.heights]\ntype = \"image\"\nfile = \"h.pfm\"\n\n\
                        [textures.normals]\ntype = \"image\"\nfile = \"n.png\"\nraw = true\n\n\
                        [textures.colours]\ntype = \"image\"\nfile = \"n.png\"\n\n\
                        [textures.checks]\ntype = \"checkerboard\"\n\n";

const SHAPE: &str = "[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n";

/// A grey 2 × 2 PFM and an RGB 2 × 2 PNG beside the scene.
fn images(dir: &Path) {
    let mut pfm = b"Pf\n2 2\n-1.0\n".to_vec();
    for h in [0.0f32, 0.5, 0.25, 1.0] {
        pfm.extend(h.to_le_bytes());
    }
    std::fs::write(dir.join("h.pfm"), pfm).unwrap();
    image::RgbImage::from_pixel(2, 2, image::Rgb([128, 128, 255]))
        .save(dir.join("n.png"))
        .unwrap();
}

/// The error of loading `text` (after the camera and textures): its message.
fn error(dir: &Path, text: &str) -> String {
    match load_text(dir, text) {
        Ok(_) => panic!("loaded without error:\n{text}"),
        Err(e) => e,
    }
}

fn load_text(dir: &Path, text: &str) -> Result<FlatScene, String> {
    images(dir);
    let path = dir.join("s.toml");
    std::fs::write(&path, format!("{CAMERA}{TEXTURES}{text}")).unwrap();
    load(&path).map_err(|e| e.to_string())
}

/// The material of the scene's first primitive.
fn drawn(scene: &FlatScene) -> (Material, u32) {
    let s = scene.geometry.surfaces[0];
    (scene.materials[s.material as usize], s.flags)
}

#[test]
fn a_displacement_wraps_its_material_in_a_bump_map() {
    let dir = tempfile::tempdir().unwrap();
    let scene = load_text(
        dir.path(),
        &format!(
            "[materials.m]\ntype = \"diffuse\"\nalbedo = 0.5\nemission = 2\n\
             displacement = \"heights\"\n\n{SHAPE}material = \"m\"\n"
        ),
    )
    .unwrap();
    let (m, flags) = drawn(&scene);
    assert_eq!(m.kind(), material_kind::BUMP);
    assert!(m.has(material_flag::COLOR_TEXTURE));
    let inner = scene.materials[m.k[0] as usize];
    assert_eq!(
        (inner.kind(), inner.color),
        (material_kind::DIFFUSE, [0.5; 3])
    );
    // The light keeps its emission; the surface computes its texture coordinates.
    assert_eq!(m.emission, [2.0; 3]);
    assert_ne!(flags & surface_flag::TEXTURED, 0);
    let effects = Effects::of(&scene, &RenderSettings::default());
    assert!(effects.material_kinds & (1 << material_kind::BUMP) != 0);
    assert!(effects.material_kinds & (1 << material_kind::DIFFUSE) != 0);

    // A constant height.
    let scene = load_text(
        dir.path(),
        &format!("[materials.m]\ntype = \"diffuse\"\nalbedo = 0.5\ndisplacement = 0.1\n\n{SHAPE}material = \"m\"\n"),
    )
    .unwrap();
    let (m, _) = drawn(&scene);
    assert_eq!((m.kind(), m.color[0]), (material_kind::BUMP, 0.1));
    assert!(!m.has(material_flag::COLOR_TEXTURE));
}

#[test]
fn a_normal_map_wraps_its_material_and_mixes_reach_it_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let scene = load_text(
        dir.path(),
        &format!(
            "[materials.a]\ntype = \"conductor\"\nreflectance = 0.9\nnormal_map = \"normals\"\n\n\
             [materials.b]\ntype = \"diffuse\"\nalbedo = 0.2\n\n\
             [materials.m]\ntype = \"mix\"\nmaterials = [\"a\", \"b\"]\n\n{SHAPE}material = \"m\"\n"
        ),
    )
    .unwrap();
    let (mix, flags) = drawn(&scene);
    assert_eq!(mix.kind(), material_kind::MIX);
    let a = scene.materials[mix.k[0] as usize];
    assert_eq!(a.kind(), material_kind::NORMAL_MAP);
    assert_eq!(
        scene.materials[a.k[0] as usize].kind(),
        material_kind::CONDUCTOR
    );
    assert_ne!(flags & surface_flag::TEXTURED, 0, "the map reads a texture");
    let effects = Effects::of(&scene, &RenderSettings::default());
    assert!(effects.material_kinds & (1 << material_kind::NORMAL_MAP) != 0);
    assert!(effects.textures);
}

#[test]
fn a_coated_material_takes_a_map_and_its_base_does_not() {
    let dir = tempfile::tempdir().unwrap();
    let base = "[materials.base]\ntype = \"diffuse\"\nalbedo = 0.5\n";
    let scene = load_text(
        dir.path(),
        &format!(
            "{base}\n[materials.c]\ntype = \"coated\"\nbase = \"base\"\ndisplacement = \"heights\"\n\n\
             {SHAPE}material = \"c\"\n"
        ),
    )
    .unwrap();
    let (m, _) = drawn(&scene);
    assert_eq!(m.kind(), material_kind::BUMP);
    let coated = scene.materials[m.k[0] as usize];
    assert_eq!(coated.kind(), material_kind::COATED_DIFFUSE);
    assert_eq!(
        scene.materials[coated.k[1] as usize].kind(),
        material_kind::DIFFUSE
    );
    let e = error(
        dir.path(),
        &format!(
            "{base}displacement = 0.1\n\n[materials.c]\ntype = \"coated\"\nbase = \"base\"\n\n\
             {SHAPE}material = \"c\"\n"
        ),
    );
    assert!(
        e.contains(":29:") && e.contains("give it to the coated material"),
        "{e}"
    );
}

#[test]
fn misused_maps_are_refused_with_their_line() {
    let dir = tempfile::tempdir().unwrap();
    for (keys, line, says) in [
        (
            "displacement = \"heights\"\nnormal_map = \"normals\"",
            26,
            "not both",
        ),
        (
            "normal_map = \"colours\"",
            25,
            "give its texture `raw = true`",
        ),
        ("normal_map = \"checks\"", 25, "no image texture"),
        ("normal_map = \"nowhere\"", 25, "unknown texture `nowhere`"),
        (
            "displacement = \"nowhere\"",
            25,
            "unknown texture `nowhere`",
        ),
        ("displacement = [1, 2]", 25, ""),
    ] {
        let e = error(dir.path(),
            &format!(
                "[materials.m]\ntype = \"diffuse\"\nalbedo = 0.5\n{keys}\n\n{SHAPE}material = \"m\"\n"
            ),
        );
        assert!(
            e.contains(&format!("s.toml:{line}:")) && e.contains(says),
            "{keys}: {e}"
        );
    }
}

const PBRT_HEAD: &str = "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n\
                         PixelFilter \"box\"\nWorldBegin\n";
const QUAD: &str = "Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0] \
                    \"point2 uv\" [0 0 1 0 0 1] \"integer indices\" [0 1 2]\n";

fn load_pbrt(dir: &Path, body: &str) -> FlatScene {
    images(dir);
    let path = dir.join("s.pbrt");
    std::fs::write(&path, format!("{PBRT_HEAD}{body}")).unwrap();
    let scene = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let warnings = &scene.import.as_ref().expect("a pbrt import").warnings;
    assert!(warnings.is_empty(), "{warnings:?}");
    scene
}

#[test]
fn pbrt_displacement_and_normal_maps_import_without_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    // A float image texture as the height, on a coated diffuse.
    let scene = load_pbrt(
        dir.path(),
        &format!(
            "Texture \"h\" \"float\" \"imagemap\" \"string filename\" \"h.pfm\"\n\
             Material \"coateddiffuse\" \"texture displacement\" \"h\"\n{QUAD}"
        ),
    );
    let (m, _) = drawn(&scene);
    assert_eq!(m.kind(), material_kind::BUMP);
    assert!(m.has(material_flag::COLOR_TEXTURE));
    assert_eq!(
        scene.materials[m.k[0] as usize].kind(),
        material_kind::COATED_DIFFUSE
    );
    // A constant one.
    let scene = load_pbrt(
        dir.path(),
        &format!("Material \"diffuse\" \"float displacement\" 0.25\n{QUAD}"),
    );
    assert_eq!(drawn(&scene).0.color[0], 0.25);
    // A normal map file, read raw; pbrt ignores the displacement beside it, and so does strata.
    let scene = load_pbrt(
        dir.path(),
        &format!(
            "Material \"conductor\" \"string normalmap\" \"n.png\" \"float displacement\" 0.25\n\
             {QUAD}Material \"diffuse\" \"string normalmap\" \"n.png\"\n{QUAD}"
        ),
    );
    let (m, _) = drawn(&scene);
    assert_eq!(m.kind(), material_kind::NORMAL_MAP);
    let t = stratapt_scene::texture::record(&scene.tables, m.color[0] as u32);
    assert_eq!(
        t.tag >> 8 & 0xff,
        stratapt_scene::records::texel_format::LINEAR8
    );
    // Both materials read one texture of the file.
    assert_eq!(scene.textures, 1);
}

#[test]
fn alpha_cuts_out_a_shape_and_is_refused_where_it_cannot_apply() {
    use stratapt_scene::records::STATIC_TRIANGLE;
    let dir = tempfile::tempdir().unwrap();
    let material = "[materials.m]\ntype = \"diffuse\"\nalbedo = 0.5\n\n";
    let quad = "[[shapes]]\ntype = \"rectangle\"\ncorner = [0, 0, 0]\nedge_u = [1, 0, 0]\n\
                edge_v = [0, 1, 0]\nmaterial = \"m\"\n";
    for (alpha, flags) in [
        ("0.25", surface_flag::ALPHA),
        (
            "\"heights\"",
            surface_flag::ALPHA | surface_flag::ALPHA_TEXTURE,
        ),
        ("1", 0),
    ] {
        let scene = load_text(dir.path(), &format!("{material}{quad}alpha = {alpha}\n")).unwrap();
        let s = scene.geometry.surfaces[0];
        let cut = surface_flag::ALPHA | surface_flag::ALPHA_TEXTURE;
        assert_eq!(s.flags & cut, flags, "{alpha}");
        // A cut-out triangle is tested with its surface, never as a static one.
        let statics = scene
            .geometry
            .prims
            .iter()
            .filter(|p| p[3] & STATIC_TRIANGLE != 0);
        assert_eq!(statics.count() == 0, flags != 0, "{alpha}");
        let effects = Effects::of(&scene, &RenderSettings::default());
        assert_eq!(effects.alpha, flags != 0);
        assert_eq!(effects.textures, flags & surface_flag::ALPHA_TEXTURE != 0);
        if flags == surface_flag::ALPHA {
            assert_eq!(f32::from_bits(s.alpha), 0.25);
        }
    }
    for (text, line, says) in [
        (
            format!("{material}{quad}alpha = 1.5\n"),
            32,
            "a probability, in [0, 1]",
        ),
        (
            format!("{material}{quad}alpha = \"none\"\n"),
            32,
            "unknown texture `none`",
        ),
        (
            format!("{material}emission = 1\n\n{quad}alpha = 0.5\n"),
            34,
            "strata's lights are opaque",
        ),
    ] {
        let e = error(dir.path(), &text);
        assert!(
            e.contains(&format!("s.toml:{line}:")) && e.contains(says),
            "{text}: {e}"
        );
    }
}

#[test]
fn pbrt_alpha_imports_without_a_warning_except_on_a_light() {
    let dir = tempfile::tempdir().unwrap();
    let scene = load_pbrt(
        dir.path(),
        &format!(
            "Texture \"a\" \"float\" \"imagemap\" \"string filename\" \"h.pfm\"\n\
             Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0] \"point2 uv\" [0 0 1 0 0 1] \
             \"integer indices\" [0 1 2] \"texture alpha\" \"a\"\n\
             Shape \"sphere\" \"float alpha\" 0.5\n"
        ),
    );
    let flags: Vec<u32> = scene.geometry.surfaces.iter().map(|s| s.flags).collect();
    let cut = surface_flag::ALPHA | surface_flag::ALPHA_TEXTURE;
    assert!(flags.contains(&(flags[0] & !cut | cut)), "{flags:?}");
    assert!(
        flags.iter().any(|f| f & cut == surface_flag::ALPHA),
        "{flags:?}"
    );
    // On an area light: warned, drawn opaque.
    images(dir.path());
    let path = dir.path().join("s.pbrt");
    std::fs::write(
        &path,
        format!(
            "{PBRT_HEAD}AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n\
             Shape \"sphere\" \"float alpha\" 0.5\nAttributeEnd\n"
        ),
    )
    .unwrap();
    let scene = load(&path).unwrap();
    let warnings = &scene.import.as_ref().unwrap().warnings;
    assert!(
        warnings
            .iter()
            .any(|w| w.message.contains("alpha on an area light")),
        "{warnings:?}"
    );
    assert!(scene.geometry.surfaces.iter().all(|s| s.flags & cut == 0));
}
