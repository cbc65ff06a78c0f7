//! Image output. Every file is written to a temporary sibling and renamed into place, so an
//! interrupted render never leaves a torn image behind.

use super::{Film, FilmError};
use std::path::{Path, PathBuf};

/// Run `write` on a temporary path next to `path`, then rename it over `path` (so no reader
/// sees a torn file, and a failed write leaves nothing).
pub fn atomically(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<(), FilmError> {
    let tmp = temp_sibling(path);
    if let Err(reason) = write(&tmp) {
        let _ = std::fs::remove_file(&tmp);
        return Err(FilmError::new(path, reason));
    }
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        FilmError::new(
            path,
            format!("cannot move the finished image into place: {e}"),
        )
    })
}

/// `dir/.name.PID.tmp.ext`: same directory (so rename is atomic), same extension (encoders
/// that look at it still work), hidden and unique per process.
fn temp_sibling(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.tmp.{ext}", std::process::id()))
}

pub(super) fn exr(film: &Film, path: &Path) -> Result<(), String> {
    use exr::prelude::*;
    let size = (film.width as usize, film.height as usize);
    let layer = Layer::new(
        size,
        exr_attributes(film),
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(exr_channels(film)),
    );
    Image::from_layer(layer)
        .write()
        .to_file(path)
        .map_err(|e| e.to_string())
}

/// The image channels of a film: `R, G, B` (the mean) and `var.R, var.G, var.B` (the
/// calibrated variance of the mean), f32.
pub(super) fn exr_channels(
    film: &Film,
) -> exr::prelude::SmallVec<[exr::prelude::AnyChannel<exr::prelude::FlatSamples>; 4]> {
    use exr::prelude::*;
    let n = film.sum.len();
    let mut mean = vec![vec![0.0f32; n]; 3];
    let mut var = vec![vec![0.0f32; n]; 3];
    let variances = film.variances();
    for i in 0..n {
        let (m, v) = (film.mean(i), variances[i]);
        for c in 0..3 {
            mean[c][i] = m[c] as f32;
            var[c][i] = v[c] as f32;
        }
    }
    let names = ["R", "G", "B"];
    let mut channels = SmallVec::<[AnyChannel<FlatSamples>; 4]>::new();
    for (c, (m, v)) in mean.into_iter().zip(var).enumerate() {
        channels.push(AnyChannel::new(names[c], FlatSamples::F32(m)));
        channels.push(AnyChannel::new(
            format!("var.{}", names[c]).as_str(),
            FlatSamples::F32(v),
        ));
    }
    channels
}

/// The header of a film's image: a comment saying what the channels are, `spp` and the
/// film-wide calibration ratio `kappa`.
pub(super) fn exr_attributes(film: &Film) -> exr::prelude::LayerAttributes {
    use exr::prelude::*;
    let mut attributes = LayerAttributes::named("strata");
    attributes.comments = Some(Text::from(
        "strata render: RGB = per-pixel mean radiance; var.* = calibrated variance of that \
         mean (per-sample variance scaled by the ratio kappa measured on twin pixels' \
         independent randomizations)",
    ));
    attributes.other.insert(
        Text::from("spp"),
        AttributeValue::I32(film.spp().min(i32::MAX as u32) as i32),
    );
    let kappa = film.calibration().film;
    attributes.other.insert(
        Text::from("kappa"),
        AttributeValue::FloatVec3((kappa[0] as f32, kappa[1] as f32, kappa[2] as f32)),
    );
    attributes
}

pub(super) fn png(film: &Film, path: &Path) -> Result<(), String> {
    let mut bytes = Vec::with_capacity(film.sum.len() * 3);
    for i in 0..film.sum.len() {
        bytes.extend(film.mean(i).map(|v| srgb_byte(v as f32)));
    }
    image::save_buffer_with_format(
        path,
        &bytes,
        film.width,
        film.height,
        image::ColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .map_err(|e| e.to_string())
}

/// Linear value → 8-bit sRGB (IEC 61966-2-1), clamped; NaN maps to 0.
pub fn srgb_byte(linear: f32) -> u8 {
    let v = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    let s = if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}
