//! pbrt-v4's `Film`, `Sampler`, `Integrator` and `PixelFilter` as strata's film and render
//! settings, with pbrt-v4's defaults where a directive or parameter is absent (a 1280×720 film,
//! 16 samples per pixel, path depth 5, a Gaussian filter of σ ½ pixel). What strata draws
//! differently becomes one warning each: another integrator or filter, a maximum depth of 0.
//! What changes only the noise, not the image the render converges to (pbrt's sampler family,
//! its `randomization`, its `lightsampler`), is read without a warning: strata's own samplers
//! and light selection converge to the same image.

use super::include::Parsed;
use super::params::Params;
use super::parse::Directive;
use super::state::Warning;
use crate::load::MAX_RESOLUTION;
use stratapt_sampling::SamplerKind;
use stratapt_scene::error::SceneError;
use stratapt_scene::records::filter_kind;

/// The film and render settings of a pbrt-v4 scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    /// Film `filename`, for a default output name.
    pub filename: Option<String>,
    pub spp: u32,
    /// Path vertices after the camera: pbrt's `maxdepth` means the same (1: direct light).
    pub max_depth: u32,
    pub sampler: SamplerKind,
    /// One of [`filter_kind`], with its width (box), radius (tent) or σ (Gaussian) in pixels.
    pub filter: u32,
    pub filter_param: f64,
    pub warnings: Vec<Warning>,
}

/// A directive and the index of its source.
pub type Located<'a> = (usize, &'a Directive);

/// The settings from the scene's (last) `Film`, `Sampler`, `Integrator` and `PixelFilter`.
pub fn settings(
    parsed: &Parsed,
    film: Option<Located>,
    sampler: Option<Located>,
    integrator: Option<Located>,
    filter: Option<Located>,
) -> Result<Settings, SceneError> {
    let mut warnings = Vec::new();
    fn params<'a>(parsed: &'a Parsed, l: Option<Located<'a>>) -> Option<Params<'a>> {
        l.map(|(s, d)| Params::new(parsed, s, d))
    }

    let (mut width, mut height, mut filename) = (1280, 720, None);
    if let Some(p) = params(parsed, film) {
        if p.kind() != "rgb" {
            warnings.push(p.warning("written as an RGB image"));
        }
        let resolution = |name: &str, default: i64| -> Result<u32, SceneError> {
            let v = p.integer(name, default)?;
            match u32::try_from(v) {
                Ok(v) if (1..=MAX_RESOLUTION).contains(&v) => Ok(v),
                _ => Err(p.err(
                    p.find(super::parse::ParamType::Integer, name)
                        .expect("read above"),
                    format!("{name} {v}: a film is 1 to {MAX_RESOLUTION} pixels on a side"),
                )),
            }
        };
        width = resolution("xresolution", 1280)?;
        height = resolution("yresolution", 720)?;
        filename = p.string("filename")?.map(str::to_string);
        warnings.extend(p.unused());
    }

    let (mut spp, mut kind) = (16, SamplerKind::Sobol);
    if let Some(p) = params(parsed, sampler) {
        let _ = p.string("randomization")?;
        let _ = p.integer("seed", 0)?;
        kind = match p.kind() {
            "independent" => SamplerKind::Independent,
            "stratified" => {
                let _ = p.bool("jitter", true)?;
                SamplerKind::Stratified
            }
            // pbrt's other low-discrepancy samplers converge to the same image as Sobol.
            "sobol" | "zsobol" | "paddedsobol" | "halton" | "pmj02bn" => SamplerKind::Sobol,
            other => {
                warnings.push(p.warning(format!(
                    "sampled with strata's Owen-scrambled Sobol, not {other}"
                )));
                SamplerKind::Sobol
            }
        };
        let n = if p.kind() == "stratified" {
            p.integer("xsamples", 4)? * p.integer("ysamples", 4)?
        } else {
            p.integer("pixelsamples", 16)?
        };
        spp = u32::try_from(n)
            .ok()
            .filter(|&n| n >= 1)
            .ok_or_else(|| p.directive_err(format!("{n} samples per pixel: at least 1")))?;
        warnings.extend(p.unused());
    }

    let mut max_depth = 5;
    if let Some(p) = params(parsed, integrator) {
        if !matches!(p.kind(), "path" | "volpath") {
            warnings.push(p.warning("rendered by strata's path tracer with MIS"));
        }
        let depth = p.integer("maxdepth", 5)?;
        let _ = p.string("lightsampler")?;
        if p.bool("regularize", false)? {
            warnings.push(p.warning("\"regularize\" ignored: strata's BSDFs are not roughened"));
        }
        max_depth = match depth {
            d if d < 0 => return Err(p.directive_err(format!("maxdepth {depth}: at least 0"))),
            0 => {
                warnings.push(p.warning(
                    "maxdepth 0 (emitters seen directly) drawn at strata's least depth, \
                     1 (direct light)",
                ));
                1
            }
            d => d.min(1024) as u32,
        };
        warnings.extend(p.unused());
    }

    let (mut filter_id, mut filter_param) = (filter_kind::GAUSSIAN, 0.5);
    let mut gaussian_note = true;
    if let Some(p) = params(parsed, filter) {
        match p.kind() {
            "box" => {
                let (x, y) = (p.float("xradius", 0.5)?, p.float("yradius", 0.5)?);
                if x != y {
                    warnings
                        .push(p.warning(format!("drawn {x} pixels wide both ways, not {y} high")));
                }
                (filter_id, filter_param) = (filter_kind::BOX, 2.0 * x);
                gaussian_note = false;
            }
            "triangle" => {
                let (x, y) = (p.float("xradius", 2.0)?, p.float("yradius", 2.0)?);
                if x != y {
                    warnings.push(p.warning(format!("drawn with radius {x} both ways, not {y}")));
                }
                (filter_id, filter_param) = (filter_kind::TENT, x);
                gaussian_note = false;
            }
            "gaussian" => {
                filter_param = p.float("sigma", 0.5)?;
                let _ = (p.float("xradius", 1.5)?, p.float("yradius", 1.5)?);
            }
            other => {
                warnings
                    .push(p.warning(format!("drawn with a Gaussian of σ 0.5 pixel, not {other}")));
                gaussian_note = false;
            }
        }
        if !(filter_param > 0.0 && filter_param.is_finite()) {
            return Err(p.directive_err(format!("filter size {filter_param}: above 0")));
        }
        warnings.extend(p.unused());
    }
    if gaussian_note && filter_id == filter_kind::GAUSSIAN {
        // pbrt's Gaussian is cut at its radius and lowered to 0 there; strata's is not.
        warnings.push(Warning {
            at: filter.map_or_else(
                || parsed.sources.main().display().to_string(),
                |(s, d)| parsed.location(s, d.at).to_string(),
            ),
            message: "PixelFilter \"gaussian\": drawn with strata's untruncated Gaussian \
                      (pbrt's is cut at its radius)"
                .into(),
        });
    }

    Ok(Settings {
        width,
        height,
        filename,
        spp,
        max_depth,
        sampler: kind,
        filter: filter_id,
        filter_param,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn run(text: &str) -> Result<Settings, SceneError> {
        let parsed = Parsed::from_text(text, Path::new("s.pbrt"))?;
        settings(
            &parsed,
            parsed.last("Film"),
            parsed.last("Sampler"),
            parsed.last("Integrator"),
            parsed.last("PixelFilter"),
        )
    }

    fn messages(s: &Settings) -> Vec<String> {
        s.warnings
            .iter()
            .map(|w| format!("{}: {}", w.at, w.message))
            .collect()
    }

    #[test]
    fn pbrts_defaults_when_absent() {
        let s = run("WorldBegin").unwrap();
        assert_eq!((s.width, s.height, s.spp, s.max_depth), (1280, 720, 16, 5));
        assert_eq!(
            (s.sampler, s.filter, s.filter_param),
            (SamplerKind::Sobol, filter_kind::GAUSSIAN, 0.5)
        );
        assert_eq!(messages(&s), vec!["s.pbrt: PixelFilter \"gaussian\": drawn with strata's untruncated Gaussian (pbrt's is cut at its radius)"]);
    }

    #[test]
    fn each_directive_maps_onto_strata() {
        let s = run(
            "Film \"rgb\" \"integer xresolution\" 400 \"integer yresolution\" 300 \"string filename\" \"a.exr\"\n\
             Sampler \"independent\" \"integer pixelsamples\" 64\n\
             Integrator \"volpath\" \"integer maxdepth\" 12 \"string lightsampler\" \"bvh\"\n\
             PixelFilter \"box\"",
        )
        .unwrap();
        assert_eq!((s.width, s.height, s.spp, s.max_depth), (400, 300, 64, 12));
        assert_eq!(s.filename.as_deref(), Some("a.exr"));
        assert_eq!(
            (s.sampler, s.filter, s.filter_param),
            (SamplerKind::Independent, filter_kind::BOX, 1.0)
        );
        assert!(s.warnings.is_empty(), "{:?}", messages(&s));
        let s = run(
            "Sampler \"stratified\" \"integer xsamples\" 3 \"integer ysamples\" 5\n\
                     PixelFilter \"triangle\" \"float xradius\" 1.5 \"float yradius\" 1.5",
        )
        .unwrap();
        assert_eq!(
            (s.spp, s.sampler, s.filter, s.filter_param),
            (15, SamplerKind::Stratified, filter_kind::TENT, 1.5)
        );
        let s = run(
            "Sampler \"zsobol\" \"integer pixelsamples\" 8 \"string randomization\" \
                     \"fastowen\"\nPixelFilter \"gaussian\" \"float sigma\" 0.7",
        )
        .unwrap();
        assert_eq!(
            (s.spp, s.sampler, s.filter_param),
            (8, SamplerKind::Sobol, 0.7)
        );
        assert_eq!(s.warnings.len(), 1, "{:?}", messages(&s));
    }

    /// What strata draws differently is one warning each, at the directive or the parameter.
    #[test]
    fn substitutions_and_unread_parameters_are_warnings() {
        let s = run("Film \"gbuffer\" \"float iso\" 400\n\
             Sampler \"lowdiscrepancy\"\n\
             Integrator \"bdpt\" \"integer maxdepth\" 0 \"bool regularize\" true\n\
             PixelFilter \"mitchell\" \"float B\" 0.3")
        .unwrap();
        let w = messages(&s);
        let expected = [
            "s.pbrt:1:1: Film \"gbuffer\": written as an RGB image",
            "s.pbrt:1:16: Film \"gbuffer\": parameter \"float iso\" ignored",
            "s.pbrt:2:1: Sampler \"lowdiscrepancy\": sampled with strata's Owen-scrambled Sobol, not lowdiscrepancy",
            "s.pbrt:3:1: Integrator \"bdpt\": rendered by strata's path tracer",
            "s.pbrt:3:1: Integrator \"bdpt\": \"regularize\" ignored",
            "s.pbrt:3:1: Integrator \"bdpt\": maxdepth 0",
            "s.pbrt:4:1: PixelFilter \"mitchell\": drawn with a Gaussian",
            "s.pbrt:4:24: PixelFilter \"mitchell\": parameter \"float B\" ignored",
        ];
        assert_eq!(w.len(), expected.len(), "{w:#?}");
        for e in expected {
            assert!(w.iter().any(|w| w.starts_with(e)), "`{e}` not in {w:#?}");
        }
        assert_eq!(s.max_depth, 1);
        // A parameter of another type is not the one read: "integer sigma" is unread.
        let s = run("PixelFilter \"gaussian\" \"integer sigma\" 1").unwrap();
        assert_eq!(s.filter_param, 0.5);
        assert!(messages(&s)
            .iter()
            .any(|w| w.contains("\"integer sigma\" ignored")));
    }

    #[test]
    fn impossible_values_are_errors_where_written() {
        for (text, words) in [
            (
                "Film \"rgb\" \"integer xresolution\" 0",
                &["s.pbrt:1:12:", "xresolution 0"][..],
            ),
            (
                "Film \"rgb\" \"integer yresolution\" 20000",
                &["s.pbrt:1:12:", "yresolution 20000"],
            ),
            (
                "Sampler \"sobol\" \"integer pixelsamples\" 0",
                &["s.pbrt:1:1:", "0 samples per pixel"],
            ),
            (
                "Integrator \"path\" \"integer maxdepth\" -1",
                &["s.pbrt:1:1:", "maxdepth -1"],
            ),
            (
                "PixelFilter \"box\" \"float xradius\" 0",
                &["s.pbrt:1:1:", "filter size 0"],
            ),
            ("Film \"rgb\" \"float xresolution\" 10", &[]),
            (
                "Sampler \"sobol\" \"integer pixelsamples\" [1 2]",
                &["s.pbrt:1:17:", "takes one number"],
            ),
        ] {
            match run(text) {
                Err(e) => {
                    let e = e.to_string();
                    assert!(!words.is_empty(), "`{text}`: {e}");
                    for w in words {
                        assert!(e.contains(w), "`{text}`: `{w}` not in {e}");
                    }
                }
                // A float resolution is not pbrt's integer: unread, the default kept.
                Ok(s) => assert!(words.is_empty() && s.width == 1280, "`{text}` accepted"),
            }
        }
    }
}
