//! The pbrt-v4 twins of strata's own scenes (`scenes/pbrt/NAME.pbrt` beside `scenes/NAME.toml`)
//! render to the same image, sample for sample: the importer turns each into the same
//! primitives, materials, lights and camera as the TOML file. And `strata convert`'s output
//! (TOML + PLY meshes) renders to the imported scene's image bit for bit.

mod common;

use std::path::Path;
use stratapt::cpu::render_with_stats;
use stratapt::scene::{load, Film, FlatScene, RenderSettings};

/// Every twin, by name.
const TWINS: [&str; 1] = ["cornell-box"];

fn load(path: &Path) -> FlatScene {
    let mut scene = load::load(path).unwrap_or_else(|e| panic!("{e}"));
    (scene.camera.width, scene.camera.height) = (40, 40);
    scene
}

/// A small, quick render of `scene` on the CPU.
fn render(scene: &FlatScene) -> Film {
    let settings = RenderSettings {
        spp: 4,
        ..scene.settings
    };
    render_with_stats(scene, &settings, &|_| {}, None).0
}

/// Every pixel's mean, bit for bit.
fn pixels(film: &Film) -> Vec<[u64; 3]> {
    (0..film.width as usize * film.height as usize)
        .map(|i| film.mean(i).map(f64::to_bits))
        .collect()
}

#[test]
fn the_twins_list_every_pbrt_scene() {
    let mut found: Vec<String> = std::fs::read_dir("scenes/pbrt")
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "pbrt"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    found.sort();
    assert_eq!(found, TWINS);
}

#[test]
fn each_twin_renders_its_toml_scenes_image() {
    for name in TWINS {
        let pbrt = load(&Path::new("scenes/pbrt").join(format!("{name}.pbrt")));
        let toml = load(&Path::new("scenes").join(format!("{name}.toml")));
        let warnings = &pbrt.import.as_ref().unwrap().warnings;
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
        assert_eq!(pbrt.settings, toml.settings, "{name}");
        assert_eq!(pbrt.lights.len(), toml.lights.len(), "{name}");
        assert_eq!(pbrt.geometry.len(), toml.geometry.len(), "{name}");
        let (a, b) = (render(&pbrt), render(&toml));
        assert!(
            pixels(&a) == pixels(&b),
            "{name}: the twin's image differs (means {:?} vs {:?})",
            a.image_mean().0,
            b.image_mean().0
        );
    }
}
