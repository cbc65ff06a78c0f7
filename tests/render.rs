//! The render loop: progress adds up to every sample, cancellation returns whole passes (the
//! same sample count in every pixel), an empty scene renders black.

mod common;

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use stratapt::cpu::render;
use stratapt::scene::RenderSettings;

const SCENE: &str = r#"
[camera]
eye = [0, 1, -3]
look_at = [0, 0.5, 0]
fov = 40
[film]
width = 13
height = 7
[materials.white]
type = "diffuse"
albedo = 0.7
[[shapes]]
type = "sphere"
center = [0, 0.5, 0]
radius = 0.5
material = "white"
[sky]
color = 1
"#;

#[test]
fn progress_counts_every_sample() {
    let scene = common::scene("progress", SCENE);
    let settings = RenderSettings {
        pattern_spp: 10,
        ..scene.settings
    };
    let done = AtomicU64::new(0);
    let (film, _) = render(
        &scene,
        &settings,
        &|n| {
            done.fetch_add(n, Ordering::Relaxed);
        },
        None,
    );
    assert_eq!(done.into_inner(), 13 * 7 * 10);
    assert!(film.count.iter().all(|&c| c == 10));
}

#[test]
fn cancel_returns_whole_passes() {
    let scene = common::scene("cancel", SCENE);
    let settings = RenderSettings {
        pattern_spp: 64,
        ..scene.settings
    };
    let cancel = AtomicBool::new(false);
    // Cancel as soon as the first row of the first pass is done.
    let (film, stats) = render(
        &scene,
        &settings,
        &|_| cancel.store(true, Ordering::Relaxed),
        Some(&cancel),
    );
    assert!(stats.cancelled);
    let spp = film.count[0];
    assert!(spp < 64, "cancel ignored");
    assert!(
        film.count.iter().all(|&c| c == spp),
        "unequal sample counts after cancel"
    );
    assert_eq!(stats.samples, spp as u64 * 13 * 7);
    assert_eq!(stats.non_finite, 0);
}

#[test]
fn empty_scene_renders_black() {
    let scene = common::scene(
        "empty",
        "[camera]\neye = [0, 0, 0]\nlook_at = [0, 0, 1]\nfov = 40\n[film]\nwidth = 4\nheight = 3\n",
    );
    let settings = RenderSettings {
        pattern_spp: 3,
        ..scene.settings
    };
    let film = render(&scene, &settings, &|_| {}, None).0;
    assert!(film.sum.iter().flatten().all(|&v| v == 0.0));
    assert_eq!(film.held_spp(), 3);
}
