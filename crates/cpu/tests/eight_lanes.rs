//! The eight-lane renderer (`stratapt_cpu::eight`) computes the reference's estimator from the
//! same samples: on the scenes it covers its film (pixels, twin pixels, peak twins, ray count)
//! is the one-lane reference's, up to the order in which each pixel's samples are summed; it
//! refuses the scenes it does not cover.

use stratapt_cpu::{Cpu8Renderer, CpuRenderer};
use stratapt_film::{Film, Render, RenderStats};
use stratapt_scene::{FlatScene, RenderSettings};

fn load(name: &str) -> FlatScene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    stratapt_import::scene_file::load(&path).unwrap()
}

fn render(
    renderer: &dyn Render,
    scene: &FlatScene,
    settings: &RenderSettings,
) -> (Film, RenderStats) {
    renderer.render(scene, settings, &|_| {}, None).unwrap()
}

/// How far apart two sums are, relative to the larger.
fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(1e-300)
}

/// Sum entries (pixels, twin pixels, peak twins) of `a` and `b` further apart than 1e-12
/// relative: summing the same f32 samples in another order moves an f64 sum by far less.
fn differing(a: &Film, b: &Film) -> usize {
    let far = |x: &[[f64; 3]], y: &[[f64; 3]]| {
        x.iter()
            .zip(y)
            .filter(|(p, q)| (0..3).any(|c| relative(p[c], q[c]) > 1e-12))
            .count()
    };
    assert_eq!(
        (a.count.len(), a.twin_sum.len(), a.peaks.len()),
        (b.count.len(), b.twin_sum.len(), b.peaks.len())
    );
    let peaks = a.peaks.iter().zip(&b.peaks).filter(|(p, q)| {
        p.pixel != q.pixel
            || p.replica != q.replica
            || (0..3).any(|c| relative(p.sum[c], q.sum[c]) > 1e-12)
    });
    far(&a.sum, &b.sum)
        + far(&a.sum_sq, &b.sum_sq)
        + far(&a.twin_sum, &b.twin_sum)
        + far(&a.twin_sum_sq, &b.twin_sum_sq)
        + peaks.count()
}

#[test]
fn eight_lanes_render_the_reference_film() {
    for name in ["mitsuba/cornell-box.toml", "cornell-box.toml"] {
        let mut scene = load(name);
        (scene.camera.width, scene.camera.height) = (40, 32);
        for seed in [0, 7] {
            let settings = RenderSettings {
                pattern_spp: 12,
                seed,
                ..scene.settings
            };
            let (one, one_stats) = render(&CpuRenderer, &scene, &settings);
            let (eight, eight_stats) = render(&Cpu8Renderer, &scene, &settings);
            assert!(
                eight.has_twins() && !eight.peaks.is_empty(),
                "{name}: no twins to compare"
            );
            assert_eq!(one.count, eight.count, "{name}");
            assert_eq!(
                (one_stats.samples, one_stats.rays, one_stats.non_finite),
                (
                    eight_stats.samples,
                    eight_stats.rays,
                    eight_stats.non_finite
                ),
                "{name}"
            );
            assert_eq!(differing(&one, &eight), 0, "{name}, seed {seed}");
        }
    }
}

/// The comparison above sees a 0.1 % change in one pixel of one channel.
#[test]
fn a_planted_difference_is_seen() {
    let mut scene = load("mitsuba/cornell-box.toml");
    (scene.camera.width, scene.camera.height) = (16, 16);
    let settings = RenderSettings {
        pattern_spp: 4,
        ..scene.settings
    };
    let (one, _) = render(&CpuRenderer, &scene, &settings);
    let mut planted = render(&Cpu8Renderer, &scene, &settings).0;
    assert_eq!(differing(&one, &planted), 0);
    planted.sum[77][1] *= 1.001;
    assert_eq!(differing(&one, &planted), 1);
}

#[test]
fn scenes_it_does_not_cover_are_refused_with_the_reason() {
    for (name, what) in [
        ("glass.toml", "materials that choose lobes"),
        ("mesh.toml", "materials other than plain diffuse"),
        ("depth-of-field.toml", "a thin lens"),
        (
            "soft-shadow-area.toml",
            "primitives other than static triangles",
        ),
    ] {
        let scene = load(name);
        let settings = RenderSettings {
            pattern_spp: 1,
            ..scene.settings
        };
        let Err(error) = Cpu8Renderer.render(&scene, &settings, &|_| {}, None) else {
            panic!("{name}: rendered");
        };
        assert!(error.to_string().contains(what), "{name}: {error}");
    }
    // The sampler and the strategy too.
    let scene = load("cornell-box.toml");
    for settings in [
        RenderSettings {
            sampler: stratapt_sampling::SamplerKind::Independent,
            ..scene.settings
        },
        RenderSettings {
            strategy: stratapt_scene::Strategy::Bsdf,
            ..scene.settings
        },
    ] {
        assert!(Cpu8Renderer
            .render(&scene, &settings, &|_| {}, None)
            .is_err());
    }
}
