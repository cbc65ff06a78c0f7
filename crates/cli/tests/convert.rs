//! pbrt-v4 scenes through the `strata` binary: `convert` writes a scene that renders to the
//! imported scene's image bit for bit, and writes nothing for a scene it cannot import; every
//! command shows the import's warnings, `info` lists them all, and `--strict` refuses them.

mod common;

use common::{scene_file, strata};
use std::path::Path;
use stratapt_film::Film;
use stratapt_import::scene_file;
use stratapt_scene::{FlatScene, RenderSettings};

/// Meshes with normals and texture coordinates under a rotation and a non-uniform scale, an
/// image texture, a sphere light and a point light: what `convert` must carry over exactly.
const SCENE: &str = r#"
Scale -1 1 1
LookAt 0 1 -4  0 0.5 0  0 1 0
Camera "perspective" "float fov" 45
Film "rgb" "integer xresolution" 24 "integer yresolution" 16
PixelFilter "box"
Sampler "independent" "integer pixelsamples" 2
Integrator "path" "integer maxdepth" 3
WorldBegin
Texture "grid" "spectrum" "imagemap" "string filename" "grid.png" "float uscale" 2
MakeNamedMaterial "floor" "string type" "diffuse" "texture reflectance" "grid"
MakeNamedMaterial "gold" "string type" "conductor"
  "spectrum eta" "metal-Au-eta" "spectrum k" "metal-Au-k" "float roughness" 0.05
AttributeBegin
  NamedMaterial "floor"
  Rotate 10 0 1 0
  Scale 3 1 2
  Shape "trianglemesh" "point3 P" [-1 0 -1  1 0 -1  1 0 1  -1 0 1]
    "integer indices" [0 2 1  0 3 2] "normal N" [0 1 0  0 1 0  0 1 0  0 1 0]
    "point2 uv" [0 0  1 0  1 1  0 1]
AttributeEnd
AttributeBegin
  NamedMaterial "gold"
  Translate 0.3 0.5 0.2
  Shape "sphere" "float radius" 0.5
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "blackbody L" 5000 "float scale" 4
  Translate -1 2.5 0
  Shape "sphere" "float radius" 0.3
AttributeEnd
LightSource "point" "point3 from" [1 2 -1] "rgb I" [2 2 2]
"#;

/// A 4×4 RGB PNG, each texel different.
fn write_grid(dir: &Path) {
    let img = image::RgbImage::from_fn(4, 4, |x, y| image::Rgb([60 * x as u8, 60 * y as u8, 90]));
    img.save(dir.join("grid.png")).unwrap();
}

fn render(scene: &FlatScene) -> Film {
    let settings = RenderSettings {
        pattern_spp: 2,
        ..scene.settings
    };
    stratapt_cpu::render(scene, &settings, &|_| {}, None).0
}

fn bits(film: &Film) -> Vec<[u64; 3]> {
    (0..(film.width * film.height) as usize)
        .map(|i| film.mean(i).map(f64::to_bits))
        .collect()
}

#[test]
fn converted_scenes_render_the_imported_image_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    write_grid(dir.path());
    let pbrt = scene_file(dir.path(), "scene.pbrt", SCENE);
    std::fs::create_dir(dir.path().join("out")).unwrap();
    let out = strata(
        dir.path(),
        &["convert", "scene.pbrt", "-o", "out/scene.toml"],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.is_empty(), "no warnings expected: {stderr}");
    let toml = dir.path().join("out/scene.toml");
    let meshes = dir.path().join("out/scene-meshes");
    assert_eq!(std::fs::read_dir(&meshes).unwrap().count(), 1, "the floor");
    // The texture's path is rewritten relative to the converted scene.
    let text = std::fs::read_to_string(&toml).unwrap();
    assert!(text.contains("file = \"../grid.png\""), "{text}");

    let imported = scene_file::load(&pbrt).unwrap();
    let converted = scene_file::load(&toml).unwrap();
    assert!(imported.import.is_some() && converted.import.is_none());
    assert_eq!(imported.geometry.points, converted.geometry.points);
    assert_eq!(imported.geometry.normals, converted.geometry.normals);
    assert_eq!(imported.geometry.uvs, converted.geometry.uvs);
    assert!(bits(&render(&imported)) == bits(&render(&converted)));
}

#[test]
fn convert_writes_nothing_for_a_scene_it_cannot_import() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "WorldBegin\nShape \"sphere\" \"float radius\" [1 2\n",
            "scene.pbrt:2:31: `radius`'s `[` is never closed",
        ),
        (
            "WorldBegin\nNamedMaterial \"nowhere\"\nShape \"sphere\"\n",
            "scene.pbrt:2:1: no material named `nowhere`",
        ),
        (
            "WorldBegin\nShape \"plymesh\" \"string filename\" \"missing.ply\"\n",
            "scene.pbrt:2:1: plymesh",
        ),
        (
            "WorldBegin\nLightSource \"infinite\" \"string filename\" \"missing.exr\"\n",
            "missing.exr",
        ),
        (
            "WorldBegin\nTexture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"gone.png\"\n",
            "scene.pbrt:2:35: no file `gone.png`",
        ),
        (
            "WorldBegin\nMakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [\"m\" \"m\"]\n\
             NamedMaterial \"m\"\nShape \"sphere\"\n",
            "scene.pbrt:2:1: Material \"mix\": `m` leads back through 16 mixes",
        ),
    ];
    for (text, error) in cases {
        scene_file(dir.path(), "scene.pbrt", text);
        let out = strata(dir.path(), &["convert", "scene.pbrt", "-o", "scene.toml"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{text}");
        assert!(
            stderr.contains(error),
            "{text}: expected `{error}` in {stderr}"
        );
        let mut left: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(left, ["scene.pbrt"], "{text}");
    }
}

#[test]
fn warnings_are_shown_listed_and_refused_under_strict() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(
        dir.path(),
        "scene.pbrt",
        "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\nPixelFilter \"box\"\n\
         WorldBegin\nLightSource \"point\" \"point3 from\" [0 0 -1]\nShape \"cylinder\"\n\
         Shape \"sphere\" \"float radius\" 1 \"float radious\" 0.5\n",
    );
    let cylinder = "scene.pbrt:5:1: Shape \"cylinder\": not drawn: strata has no cylinder shape";
    let alpha = "scene.pbrt:6:33: Shape \"sphere\": parameter \"float radious\" ignored";

    let out = strata(
        dir.path(),
        &["render", "scene.pbrt", "--device", "cpu", "--spp", "1"],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains(&format!("warning: {cylinder}")), "{stderr}");
    assert!(dir.path().join("scene.exr").exists());

    let out = strata(dir.path(), &["info", "scene.pbrt"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("warnings   2"), "{stdout}");
    assert!(
        stdout.contains(cylinder) && stdout.contains(alpha),
        "{stdout}"
    );
    assert!(stdout.contains("imported   pbrt-v4: 1 shapes"), "{stdout}");

    std::fs::remove_file(dir.path().join("scene.exr")).unwrap();
    std::fs::remove_file(dir.path().join("scene.png")).unwrap();
    for command in ["render", "info", "convert"] {
        let mut args = vec![command, "scene.pbrt", "--strict"];
        if command == "convert" {
            args.extend(["-o", "scene.toml"]);
        }
        let out = strata(dir.path(), &args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{command} --strict");
        assert!(
            stderr.contains("--strict, and the import has 2 warnings")
                && stderr.contains(cylinder)
                && stderr.contains(alpha),
            "{command}: {stderr}"
        );
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            1,
            "{command}"
        );
    }
}

#[test]
fn convert_writes_any_scene_as_mitsuba_xml_with_its_files_and_nothing_on_error() {
    let dir = tempfile::tempdir().unwrap();
    write_grid(dir.path());
    scene_file(dir.path(), "scene.pbrt", SCENE);
    // A pbrt-v4 scene and a strata scene, each into an XML file and its folder.
    let out = strata(
        dir.path(),
        &["convert", "scene.pbrt", "-o", "out/scene.xml"],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let xml = std::fs::read_to_string(dir.path().join("out/scene.xml")).unwrap();
    for name in ["mesh0.ply", "texture0.pfm"] {
        let file = format!("scene-mitsuba/{name}");
        assert!(
            xml.contains(&format!("\"{file}\"")),
            "{name} not named in\n{xml}"
        );
        assert!(
            dir.path().join("out").join(&file).is_file(),
            "{file} not written"
        );
    }
    assert!(xml.contains("<emitter type=\"point\">") && xml.contains("<shape type=\"sphere\">"));
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/soft-shadow-line.toml");
    let out = strata(
        dir.path(),
        &["convert", root.to_str().unwrap(), "-o", "line.xml"],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("warning: Mitsuba: line light"), "{stderr}");
    // Writing again replaces the folder; a scene that does not load writes nothing; nor does an
    // output of another kind.
    let again = strata(
        dir.path(),
        &["convert", "scene.pbrt", "-o", "out/scene.xml"],
    );
    assert!(again.status.success());
    let before: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    scene_file(
        dir.path(),
        "bad.pbrt",
        "WorldBegin\nNamedMaterial \"nowhere\"\nShape \"sphere\"\n",
    );
    for (args, error) in [
        (
            ["convert", "bad.pbrt", "-o", "bad.xml"],
            "bad.pbrt:2:1: no material named `nowhere`",
        ),
        (
            ["convert", "scene.pbrt", "-o", "scene.obj"],
            "a .toml file (strata's format) or a .xml file",
        ),
    ] {
        let out = strata(dir.path(), &args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && stderr.contains(error),
            "{args:?}: {stderr}"
        );
    }
    let mut after: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    after.retain(|n| n != "bad.pbrt");
    assert_eq!(before.len(), after.len(), "{after:?}");
}

#[test]
fn a_convert_that_fails_at_its_last_step_puts_the_earlier_files_back() {
    let dir = tempfile::tempdir().unwrap();
    let cb = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml");
    let cb = cb.to_str().unwrap();
    let out = strata(dir.path(), &["convert", cb, "-o", "out/scene.xml"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let files = |d: &str| {
        let mut names: Vec<String> = std::fs::read_dir(dir.path().join(d))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    };
    let meshes = files("out/scene-mitsuba");
    // The XML file cannot be replaced (a folder stands in its place): the new folder of meshes
    // is rolled back, the earlier one put back, and nothing temporary is left.
    std::fs::remove_file(dir.path().join("out/scene.xml")).unwrap();
    std::fs::create_dir(dir.path().join("out/scene.xml")).unwrap();
    std::fs::write(dir.path().join("out/scene.xml/keep"), "").unwrap();
    let out = strata(dir.path(), &["convert", cb, "-o", "out/scene.xml"]);
    assert!(!out.status.success());
    assert_eq!(files("out"), ["scene-mitsuba", "scene.xml"]);
    assert_eq!(files("out/scene-mitsuba"), meshes);
}
