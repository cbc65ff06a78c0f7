//! The pbrt-v4 twins of strata's own scenes (`scenes/pbrt/NAME.pbrt` beside `scenes/NAME.toml`)
//! render to the same image, sample for sample: the importer turns each into the same
//! primitives, materials, lights and camera as the TOML file. And `strata convert`'s output
//! (TOML + PLY meshes) renders to the imported scene's image bit for bit.

mod common;

use std::path::Path;
use stratapt::film::Film;
use stratapt::import::scene_file;
use stratapt::scene::{FlatScene, RenderSettings};

/// How alike a twin's image must be to its TOML scene's.
#[derive(Clone, Copy, PartialEq)]
enum Alike {
    /// Bit for bit.
    Bits,
    /// 90 % of the pixels within 10⁻⁶, the image means within 10⁻⁵.
    Close,
    /// The image means within 4.5 standard errors: a coated material's random walk draws its
    /// numbers from a hash of the directions, and a direction that differs in its last bit
    /// (a rotation computed in f32 against f64) draws other ones. Its records are compared.
    Statistically,
}

/// Every twin, by name: how alike its image is to the TOML scene's, and the warnings its import
/// gives (each a substring of one). The Cornell box's geometry is the TOML file's numbers; the
/// others place theirs with a rotation, which strata's TOML loader computes in f32 and the
/// importer in f64, so their vertices may differ in the last bit.
const TWINS: [(&str, Alike, &[&str]); 4] = [
    ("cornell-box", Alike::Bits, &[]),
    ("environment-octahedral", Alike::Statistically, &[]),
    ("sheets", Alike::Close, &[]),
    ("soft-shadow-area", Alike::Close, &[]),
];

fn load(path: &Path) -> FlatScene {
    let mut scene = scene_file::load(path).unwrap_or_else(|e| panic!("{e}"));
    (scene.camera.width, scene.camera.height) = (40, 40);
    scene
}

/// A small, quick render of `scene` on the CPU.
fn render(scene: &FlatScene) -> Film {
    let settings = RenderSettings {
        pattern_spp: 4,
        ..scene.settings
    };
    stratapt::cpu::render(scene, &settings, &|_| {}, None).0
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
    assert_eq!(found, TWINS.map(|t| t.0));
}

/// The two scenes hold the same material records, whatever their order and names: each record
/// of one (a coated material's base index aside) is one of the other's.
fn same_materials(name: &str, a: &FlatScene, b: &FlatScene) {
    let key = |m: &stratapt::scene::records::Material| {
        let mut m = *m;
        m.k[1] = 0.0;
        format!("{m:?}")
    };
    let mut ka: Vec<String> = a.materials.iter().map(key).collect();
    let mut kb: Vec<String> = b.materials.iter().map(key).collect();
    ka.sort();
    kb.sort();
    assert_eq!(ka, kb, "{name}: the material records differ");
}

#[test]
fn each_twin_renders_its_toml_scenes_image() {
    for (name, exact, expected) in TWINS {
        let pbrt = load(&Path::new("scenes/pbrt").join(format!("{name}.pbrt")));
        let toml = load(&Path::new("scenes").join(format!("{name}.toml")));
        let warnings = &pbrt.import.as_ref().unwrap().warnings;
        assert_eq!(warnings.len(), expected.len(), "{name}: {warnings:?}");
        for (w, e) in warnings.iter().zip(expected) {
            assert!(w.message.contains(e), "{name}: {w:?}");
        }
        assert_eq!(pbrt.settings, toml.settings, "{name}");
        assert_eq!(pbrt.lights.len(), toml.lights.len(), "{name}");
        assert_eq!(pbrt.geometry.len(), toml.geometry.len(), "{name}");
        let (a, b) = (render(&pbrt), render(&toml));
        let (pa, pb) = (pixels(&a), pixels(&b));
        let same = pa.iter().zip(&pb).filter(|(x, y)| x == y).count();
        // Pixels within a millionth of each other.
        let close = (0..pa.len())
            .filter(|&i| {
                let (x, y) = (a.mean(i), b.mean(i));
                (0..3).all(|c| (x[c] - y[c]).abs() <= 1e-6 * (1.0 + y[c].abs()))
            })
            .count();
        let (ma, mb) = (a.image_mean().0, b.image_mean().0);
        let worst = (0..3)
            .map(|c| (ma[c] / mb[c] - 1.0).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "{name}: {same} of {} pixels the same bits, {close} within 10⁻⁶; image means \
             {ma:?} vs {mb:?} ({worst:.2e})",
            pa.len()
        );
        if exact == Alike::Statistically {
            same_materials(name, &pbrt, &toml);
            let (sa, sb) = (a.image_mean().1, b.image_mean().1);
            for c in 0..3 {
                let z = (ma[c] - mb[c]) / (sa[c] * sa[c] + sb[c] * sb[c]).sqrt();
                assert!(z.abs() < 4.5, "{name}: image means {ma:?} vs {mb:?}, z {z}");
            }
        } else if exact == Alike::Bits {
            assert!(pa == pb, "{name}: the twin's image differs");
        } else {
            assert!(
                close * 10 >= pa.len() * 9,
                "{name}: {close} pixels of {} alike",
                pa.len()
            );
            assert!(worst < 1e-5, "{name}: image means {ma:?} vs {mb:?}");
        }
    }
}
