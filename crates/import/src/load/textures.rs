//! Named textures (`[textures.NAME]`) → texture records and texels in
//! [`stratapt_scene::FlatScene::tables`] ([`stratapt_scene::texture`]).

use super::validate::{Ctx, Result};
use crate::desc::Spanned;
use crate::desc::{CheckerboardDesc, ImageTextureDesc, Pair, TextureDesc, Triple};
use std::collections::HashMap;
use std::ops::Range;
use std::path::Path;
use stratapt_scene::records::{
    texel_format, texture_flag, texture_kind, texture_wrap, Texture, TEXTURE_WORDS,
};
use stratapt_scene::texture;

/// The scene's textures. Their records are the first words of `tables` (so that a record's
/// index is small), their texels the last ([`Textures::place`]: the materials' and the
/// environment map's tables, whose offsets the records hold as exact floats, come first).
#[derive(Default)]
pub struct Textures {
    by_name: HashMap<String, u32>,
    names: Vec<String>,
    records: Vec<Texture>,
    /// The texels and decode tables, at the records' offsets less where they will be placed.
    data: Vec<f32>,
    /// Per texture: the largest and smallest channel value it can return, and its mean (the
    /// luminance averaged over the texels, as Mitsuba 3's `mean()`), each of the clamped
    /// values for a texture that clamps its lookups.
    pub stats: Vec<TextureStats>,
}

/// What validation and a plastic's lobe weight need to know of a texture's values.
#[derive(Clone, Copy, Debug, Default)]
pub struct TextureStats {
    pub min: f32,
    pub max: f32,
    pub mean: f32,
}

impl Textures {
    /// Validate and load the `[textures.NAME]` tables.
    pub fn from_descs(
        ctx: &Ctx,
        descs: &[(Spanned<String>, TextureDesc)],
        base_dir: &Path,
    ) -> Result<Self> {
        let mut out = Textures::default();
        let mut decode = None;
        let mut files = HashMap::new();
        for (name, desc) in descs {
            let (record, stats) = match desc {
                TextureDesc::Image(d) => {
                    image(ctx, d, base_dir, &mut out.data, &mut decode, &mut files)?
                }
                TextureDesc::Checkerboard(d) => checkerboard(ctx, d)?,
            };
            if out.data.len() > (u32::MAX / 2) as usize {
                return Err(ctx.err(name.span(), "the textures exceed 2³¹ words (8 GiB)"));
            }
            out.by_name
                .insert(name.get_ref().clone(), out.records.len() as u32);
            out.names.push(name.get_ref().clone());
            out.records.push(record);
            out.stats.push(stats);
        }
        Ok(out)
    }

    /// The tables that start with room for the records.
    pub fn tables(&self) -> Vec<f32> {
        vec![0.0; TEXTURE_WORDS * self.records.len()]
    }

    /// Append the texels to `tables` (which [`Textures::tables`] started) and write the records,
    /// their offsets moved there.
    pub fn place(self, ctx: &Ctx, tables: &mut Vec<f32>) -> Result<()> {
        let base = tables.len();
        if base + self.data.len() > u32::MAX as usize {
            return Err(ctx.file_err("the scene's tables and textures exceed 2³² words"));
        }
        tables.extend_from_slice(&self.data);
        for (i, mut record) in self.records.into_iter().enumerate() {
            if record.tag & 0xff == texture_kind::IMAGE {
                record.texels += base as u32;
                record.decode += base as u32;
            }
            let words: &[f32] = bytemuck::cast_slice(std::slice::from_ref(&record));
            tables[TEXTURE_WORDS * i..][..TEXTURE_WORDS].copy_from_slice(words);
        }
        Ok(())
    }

    /// Bytes of the textures' records, texels and decode tables.
    pub fn bytes(&self) -> usize {
        4 * (TEXTURE_WORDS * self.records.len() + self.data.len())
    }

    /// Texture `i`'s record (its texel offsets not yet placed).
    pub fn record(&self, i: u32) -> &Texture {
        &self.records[i as usize]
    }

    /// The index of the texture a material parameter names.
    pub fn lookup(&self, ctx: &Ctx, span: Range<usize>, name: &str) -> Result<u32> {
        match self.by_name.get(name) {
            Some(&i) => Ok(i),
            None => {
                let known = match self.names.is_empty() {
                    true => "none defined".to_string(),
                    false => self.names.join(", "),
                };
                Err(ctx.err(
                    span,
                    format!("unknown texture `{name}`; known textures: {known}"),
                ))
            }
        }
    }
}

/// An image file's texels once placed in the tables: where, and how they are stored.
#[derive(Clone, Copy)]
struct Placed {
    texels: u32,
    width: u32,
    height: u32,
    format: u32,
}

/// An `image` texture: its texels appended to `tables` unless another texture read the same
/// file the same way (`files`, by path and `raw`, remembers where), and the decode tables, once,
/// for 8-bit images (`decode` remembers where).
fn image(
    ctx: &Ctx,
    d: &ImageTextureDesc,
    base_dir: &Path,
    tables: &mut Vec<f32>,
    decode: &mut Option<u32>,
    files: &mut HashMap<(std::path::PathBuf, bool), Placed>,
) -> Result<(Texture, TextureStats)> {
    let file = d.file.get_ref();
    let path = base_dir.join(file);
    let fail = |reason: String| {
        ctx.err(
            d.file.span(),
            format!("texture `{file}` ({}): {reason}", path.display()),
        )
    };
    let raw = d.raw == Some(true);
    let placed = match files.get(&(path.clone(), raw)) {
        Some(&placed) => placed,
        None => {
            let loaded = read(&path, raw).map_err(fail)?;
            let placed = Placed {
                texels: tables.len() as u32,
                width: loaded.width,
                height: loaded.height,
                format: loaded.format,
            };
            tables.extend_from_slice(&loaded.words);
            files.insert((path.clone(), raw), placed);
            placed
        }
    };
    let scale = match &d.scale {
        Some(s) => ctx.non_negative3(s, "scale")?,
        None => [1.0; 3],
    };
    let wrap = match &d.wrap {
        Some(w) => ctx.one_of(w, "wrap", &["repeat", "clamp", "mirror"], |s| match s {
            "repeat" => Some(texture_wrap::REPEAT),
            "clamp" => Some(texture_wrap::CLAMP),
            "mirror" => Some(texture_wrap::MIRROR),
            _ => None,
        })?,
        None => texture_wrap::REPEAT,
    };
    let (uv_u, uv_v) = uv_transform(ctx, &d.uv_scale, &d.uv_offset, &d.uv_transform)?;
    let decode_at = match placed.format {
        texel_format::SRGB8 | texel_format::LINEAR8 => {
            let at = *decode.get_or_insert_with(|| {
                let at = tables.len() as u32;
                tables.extend_from_slice(&texture::decode_tables());
                at
            });
            // The linear table follows the sRGB one.
            at + 256 * (placed.format == texel_format::LINEAR8) as u32
        }
        _ => 0,
    };
    let clamp = d.clamp == Some(true);
    let record = Texture {
        tag: texture::tag(texture_kind::IMAGE, placed.format, wrap)
            | if clamp { texture_flag::CLAMP } else { 0 },
        texels: placed.texels,
        width: placed.width,
        height: placed.height,
        uv_u,
        decode: decode_at,
        uv_v,
        value: scale,
        ..Texture::default()
    };
    Ok((record, image_stats(tables, placed, scale, clamp)))
}

/// The stats of an image's scaled values (clamped to `[0, 1]` when `clamp`), from its decoded
/// texels: a lookup interpolates texels, so it reads nothing beyond them.
fn image_stats(tables: &[f32], placed: Placed, scale: [f32; 3], clamp: bool) -> TextureStats {
    let decoded = texture::decode_tables();
    let mut stats = TextureStats {
        min: f32::INFINITY,
        max: 0.0,
        mean: 0.0,
    };
    let mut sum = 0.0f64;
    let count = placed.width as usize * placed.height as usize;
    let words = &tables[placed.texels as usize..];
    for i in 0..count {
        let rgb = match placed.format {
            texel_format::RGB32F => [0, 1, 2].map(|k| words[3 * i + k]),
            texel_format::GREY32F => [words[i]; 3],
            _ => {
                let word = words[i].to_bits();
                let base = 256 * (placed.format == texel_format::LINEAR8) as usize;
                [0, 8, 16].map(|s| decoded[base + ((word >> s) & 0xff) as usize])
            }
        };
        let scaled: [f32; 3] = std::array::from_fn(|k| match clamp {
            true => (rgb[k] * scale[k]).clamp(0.0, 1.0),
            false => rgb[k] * scale[k],
        });
        for x in scaled {
            stats.min = stats.min.min(x);
            stats.max = stats.max.max(x);
        }
        sum += stratapt_scene::light_table::luminance(scaled);
    }
    stats.mean = (sum / count as f64) as f32;
    stats
}

/// A `checkerboard` texture.
fn checkerboard(ctx: &Ctx, d: &CheckerboardDesc) -> Result<(Texture, TextureStats)> {
    let color = |c: &Option<Spanned<Triple>>, key, default| match c {
        Some(c) => ctx.non_negative3(c, key),
        None => Ok([default; 3]),
    };
    let value = color(&d.color0, "color0", 0.4)?;
    let other = color(&d.color1, "color1", 0.2)?;
    let (uv_u, uv_v) = uv_transform(ctx, &d.uv_scale, &d.uv_offset, &d.uv_transform)?;
    let all = value.iter().chain(&other);
    // Mitsuba's mean: the two colours' mean channel values, averaged.
    let mean3 = |c: [f32; 3]| (c[0] + c[1] + c[2]) / 3.0;
    let stats = TextureStats {
        min: all.clone().fold(f32::INFINITY, |a, &b| a.min(b)),
        max: all.fold(0.0, |a, &b| a.max(b)),
        mean: 0.5 * (mean3(value) + mean3(other)),
    };
    let record = Texture {
        tag: texture::tag(texture_kind::CHECKERBOARD, 0, 0),
        uv_u,
        uv_v,
        value,
        other,
        ..Texture::default()
    };
    Ok((record, stats))
}

/// The uv transform's two rows from `uv_scale` / `uv_offset`, or `uv_transform` (not both).
fn uv_transform(
    ctx: &Ctx,
    scale: &Option<Spanned<Pair>>,
    offset: &Option<Spanned<Pair>>,
    transform: &Option<Spanned<[[f64; 3]; 2]>>,
) -> Result<([f32; 3], [f32; 3])> {
    if let Some(t) = transform {
        if let Some(other) = scale
            .as_ref()
            .map(|s| s.span())
            .or(offset.as_ref().map(|o| o.span()))
        {
            return Err(ctx.err(
                other,
                "give `uv_transform`, or `uv_scale` and `uv_offset`, not both",
            ));
        }
        let [u, v] = t.get_ref();
        let u = ctx.finite3(*u, t.span(), "uv_transform")?;
        let v = ctx.finite3(*v, t.span(), "uv_transform")?;
        return Ok((u.to_array(), v.to_array()));
    }
    let pair = |p: &Option<Spanned<Pair>>, key, default: f64| -> Result<[f32; 2]> {
        let Some(p) = p else {
            return Ok([default as f32; 2]);
        };
        let [a, b] = p.get_ref().0;
        let v = ctx.finite3([a, b, 0.0], p.span(), key)?;
        Ok([v.x, v.y])
    };
    let [su, sv] = pair(scale, "uv_scale", 1.0)?;
    let [du, dv] = pair(offset, "uv_offset", 0.0)?;
    Ok(([su, 0.0, du], [0.0, sv, dv]))
}

/// An image file's texels as a texture stores them.
struct Loaded {
    width: u32,
    height: u32,
    /// One of [`texel_format`].
    format: u32,
    words: Vec<f32>,
}

/// Read an image: 8-bit PNG, JPEG, TGA (grey or colour, alpha dropped) as packed bytes, sRGB
/// unless `raw`; 16-bit PNG decoded to linear floats here (sRGB unless `raw`); OpenEXR, Radiance
/// HDR and PFM as linear floats. Grey float images keep one channel. Errors are reasons.
fn read(path: &Path, raw: bool) -> std::result::Result<Loaded, String> {
    let (words, width, height, format) = match stratapt_scene::environment::read_float_image(path)?
    {
        Some((texels, w, h)) => {
            stratapt_scene::environment::check_texels(&texels, w, "texels")?;
            let grey = texels.chunks_exact(3).all(|c| c[0] == c[1] && c[1] == c[2]);
            match grey {
                true => {
                    let words = texels.chunks_exact(3).map(|c| c[0]).collect();
                    (words, w, h, texel_format::GREY32F)
                }
                false => (texels, w, h, texel_format::RGB32F),
            }
        }
        None => {
            let ext = stratapt_scene::environment::extension(path);
            if !matches!(ext.as_str(), "png" | "jpg" | "jpeg" | "tga") {
                return Err(format!(
                    "a texture is a .png, .jpg, .tga (8-bit) or .exr, .hdr, .pfm (float) image, \
                     not `.{ext}`"
                ));
            }
            let image = image::open(path).map_err(|e| e.to_string())?;
            let (w, h) = (image.width() as usize, image.height() as usize);
            let eight_bit = matches!(
                image.color(),
                image::ColorType::L8
                    | image::ColorType::La8
                    | image::ColorType::Rgb8
                    | image::ColorType::Rgba8
            );
            match eight_bit {
                true => {
                    let rgb = image.into_rgb8();
                    let words = rgb.pixels().map(|p| texture::pack_rgb8(p.0)).collect();
                    let format = match raw {
                        true => texel_format::LINEAR8,
                        false => texel_format::SRGB8,
                    };
                    (words, w, h, format)
                }
                false => {
                    // 16-bit (or float) channels: to [0, 1], decoded here (Mitsuba does too).
                    let rgb = image.into_rgb32f().into_raw();
                    let words = rgb
                        .into_iter()
                        .map(|x| match raw {
                            true => x,
                            false => texture::srgb_to_linear(x as f64) as f32,
                        })
                        .collect();
                    (words, w, h, texel_format::RGB32F)
                }
            }
        }
    };
    if width == 0 || height == 0 {
        return Err("the image has no texels".into());
    }
    if width > u32::MAX as usize / 4 || height > u32::MAX as usize / 4 {
        return Err(format!("{width}×{height} texels: too large"));
    }
    Ok(Loaded {
        width: width as u32,
        height: height as u32,
        format,
        words,
    })
}
