//! pbrt-v4's textures as strata's: `imagemap` (`filename`, `uscale`, `vscale`, `udelta`,
//! `vdelta`, `wrap`, `scale`, `encoding`) as strata's `image`, with the `uv_transform` that gives
//! pbrt's lookup at `(s, 1 − t)`; `checkerboard` (2D, constant `tex1`, `tex2`) as strata's
//! (pbrt's squares are one unit of `(s, t)` wide, Mitsuba's two); `constant`; and `scale` of an
//! image or a constant by a constant. Others are warned, and what reads them takes its default.
//!
//! pbrt-v4 clamps a reflectance to [0, 1] at every lookup (`Clamp(texEval(reflectance), 0, 1)`
//! in its diffuse and coated diffuse materials; a conductor's to [0, 0.9999]): an image texture
//! read so whose values can exceed 1 is flagged to clamp each lookup (strata's `clamp = true`),
//! warned where the material names it. Where other materials read the same texture unclamped (a
//! conductor's η or k), the clamped and the unclamped readers each get their own copy of it.

use super::import::Builder;
use super::materials::Value;
use super::params::Params;
use super::parse::{Directive, ParamType};
use super::spectrum::SpectrumKind;
use crate::desc::Spanned;
use crate::desc::{CheckerboardDesc, ImageTextureDesc, Numbers, TextureDesc};
use std::path::Path;
use stratapt_scene::error::SceneError;

/// A pbrt texture as strata sees it.
#[derive(Clone, Debug)]
pub enum Texture {
    /// A `[textures.NAME]` strata has.
    Named(String),
    /// A constant.
    Const([f64; 3]),
    /// One strata cannot draw (warned where it is defined): parameters that name it take
    /// their default.
    Missing,
}

impl Builder<'_> {
    /// `Texture "name" "spectrum"|"float" "class" …`.
    pub(super) fn texture(&mut self, source: usize, d: &Directive) -> Result<(), SceneError> {
        let p = Params::new(self.parsed, source, d);
        let super::parse::Arg::Str(name) = &d.args[0] else {
            unreachable!("Texture takes strings")
        };
        let (super::parse::Arg::Str(ty), super::parse::Arg::Str(class)) = (&d.args[1], &d.args[2])
        else {
            unreachable!("Texture takes strings")
        };
        let float = match ty.as_str() {
            "float" => true,
            "spectrum" | "color" => false,
            other => {
                return Err(
                    p.directive_err(format!("Texture type `{other}`: \"float\" or \"spectrum\""))
                )
            }
        };
        if self.textures.contains_key(&(float, name.clone())) {
            // pbrt-v4 refuses it too.
            return Err(p.directive_err(format!("texture `{name}` defined again")));
        }
        let strata_name = match float {
            true => format!("{name} (float)"),
            false => name.clone(),
        };
        let warn = |b: &mut Self, message: String| b.report.warnings.push(p.warning(message));
        let texture = match class.as_str() {
            "imagemap" => self.image_texture(&p, &strata_name)?,
            "checkerboard" => {
                let dim = p.integer("dimension", 2)?;
                let tex1 = self.color_or_float(&p, "tex1", 1.0, float)?;
                let tex2 = self.color_or_float(&p, "tex2", 0.0, float)?;
                match (tex1.constant(), tex2.constant(), dim) {
                    (Some(a), Some(b), 2) => {
                        let (su, sv, du, dv) = uv_mapping(self, &p)?;
                        // pbrt: tex1 where ⌊s⌋ + ⌊t⌋ is even, squares one unit wide; strata
                        // (Mitsuba): color0 where frac(u) > ½ and frac(v) > ½ agree, two units.
                        // With strata's v = 1 − pbrt's v: u' = s/2, v' = t/2.
                        let u_row = [su / 2.0, 0.0, du / 2.0];
                        let v_row = [0.0, -sv / 2.0, (sv + dv) / 2.0];
                        let checkerboard = CheckerboardDesc {
                            color0: Some(Spanned::new(p.span_of("tex1"), Numbers(a))),
                            color1: Some(Spanned::new(p.span_of("tex2"), Numbers(b))),
                            uv_transform: Some(Spanned::new(p.directive_span(), [u_row, v_row])),
                            ..CheckerboardDesc::default()
                        };
                        self.push_texture(
                            &p,
                            &strata_name,
                            TextureDesc::Checkerboard(checkerboard),
                        );
                        Texture::Named(strata_name)
                    }
                    _ => {
                        warn(
                            self,
                            "drawn as its tex1: strata's checkerboard is two-dimensional with \
                             constant squares"
                                .into(),
                        );
                        match tex1 {
                            Value::Rgb(c) => Texture::Const(c),
                            Value::Tex(t) => Texture::Named(t),
                        }
                    }
                }
            }
            "constant" => match self.color_or_float(&p, "value", 1.0, float)? {
                Value::Rgb(c) => Texture::Const(c),
                Value::Tex(t) => Texture::Named(t),
            },
            "scale" => {
                let tex = self.color_or_float(&p, "tex", 1.0, float)?;
                let scale = self.color_or_float(&p, "scale", 1.0, true)?;
                match (tex, scale) {
                    (Value::Rgb(a), Value::Rgb(s)) => {
                        Texture::Const([0, 1, 2].map(|c| a[c] * s[c]))
                    }
                    (Value::Tex(t), Value::Rgb(s)) if s == [1.0; 3] => Texture::Named(t),
                    (Value::Tex(t), Value::Rgb(s)) => {
                        // A copy of the image texture, scaled.
                        match self.scaled_image(&t, s[0]) {
                            Some(copy) => {
                                self.push_texture(&p, &strata_name, TextureDesc::Image(copy));
                                Texture::Named(strata_name)
                            }
                            None => {
                                warn(self, format!("drawn as `{t}` unscaled (strata scales image textures only)"));
                                Texture::Named(t)
                            }
                        }
                    }
                    (tex, Value::Tex(_)) => {
                        warn(self, "a texture scaled by a texture: drawn unscaled".into());
                        match tex {
                            Value::Rgb(c) => Texture::Const(c),
                            Value::Tex(t) => Texture::Named(t),
                        }
                    }
                }
            }
            other => {
                warn(
                    self,
                    format!("strata has no {other} texture: what reads it takes its default"),
                );
                Texture::Missing
            }
        };
        self.report.warnings.extend(p.unused());
        self.textures.insert((float, name.clone()), texture);
        Ok(())
    }

    /// strata's texture `name`, defined where `p`'s directive is.
    fn push_texture(&mut self, p: &Params, name: &str, texture: TextureDesc) {
        let name = Spanned::new(p.directive_span(), name.to_string());
        self.desc.textures.push((name, texture));
    }

    pub(super) fn color_or_float(
        &mut self,
        p: &Params,
        name: &str,
        default: f64,
        float: bool,
    ) -> Result<Value, SceneError> {
        match float {
            true => self.float_value(p, name, default),
            false => self.color(p, name, [default; 3], SpectrumKind::Reflectance),
        }
    }

    /// `imagemap` as strata's `image` texture.
    fn image_texture(&mut self, p: &Params, strata_name: &str) -> Result<Texture, SceneError> {
        let Some(file) = p.string("filename")? else {
            return Err(p.directive_err("Texture \"imagemap\" needs \"string filename\""));
        };
        self.existing_file(p, "filename", file)?;
        let (su, sv, du, dv) = uv_mapping(self, p)?;
        let mut body = ImageTextureDesc {
            file: Spanned::new(p.span_of("filename"), self.file_path(file)),
            ..ImageTextureDesc::default()
        };
        let wrap = p.string("wrap")?.unwrap_or("repeat");
        let wrap = match wrap {
            "repeat" | "clamp" => wrap,
            "black" => {
                self.report
                    .warnings
                    .push(p.warning("wrap \"black\" drawn as \"clamp\""));
                "clamp"
            }
            other => {
                self.report
                    .warnings
                    .push(p.warning(format!("wrap \"{other}\" drawn as \"repeat\"")));
                "repeat"
            }
        };
        body.wrap = Some(Spanned::new(p.span_of("wrap"), wrap.to_string()));
        // 8-bit images are sRGB unless the encoding says linear; float images are linear.
        match p.string("encoding")? {
            Some("linear") => body.raw = Some(true),
            Some("sRGB") | None => {}
            Some(other) => self
                .report
                .warnings
                .push(p.warning(format!("encoding \"{other}\" read as sRGB"))),
        }
        let scale = p.float("scale", 1.0)?;
        if !(scale >= 0.0 && scale.is_finite()) {
            let param = p.find(ParamType::Float, "scale").expect("read above");
            return Err(p.err(param, format!("scale {scale}: finite and not negative")));
        }
        if scale != 1.0 {
            body.scale = Some(Spanned::new(p.span_of("scale"), Numbers([scale; 3])));
        }
        if p.bool("invert", false)? {
            self.report
                .warnings
                .push(p.warning("invert ignored: strata does not invert textures"));
        }
        let _ = p.string("filter")?;
        let _ = p.float("maxanisotropy", 8.0)?;
        // pbrt looks up (s, 1 − t) with s = su·u + du, t = sv·v + dv; strata's v is 1 − pbrt's.
        let u_row = [su, 0.0, du];
        let v_row = [0.0, sv, 1.0 - sv - dv];
        if u_row != [1.0, 0.0, 0.0] || v_row != [0.0, 1.0, 0.0] {
            body.uv_transform = Some(Spanned::new(p.directive_span(), [u_row, v_row]));
        }
        self.image_bodies
            .insert(strata_name.to_string(), body.clone());
        self.push_texture(p, strata_name, TextureDesc::Image(body));
        Ok(Texture::Named(strata_name.to_string()))
    }

    /// strata's texture for texture `name` (strata's name) read where pbrt-v4 clamps it to
    /// [0, 1] at every lookup (parameter `param`, a reflectance): when its values can exceed 1,
    /// `name` flagged to clamp (warned at `param`), or its clamped copy where a reader that must
    /// not clamp reads `name` ([`Builder::unclamped_texture`]); else `name` as it is.
    pub(super) fn clamped_texture(&mut self, p: &Params, param: &str, name: String) -> String {
        let why = match self.texture_desc(&name) {
            Some((_, TextureDesc::Image(d))) => exceeds_one(d),
            // A checkerboard's colours were clamped as they were read (`Builder::color`).
            _ => None,
        };
        let Some(why) = why else {
            return name;
        };
        let at = p
            .find(ParamType::Texture, param)
            .map_or(p.location().1, |q| q.at);
        self.report.warnings.push(p.warning_at(
            at,
            format!(
                "{param} texture `{name}` may exceed 1 ({why}): clamped to [0, 1] at each \
                 lookup, as pbrt clamps a reflectance"
            ),
        ));
        self.texture_read(name, true)
    }

    /// strata's texture for texture `name` read unclamped (a conductor's η or k): `name`, or its
    /// unclamped copy where a reflectance made `name` clamp.
    pub(super) fn unclamped_texture(&mut self, name: String) -> String {
        self.texture_read(name, false)
    }

    /// Texture `name` read clamped (`clamp`) or not: `name` itself (flagged to clamp if it is
    /// read so) unless its first reader read it the other way; then its copy `NAME (clamped)` or
    /// `NAME (unclamped)`, made once, beside it.
    fn texture_read(&mut self, name: String, clamp: bool) -> String {
        let first = *self.texture_clamping.entry(name.clone()).or_insert(clamp);
        let copy = match first == clamp {
            true => name.clone(),
            false => format!("{name} ({})", if clamp { "clamped" } else { "unclamped" }),
        };
        if self.texture_desc(&copy).is_none() {
            let Some((span, body)) = self.texture_desc(&name) else {
                return name;
            };
            let body = body.clone();
            self.desc
                .textures
                .push((Spanned::new(span, copy.clone()), body));
        }
        if let Some((_, TextureDesc::Image(d))) = self.texture_desc_mut(&copy) {
            d.clamp = clamp.then_some(true);
        }
        copy
    }

    /// strata's texture `name`: where it is defined, and its description.
    fn texture_desc(&self, name: &str) -> Option<(std::ops::Range<usize>, &TextureDesc)> {
        self.desc
            .textures
            .iter()
            .find(|(n, _)| n.get_ref() == name)
            .map(|(n, body)| (n.span(), body))
    }

    fn texture_desc_mut(
        &mut self,
        name: &str,
    ) -> Option<(std::ops::Range<usize>, &mut TextureDesc)> {
        self.desc
            .textures
            .iter_mut()
            .find(|(n, _)| n.get_ref() == name)
            .map(|(n, body)| (n.span(), body))
    }

    /// strata's texture for texture `name` scaled by `s` (a material's `scale`): `name` for 1,
    /// else its copy `NAME (×s)`, made once; `None` for a texture strata cannot scale (not an
    /// image).
    pub(super) fn scaled_texture(&mut self, p: &Params, name: String, s: f64) -> Option<String> {
        if s == 1.0 {
            return Some(name);
        }
        let copy = format!("{name} (×{s})");
        if self.texture_desc(&copy).is_none() {
            let image = self.scaled_image(&name, s)?;
            self.image_bodies.insert(copy.clone(), image.clone());
            self.push_texture(p, &copy, TextureDesc::Image(image));
        }
        Some(copy)
    }

    /// Image texture `name` with its `scale` multiplied by `s`.
    fn scaled_image(&self, name: &str, s: f64) -> Option<ImageTextureDesc> {
        let mut image = self.image_bodies.get(name)?.clone();
        let (span, old) = match &image.scale {
            Some(scale) => (scale.span(), scale.get_ref().0[0]),
            None => (image.file.span(), 1.0),
        };
        image.scale = Some(Spanned::new(span, Numbers([old * s; 3])));
        Some(image)
    }
}

/// pbrt's `uv` texture mapping: `(uscale, vscale, udelta, vdelta)`; another mapping is drawn as
/// `uv` with a warning.
fn uv_mapping(b: &mut Builder, p: &Params) -> Result<(f64, f64, f64, f64), SceneError> {
    let mapping = p.string("mapping")?.unwrap_or("uv");
    if mapping != "uv" {
        b.report.warnings.push(p.warning(format!(
            "mapping \"{mapping}\" drawn as \"uv\" (the surface's texture coordinates)"
        )));
    }
    Ok((
        p.float("uscale", 1.0)?,
        p.float("vscale", 1.0)?,
        p.float("udelta", 0.0)?,
        p.float("vdelta", 0.0)?,
    ))
}

/// Why the values of image texture `d` may exceed 1 (`None`: they cannot): a scale above 1, or a
/// float image (OpenEXR, Radiance HDR, PFM), whose texels may be anything. 8-bit and 16-bit
/// images hold values in [0, 1].
fn exceeds_one(d: &ImageTextureDesc) -> Option<String> {
    let scale = d.scale.as_ref().map_or([1.0; 3], |s| s.get_ref().0);
    if scale.iter().any(|&x| x > 1.0) {
        return Some(match scale[0] == scale[1] && scale[1] == scale[2] {
            true => format!("scaled by {}", scale[0]),
            false => format!("scaled by {scale:?}"),
        });
    }
    let ext = stratapt_scene::environment::extension(Path::new(d.file.get_ref()));
    matches!(ext.as_str(), "exr" | "hdr" | "pfm").then(|| format!("a float image, .{ext}"))
}
