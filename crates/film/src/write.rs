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
    exr_file(path, |out| {
        Image::from_layer(layer).write().to_buffered(out)
    })
}

/// Encode an EXR image with `encode` into memory, put its header attributes in name order
/// ([`sort_exr_attributes`]) and write the bytes to `path`: the same film always gives the
/// same file.
pub(super) fn exr_file(
    path: &Path,
    encode: impl FnOnce(&mut std::io::Cursor<Vec<u8>>) -> exr::error::UnitResult,
) -> Result<(), String> {
    let mut out = std::io::Cursor::new(Vec::new());
    encode(&mut out).map_err(|e| e.to_string())?;
    let mut bytes = out.into_inner();
    sort_exr_attributes(&mut bytes)?;
    std::fs::write(path, bytes).map_err(|e| e.to_string())
}

/// Put the attributes of every header of an OpenEXR file in name order, in place. The exr
/// crate writes a layer's custom attributes (`spp`, `kappa`, a part's description) in the
/// order of a randomly seeded hash map, so two writes of one film differed in their header
/// bytes; OpenEXR's own library writes attributes sorted by name. Each header keeps its
/// length, so the offset tables after the headers stay valid.
///
/// Layout (OpenEXR file layout): magic `76 2f 31 01`, a 4-byte version field (bit 12: multi-
/// part), then headers, each a list of attributes (name NUL, type NUL, 4-byte little-endian
/// size, value) closed by a NUL byte; a multi-part file closes its list of headers by one more
/// NUL.
pub(super) fn sort_exr_attributes(bytes: &mut [u8]) -> Result<(), String> {
    let broken = |what: &str| format!("cannot order the EXR header attributes: {what}");
    if bytes.len() < 8 || bytes[..4] != [0x76, 0x2f, 0x31, 0x01] {
        return Err(broken("not an OpenEXR file"));
    }
    let multipart = bytes[5] & 0x10 != 0;
    let nul_after = |bytes: &[u8], from: usize| {
        bytes
            .get(from..)
            .and_then(|rest| rest.iter().position(|&b| b == 0))
            .map(|i| from + i)
            .ok_or_else(|| broken("a name runs past the end"))
    };
    let mut pos = 8;
    loop {
        let start = pos;
        // (start, end of name, end) of each attribute.
        let mut attributes = Vec::new();
        while *bytes
            .get(pos)
            .ok_or_else(|| broken("a header runs past the end"))?
            != 0
        {
            let name_end = nul_after(bytes, pos)?;
            let type_end = nul_after(bytes, name_end + 1)?;
            let size = bytes
                .get(type_end + 1..type_end + 5)
                .ok_or_else(|| broken("an attribute size runs past the end"))?;
            let size = i32::from_le_bytes(size.try_into().expect("four bytes"));
            let end = usize::try_from(size)
                .ok()
                .map(|size| type_end + 5 + size)
                .filter(|&end| end <= bytes.len())
                .ok_or_else(|| broken("an attribute value runs past the end"))?;
            attributes.push((pos, name_end, end));
            pos = end;
        }
        let mut sorted = attributes.clone();
        sorted.sort_by(|a, b| bytes[a.0..a.1].cmp(&bytes[b.0..b.1]));
        if sorted != attributes {
            let ordered: Vec<u8> = sorted
                .iter()
                .flat_map(|&(a, _, end)| bytes[a..end].iter().copied())
                .collect();
            bytes[start..pos].copy_from_slice(&ordered);
        }
        pos += 1;
        if !multipart || bytes.get(pos) == Some(&0) {
            return Ok(());
        }
    }
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
        AttributeValue::I32(film.held_spp().min(i32::MAX as u32) as i32),
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

#[cfg(test)]
mod tests {
    use super::sort_exr_attributes;

    /// One attribute as OpenEXR lays it out.
    fn attribute(name: &str, kind: &str, value: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        for text in [name, kind] {
            out.extend(text.as_bytes());
            out.push(0);
        }
        out.extend((value.len() as i32).to_le_bytes());
        out.extend(value);
        out
    }

    fn file(multipart: bool, headers: &[Vec<Vec<u8>>], tail: &[u8]) -> Vec<u8> {
        let mut out = vec![
            0x76,
            0x2f,
            0x31,
            0x01,
            2,
            if multipart { 0x10 } else { 0 },
            0,
            0,
        ];
        for header in headers {
            out.extend(header.concat());
            out.push(0);
        }
        if multipart {
            out.push(0);
        }
        out.extend(tail);
        out
    }

    #[test]
    fn attributes_are_put_in_name_order_and_nothing_else_moves() {
        let (a, b, c) = (
            attribute("spp", "int", &[64, 0, 0, 0]),
            attribute("kappa", "v3f", &[0; 12]),
            attribute("channels", "chlist", &[b'R', 0, 0, 0]),
        );
        let tail = [9, 8, 7, 0, 0, 6];
        let mut bytes = file(false, &[vec![a.clone(), b.clone(), c.clone()]], &tail);
        sort_exr_attributes(&mut bytes).unwrap();
        assert_eq!(
            bytes,
            file(false, &[vec![c.clone(), b.clone(), a.clone()]], &tail)
        );
        // Multi-part: every header on its own; the offset tables after them untouched.
        let d = attribute("name", "string", b"twins");
        let mut bytes = file(
            true,
            &[vec![a.clone(), c.clone()], vec![d.clone(), b.clone()]],
            &tail,
        );
        sort_exr_attributes(&mut bytes).unwrap();
        assert_eq!(bytes, file(true, &[vec![c, a], vec![b, d]], &tail));
    }

    #[test]
    fn a_broken_file_is_an_error_not_a_panic() {
        let a = attribute("spp", "int", &[64, 0, 0, 0]);
        let whole = file(false, &[vec![a.clone(), a]], &[]);
        for cut in 0..whole.len() - 1 {
            assert!(
                sort_exr_attributes(&mut whole[..cut].to_vec()).is_err(),
                "cut at {cut}"
            );
        }
        let mut huge = file(false, &[vec![attribute("spp", "int", &[64, 0, 0, 0])]], &[]);
        huge[8 + 8..8 + 12].copy_from_slice(&i32::MAX.to_le_bytes());
        assert!(sort_exr_attributes(&mut huge).is_err());
    }
}
