//! The probe harness itself: a probe reads its input and the uploaded scene and writes back.

use std::path::Path;
use stratapt_gpu::testing::{run_probe, software_device};

#[test]
fn probe_reads_input_params_and_scene() {
    let (device, queue) = software_device().unwrap_or_else(|e| panic!("{e}"));
    let scene =
        stratapt_import::scene_file::load(Path::new("../../scenes/cornell-box.toml")).unwrap();
    let settings = scene.settings;
    let probe = r#"
fn probe(i: u32) {
    probe_out[3u * i] = probe_in[i] * 2u;
    probe_out[3u * i + 1u] = params.camera.width + params.spp;
    probe_out[3u * i + 2u] = bitcast<u32>(prim_at(i).a.x);
}
"#;
    let input: Vec<u32> = (0..100).collect();
    let out = run_probe(
        &device,
        &queue,
        &scene,
        &settings,
        &[],
        probe,
        &input,
        300,
        100,
    );
    for i in 0..100 {
        assert_eq!(out[3 * i], 2 * i as u32);
        assert_eq!(out[3 * i + 1], scene.camera.width + settings.pattern_spp);
        if i < scene.geometry.len() {
            let expected = scene.geometry.prim(i as u32).a[0].to_bits();
            assert_eq!(out[3 * i + 2], expected, "prim {i}");
        }
    }
}
