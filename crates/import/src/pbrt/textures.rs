//! pbrt-v4's textures as strata's: `imagemap` (`filename`, `uscale`, `vscale`, `udelta`,
//! `vdelta`, `wrap`, `scale`, `encoding`) as strata's `image`, with the `uv_transform` that gives
//! pbrt's lookup at `(s, 1 − t)`; `checkerboard` (2D, constant `tex1`, `tex2`) as strata's
//! (pbrt's squares are one unit of `(s, t)` wide, Mitsuba's two); `constant`; and `scale` of an
//! image or a constant by a constant. Others are warned, and what reads them takes its default.

use super::import::Builder;
use super::materials::Value;
use super::params::Params;
use super::parse::{Directive, ParamType};
use super::spectrum::SpectrumKind;
use crate::desc::Spanned;
use crate::desc::{CheckerboardDesc, ImageTextureDesc, Numbers, TextureDesc};
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
        if !self.resolve(file).is_file() {
            let param = p.find(ParamType::String, "filename").expect("read above");
            return Err(p.err(
                param,
                format!("no file `{file}` ({})", self.resolve(file).display()),
            ));
        }
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
