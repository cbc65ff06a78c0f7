//! The eight-lane renderer (`stratapt_cpu::eight`) computes the reference's estimator from the
//! same samples: on the scenes it covers its film is the one-lane reference's, pixel for pixel
//! (up to the order in which each pixel's samples are summed), and it refuses the others.

use stratapt_cpu::{Cpu8Renderer, CpuRenderer};
use stratapt_film::{Film, Render};
use stratapt_scene::{FlatScene, RenderSettings};

fn load(name: &str) -> FlatScene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    stratapt_import::scene_file::load(&path).unwrap()
}

fn render(renderer: &dyn Render, scene: &FlatScene, settings: &RenderSettings) -> Film {
    renderer.render(scene, settings, &|_| {}, None).unwrap().0
}

/// Pixels whose means differ by more than `relative` (and the largest difference).
fn differing(a: &Film, b: &Film, relative: f64) -> (usize, f64) {
    let mut worst = 0.0f64;
    let mut count = 0;
    for i in 0..a.sum.len() {
        let (ma, mb) = (a.mean(i), b.mean(i));
        let d = (0..3)
            .map(|c| (ma[c] - mb[c]).abs() / ma[c].abs().max(mb[c].abs()).max(1e-30))
            .fold(0.0, f64::max);
        worst = worst.max(d);
        count += (d > relative) as usize;
    }
    (count, worst)
}

#[test]
fn eight_lanes_render_the_reference_film() {
    let mut scene = load("mitsuba/cornell-box.toml");
    (scene.camera.width, scene.camera.height) = (48, 48);
    let settings = RenderSettings {
        pattern_spp: 16,
        ..scene.settings
    };
    let one = render(&CpuRenderer, &scene, &settings);
    let eight = render(&Cpu8Renderer, &scene, &settings);
    assert_eq!(one.count, eight.count);
    let (count, worst) = differing(&one, &eight, 1e-12);
    eprintln!(
        "pixels differing beyond 1e-12: {count} of {}, worst {worst:.2e}",
        one.sum.len()
    );
    assert_eq!(count, 0, "worst relative difference {worst:.2e}");
}
