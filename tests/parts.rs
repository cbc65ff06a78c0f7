//! Render parts (`Film::first_sample`, `film::part`): a render split into sample-index ranges,
//! each written as a part EXR and read back, merges into the whole render exactly, for every
//! sampler, on the CPU reference and on the GPU; parts that cannot make a whole are refused.
//!
//! "Exactly": the CPU reference adds the same f64 values in another grouping (its passes start
//! at each part's first sample), so merged sums equal the whole render's to f64 rounding
//! (relative 10⁻¹²); the GPU folds each batch's f32 sums into f64, and parts batch differently,
//! so its sums agree to f32 rounding (relative 10⁻⁶; measured at most 1.1·10⁻⁷). A part rendered
//! from the wrong samples is caught by the same comparison.

mod common;

use common::{scene, shared_renderer};
use std::ops::Range;
use stratapt::cpu::CpuRenderer;
use stratapt::film::part::{self, MergeError, PartInfo};
use stratapt::film::{Film, Render};
use stratapt::scene::{FlatScene, RenderSettings, SamplerKind};

/// A small closed room with a ceiling light and a red box, seen from inside; the film not
/// square (rows and columns differ).
const ROOM: &str = r#"
[camera]
eye = [0, 1, 0.9]
look_at = [0, 1, 0]
fov = 70
[film]
width = 20
height = 14
[materials.white]
type = "diffuse"
albedo = 0.7
[materials.red]
type = "diffuse"
albedo = [0.6, 0.1, 0.1]
[materials.lamp]
type = "diffuse"
albedo = 0
emission = 8
[[shapes]]
type = "box"
min = [-1, 0, -1]
max = [1, 2, 1]
material = "white"
[[shapes]]
type = "box"
min = [-0.5, 0, -0.4]
max = [0.1, 0.9, 0.2]
material = "red"
[[shapes]]
type = "rectangle"
corner = [-0.3, 1.99, -0.3]
edge_u = [0.6, 0, 0]
edge_v = [0, 0, 0.6]
material = "lamp"
"#;

const TOTAL: u32 = 12;
/// Uneven parts, listed out of order.
const PARTS: [Range<u32>; 3] = [7..12, 0..5, 5..7];

fn settings(scene: &FlatScene, sampler: SamplerKind) -> RenderSettings {
    RenderSettings {
        pattern_spp: TOTAL,
        sampler,
        max_depth: 5,
        ..scene.settings
    }
}

/// Samples `range` of every pixel, as `strata render --samples` renders them.
fn render_range(
    renderer: &dyn Render,
    scene: &FlatScene,
    settings: &RenderSettings,
    range: Range<u32>,
) -> Film {
    let mut film = Film::for_render(scene, settings);
    film.first_sample = range.start;
    let stats = renderer
        .render_into(
            scene,
            settings,
            &mut film,
            range.end - range.start,
            &|_| {},
            None,
        )
        .unwrap_or_else(|e| panic!("{}: {e}", renderer.describe()));
    assert_eq!(stats.non_finite, 0);
    film
}

fn info(scene: &FlatScene, settings: &RenderSettings, samples: Range<u32>) -> PartInfo {
    PartInfo {
        samples: vec![samples],
        settings: *settings,
        scene_hash: scene.content_hash(),
        scene: "room".into(),
    }
}

/// The largest relative difference between two films' sums (per pixel, channel, twin), or
/// `None` when their counts or twins differ.
fn max_difference(a: &Film, b: &Film) -> Option<f64> {
    if a.count != b.count || a.has_twins() != b.has_twins() {
        return None;
    }
    let pairs = a
        .sum
        .iter()
        .zip(&b.sum)
        .chain(a.sum_sq.iter().zip(&b.sum_sq))
        .chain(a.twin_sum.iter().zip(&b.twin_sum))
        .chain(a.twin_sum_sq.iter().zip(&b.twin_sum_sq));
    let worst = pairs
        .flat_map(|(x, y)| (0..3).map(move |c| (x[c], y[c])))
        .map(|(x, y)| (x - y).abs() / x.abs().max(y.abs()).max(1e-30))
        .fold(0.0, f64::max);
    Some(worst)
}

/// Write each part and read it back (the file keeps the film bit for bit), then merge.
fn merge_through_files(
    dir: &std::path::Path,
    parts: Vec<(Film, PartInfo)>,
    allow_partial: bool,
) -> Result<part::Merged, MergeError> {
    let mut read = Vec::new();
    for (k, (film, info)) in parts.into_iter().enumerate() {
        let path = dir.join(format!("part-{k}.exr"));
        part::write(&film, &info, &path).unwrap();
        let (back, back_info) = part::read(&path).unwrap();
        assert_eq!(back_info, info, "part {k}'s header changed in its file");
        // The film's sums bit for bit; it starts where its header says. Its peak twins stay
        // out: they hold the part's samples, not the merged render's.
        let expected = Film {
            first_sample: info.samples[0].start,
            peaks: Vec::new(),
            ..film
        };
        assert!(back == expected, "part {k}'s film changed in its file");
        read.push((path, back, back_info));
    }
    part::merge(read, allow_partial)
}

#[test]
fn parts_merge_into_the_whole_render_for_every_sampler_on_both_devices() {
    let scene = scene("room.toml", ROOM);
    let dir = tempfile::tempdir().unwrap();
    let devices: [(&dyn Render, f64); 2] = [(&CpuRenderer, 1e-12), (shared_renderer(), 1e-6)];
    for (renderer, tolerance) in devices {
        for sampler in SamplerKind::ALL {
            let what = format!("{} / {sampler}", renderer.describe());
            let settings = settings(&scene, sampler);
            let whole = render_range(renderer, &scene, &settings, 0..TOTAL);
            let parts = PARTS
                .iter()
                .map(|r| {
                    let film = render_range(renderer, &scene, &settings, r.clone());
                    (film, info(&scene, &settings, r.clone()))
                })
                .collect();
            let merged = merge_through_files(dir.path(), parts, false).unwrap();
            assert_eq!(merged.info.samples, vec![0..TOTAL], "{what}");
            assert!(merged.info.missing().is_empty());
            let worst = max_difference(&merged.film, &whole).expect("same counts and twins");
            println!("{what}: merged sums within {worst:.1e} of the whole render's");
            assert!(
                worst <= tolerance,
                "{what}: merged sums {worst:e} off the whole"
            );
            // The calibrated error of the whole, from the merged sums: on its uniform twins (a
            // merged film has no peak twins, see `Film::peaks`).
            assert!(merged.film.peaks.is_empty());
            let uniform = Film {
                peaks: Vec::new(),
                ..whole.clone()
            };
            let (a, b) = (merged.film.relative_error(), uniform.relative_error());
            let off = (a.image_mean / b.image_mean - 1.0).abs();
            assert!(off <= 1e3 * tolerance, "{what}: error {a:?} vs {b:?}");
            // A part rendered from the wrong samples (one index on) is caught.
            let shifted = render_range(renderer, &scene, &settings, 6..8);
            let mut wrong: Vec<(Film, PartInfo)> = vec![(shifted, info(&scene, &settings, 5..7))];
            for r in [0..5, 7..12] {
                let film = render_range(renderer, &scene, &settings, r.clone());
                wrong.push((film, info(&scene, &settings, r)));
            }
            let bad = merge_through_files(dir.path(), wrong, false).unwrap();
            let worst = max_difference(&bad.film, &whole).unwrap();
            assert!(
                worst > 1e3 * tolerance,
                "{what}: a shifted part went unnoticed ({worst:e})"
            );
        }
    }
}

#[test]
fn parts_that_cannot_make_the_whole_are_refused() {
    let scene = scene("room.toml", ROOM);
    let dir = tempfile::tempdir().unwrap();
    let settings = settings(&scene, SamplerKind::Sobol);
    let part = |r: Range<u32>, s: &RenderSettings| {
        (
            render_range(&CpuRenderer, &scene, s, r.clone()),
            info(&scene, s, r),
        )
    };
    // Overlapping ranges.
    let e = merge_through_files(
        dir.path(),
        vec![part(0..6, &settings), part(4..12, &settings)],
        false,
    )
    .unwrap_err();
    assert!(
        matches!(&e, MergeError::Overlap { overlap, .. } if *overlap == (4..6)),
        "{e}"
    );
    assert!(e.to_string().contains("both hold samples 4..6"), "{e}");
    // Missing samples: refused, or merged and named with --allow-partial.
    let e = merge_through_files(
        dir.path(),
        vec![part(0..4, &settings), part(8..12, &settings)],
        false,
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("samples 4..8 of 12 are in no part"),
        "{e}"
    );
    let partial = merge_through_files(
        dir.path(),
        vec![part(0..4, &settings), part(8..12, &settings)],
        true,
    )
    .unwrap();
    assert_eq!(partial.info.missing(), vec![4..8]);
    assert_eq!(partial.film.held_spp(), 8);
    // Other settings, and another scene.
    let other_seed = RenderSettings {
        seed: 9,
        ..settings
    };
    let e = merge_through_files(
        dir.path(),
        vec![part(0..6, &settings), part(6..12, &other_seed)],
        false,
    )
    .unwrap_err();
    assert!(e.to_string().contains("seed differs"), "{e}");
    let (film, mut other_scene) = part(6..12, &settings);
    other_scene.scene_hash ^= 1;
    let e = merge_through_files(
        dir.path(),
        vec![part(0..6, &settings), (film, other_scene)],
        false,
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("scene (content hash) differs"),
        "{e}"
    );
    // A render that is not a part, and a file that is not an EXR.
    let whole = dir.path().join("whole.exr");
    render_range(&CpuRenderer, &scene, &settings, 0..TOTAL)
        .write(&whole)
        .unwrap();
    let e = part::read(&whole).unwrap_err();
    assert!(e.to_string().contains("not a strata part"), "{e}");
    let junk = dir.path().join("junk.exr");
    std::fs::write(&junk, "not an image").unwrap();
    assert!(part::read(&junk)
        .unwrap_err()
        .to_string()
        .contains("not a readable EXR"));
    assert!(matches!(
        part::merge(Vec::new(), false),
        Err(MergeError::Empty)
    ));
}

#[test]
fn the_scene_hash_tells_scenes_apart() {
    let a = scene("room.toml", ROOM);
    assert_eq!(
        a.content_hash(),
        scene("copy.toml", ROOM).content_hash(),
        "same content"
    );
    let brighter = scene("room.toml", &ROOM.replace("emission = 8", "emission = 9"));
    let wider = scene("room.toml", &ROOM.replace("width = 20", "width = 21"));
    assert_ne!(a.content_hash(), brighter.content_hash());
    assert_ne!(a.content_hash(), wider.content_hash());
}
