//! A conductor's `tint` scales its reflection: the same samples give a tinted rough gold sphere
//! exactly `tint` times the untinted one's radiance in every pixel (to f32 rounding). What Bitterli's classroom and kitchen lose in their pbrt-v4 files:
//! Tungsten's conductors carry an albedo (window frames 0.47, the extractor hood 0.58) that
//! pbrt-v4's conductor has no parameter for; strata's `tint` is it
//! (docs/measurements/mitsuba-diff.md#the-classroom-and-the-kitchen-wall).

use std::path::Path;

/// One rough gold sphere under a gradient sky, filling the view (a pixel that also saw the sky
/// would not scale), seen directly (one bounce: no roulette, whose survival depends on the
/// throughput), with `tint`.
fn scene(tint: &str) -> String {
    format!(
        r#"
[camera]
eye = [0, 0, 4]
look_at = [0, 0, 0]
fov = 10
[film]
width = 24
height = 24
[render]
spp = 16
max_depth = 1
[sky]
top = [1.0, 0.9, 0.8]
bottom = [0.1, 0.2, 0.3]
[materials.gold]
type = "conductor"
eta = [0.143, 0.374, 1.442]
k = [3.983, 2.385, 1.603]
roughness = 0.3
{tint}
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "gold"
"#
    )
}

fn render(text: &str) -> Vec<[f64; 3]> {
    let scene = stratapt_import::load::load_str(text, Path::new("tint.toml")).unwrap();
    let film = stratapt_cpu::render(&scene, &scene.settings, &|_| {}, None).0;
    let (w, h) = (scene.camera.width, scene.camera.height);
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| film.mean(film.index(x, y)))
        .collect()
}

#[test]
fn a_conductor_tint_scales_its_reflection_exactly() {
    let tint = [0.471008, 0.751534, 0.578596];
    let plain = render(&scene(""));
    let tinted = render(&scene(&format!("tint = {tint:?}")));
    for (p, t) in plain.iter().zip(&tinted) {
        for c in 0..3 {
            let expected = p[c] * tint[c];
            assert!(
                expected > 0.0 && (t[c] - expected).abs() <= 1e-5 * expected,
                "channel {c}: {} against {expected}",
                t[c]
            );
        }
    }
}
