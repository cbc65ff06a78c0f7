//! Every scene in `scenes/`, rendered tiny (16×16, 4 spp) with every strategy: no sample is
//! NaN or infinite and no pixel is negative.

use std::path::Path;
use stratapt::cpu::render;
use stratapt::film::Render;
use stratapt::import::scene_file::load;
use stratapt::scene::{RenderSettings, Strategy};

#[test]
fn every_scene_renders_finite_non_negative_samples() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let paths = stratapt::import::load::scene_files(&dir).expect("scenes/ directory");
    assert!(!paths.is_empty(), "no scenes in {}", dir.display());
    for path in paths {
        let mut scene = load(&path).unwrap_or_else(|e| panic!("{e}"));
        scene.camera.width = 16;
        scene.camera.height = 16;
        for strategy in Strategy::ALL {
            let settings = RenderSettings {
                pattern_spp: 4,
                strategy,
                ..scene.settings
            };
            let (film, stats) = render(&scene, &settings, &|_| {}, None);
            let name = format!("{} / {strategy}", path.display());
            assert_eq!(stats.non_finite, 0, "{name}: non-finite samples");
            assert!(!film.has_non_finite(), "{name}: non-finite film");
            assert_eq!(film.held_spp(), 4, "{name}");
            assert!(
                film.sum.iter().flatten().all(|&v| v >= 0.0),
                "{name}: negative radiance"
            );
        }
    }
}

/// The non-finite counter counts: a scene whose light emits NaN (a value the loader would
/// refuse, planted in the flattened scene) makes both renderers count non-finite samples,
/// replace them by zero, and leave a finite image.
#[test]
fn a_planted_nan_is_counted_and_kept_out_of_the_image() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box.toml");
    let mut scene = load(&path).unwrap_or_else(|e| panic!("{e}"));
    (scene.camera.width, scene.camera.height) = (16, 16);
    for light in &mut scene.lights {
        light.radiance = [f32::NAN; 3];
    }
    for material in &mut scene.materials {
        if material.emission.iter().any(|&e| e > 0.0) {
            material.emission = [f32::NAN; 3];
        }
    }
    let settings = RenderSettings {
        pattern_spp: 4,
        ..scene.settings
    };
    let (device, queue) =
        stratapt::gpu::testing::software_device().unwrap_or_else(|e| panic!("{e}"));
    let gpu = stratapt::gpu_renderer(&device, &queue).unwrap();
    let (cpu_film, cpu) = render(&scene, &settings, &|_| {}, None);
    let (gpu_film, gpu) = gpu.render(&scene, &settings, &|_| {}, None).unwrap();
    for (name, film, stats) in [("CPU", &cpu_film, cpu), ("GPU", &gpu_film, gpu)] {
        assert!(stats.non_finite > 0, "{name}: no non-finite sample counted");
        // Out of the film's samples and its twins' (which take the same number each).
        let taken = stats.samples + film.twin_sum.len() as u64 * settings.pattern_spp as u64;
        assert!(
            stats.non_finite <= taken,
            "{name}: {} of {taken}",
            stats.non_finite
        );
        assert!(!film.has_non_finite(), "{name}: a NaN reached the image");
        let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("planted-nan-{name}.exr"));
        film.write(&out).unwrap();
        let written = exr::prelude::read_all_data_from_file(&out).unwrap();
        for layer in &written.layer_data {
            for channel in &layer.channel_data.list {
                let finite =
                    channel
                        .sample_data
                        .levels_as_slice()
                        .iter()
                        .all(|level| match level {
                            exr::prelude::FlatSamples::F32(v) => v.iter().all(|x| x.is_finite()),
                            exr::prelude::FlatSamples::F16(v) => {
                                v.iter().all(|x| x.to_f32().is_finite())
                            }
                            exr::prelude::FlatSamples::U32(_) => true,
                        });
                assert!(
                    finite,
                    "{name}: channel {} of the EXR is not finite",
                    channel.name
                );
            }
        }
    }
    // Same samples, same decisions: both count the same samples.
    assert_eq!(cpu.non_finite, gpu.non_finite);
}
