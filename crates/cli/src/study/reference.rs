//! What a study measures errors against: the scene's closed form, an EXR from anywhere, or a
//! high-spp render of the best configuration cached next to the study's output.

use anyhow::{bail, Context};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use stratapt_film::Render;
use stratapt_scene::{FlatScene, RenderSettings, SamplerKind, Strategy};

/// Per-pixel reference values, with the variance of each where the reference is itself an
/// estimate (so that its own noise can be subtracted from the measured error).
pub struct Reference {
    /// Where it came from, for the report.
    pub source: String,
    pub mean: Vec<[f64; 3]>,
    /// Variance of each pixel's reference value (zeros for a closed form or an EXR without
    /// `var.*` channels).
    pub variance: Vec<[f64; 3]>,
}

impl Reference {
    /// Every pixel equal to `value` (the scene's `[render] exact`).
    pub fn exact(value: [f64; 3], pixels: usize) -> Self {
        Self {
            source: format!("the scene's exact value {value:?}"),
            mean: vec![value; pixels],
            variance: vec![[0.0; 3]; pixels],
        }
    }

    /// An RGB EXR (`R`, `G`, `B`, and `var.R` … when present) of exactly `width × height`.
    pub fn read_exr(path: &Path, width: u32, height: u32) -> anyhow::Result<Self> {
        use exr::prelude::*;
        let image = read_all_flat_layers_from_file(path)
            .map_err(|e| anyhow::anyhow!("{}: not a readable EXR image: {e}", path.display()))?;
        let layer = image
            .layer_data
            .first()
            .with_context(|| format!("{}: the EXR has no layer", path.display()))?;
        let size = (layer.size.0 as u32, layer.size.1 as u32);
        if size != (width, height) {
            bail!(
                "{}: the reference is {}×{} but the study renders {width}×{height} \
                 (pass --size {}x{} or a reference of the film's size)",
                path.display(),
                size.0,
                size.1,
                size.0,
                size.1
            );
        }
        let channel = |name: &str| -> Option<Vec<f32>> {
            layer
                .channel_data
                .list
                .iter()
                .find(|c| c.name.eq(name))
                .map(|c| c.sample_data.values_as_f32().collect())
        };
        let mut rgb = Vec::new();
        for name in ["R", "G", "B"] {
            rgb.push(channel(name).with_context(|| {
                format!(
                    "{}: the EXR has no `{name}` channel (an RGB image is needed)",
                    path.display()
                )
            })?);
        }
        let var: Vec<Option<Vec<f32>>> = ["var.R", "var.G", "var.B"].map(channel).into();
        let n = (width * height) as usize;
        let mean = (0..n)
            .map(|i| [0, 1, 2].map(|c| rgb[c][i] as f64))
            .collect::<Vec<_>>();
        if mean.iter().flatten().any(|v| !v.is_finite()) {
            bail!("{}: the reference has non-finite pixels", path.display());
        }
        let variance = (0..n)
            .map(|i| [0, 1, 2].map(|c| var[c].as_ref().map_or(0.0, |v| v[i] as f64)))
            .collect();
        Ok(Self {
            source: path.display().to_string(),
            mean,
            variance,
        })
    }
}

/// The settings of a cached reference: the best configuration (Sobol, MIS) at `spp`.
pub fn reference_settings(scene: &FlatScene, spp: u32) -> RenderSettings {
    RenderSettings {
        pattern_spp: spp,
        sampler: SamplerKind::Sobol,
        strategy: Strategy::Mis,
        seed: 0x5eed_0f0f,
        ..scene.settings
    }
}

/// `DIR/reference-HASH.exr`: the hash covers what the renderers read of the scene
/// ([`FlatScene::content_hash`]: geometry from every mesh file, textures, materials, lights, the
/// film size), the depth, the spp and the configuration, so any change renders a new one (an
/// edited mesh, texture or included file too, not only the scene file's own text).
pub fn cache_path(dir: &Path, scene: &FlatScene, settings: &RenderSettings) -> PathBuf {
    let key = format!(
        "strata-reference-v2 scene {:016x} depth {} spp {} {} {} seed {}",
        scene.content_hash(),
        settings.max_depth,
        settings.pattern_spp,
        settings.sampler,
        settings.strategy,
        settings.seed
    );
    let hash = stratapt_scene::content_hash::fnv1a(key.as_bytes());
    dir.join(format!("reference-{hash:016x}.exr"))
}

/// The cached reference at `path`, rendered (and written there) first if absent. `None` if
/// the render was cancelled.
pub fn cached(
    renderer: &dyn Render,
    scene: &FlatScene,
    settings: &RenderSettings,
    path: &Path,
    cancel: &AtomicBool,
) -> anyhow::Result<Option<Reference>> {
    if !path.exists() {
        eprintln!(
            "study: rendering the reference ({} spp, {} / {}) to {}",
            settings.pattern_spp,
            settings.sampler,
            settings.strategy,
            path.display()
        );
        let total =
            scene.camera.width as u64 * scene.camera.height as u64 * settings.pattern_spp as u64;
        let bar = indicatif::ProgressBar::new(total);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40.cyan/blue} {percent:>3}% reference: {human_pos}/{human_len} samples, eta {eta}",
            )
            .expect("valid progress template"),
        );
        let rendered = renderer.render(scene, settings, &|n| bar.inc(n), Some(cancel));
        bar.finish_and_clear();
        let (film, stats) =
            rendered.map_err(|e| anyhow::anyhow!("{}: {e}", renderer.describe()))?;
        if stats.cancelled {
            return Ok(None);
        }
        film.write(path)?;
    } else {
        eprintln!("study: reusing the reference {}", path.display());
    }
    let mut reference = Reference::read_exr(path, scene.camera.width, scene.camera.height)?;
    reference.source = format!(
        "{} ({} spp, {} / {}, cached)",
        path.display(),
        settings.pattern_spp,
        settings.sampler,
        settings.strategy
    );
    Ok(Some(reference))
}
