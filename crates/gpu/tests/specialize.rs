//! Every specialization of the kernel parses, validates and translates, with no device: naga
//! substitutes each scene's override constants (for every strategy and both BVH layouts),
//! validates the result and writes the SPIR-V a Vulkan driver would get. A shader error in a
//! branch only some scene enables is caught here rather than on a user's GPU.

use std::path::{Path, PathBuf};
use stratapt_gpu::testing::{compose_modules as compose, kernel_modules, validate};
use stratapt_gpu::{BvhLayout, Renderer, Specialization};
use stratapt_scene::{FlatScene, RenderSettings, Strategy};

fn scene_files() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    stratapt_import::load::scene_files(&dir).unwrap()
}

/// Apply `constants` to the kernel, validate, and translate the `render` entry point to SPIR-V.
fn specialize(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
    constants: &[(&str, f64)],
) -> Result<usize, String> {
    let mut map = naga::back::PipelineConstants::default();
    for (name, value) in constants {
        map.insert(name.to_string(), *value);
    }
    let entry = Some((naga::ShaderStage::Compute, "render"));
    let (module, info) =
        naga::back::pipeline_constants::process_overrides(module, info, entry, &map)
            .map_err(|e| format!("overrides: {e}"))?;
    let options = naga::back::spv::Options::default();
    let pipeline = naga::back::spv::PipelineOptions {
        shader_stage: naga::ShaderStage::Compute,
        entry_point: "render".into(),
    };
    naga::back::spv::write_vec(&module, &info, &options, Some(&pipeline))
        .map(|words| words.len())
        .map_err(|e| format!("SPIR-V: {e}"))
}

#[test]
fn every_scene_specialization_validates_and_translates() {
    let source = compose(&kernel_modules(), "").unwrap_or_else(|e| panic!("{e}"));
    let module = validate(&source).unwrap_or_else(|e| panic!("{e}"));
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap();
    let mut seen = std::collections::HashSet::new();
    let mut words = Vec::new();
    for path in scene_files() {
        let scene = stratapt_import::scene_file::load(&path).unwrap_or_else(|e| panic!("{e}"));
        for strategy in Strategy::ALL {
            let settings = RenderSettings {
                strategy,
                ..scene.settings
            };
            for bvh in BvhLayout::ALL {
                for uniform_scene in [false, true] {
                    let spec = Specialization {
                        bvh,
                        uniform_scene,
                        ..Renderer::specialization(&scene, &settings)
                    };
                    if !seen.insert(spec) {
                        continue;
                    }
                    let size = specialize(&module, &info, &spec.constants()).unwrap_or_else(|e| {
                        panic!(
                            "{} / {strategy} / {bvh} / {uniform_scene}: {e}",
                            path.display()
                        )
                    });
                    words.push(size);
                }
            }
        }
    }
    // The unspecialized kernel (every override at its default: every effect on) too.
    specialize(&module, &info, &[]).unwrap_or_else(|e| panic!("defaults: {e}"));
    assert!(
        seen.len() >= 20,
        "only {} distinct specializations",
        seen.len()
    );
    for bvh in BvhLayout::ALL {
        assert!(seen.iter().any(|s| s.bvh == bvh), "no {bvh} specialization");
    }
    // naga substitutes the constants but leaves dead branches to the driver's compiler, so the
    // SPIR-V sizes barely differ; what a specialization saves is measured on a device.
    let (min, max) = (words.iter().min().unwrap(), words.iter().max().unwrap());
    println!("{} specializations, {min}..{max} SPIR-V words", seen.len());
}

/// The path depth is a run-time parameter: past the depths that switch paths and roulette on,
/// every depth shares one kernel (the specialization key does not hold it).
#[test]
fn depth_does_not_recompile() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml");
    let scene = stratapt_import::scene_file::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let at = |max_depth| {
        Renderer::specialization(
            &scene,
            &RenderSettings {
                max_depth,
                ..scene.settings
            },
        )
    };
    assert_eq!(at(5), at(8));
    assert_eq!(at(8), at(64));
    // Direct light only has no path dimensions, so it is its own kernel.
    assert_ne!(at(1), at(8));
}

/// Each module's `// needs:` line names every dependency: each module composes (and validates)
/// alone with what its line resolves to, and the kernel is built from every module.
#[test]
fn every_module_composes_with_its_declared_dependencies() {
    use stratapt_gpu::testing::MODULES;
    for module in MODULES {
        compose(&[module.stem], "").unwrap_or_else(|e| panic!("{}: {e}", module.stem));
    }
    let kernel = kernel_modules();
    // `scene.wgsl` goes into every composition without being named.
    let all: Vec<&str> = MODULES
        .iter()
        .map(|m| m.stem)
        .filter(|s| *s != "scene")
        .collect();
    assert_eq!(
        kernel, all,
        "a module of shaders/ the kernel does not reach"
    );
    // The check is not vacuous: a dependency left out is a validation error.
    let intersect = MODULES.iter().find(|m| m.stem == "intersect").unwrap();
    assert!(intersect.needs().unwrap().contains(&"motion"));
    let alone = format!(
        "{}{}",
        stratapt_gpu::testing::compose_modules(&[], "").unwrap(),
        intersect.source
    );
    assert!(
        validate(&alone).is_err(),
        "intersect.wgsl validated without motion.wgsl"
    );
}

/// The modules' needs form no cycle: the composition order lists each module after every module
/// it needs. Every file of `shaders/` is a module or a part composed into one (`bsdf_layered`
/// into `bsdf`), and each names only modules that exist.
#[test]
fn module_needs_are_one_way() {
    use stratapt_gpu::testing::MODULES;
    let position = |stem: &str| MODULES.iter().position(|m| m.stem == stem);
    for (i, module) in MODULES.iter().enumerate() {
        for need in module.needs().unwrap_or_else(|e| panic!("{e}")) {
            let at =
                position(need).unwrap_or_else(|| panic!("{}: no module `{need}`", module.stem));
            assert!(
                at < i,
                "{} needs {need}, which is not before it: a cycle, or the order is wrong",
                module.stem
            );
        }
    }
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.unwrap().file_name().into_string().ok())
        .filter_map(|name| name.strip_suffix(".wgsl").map(String::from))
        .collect();
    files.sort();
    // A replacement (a kernel variant's module in place of one of them) needs only modules
    // that come before the one it replaces.
    for (module, replaced) in stratapt_gpu::testing::REPLACEMENTS {
        let at = position(replaced).unwrap_or_else(|| panic!("no module `{replaced}`"));
        for need in module.needs().unwrap_or_else(|e| panic!("{e}")) {
            assert!(
                position(need).is_some_and(|p| p < at),
                "{} needs {need}",
                module.stem
            );
        }
    }
    let mut stems: Vec<String> = MODULES
        .iter()
        .map(|m| m.stem)
        .chain(
            stratapt_gpu::testing::REPLACEMENTS
                .iter()
                .map(|(m, _)| m.stem),
        )
        .map(String::from)
        .collect();
    stems.sort();
    // A part is a file whose text a module's source holds.
    files.retain(|file| {
        let path = dir.join(format!("{file}.wgsl"));
        let text = std::fs::read_to_string(path).unwrap();
        stems.contains(file) || !MODULES.iter().any(|m| m.source.contains(&text))
    });
    assert_eq!(files, stems, "shaders/ and the module list differ");
    // A module without its needs line is refused, naming the file.
    let bare = stratapt_gpu::testing::ShaderModule {
        stem: "bare",
        source: "fn bare_f() {}\n",
    };
    let e = bare.needs().unwrap_err().to_string();
    assert!(
        e.contains("shaders/bare.wgsl") && e.contains("// needs:"),
        "{e}"
    );
}

/// The ray-query kernel composes and validates (naga, no device): `enable wgpu_ray_query;`
/// first, `accel_ray_query.wgsl` in place of `accel.wgsl`, and nothing else changed.
#[test]
fn the_ray_query_kernel_validates() {
    let source = stratapt_gpu::testing::ray_query_kernel(1024).unwrap_or_else(|e| panic!("{e}"));
    assert!(source.starts_with("enable wgpu_ray_query;"));
    assert!(source.contains("// ==== shaders/accel_ray_query.wgsl ===="));
    assert!(!source.contains("// ==== shaders/accel.wgsl ===="));
    assert!(source.contains("fn accel_closest_hit(") && source.contains("rayQueryInitialize"));
}

/// The kernel size `strata info` reports follows the effects: every scene's specialized kernel
/// is smaller than the generic one, and taking roulette away (depth 3) or adding a lens makes
/// the Cornell box's kernel smaller or larger.
#[test]
fn kernel_size_follows_the_effects() {
    use stratapt_gpu::Kernel;
    let mut generic = None;
    for path in scene_files() {
        let scene = stratapt_import::scene_file::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let spec = Renderer::specialization(&scene, &scene.settings);
        let size = spec.kernel_size().unwrap().operations;
        let all = *generic.get_or_insert_with(|| {
            spec.for_kernel(Kernel::Generic)
                .kernel_size()
                .unwrap()
                .operations
        });
        assert!(size < all, "{}: {size} ≥ generic {all}", path.display());
    }
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml");
    let mut scene = stratapt_import::scene_file::load(&path).unwrap();
    let size = |scene: &FlatScene, max_depth| {
        let settings = RenderSettings {
            max_depth,
            ..scene.settings
        };
        let spec = Renderer::specialization(scene, &settings);
        spec.kernel_size().unwrap().operations
    };
    let base = size(&scene, 8);
    assert!(size(&scene, 3) < base, "no roulette, no smaller");
    scene.camera.lens_radius = 1.0;
    assert!(size(&scene, 8) > base, "a lens, no larger");
}
