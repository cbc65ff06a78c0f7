//! Textures: images and checkerboards that a material's colours and numbers may read at a
//! surface point's `(u, v)`, looked up here for the CPU reference and by the same operations in
//! `shaders/texture.wgsl` for the kernel.
//!
//! The lookup is Mitsuba 3's `bitmap` / `checkerboard` (so that images can be compared with it
//! pixel by pixel): `(u, v)` through the texture's affine transform, then for an image the
//! bilinear interpolation of the texels around `x = u·W − ½`, `y = v·H − ½` (texel `(i, j)`'s
//! centre at `((i + ½)/W, (j + ½)/H)`; `v = 0` is the image's top row), each of the four
//! integer indices wrapped on its own ([`texture_wrap`]). 8-bit texels are decoded to linear
//! before they are interpolated (sRGB by a 256-entry table, which the kernel reads too, so the
//! decode is the same bits on both sides); the interpolation is computed in `f32` by the same
//! operations in the same order in Rust and WGSL, never by a hardware sampler (whose filtering
//! weights are 8-bit fixed point on many GPUs). A texture flagged [`texture_flag::CLAMP`] clamps
//! each lookup to `[0, 1]` per channel, after the interpolation, as pbrt-v4 clamps a diffuse
//! reflectance.
//!
//! No minification filter: a texel smaller than a pixel is averaged by the pixel's own samples
//! (the pixel filter integrates the texture over the pixel's footprint), so an estimate converges
//! to the filtered image as the samples grow, and CPU and GPU never disagree about a mip level.
//! The price is noise: a pixel that covers many texels needs the samples to average them.
//!
//! Every texture's record sits at the start of [`crate::FlatScene::tables`] (texture `i` at
//! word `TEXTURE_WORDS · i`); its texels and decode table further on, at the record's offsets.

use crate::records::{
    material_flag, texel_format, texture_flag, texture_kind, texture_wrap, Material, Texture,
    TEXTURE_WORDS,
};

/// Texture `index`'s record in `tables`.
#[inline]
pub fn record(tables: &[f32], index: u32) -> Texture {
    let start = TEXTURE_WORDS * index as usize;
    bytemuck::pod_read_unaligned(bytemuck::cast_slice(&tables[start..start + TEXTURE_WORDS]))
}

/// The value of texture `index` at `uv` (linear RGB), clamped to `[0, 1]` per channel when the
/// texture says so ([`texture_flag::CLAMP`]).
#[allow(clippy::manual_clamp)] // max, then min, as texture.wgsl (f32::clamp would keep a NaN)
pub fn eval(tables: &[f32], index: u32, uv: [f32; 2]) -> [f32; 3] {
    let t = record(tables, index);
    let value = lookup(tables, &t, uv);
    match t.tag & texture_flag::CLAMP != 0 {
        // `min(max(x, 0), 1)`, as texture.wgsl computes it: the same bits on both sides.
        true => value.map(|x| x.max(0.0).min(1.0)),
        false => value,
    }
}

/// The value of texture `t` at `uv`, unclamped.
fn lookup(tables: &[f32], t: &Texture, uv: [f32; 2]) -> [f32; 3] {
    // Plain multiplies and adds, never `mul_add`: lavapipe computes WGSL's `fma` unfused, and
    // plain ones give the same bits on both sides (a texture magnifies (u, v) by its
    // resolution, so one ulp of difference there is many in the value;
    // `crates/gpu/tests/shading/textures.rs` holds the lookups to the bit).
    let u = t.uv_u[0] * uv[0] + (t.uv_u[1] * uv[1] + t.uv_u[2]);
    let v = t.uv_v[0] * uv[0] + (t.uv_v[1] * uv[1] + t.uv_v[2]);
    if t.tag & 0xff == texture_kind::CHECKERBOARD {
        let a = u - u.floor() > 0.5;
        let b = v - v.floor() > 0.5;
        return if a == b { t.value } else { t.other };
    }
    let wrap_u = (t.tag >> 16) & 0xf;
    let wrap_v = (t.tag >> 20) & 0xf;
    // Continuous texel coordinates, reduced to one period of the wrap first so that the integer
    // indices stay small whatever (u, v) is.
    let x = reduce(u, wrap_u) * t.width as f32 - 0.5;
    let y = reduce(v, wrap_v) * t.height as f32 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (x0, y0) = (x0 as i32, y0 as i32);
    let (c0, c1) = (wrap(x0, t.width, wrap_u), wrap(x0 + 1, t.width, wrap_u));
    let (r0, r1) = (wrap(y0, t.height, wrap_v), wrap(y0 + 1, t.height, wrap_v));
    let texel = |c: u32, r: u32| texel(tables, t, r * t.width + c);
    let (t00, t10, t01, t11) = (texel(c0, r0), texel(c1, r0), texel(c0, r1), texel(c1, r1));
    let (gx, gy) = (1.0 - fx, 1.0 - fy);
    std::array::from_fn(|k| {
        let top = t00[k] * gx + t10[k] * fx;
        let bottom = t01[k] * gx + t11[k] * fx;
        (top * gy + bottom * fy) * t.value[k]
    })
}

/// A number from a texture (a roughness): a grey value itself, else the luminance of the RGB
/// (Mitsuba 3's `eval_1`).
pub fn eval_scalar(tables: &[f32], index: u32, uv: [f32; 2]) -> f32 {
    scalar(eval(tables, index, uv))
}

/// A grey colour's value, else its Rec. 709 luminance.
#[inline]
pub fn scalar([r, g, b]: [f32; 3]) -> f32 {
    if r == g && g == b {
        r
    } else {
        0.212_671 * r + 0.715_160 * g + 0.072_169 * b
    }
}

/// `material` with its textured parameters looked up at `uv` and its texture flags cleared: the
/// material of one surface point, which the BSDFs read as an untextured one.
pub fn resolve(material: &Material, tables: &[f32], uv: [f32; 2]) -> Material {
    let mut m = *material;
    if m.has(material_flag::COLOR_TEXTURE) {
        m.color = eval(tables, m.color[0] as u32, uv);
    }
    if m.has(material_flag::ALPHA_TEXTURE) {
        let (iu, iv) = (m.alpha_u as u32, m.alpha_v as u32);
        m.alpha_u = eval_scalar(tables, iu, uv);
        m.alpha_v = if iv == iu {
            m.alpha_u
        } else {
            eval_scalar(tables, iv, uv)
        };
    }
    if m.has(material_flag::ETA_TEXTURE) {
        m.eta = eval(tables, m.eta[0] as u32, uv);
    }
    if m.has(material_flag::K_TEXTURE) {
        m.k = eval(tables, m.k[0] as u32, uv);
    }
    m.tag &= !material_flag::TEXTURES;
    m
}

/// `t` reduced to one period of `wrap`: `[0, 1)` repeating, `[0, 2)` mirrored (a period is
/// the image and its reflection), `[−1, 2]` clamped (every index beyond it clamps alike). Not a
/// number reads as 0.
#[inline]
fn reduce(t: f32, wrap: u32) -> f32 {
    let t = if t.is_nan() { 0.0 } else { t };
    match wrap {
        texture_wrap::CLAMP => t.clamp(-1.0, 2.0),
        texture_wrap::MIRROR => t - 2.0 * (0.5 * t).floor(),
        _ => t - t.floor(),
    }
}

/// Integer texel index `i` of an axis of `n` texels, wrapped (`i` is within a few periods).
#[inline]
fn wrap(i: i32, n: u32, wrap: u32) -> u32 {
    let n = n as i32;
    let k = match wrap {
        texture_wrap::CLAMP => i.clamp(0, n - 1),
        texture_wrap::MIRROR => {
            let m = i.rem_euclid(2 * n);
            if m < n {
                m
            } else {
                2 * n - 1 - m
            }
        }
        _ => i.rem_euclid(n),
    };
    // Rounding at the top of a period may land one past the end.
    (k as u32).min(n as u32 - 1)
}

/// Texel `i` (row-major from the top-left) of image `t`, linear RGB, unscaled.
#[inline]
pub fn texel(tables: &[f32], t: &Texture, i: u32) -> [f32; 3] {
    let base = t.texels as usize;
    match (t.tag >> 8) & 0xff {
        texel_format::RGB32F => {
            let at = base + 3 * i as usize;
            [tables[at], tables[at + 1], tables[at + 2]]
        }
        texel_format::GREY32F => [tables[base + i as usize]; 3],
        _ => {
            let word = tables[base + i as usize].to_bits();
            let decode = &tables[t.decode as usize..t.decode as usize + 256];
            [0, 8, 16].map(|shift| decode[((word >> shift) & 0xff) as usize])
        }
    }
}

/// The 8-bit decode tables, sRGB then linear (256 entries each): what
/// [`Texture::decode`] points at for [`texel_format::SRGB8`] and [`texel_format::LINEAR8`].
pub fn decode_tables() -> [f32; 512] {
    std::array::from_fn(|i| {
        let x = (i % 256) as f64 / 255.0;
        if i >= 256 {
            x as f32
        } else {
            srgb_to_linear(x) as f32
        }
    })
}

/// The sRGB transfer function's inverse (IEC 61966-2-1), exactly.
pub fn srgb_to_linear(x: f64) -> f64 {
    if x <= 0.04045 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

/// Pack 8-bit red, green, blue as one texel word of [`texel_format::SRGB8`] /
/// [`texel_format::LINEAR8`] (as the `f32` with those bits, which `tables` holds).
pub fn pack_rgb8([r, g, b]: [u8; 3]) -> f32 {
    f32::from_bits(r as u32 | (g as u32) << 8 | (b as u32) << 16)
}

/// A texture's tag from its kind, texel format and wrap mode (the same on both axes).
pub fn tag(kind: u32, format: u32, wrap: u32) -> u32 {
    kind | format << 8 | wrap << 16 | wrap << 20
}

/// Tables holding one image texture (index 0) of `w × h` `texels` (RGB32F, the top row first)
/// with `wrap` on both axes, scale 1 and the identity uv transform: for tests and tools that
/// need a texture without a scene file.
pub fn image_tables(w: u32, h: u32, texels: &[[f32; 3]], wrap: u32) -> Vec<f32> {
    let t = Texture {
        tag: tag(texture_kind::IMAGE, texel_format::RGB32F, wrap),
        texels: TEXTURE_WORDS as u32,
        width: w,
        height: h,
        uv_u: [1.0, 0.0, 0.0],
        uv_v: [0.0, 1.0, 0.0],
        value: [1.0; 3],
        ..Texture::default()
    };
    let mut tables: Vec<f32> = bytemuck::cast_slice(&[t]).to_vec();
    tables.extend(texels.iter().flatten());
    tables
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32, texels: &[[f32; 3]], wrap: u32) -> Vec<f32> {
        image_tables(w, h, texels, wrap)
    }

    #[test]
    fn texel_centres_read_their_texel_and_midpoints_average() {
        // 2×2: red, green / blue, white (top row first).
        let texels = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0; 3]];
        let tables = image(2, 2, &texels, texture_wrap::CLAMP);
        for (i, expected) in texels.iter().enumerate() {
            let uv = [0.25 + 0.5 * (i % 2) as f32, 0.25 + 0.5 * (i / 2) as f32];
            assert_eq!(eval(&tables, 0, uv), *expected, "texel {i}");
        }
        // The centre of the image weighs all four alike.
        assert_eq!(eval(&tables, 0, [0.5, 0.5]), [0.5, 0.5, 0.5]);
        // Clamped: the outer half-texel is the edge texel alone.
        assert_eq!(eval(&tables, 0, [0.0, 0.0]), texels[0]);
        assert_eq!(eval(&tables, 0, [-3.0, 7.0]), texels[2]);
    }

    /// A clamped texture clamps each lookup, after the interpolation (pbrt-v4's
    /// `Clamp(texEval(reflectance), 0, 1)`): between a texel of 2 and one of 0 it reads the
    /// clamp of their blend, which is not the blend of the clamped texels.
    #[test]
    fn clamping_applies_to_each_lookup_not_to_the_texels() {
        let with_clamp = |mut tables: Vec<f32>| {
            // The tag is the record's first word.
            tables[0] = f32::from_bits(tables[0].to_bits() | texture_flag::CLAMP);
            tables
        };
        let texels = [[2.0, -1.0, 0.5], [0.0; 3]];
        let plain = image(2, 1, &texels, texture_wrap::CLAMP);
        let clamped = with_clamp(plain.clone());
        let clamped_texels = image(2, 1, &[[1.0, 0.0, 0.5], [0.0; 3]], texture_wrap::CLAMP);
        // Texel 0's centre: each channel clamped on its own.
        assert_eq!(eval(&plain, 0, [0.25, 0.5]), [2.0, -1.0, 0.5]);
        assert_eq!(eval(&clamped, 0, [0.25, 0.5]), [1.0, 0.0, 0.5]);
        // Halfway between the texels: clamp(1) = 1, where the clamped texels' blend is ½.
        assert_eq!(eval(&plain, 0, [0.5, 0.5])[0], 1.0);
        assert_eq!(eval(&clamped, 0, [0.5, 0.5])[0], 1.0);
        assert_eq!(eval(&clamped_texels, 0, [0.5, 0.5])[0], 0.5);
        // A quarter of the way: 1.5 clamped to 1; three quarters: ½ as it is.
        assert_eq!(eval(&plain, 0, [0.375, 0.5])[0], 1.5);
        assert_eq!(eval(&clamped, 0, [0.375, 0.5])[0], 1.0);
        assert_eq!(eval(&clamped_texels, 0, [0.375, 0.5])[0], 0.75);
        assert_eq!(eval(&clamped, 0, [0.625, 0.5])[0], 0.5);
        // The scalar lookup reads the clamped value too.
        assert_eq!(
            eval_scalar(&clamped, 0, [0.375, 0.5]),
            scalar([1.0, 0.0, 0.375])
        );
    }

    #[test]
    fn wrap_modes_index_as_mitsuba() {
        // Closed forms of Dr.Jit's `tex_wrap` for n = 4, i = −5 … 8.
        let repeat = [3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0];
        let mirror = [3, 3, 2, 1, 0, 0, 1, 2, 3, 3, 2, 1, 0, 0];
        let clamp = [0, 0, 0, 0, 0, 0, 1, 2, 3, 3, 3, 3, 3, 3];
        for (k, i) in (-5..=8).enumerate() {
            assert_eq!(wrap(i, 4, texture_wrap::REPEAT), repeat[k], "repeat {i}");
            assert_eq!(wrap(i, 4, texture_wrap::MIRROR), mirror[k], "mirror {i}");
            assert_eq!(wrap(i, 4, texture_wrap::CLAMP), clamp[k], "clamp {i}");
        }
    }

    #[test]
    fn repeat_blends_across_the_seam_and_is_periodic() {
        let texels = [[0.0; 3], [1.0; 3], [2.0; 3], [4.0; 3]];
        let tables = image(4, 1, &texels, texture_wrap::REPEAT);
        // u = 0 is halfway between the last texel and the first.
        assert_eq!(eval(&tables, 0, [0.0, 0.5]), [2.0; 3]);
        for u in [0.1f32, 0.3, 0.55, 0.9] {
            let here = eval(&tables, 0, [u, 0.5]);
            for period in [-2.0f32, 1.0, 3.0] {
                let there = eval(&tables, 0, [u + period, 0.5]);
                for k in 0..3 {
                    assert!((here[k] - there[k]).abs() < 1e-5, "u {u} + {period}");
                }
            }
        }
        let mirrored = image(4, 1, &texels, texture_wrap::MIRROR);
        // Mirrored: u and 2 − u read the same.
        let (a, b) = (
            eval(&mirrored, 0, [0.3, 0.5]),
            eval(&mirrored, 0, [1.7, 0.5]),
        );
        assert!((a[0] - b[0]).abs() < 1e-5, "{a:?} {b:?}");
        // Not a number reads somewhere in the image, not out of it.
        assert!(eval(&tables, 0, [f32::NAN, f32::INFINITY])[0].is_finite());
    }

    #[test]
    fn eight_bit_texels_are_decoded_before_they_are_interpolated() {
        let t = Texture {
            tag: tag(
                texture_kind::IMAGE,
                texel_format::SRGB8,
                texture_wrap::CLAMP,
            ),
            texels: TEXTURE_WORDS as u32,
            width: 2,
            height: 1,
            uv_u: [1.0, 0.0, 0.0],
            uv_v: [0.0, 1.0, 0.0],
            decode: TEXTURE_WORDS as u32 + 2,
            value: [1.0; 3],
            ..Texture::default()
        };
        let mut tables: Vec<f32> = bytemuck::cast_slice(&[t]).to_vec();
        tables.extend([pack_rgb8([0, 128, 255]), pack_rgb8([255, 128, 0])]);
        tables.extend(decode_tables());
        let mid = srgb_to_linear(128.0 / 255.0) as f32;
        assert_eq!(eval(&tables, 0, [0.25, 0.5]), [0.0, mid, 1.0]);
        // Halfway: the mean of the linear values (0.5), not the decoded mean byte (0.21).
        let half = eval(&tables, 0, [0.5, 0.5]);
        assert_eq!(half, [0.5, mid, 0.5]);
        // sRGB 50 % grey is 21.4 % linear; the linear table is x / 255.
        assert!((decode_tables()[128] - 0.2158605).abs() < 1e-6);
        assert_eq!(decode_tables()[256 + 51], 0.2);
    }

    #[test]
    fn checkerboard_cells_follow_mitsuba() {
        let t = Texture {
            tag: tag(texture_kind::CHECKERBOARD, 0, 0),
            uv_u: [4.0, 0.0, 0.0],
            uv_v: [0.0, 4.0, 0.0],
            value: [0.4; 3],
            other: [0.2; 3],
            ..Texture::default()
        };
        let tables: Vec<f32> = bytemuck::cast_slice(&[t]).to_vec();
        // Scaled 4×: cells of 1/8; (frac > ½) equal on both axes → `value`.
        assert_eq!(eval(&tables, 0, [0.01, 0.01]), [0.4; 3]);
        assert_eq!(eval(&tables, 0, [0.2, 0.01]), [0.2; 3]);
        assert_eq!(eval(&tables, 0, [0.2, 0.2]), [0.4; 3]);
        // frac exactly ½ is the low half.
        assert_eq!(eval(&tables, 0, [0.125, 0.01]), [0.4; 3]);
    }

    #[test]
    fn resolving_replaces_textured_parameters_only() {
        let texels = [[0.25; 3], [0.25; 3], [0.25; 3], [0.25; 3]];
        let tables = image(2, 2, &texels, texture_wrap::REPEAT);
        let m = Material {
            color: [0.0; 3],
            tag: crate::records::material_kind::CONDUCTOR
                | material_flag::COLOR_TEXTURE
                | material_flag::ALPHA_TEXTURE
                | material_flag::SEPARABLE_MASKING,
            alpha_u: 0.0,
            alpha_v: 0.0,
            eta: [0.7; 3],
            ..Material::default()
        };
        let r = resolve(&m, &tables, [0.3, 0.6]);
        assert_eq!(r.color, [0.25; 3]);
        assert_eq!((r.alpha_u, r.alpha_v), (0.25, 0.25));
        assert_eq!(r.eta, [0.7; 3]);
        assert_eq!(
            r.tag,
            crate::records::material_kind::CONDUCTOR | material_flag::SEPARABLE_MASKING
        );
        // A grey value is itself; a colour its luminance.
        assert_eq!(scalar([0.3; 3]), 0.3);
        assert!((scalar([1.0, 0.0, 0.0]) - 0.212671).abs() < 1e-7);
    }
}
