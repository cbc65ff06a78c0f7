//! The specialized kernel and the generic one compute the same estimator: every scene renders to
//! the same image with either (same samples, so equal up to float rounding); the constants a
//! scene hands to the pipeline are the effects it calls for (a table written from the scene
//! files, not from `Effects::of`); and adding what a scene does not use changes neither its
//! kernel nor its image. On lavapipe.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use stratapt_film::{Film, Render};
use stratapt_gpu::{testing::software_device, Kernel, Renderer, Runtime, Specialization};
use stratapt_scene::{FlatScene, RenderSettings};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// Renderers share compiled kernels within this test binary.
fn renderer(kernel: Kernel) -> &'static Renderer {
    static RENDERERS: OnceLock<(Renderer, Renderer)> = OnceLock::new();
    let (specialized, generic) = RENDERERS.get_or_init(|| {
        let (device, queue) = software_device().unwrap_or_else(|e| panic!("{e}"));
        let make = |kernel| {
            Renderer::new(&device, &queue)
                .map(with_cpu_twins)
                .unwrap_or_else(|e| panic!("{e}"))
                .with_kernel(kernel)
        };
        (make(Kernel::Specialized), make(Kernel::Generic))
    });
    match kernel {
        Kernel::Generic => generic,
        _ => specialized,
    }
}

/// `scene` at 32 pixels on its long side (aspect kept).
fn small(mut scene: FlatScene) -> FlatScene {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let side = |s: u32| ((s * 32) as f64 / w.max(h) as f64).round().max(1.0) as u32;
    (scene.camera.width, scene.camera.height) = (side(w), side(h));
    scene
}

fn settings(scene: &FlatScene) -> RenderSettings {
    RenderSettings {
        pattern_spp: 4,
        max_depth: scene.settings.max_depth.min(6),
        ..scene.settings
    }
}

fn render(kernel: Kernel, scene: &FlatScene, settings: &RenderSettings) -> Film {
    renderer(kernel)
        .render(scene, settings, &|_| {}, None)
        .unwrap_or_else(|e| panic!("{kernel:?}: {e}"))
        .0
}

/// Fraction of pixels whose three channel means agree within `rel` (relative), and the largest
/// relative difference of the image means' channels.
fn closeness(a: &Film, b: &Film, rel: f64) -> (f64, f64) {
    let n = a.sum.len();
    let close = (0..n)
        .filter(|&i| {
            let (ma, mb) = (a.mean(i), b.mean(i));
            (0..3).all(|c| (ma[c] - mb[c]).abs() <= rel * ma[c].abs().max(mb[c].abs()))
        })
        .count();
    let (ma, mb) = (a.image_mean().0, b.image_mean().0);
    let mean_diff = (0..3)
        .map(|c| (ma[c] - mb[c]).abs() / ma[c].abs().max(mb[c].abs()).max(1e-30))
        .fold(0.0, f64::max);
    (close as f64 / n as f64, mean_diff)
}

/// Every scene: the generic kernel's image equals the specialized one's. Measured (32 px, 4 spp,
/// lavapipe, Mesa 25.0.7): 100 % of pixels within 1e-6 relative in every scene, image means
/// identical except depth-of-field's (2.3e-9 apart: the driver rounds a lens sample's
/// arithmetic differently once the lens is a run-time branch). The floors leave room for
/// rounding on other drivers only: one wrong dimension or effect decision changes most pixels
/// (`a_wrong_runtime_layout_is_caught`).
#[test]
fn generic_kernel_renders_the_same_images() {
    let mut report = Vec::new();
    let mut failures = Vec::new();
    for path in stratapt_import::load::scene_files(&scenes_dir()).unwrap() {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let scene =
            small(stratapt_import::scene_file::load(&path).unwrap_or_else(|e| panic!("{e}")));
        let settings = settings(&scene);
        let specialized = render(Kernel::Specialized, &scene, &settings);
        let generic = render(Kernel::Generic, &scene, &settings);
        let (fraction, mean_diff) = closeness(&specialized, &generic, 1e-6);
        report.push(format!(
            "{name}: {:.2} % of pixels bit-close, image means {mean_diff:.1e} apart",
            100.0 * fraction
        ));
        if fraction < 0.995 || mean_diff > 1e-6 {
            failures.push(name);
        }
    }
    eprintln!("{}", report.join("\n"));
    assert!(failures.is_empty(), "generic ≠ specialized: {failures:?}");
}

/// The planted error: a generic kernel given another scene's dimension layout (lens and time
/// dimensions the Cornell box does not have) renders a different image, and the check above
/// rejects it.
#[test]
fn a_wrong_runtime_layout_is_caught() {
    let scene =
        small(stratapt_import::scene_file::load(&scenes_dir().join("cornell-box.toml")).unwrap());
    let settings = settings(&scene);
    let specialized = render(Kernel::Specialized, &scene, &settings);
    // A thin lens of zero radius adds the lens domain (2 dimensions) to the effects without
    // changing the camera: every later dimension shifts.
    let mut shifted =
        small(stratapt_import::scene_file::load(&scenes_dir().join("cornell-box.toml")).unwrap());
    shifted.camera.lens_radius = f32::MIN_POSITIVE;
    let other = render(Kernel::Generic, &shifted, &settings);
    let (fraction, _) = closeness(&specialized, &other, 1e-6);
    assert!(fraction < 0.5, "{:.1} % still bit-close", 100.0 * fraction);
}

/// A scene's name, whether it has a lens, time and object motion, its light and material kinds.
type Expected = (
    &'static str,
    bool,
    bool,
    bool,
    &'static [&'static str],
    &'static [&'static str],
);

/// What each bundled scene calls for, from reading its file.
const EXPECTED: &[Expected] = &[
    (
        "coated",
        false,
        false,
        false,
        &["rectangle", "sky"],
        &[
            "diffuse",
            "complex-conductor",
            "coated-diffuse",
            "coated-conductor",
        ],
    ),
    (
        "cornell-box",
        false,
        false,
        false,
        &["rectangle"],
        &["diffuse"],
    ),
    (
        "depth-of-field",
        true,
        false,
        false,
        &["rectangle", "sky"],
        &["diffuse", "conductor"],
    ),
    (
        "detail",
        false,
        false,
        false,
        &["rectangle", "sky"],
        &[
            "diffuse",
            "complex-conductor",
            "plastic",
            "rough-plastic",
            "mix",
            "bump",
            "normal-map",
        ],
    ),
    (
        "environment",
        false,
        false,
        false,
        &["environment"],
        &["diffuse", "complex-conductor", "rough-plastic"],
    ),
    (
        "environment-octahedral",
        false,
        false,
        false,
        &["octahedral-environment"],
        &["diffuse", "complex-conductor", "coated-diffuse"],
    ),
    (
        "glass",
        false,
        false,
        false,
        &["disk", "sky"],
        &["diffuse", "dielectric"],
    ),
    (
        "mesh",
        false,
        false,
        false,
        &["triangle", "sky"],
        &["diffuse", "conductor"],
    ),
    (
        "metals",
        false,
        false,
        false,
        &["rectangle", "sky"],
        &["diffuse", "complex-conductor"],
    ),
    (
        "mix",
        false,
        false,
        false,
        &["rectangle", "sky"],
        &["diffuse", "dielectric", "complex-conductor", "mix"],
    ),
    (
        "motion-blur-camera",
        false,
        true,
        false,
        &["rectangle", "sky"],
        &["diffuse"],
    ),
    (
        "motion-blur-object",
        false,
        true,
        true,
        &["rectangle", "sky"],
        &["diffuse"],
    ),
    (
        "plastics",
        false,
        false,
        false,
        &["rectangle", "sky"],
        &["diffuse", "plastic", "rough-plastic"],
    ),
    (
        "rough-glass",
        false,
        false,
        false,
        &["rectangle", "sky"],
        &["diffuse", "rough-dielectric"],
    ),
    (
        "sheets",
        false,
        false,
        false,
        &["rectangle", "sphere"],
        &["diffuse", "thin-dielectric", "diffuse-transmission"],
    ),
    (
        "soft-shadow-area",
        false,
        false,
        false,
        &["rectangle"],
        &["diffuse"],
    ),
    (
        "soft-shadow-line",
        false,
        false,
        false,
        &["line", "sky"],
        &["diffuse"],
    ),
    (
        "soft-shadow-sun",
        false,
        false,
        false,
        &["distant", "sky"],
        &["diffuse"],
    ),
    (
        "textures",
        false,
        false,
        false,
        &["rectangle", "sky"],
        &["diffuse", "complex-conductor", "rough-plastic"],
    ),
    (
        "veach-mis",
        false,
        false,
        false,
        &["sphere"],
        &["diffuse", "conductor"],
    ),
];

fn constant(spec: &Specialization, name: &str) -> f64 {
    spec.constants()
        .iter()
        .find(|(n, _)| *n == name)
        .unwrap_or_else(|| panic!("no constant {name}"))
        .1
}

fn mask(names: &[&str], all: &[&str]) -> f64 {
    names
        .iter()
        .map(|n| 1u32 << all.iter().position(|a| a == n).expect("kind name"))
        .fold(0, |a, b| a | b) as f64
}

#[test]
fn pipeline_constants_are_the_scenes_effects() {
    use stratapt_scene::effects::{LIGHT_KIND_NAMES, MATERIAL_KIND_NAMES};
    let files = stratapt_import::load::scene_files(&scenes_dir()).unwrap();
    assert_eq!(files.len(), EXPECTED.len(), "add new scenes to EXPECTED");
    for &(name, lens, time, motion, lights, materials) in EXPECTED {
        let scene =
            stratapt_import::scene_file::load(&scenes_dir().join(format!("{name}.toml"))).unwrap();
        let spec = Renderer::specialization(&scene, &scene.settings);
        let flag = |b: bool| if b { 1.0 } else { 0.0 };
        let want = [
            ("HAS_LENS", flag(lens)),
            ("HAS_TIME", flag(time)),
            ("HAS_MOTION", flag(motion)),
            // Only the scenes that read textures compile their lookups (mix.toml's amount,
            // detail.toml's maps), and only detail.toml its alpha tests.
            (
                "HAS_TEXTURES",
                flag(["textures", "mix", "detail"].contains(&name)),
            ),
            ("HAS_ALPHA", flag(name == "detail")),
            ("LIGHT_KINDS", mask(lights, &LIGHT_KIND_NAMES)),
            ("MATERIAL_KINDS", mask(materials, &MATERIAL_KIND_NAMES)),
            (
                "HAS_LOBE",
                // Two-lobed materials: dielectrics, plastics, diffuse transmission, coats.
                flag(materials.iter().any(|m| {
                    ["dielectric", "plastic", "transmission", "coated"]
                        .iter()
                        .any(|k| m.contains(k))
                })),
            ),
            ("RUNTIME_EFFECTS", 0.0),
            ("RUNTIME_LIGHT_KINDS", 0.0),
            ("RUNTIME_MATERIAL_KINDS", 0.0),
            ("RUNTIME_DIMS", 0.0),
        ];
        for (constant_name, value) in want {
            assert_eq!(
                constant(&spec, constant_name),
                value,
                "{name}: {constant_name}"
            );
        }
        // An absent domain has no dimension (and says so with NONE).
        let none = u32::MAX as f64;
        assert_eq!(
            constant(&spec, "DIM_LENS") == none,
            !lens,
            "{name}: DIM_LENS"
        );
        assert_eq!(
            constant(&spec, "DIM_TIME") == none,
            !time,
            "{name}: DIM_TIME"
        );
        // The generic kernel is one kernel: the same constants whatever the scene.
        let generic = spec.for_kernel(Kernel::Generic);
        assert_eq!(generic.runtime, Runtime::ALL);
        let cornell =
            stratapt_import::scene_file::load(&scenes_dir().join("cornell-box.toml")).unwrap();
        assert_eq!(
            generic,
            Renderer::specialization(&cornell, &cornell.settings).for_kernel(Kernel::Generic),
            "{name}: the generic kernel's key depends on the scene"
        );
    }
}

/// The Cornell box with what it does not use added: a line light of zero intensity, an open
/// shutter with nothing moving, a zero aperture, a material no shape uses. Same kernel, same
/// image, sample for sample.
#[test]
fn unused_additions_change_nothing() {
    let path = scenes_dir().join("cornell-box.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let base = small(stratapt_import::scene_file::load(&path).unwrap());
    let settings = settings(&base);
    let film = render(Kernel::Specialized, &base, &settings);
    let key = renderer(Kernel::Specialized).specialize(&base, &settings);
    let variants = [
        (
            "a zero-intensity line light",
            format!(
                "{text}\n[[lights]]\ntype = \"line\"\nfrom = [100, 500, 100]\nto = [400, 500, \
                 100]\nintensity = 0\n"
            ),
        ),
        (
            "an open shutter, nothing moving",
            text.replace("fov = 39.3077", "fov = 39.3077\nshutter = [0, 1]"),
        ),
        (
            "a zero aperture",
            text.replace(
                "fov = 39.3077",
                "fov = 39.3077\naperture = 0\nfocus_distance = 800",
            ),
        ),
        (
            "an unused conductor",
            format!("{text}\n[materials.unused]\ntype = \"conductor\"\nreflectance = 0.9\nroughness = 0.1\n"),
        ),
    ];
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("unused-additions");
    std::fs::create_dir_all(&dir).unwrap();
    for (i, (what, toml)) in variants.iter().enumerate() {
        assert_ne!(toml, &text, "{what}: the edit did not apply");
        let file = dir.join(format!("variant-{i}.toml"));
        std::fs::write(&file, toml).unwrap();
        let scene = small(
            stratapt_import::scene_file::load(&file).unwrap_or_else(|e| panic!("{what}: {e}")),
        );
        assert_eq!(
            renderer(Kernel::Specialized).specialize(&scene, &settings),
            key,
            "{what}: another kernel"
        );
        let other = render(Kernel::Specialized, &scene, &settings);
        assert_eq!(other.sum, film.sum, "{what}: another image");
    }
}

/// `renderer` with its films' peak twins rendered by the CPU reference, as the `strata` command
/// builds it.
fn with_cpu_twins(renderer: Renderer) -> Renderer {
    renderer.with_peak_twins(std::sync::Arc::new(stratapt_cpu::render_peak_twins))
}
