//! Every scene in `scenes/`, rendered tiny (16×16, 4 spp) with every strategy: no sample is
//! NaN or infinite and no pixel is negative.

use std::path::Path;
use stratapt::cpu::render_with_stats;
use stratapt::scene::{load::load, RenderSettings, Strategy};

#[test]
fn every_scene_renders_finite_non_negative_samples() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let paths = stratapt::scene::load::scene_files(&dir).expect("scenes/ directory");
    assert!(!paths.is_empty(), "no scenes in {}", dir.display());
    for path in paths {
        let mut scene = load(&path).unwrap_or_else(|e| panic!("{e}"));
        scene.camera.width = 16;
        scene.camera.height = 16;
        for strategy in Strategy::ALL {
            let settings = RenderSettings {
                spp: 4,
                strategy,
                ..scene.settings
            };
            let (film, stats) = render_with_stats(&scene, &settings, &|_| {}, None);
            let name = format!("{} / {strategy}", path.display());
            assert_eq!(stats.non_finite, 0, "{name}: non-finite samples");
            assert!(!film.has_non_finite(), "{name}: non-finite film");
            assert_eq!(film.spp(), 4, "{name}");
            assert!(
                film.sum.iter().flatten().all(|&v| v >= 0.0),
                "{name}: negative radiance"
            );
        }
    }
}
