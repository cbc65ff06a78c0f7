//! Parts of a render: films that hold some of its sample indices, written so that merging
//! them is exact, and the merge itself.
//!
//! The samplers are pure functions of (pixel, sample index, dimension, seed), so the samples
//! `A..B` of every pixel can be rendered anywhere, on either device, and sums over disjoint
//! ranges add up to the sums of the whole render. A part's EXR is an ordinary image (`R, G, B`
//! mean, `var.*` calibrated variance, readable by any viewer) that also keeps the film's f64
//! sums bit for bit (each as two `u32` channels, `sum.R.hi`/`sum.R.lo` …; the twins' in a
//! second layer, `twins`) and, in its header, what merging checks: the sample ranges held
//! (`samples`, e.g. `0..16,32..48`), the render's total `total-spp` (it sizes the stratified
//! sampler's strata), the scene's content hash and the settings. A film's peak twins
//! ([`Film::peaks`]) are not written: they hold the part's samples at pixels chosen from the
//! part, and cannot be summed with other parts', so a merged film calibrates on its uniform
//! twins alone.

use super::{Film, FilmError};
use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use stratapt_scene::{RenderSettings, SamplerKind, Strategy};

/// The header attribute that marks a strata part, with the format's version.
const MARK: &str = "strata-part";
const VERSION: &str = "1";

/// What a part holds besides its sums.
#[derive(Clone, Debug, PartialEq)]
pub struct PartInfo {
    /// Sample-index ranges held, sorted and disjoint.
    pub samples: Vec<Range<u32>>,
    /// The whole render's settings; `settings.pattern_spp` is its total samples per pixel.
    pub settings: RenderSettings,
    /// [`stratapt_scene::FlatScene::content_hash`] of the scene rendered.
    pub scene_hash: u64,
    /// The scene file, for people (not compared).
    pub scene: String,
}

impl PartInfo {
    /// The samples in `0..settings.pattern_spp` that no range holds.
    pub fn missing(&self) -> Vec<Range<u32>> {
        let mut missing = Vec::new();
        let mut next = 0;
        for r in &self.samples {
            if r.start > next {
                missing.push(next..r.start);
            }
            next = next.max(r.end);
        }
        if next < self.settings.pattern_spp {
            missing.push(next..self.settings.pattern_spp);
        }
        missing
    }
}

/// Sample ranges as people write them: `0..16,32..48` (`none` when empty).
pub fn format_ranges(ranges: &[Range<u32>]) -> String {
    if ranges.is_empty() {
        return "none".into();
    }
    let parts: Vec<String> = ranges
        .iter()
        .map(|r| format!("{}..{}", r.start, r.end))
        .collect();
    parts.join(",")
}

/// Parse [`format_ranges`]' output.
pub fn parse_ranges(text: &str) -> Option<Vec<Range<u32>>> {
    if text == "none" {
        return Some(Vec::new());
    }
    text.split(',')
        .map(|r| {
            let (a, b) = r.trim().split_once("..")?;
            let (a, b) = (a.trim().parse().ok()?, b.trim().parse().ok()?);
            (a < b).then_some(a..b)
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Writing and reading
// ---------------------------------------------------------------------------------------------

/// Write `film` (holding `info.samples`) as a part EXR, atomically.
pub fn write(film: &Film, info: &PartInfo, path: &Path) -> Result<(), FilmError> {
    super::write::atomically(path, |tmp| write_exr(film, info, tmp))
}

fn write_exr(film: &Film, info: &PartInfo, path: &Path) -> Result<(), String> {
    use exr::prelude::*;
    let mut main = super::write::exr_channels(film);
    push_sums(&mut main, &film.sum, &film.sum_sq);
    main.push(AnyChannel::new(
        "count",
        FlatSamples::U32(film.count.clone()),
    ));
    let mut attributes = super::write::exr_attributes(film);
    let s = &info.settings;
    let text = |v: String| AttributeValue::Text(Text::from(v.as_str()));
    for (key, value) in [
        (MARK, VERSION.to_string()),
        ("samples", format_ranges(&info.samples)),
        ("total-spp", s.pattern_spp.to_string()),
        ("scene-hash", format!("{:016x}", info.scene_hash)),
        ("scene", info.scene.clone()),
        ("sampler", s.sampler.name().to_string()),
        ("strategy", s.strategy.name().to_string()),
        ("seed", s.seed.to_string()),
        ("max-depth", s.max_depth.to_string()),
        ("calibrate", s.calibrate.to_string()),
    ] {
        attributes.other.insert(Text::from(key), text(value));
    }
    let size = (film.width as usize, film.height as usize);
    let mut layers = vec![Layer::new(
        size,
        attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(main),
    )];
    if film.has_twins() {
        let mut twins = SmallVec::new();
        push_sums(&mut twins, &film.twin_sum, &film.twin_sum_sq);
        layers.push(Layer::new(
            (film.twin_sum.len(), 1),
            LayerAttributes::named("twins"),
            Encoding::SMALL_LOSSLESS,
            AnyChannels::sort(twins),
        ));
    }
    let image = Image::from_layers(ImageAttributes::with_size(size), layers);
    super::write::exr_file(path, |out| image.write().to_buffered(out))
}

type Channels = exr::prelude::SmallVec<[exr::prelude::AnyChannel<exr::prelude::FlatSamples>; 4]>;

/// `sum.R.hi`, `sum.R.lo`, … and `sum_sq.*`: each f64 as the two halves of its bits.
fn push_sums(channels: &mut Channels, sum: &[[f64; 3]], sum_sq: &[[f64; 3]]) {
    use exr::prelude::*;
    for (name, values) in [("sum", sum), ("sum_sq", sum_sq)] {
        for (c, rgb) in ["R", "G", "B"].into_iter().enumerate() {
            let bits: Vec<u64> = values.iter().map(|v| v[c].to_bits()).collect();
            let hi = bits.iter().map(|b| (b >> 32) as u32).collect();
            let lo = bits.iter().map(|&b| b as u32).collect();
            let base = format!("{name}.{rgb}");
            channels.push(AnyChannel::new(
                format!("{base}.hi").as_str(),
                FlatSamples::U32(hi),
            ));
            channels.push(AnyChannel::new(
                format!("{base}.lo").as_str(),
                FlatSamples::U32(lo),
            ));
        }
    }
}

/// Read a part EXR written by [`write()`]: the film (its sums exactly) and what it holds.
pub fn read(path: &Path) -> Result<(Film, PartInfo), FilmError> {
    use exr::prelude::*;
    let fail = |reason: String| FilmError::new(path, reason);
    let image = read_all_flat_layers_from_file(path)
        .map_err(|e| fail(format!("not a readable EXR image: {e}")))?;
    let main = image
        .layer_data
        .iter()
        .find(|l| l.attributes.other.contains_key(&Text::from(MARK)))
        .ok_or_else(|| {
            fail("not a strata part (render one with `strata render --part K/N` or `--samples A..B`)".into())
        })?;
    let info = part_info(&main.attributes.other).map_err(fail)?;
    let (width, height) = (main.size.0 as u32, main.size.1 as u32);
    let twins = info.settings.twins();
    let mut film = Film::with_twins(width, height, twins);
    let n = film.sum.len();
    (film.sum, film.sum_sq) = sums(&main.channel_data.list, n).map_err(fail)?;
    film.count = u32_channel(&main.channel_data.list, "count", n).map_err(fail)?;
    if twins {
        let layer = image
            .layer_data
            .iter()
            .find(|l| l.attributes.layer_name == Some(Text::from("twins")))
            .ok_or_else(|| fail("the part has no `twins` layer".into()))?;
        let k = film.twin_sum.len();
        (film.twin_sum, film.twin_sum_sq) = sums(&layer.channel_data.list, k).map_err(fail)?;
    }
    // Every pixel holds every sample of its ranges.
    let held: u64 = info.samples.iter().map(|r| (r.end - r.start) as u64).sum();
    if film.count.iter().any(|&c| c as u64 != held) {
        return Err(fail(format!(
            "its sample counts do not match the samples it says it holds ({})",
            format_ranges(&info.samples)
        )));
    }
    film.first_sample = info.samples.first().map_or(0, |r| r.start);
    Ok((film, info))
}

fn part_info(
    attrs: &HashMap<exr::prelude::Text, exr::prelude::AttributeValue>,
) -> Result<PartInfo, String> {
    use exr::prelude::{AttributeValue, Text};
    let get = |key: &str| -> Result<String, String> {
        match attrs.get(&Text::from(key)) {
            Some(AttributeValue::Text(t)) => Ok(t.to_string()),
            _ => Err(format!("the part's header has no `{key}`")),
        }
    };
    let number = |key: &str| -> Result<u32, String> {
        let v = get(key)?;
        v.parse()
            .map_err(|_| format!("the part's `{key}` is not a number: {v}"))
    };
    let version = get(MARK)?;
    if version != VERSION {
        return Err(format!(
            "a strata part of format {version}; this strata reads format {VERSION}"
        ));
    }
    let samples = get("samples")?;
    let samples = parse_ranges(&samples)
        .filter(|r| r.windows(2).all(|w| w[0].end <= w[1].start))
        .ok_or_else(|| format!("the part's `samples` are not sorted ranges: {samples}"))?;
    let sampler = get("sampler")?;
    let strategy = get("strategy")?;
    let settings = RenderSettings {
        pattern_spp: number("total-spp")?,
        max_depth: number("max-depth")?,
        sampler: SamplerKind::from_name(&sampler).ok_or(format!("unknown sampler {sampler}"))?,
        strategy: Strategy::from_name(&strategy).ok_or(format!("unknown strategy {strategy}"))?,
        seed: number("seed")?,
        calibrate: get("calibrate")? == "true",
    };
    let hash = get("scene-hash")?;
    let scene_hash = u64::from_str_radix(&hash, 16)
        .map_err(|_| format!("the part's `scene-hash` is not hex: {hash}"))?;
    if samples.last().is_some_and(|r| r.end > settings.pattern_spp) {
        return Err(format!(
            "the part holds samples beyond its total of {}",
            settings.pattern_spp
        ));
    }
    Ok(PartInfo {
        samples,
        settings,
        scene_hash,
        scene: get("scene")?,
    })
}

/// The f64 sums `sum.*` and `sum_sq.*` (`n` values each) from their bit halves.
#[allow(clippy::type_complexity)]
fn sums(channels: &Channels, n: usize) -> Result<(Vec<[f64; 3]>, Vec<[f64; 3]>), String> {
    let mut out = [vec![[0.0; 3]; n], vec![[0.0; 3]; n]];
    for (which, name) in ["sum", "sum_sq"].into_iter().enumerate() {
        for (c, rgb) in ["R", "G", "B"].into_iter().enumerate() {
            let hi = u32_channel(channels, &format!("{name}.{rgb}.hi"), n)?;
            let lo = u32_channel(channels, &format!("{name}.{rgb}.lo"), n)?;
            for i in 0..n {
                out[which][i][c] = f64::from_bits(((hi[i] as u64) << 32) | lo[i] as u64);
            }
        }
    }
    let [sum, sum_sq] = out;
    Ok((sum, sum_sq))
}

fn u32_channel(channels: &Channels, name: &str, n: usize) -> Result<Vec<u32>, String> {
    use exr::prelude::FlatSamples;
    let channel = channels
        .iter()
        .find(|c| c.name.eq(name))
        .ok_or_else(|| format!("the part has no `{name}` channel"))?;
    match &channel.sample_data {
        FlatSamples::U32(v) if v.len() == n => Ok(v.clone()),
        _ => Err(format!("the part's `{name}` channel is not {n} u32 values")),
    }
}

// ---------------------------------------------------------------------------------------------
// Merging
// ---------------------------------------------------------------------------------------------

/// Parts merged into one film.
#[derive(Clone, Debug)]
pub struct Merged {
    pub film: Film,
    /// What the merged film holds (its `samples` the union of the parts').
    pub info: PartInfo,
}

/// Why parts cannot be merged.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    #[error(transparent)]
    Read(#[from] FilmError),
    #[error("no parts to merge")]
    Empty,
    #[error("{}: {what} differs from {}'s ({theirs} vs {ours}): parts of different renders", path.display(), first.display())]
    Mismatch {
        path: PathBuf,
        first: PathBuf,
        what: &'static str,
        theirs: String,
        ours: String,
    },
    #[error("{} and {} both hold samples {}: a sample would be counted twice", a.display(), b.display(), format_ranges(std::slice::from_ref(overlap)))]
    Overlap {
        a: PathBuf,
        b: PathBuf,
        overlap: Range<u32>,
    },
    #[error("samples {} of {} are in no part: add the parts that hold them, or pass --allow-partial to merge what is here", format_ranges(missing), total)]
    Missing {
        missing: Vec<Range<u32>>,
        total: u32,
    },
}

/// Sum `parts` (path, film, info) into one film, exactly: the same sums as one render of the
/// union of their ranges, up to the order f64 additions are done in. The parts must be of one
/// scene and one set of settings and hold disjoint ranges; unless `allow_partial`, together
/// they must hold every sample `0..total-spp`.
pub fn merge(
    mut parts: Vec<(PathBuf, Film, PartInfo)>,
    allow_partial: bool,
) -> Result<Merged, MergeError> {
    if parts.is_empty() {
        return Err(MergeError::Empty);
    }
    // In sample order, so the sums are added in the same order however the parts are listed.
    parts.sort_by_key(|(_, _, info)| info.samples.first().map_or(0, |r| r.start));
    let (first_path, first_film, first_info) = &parts[0];
    for (path, film, info) in &parts[1..] {
        let mismatch = |what, theirs: String, ours: String| MergeError::Mismatch {
            path: path.clone(),
            first: first_path.clone(),
            what,
            theirs,
            ours,
        };
        let (a, b) = (&info.settings, &first_info.settings);
        let checks: [(&'static str, String, String); 8] = [
            (
                "scene (content hash)",
                format!("{:016x}", info.scene_hash),
                format!("{:016x}", first_info.scene_hash),
            ),
            (
                "film size",
                format!("{}×{}", film.width, film.height),
                format!("{}×{}", first_film.width, first_film.height),
            ),
            (
                "total spp",
                a.pattern_spp.to_string(),
                b.pattern_spp.to_string(),
            ),
            ("sampler", a.sampler.to_string(), b.sampler.to_string()),
            ("strategy", a.strategy.to_string(), b.strategy.to_string()),
            ("seed", a.seed.to_string(), b.seed.to_string()),
            (
                "max depth",
                a.max_depth.to_string(),
                b.max_depth.to_string(),
            ),
            (
                "calibration",
                a.calibrate.to_string(),
                b.calibrate.to_string(),
            ),
        ];
        if let Some((what, theirs, ours)) = checks.into_iter().find(|(_, t, o)| t != o) {
            return Err(mismatch(what, theirs, ours));
        }
    }
    // ---- Disjoint ranges ---------------------------------------------------------------------
    let mut ranges: Vec<(Range<u32>, &PathBuf)> = parts
        .iter()
        .flat_map(|(path, _, info)| info.samples.iter().map(move |r| (r.clone(), path)))
        .collect();
    ranges.sort_by_key(|(r, _)| (r.start, r.end));
    for w in ranges.windows(2) {
        let ((a, pa), (b, pb)) = (&w[0], &w[1]);
        if b.start < a.end {
            return Err(MergeError::Overlap {
                a: pa.to_path_buf(),
                b: pb.to_path_buf(),
                overlap: b.start..a.end.min(b.end),
            });
        }
    }
    // ---- The union, its gaps, and the sums -----------------------------------------------------
    let mut samples: Vec<Range<u32>> = Vec::new();
    for (r, _) in &ranges {
        match samples.last_mut() {
            Some(last) if last.end == r.start => last.end = r.end,
            _ => samples.push(r.clone()),
        }
    }
    let info = PartInfo {
        samples,
        ..first_info.clone()
    };
    let missing = info.missing();
    if !missing.is_empty() && !allow_partial {
        return Err(MergeError::Missing {
            missing,
            total: info.settings.pattern_spp,
        });
    }
    let mut film = Film::with_twins(first_film.width, first_film.height, first_film.has_twins());
    for (_, part, _) in &parts {
        film.merge(part);
    }
    film.first_sample = info.samples.first().map_or(0, |r| r.start);
    Ok(Merged { film, info })
}
