//! Environment maps: an HDR image of the radiance arriving from every direction, in
//! latitude–longitude (equirectangular) layout exactly as Mitsuba 3's `envmap` reads it, so that
//! the two renderers' images can be compared pixel by pixel.
//!
//! A direction `d` in the map's frame has `θ = acos(d.y)`, `φ = atan2(d.x, −d.z)`, and image
//! coordinates `u = φ / 2π` (wrapped to [0, 1)) and `v = θ / π`: the top row looks up (+y), the
//! image's centre column looks along −z. The radiance is the bilinear interpolation of the
//! texels at `x = u·W − ½` (texel centres at `(i + ½) / W`, wrapping around in φ) and
//! `y = v·(H − 1)` (the first row's centre at the upper pole, the last row's at the lower one).
//!
//! Importance sampling uses a piecewise-constant distribution over a `W × H` grid of cells in
//! `(u, v)` ([`stratapt_sampling::warp::piecewise`]) whose weights are the largest luminance
//! among the texels a cell's bilinear lookup reads, times `sin θ` at the cell's centre (the
//! solid angle of the cell): never 0 where the radiance is not, so light sampling alone is
//! unbiased. The solid-angle density of a direction is the cell's density over `(u, v)` divided
//! by `2π² sin θ`.
//!
//! Both renderers read the map from [`crate::FlatScene::tables`] at the light's offset: the
//! texels (RGB, row-major from the top row) followed by the distribution's tables.
//!
//! pbrt-v4's equal-area octahedral square maps are the other layout ([`octahedral`]).

pub mod octahedral;

use crate::light_table::luminance;
use glam::{Vec2, Vec3};
use std::f32::consts::{PI, TAU};
use stratapt_sampling::atan::atan2;
use stratapt_sampling::warp::piecewise;

/// The `(u, v)` of direction `d` (unit, in the map's frame). θ is `atan2(√(x² + z²), y)`
/// (Mitsuba's `acos(y)`, without its loss of precision near the poles), both angles by
/// [`atan2`], which the kernel evaluates alike.
pub fn direction_to_uv(d: Vec3) -> Vec2 {
    let u = atan2(d.x, -d.z) * (0.5 / PI);
    let u = u - u.floor();
    let v = atan2((d.x * d.x + d.z * d.z).sqrt(), d.y) * (1.0 / PI);
    Vec2::new(if u >= 1.0 { 0.0 } else { u }, v)
}

/// The direction (in the map's frame) at `(u, v)`, with `sin θ`.
pub fn uv_to_direction(uv: Vec2) -> (Vec3, f32) {
    let (sin_theta, cos_theta) = (PI * uv.y).sin_cos();
    let (sin_phi, cos_phi) = (TAU * uv.x).sin_cos();
    (
        Vec3::new(sin_phi * sin_theta, cos_theta, -cos_phi * sin_theta),
        sin_theta,
    )
}

/// The bilinear radiance of `texels` (`w × h` RGB, `w, h ≥ 2`) at `(u, v)`.
pub fn lookup(texels: &[f32], w: usize, h: usize, uv: Vec2) -> Vec3 {
    let (x, y) = texel_position(w, h, uv);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let col = |i: f32| (i as i64).rem_euclid(w as i64) as usize;
    let (c0, c1) = (col(x0), col(x0 + 1.0));
    let r0 = (y0 as usize).min(h - 1);
    let r1 = (r0 + 1).min(h - 1);
    let texel = |r: usize, c: usize| Vec3::from_slice(&texels[3 * (r * w + c)..]);
    let top = texel(r0, c0) * (1.0 - fx) + texel(r0, c1) * fx;
    let bottom = texel(r1, c0) * (1.0 - fx) + texel(r1, c1) * fx;
    top * (1.0 - fy) + bottom * fy
}

/// Continuous texel coordinates of `(u, v)`: x in `[−½, W − ½)`, y in `[0, H − 1]`.
fn texel_position(w: usize, h: usize, uv: Vec2) -> (f32, f32) {
    let v = uv.y.clamp(0.0, 1.0);
    (uv.x * w as f32 - 0.5, v * (h - 1) as f32)
}

/// The sampling weights of a `w × h` map's cells (see the module's documentation).
pub fn weights(texels: &[f32], w: usize, h: usize) -> Vec<f32> {
    let lum: Vec<f32> = texels
        .chunks(3)
        .map(|c| luminance([c[0], c[1], c[2]]).max(0.0) as f32)
        .collect();
    let mut out = Vec::with_capacity(w * h);
    for j in 0..h {
        // Rows the cell's v range [j/H, (j+1)/H] reads: y from j (H−1)/H to (j+1)(H−1)/H.
        let y_lo = (j as f32 * (h - 1) as f32 / h as f32).floor() as usize;
        let y_hi = (((j + 1) as f32 * (h - 1) as f32 / h as f32).ceil() as usize).min(h - 1);
        let sin_theta = (PI * (j as f32 + 0.5) / h as f32).sin();
        for i in 0..w {
            // Columns its u range reads: x from i − ½ to i + ½, so i − 1, i and i + 1.
            let mut max = 0.0f32;
            for r in y_lo..=y_hi {
                for c in [i + w - 1, i, i + 1] {
                    max = max.max(lum[r * w + c % w]);
                }
            }
            out.push(max * sin_theta);
        }
    }
    out
}

/// An environment map ready for the renderers: its texels and its distribution, one array.
pub struct EnvironmentMap {
    pub width: usize,
    pub height: usize,
    /// Texels (RGB) then the distribution's tables.
    pub data: Vec<f32>,
    /// Mean radiance over the sphere of directions, `∫ L dω / 4π` (for the light's power).
    pub mean_radiance: [f32; 3],
}

impl EnvironmentMap {
    /// From `texels` (`w × h` RGB, finite, `≥ 0`, `w, h ≥ 2`); `None` when all black.
    pub fn new(texels: Vec<f32>, w: usize, h: usize) -> Option<Self> {
        let weights = weights(&texels, w, h);
        let tables = piecewise::build(&weights, w, h)?;
        // ∫ L dω ≈ Σ L(texel) sin θ ΔθΔφ over the rows' centres θ = π j / (H − 1).
        let mut sum = [0.0f64; 3];
        for j in 0..h {
            let sin_theta = (std::f64::consts::PI * j as f64 / (h - 1) as f64).sin();
            for c in texels[3 * j * w..3 * (j + 1) * w].chunks(3) {
                for k in 0..3 {
                    sum[k] += f64::from(c[k]) * sin_theta;
                }
            }
        }
        let d_omega = (std::f64::consts::PI / (h - 1) as f64) * (std::f64::consts::TAU / w as f64);
        let mean_radiance = sum.map(|s| (s * d_omega / (4.0 * std::f64::consts::PI)) as f32);
        let mut data = texels;
        data.extend(tables);
        Some(Self {
            width: w,
            height: h,
            data,
            mean_radiance,
        })
    }
}

/// Split a map's `data` (as in [`EnvironmentMap::data`]) into texels and distribution tables.
pub fn split(data: &[f32], w: usize, h: usize) -> (&[f32], &[f32]) {
    let (texels, rest) = data.split_at(3 * w * h);
    (texels, &rest[..piecewise::len(w, h)])
}

/// Entries of a `w × h` map's data.
pub fn data_len(w: usize, h: usize) -> usize {
    3 * w * h + piecewise::len(w, h)
}

/// A direction sampled from the map's data, in the map's frame, with its solid-angle density;
/// `None` at the poles (`sin θ = 0`) or in a cell of density 0.
pub fn sample(data: &[f32], w: usize, h: usize, u: Vec2) -> Option<(Vec3, f32)> {
    let (_, tables) = split(data, w, h);
    let (uv, density) = piecewise::sample(tables, w, h, u)?;
    let (d, sin_theta) = uv_to_direction(uv);
    let pdf = density / (2.0 * PI * PI * sin_theta);
    (sin_theta > 0.0 && pdf.is_finite()).then_some((d, pdf))
}

/// The solid-angle density of [`sample`] for `d` (unit, in the map's frame).
pub fn pdf(data: &[f32], w: usize, h: usize, d: Vec3) -> f32 {
    let (_, tables) = split(data, w, h);
    let sin_theta = (d.x * d.x + d.z * d.z).sqrt();
    if !(sin_theta > 0.0) {
        return 0.0;
    }
    let density = piecewise::pdf(tables, w, h, direction_to_uv(d));
    density / (2.0 * PI * PI * sin_theta)
}

/// The radiance of the map's data along `d` (unit, in the map's frame).
pub fn radiance(data: &[f32], w: usize, h: usize, d: Vec3) -> Vec3 {
    let (texels, _) = split(data, w, h);
    lookup(texels, w, h, direction_to_uv(d))
}

/// Read an HDR image as linear RGB texels (row-major from the top row) with its width and
/// height: OpenEXR (`.exr`, its first RGB(A) layer), Radiance (`.hdr`) and portable float maps
/// (`.pfm`, colour or grey, either byte order). The error says what is wrong, without the path.
pub fn read_image(path: &std::path::Path) -> Result<(Vec<f32>, usize, usize), String> {
    let Some((texels, w, h)) = read_float_image(path)? else {
        return Err(format!(
            "an environment map is an HDR image: .exr, .hdr or .pfm, not `.{}`",
            extension(path)
        ));
    };
    check_map_size(w, h)?;
    check_texels(&texels, w, "radiance")?;
    Ok((texels, w, h))
}

/// Most texels on a side of an environment map: the kernel reads the size as an f32 (exact to
/// 2²⁴) and divides by it as an i32, and its binary searches add two indices in a u32.
pub const MAX_MAP_SIDE: usize = 1 << 24;

/// An error unless a `w`×`h` environment map is 2×2 to [`MAX_MAP_SIDE`] a side.
fn check_map_size(w: usize, h: usize) -> Result<(), String> {
    if w < 2 || h < 2 {
        return Err(format!(
            "{w}×{h} texels: an environment map needs at least 2×2"
        ));
    }
    if w > MAX_MAP_SIDE || h > MAX_MAP_SIDE {
        return Err(format!(
            "{w}×{h} texels: an environment map has at most {MAX_MAP_SIDE} a side"
        ));
    }
    Ok(())
}

/// An error naming the first texel of an RGB image `w` texels wide that is not finite and
/// `≥ 0`, where it is and what `quantity` (radiance, texels) must be.
pub fn check_texels(texels: &[f32], w: usize, quantity: &str) -> Result<(), String> {
    match texels.iter().position(|x| !(x.is_finite() && *x >= 0.0)) {
        Some(bad) => {
            let texel = bad / 3;
            Err(format!(
                "texel ({}, {}) holds {}: {quantity} must be finite and ≥ 0",
                texel % w,
                texel / w,
                texels[bad]
            ))
        }
        None => Ok(()),
    }
}

/// A float image (`.exr`, `.hdr`, `.pfm`, by the extension in any case) as linear RGB texels,
/// row-major from the top row, with its width and height; `None` for another extension. The
/// error says what is wrong, without the path; the texels are not checked.
pub fn read_float_image(
    path: &std::path::Path,
) -> Result<Option<(Vec<f32>, usize, usize)>, String> {
    Ok(Some(match extension(path).as_str() {
        "exr" => read_exr(path)?,
        "hdr" => {
            let image = image::open(path).map_err(|e| e.to_string())?.into_rgb32f();
            let (w, h) = (image.width() as usize, image.height() as usize);
            (image.into_raw(), w, h)
        }
        "pfm" => read_pfm(&std::fs::read(path).map_err(|e| e.to_string())?)?,
        _ => return Ok(None),
    }))
}

/// `path`'s extension in lower case ("" without one).
pub fn extension(path: &std::path::Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default()
}

fn read_exr(path: &std::path::Path) -> Result<(Vec<f32>, usize, usize), String> {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
        |resolution, _| {
            (
                vec![0.0f32; 3 * resolution.width() * resolution.height()],
                resolution.width(),
            )
        },
        |(texels, w), position, (r, g, b, _): (f32, f32, f32, f32)| {
            let i = 3 * (position.y() * *w + position.x());
            texels[i..i + 3].copy_from_slice(&[r, g, b]);
        },
    )
    .map_err(|e| e.to_string())?;
    let size = image.layer_data.size;
    let (texels, _) = image.layer_data.channel_data.pixels;
    Ok((texels, size.width(), size.height()))
}

/// A portable float map: `PF` (RGB) or `Pf` (grey), width and height, a scale whose sign is the
/// byte order (negative: little-endian), then the rows from the bottom up.
fn read_pfm(bytes: &[u8]) -> Result<(Vec<f32>, usize, usize), String> {
    let mut fields = Vec::new();
    let mut at = 0;
    while fields.len() < 4 {
        while at < bytes.len() && bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        let start = at;
        while at < bytes.len() && !bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        if start == at {
            return Err("a truncated PFM header".into());
        }
        fields.push(String::from_utf8_lossy(&bytes[start..at]).into_owned());
    }
    at += 1; // the single whitespace byte after the scale
    let channels = match fields[0].as_str() {
        "PF" => 3,
        "Pf" => 1,
        other => return Err(format!("not a PFM file (starts with `{other}`)")),
    };
    let parse = |s: &str, what: &str| {
        s.parse::<usize>()
            .map_err(|_| format!("PFM {what} `{s}` is not a number"))
    };
    let (w, h) = (parse(&fields[1], "width")?, parse(&fields[2], "height")?);
    let scale: f32 = fields[3]
        .parse()
        .map_err(|_| format!("PFM scale `{}` is not a number", fields[3]))?;
    let data = &bytes[at.min(bytes.len())..];
    let count = w * h * channels;
    if data.len() < 4 * count {
        return Err(format!(
            "PFM data holds {} bytes, {w}×{h}×{channels} floats need {}",
            data.len(),
            4 * count
        ));
    }
    let value = |i: usize| {
        let b: [u8; 4] = data[4 * i..4 * i + 4].try_into().unwrap();
        if scale < 0.0 {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        }
    };
    let mut texels = Vec::with_capacity(3 * w * h);
    for row in (0..h).rev() {
        for col in 0..w {
            let i = (row * w + col) * channels;
            match channels {
                3 => texels.extend([value(i), value(i + 1), value(i + 2)]),
                _ => texels.extend([value(i); 3]),
            }
        }
    }
    Ok((texels, w, h))
}

/// Write `texels` (`w × h` RGB, top row first) as a little-endian colour PFM (for tests and the
/// scripts that make the bundled maps).
pub fn pfm_bytes(texels: &[f32], w: usize, h: usize) -> Vec<u8> {
    let mut out = format!("PF\n{w} {h}\n-1.0\n").into_bytes();
    for row in (0..h).rev() {
        for x in &texels[3 * row * w..3 * (row + 1) * w] {
            out.extend(x.to_le_bytes());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_map_is_two_to_two_to_the_24_texels_a_side() {
        assert!(check_map_size(2, 2).is_ok());
        assert!(check_map_size(MAX_MAP_SIDE, 2).is_ok());
        assert!(check_map_size(1, 4).unwrap_err().contains("at least 2×2"));
        let wide = check_map_size(MAX_MAP_SIDE + 1, 2).unwrap_err();
        assert!(wide.contains("at most 16777216 a side"), "{wide}");
    }

    #[test]
    fn directions_and_uv_round_trip_and_follow_mitsubas_axes() {
        // Up is the top row, −z the centre column, +x a quarter turn to the right.
        assert!((direction_to_uv(Vec3::Y).y).abs() < 1e-6);
        assert!((direction_to_uv(-Vec3::Z) - Vec2::new(0.0, 0.5)).length() < 1e-6);
        assert!((direction_to_uv(Vec3::X) - Vec2::new(0.25, 0.5)).length() < 1e-6);
        assert!((direction_to_uv(Vec3::Z) - Vec2::new(0.5, 0.5)).length() < 1e-6);
        for i in 0..100 {
            let uv = Vec2::new((i as f32 * 0.37).fract(), (i as f32 + 0.5) / 100.0);
            let (d, _) = uv_to_direction(uv);
            let back = direction_to_uv(d);
            let du = (back.x - uv.x).abs().min(1.0 - (back.x - uv.x).abs());
            assert!(
                du < 1e-5 && (back.y - uv.y).abs() < 1e-5,
                "{uv} → {d} → {back}"
            );
        }
    }

    #[test]
    fn lookup_is_bilinear_between_texel_centres_and_wraps_in_phi() {
        // 4 × 3, texel value = 10 r + c.
        let texels: Vec<f32> = (0..3)
            .flat_map(|r| (0..4).flat_map(move |c| [(10 * r + c) as f32; 3]))
            .collect();
        let at = |u: f32, v: f32| lookup(&texels, 4, 3, Vec2::new(u, v)).x;
        assert!((at(0.125, 0.0) - 0.0).abs() < 1e-5); // texel (0, 0)'s centre, top row
        assert!((at(0.375, 0.5) - 11.0).abs() < 1e-5); // texel (1, 1)
        assert!((at(0.25, 1.0) - 20.5).abs() < 1e-5); // between (2, 0) and (2, 1)
                                                      // u = 0: halfway between the last column and the first.
        assert!((at(0.0, 0.0) - 1.5).abs() < 1e-5);
    }

    #[test]
    fn weights_cover_every_direction_with_radiance() {
        // A single bright texel: every cell whose lookup reads it has weight.
        let (w, h) = (8, 5);
        let mut texels = vec![0.0; 3 * w * h];
        texels[3 * (2 * w + 7)..][..3].copy_from_slice(&[1.0, 1.0, 1.0]);
        let weights = weights(&texels, w, h);
        for j in 0..200 {
            for i in 0..400 {
                let uv = Vec2::new((i as f32 + 0.5) / 400.0, (j as f32 + 0.5) / 200.0);
                let l = lookup(&texels, w, h, uv).x;
                let cell = ((uv.y * h as f32) as usize) * w + (uv.x * w as f32) as usize;
                assert!(
                    l == 0.0 || weights[cell] > 0.0,
                    "{uv}: radiance {l}, no weight"
                );
            }
        }
    }
}
