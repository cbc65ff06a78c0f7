//! pbrt-v4's materials as strata's.
//!
//! | pbrt-v4 | strata |
//! |---|---|
//! | `diffuse` (`reflectance`) | `diffuse` (`albedo`) |
//! | `conductor` (`eta`, `k` or `reflectance`; `roughness`, `uroughness`, `vroughness`, `remaproughness`) | `conductor` (`eta`, `k`, `roughness` α = √roughness when remapped, pbrt's `RoughnessToAlpha`); a constant `reflectance` r as pbrt turns it into η = 1, k = 2√r / √(1 − r) |
//! | `dielectric` (`eta` a number or a spectrum, `roughness`…) | `dielectric` (`ior`; a spectrum's mean index weighted by ȳ, with a warning: strata does not disperse) |
//! | `diffusetransmission` (`reflectance`, `transmittance`, `scale`) | `diffuse` with `transmittance`, each scaled then clamped to [0, 1] as pbrt-v4 does |
//! | `thindielectric` (`eta`) | `dielectric` with `thin = true` |
//! | `mix` (`materials`, `amount`) | `mix` of strata's materials for the two, the second with probability `amount` (a number clamped to [0, 1], or a float texture) |
//! | `coateddiffuse` (`reflectance`, `eta`, `roughness`…, `thickness`, `albedo`, `g`, `maxdepth`, `nsamples`) | `coated` over a `diffuse` of the reflectance (written beside it): pbrt's layered BSDF and its random walk |
//! | `coatedconductor` (`interface.*`, `conductor.*` or `reflectance`, and the coat's) | `coated` over the `conductor` |
//! | `interface` | no surface (the shape is a boundary between media) |
//! | any material's `displacement` (a float texture or a number) | its `displacement`: pbrt's bump map |
//! | any material's `normalmap` (an image file) | its `normal_map`, a `raw` image texture of the file (pbrt ignores the displacement then, and so does strata) |
//! | others | the nearest strata has, with a warning |
//!
//! Colours and numbers may come from textures ([`super::textures`]); spectra become RGB in
//! [`super::spectrum`]. Each type is converted in its submodule `convert`; here, the
//! parameters they read and strata's material named for each pbrt material and light.

mod convert;

use super::import::{numbers, AreaLight, Builder, MaterialRef};
use super::params::Params;
use super::parse::{ParamType, Values};
use super::spectrum::{named_rgb, read_spd, sampled_rgb, SpectrumKind};
use super::textures::Texture;
use crate::desc::Spanned;
use crate::desc::{
    ColorParam, DiffuseDesc, ImageTextureDesc, MaterialDesc, Numbers, RoughnessParam, TextureDesc,
    Textured,
};
use std::ops::Range;
use stratapt_scene::error::SceneError;

/// A material parameter: a colour or a texture's name.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Rgb([f64; 3]),
    Tex(String),
}

impl Value {
    /// As a colour parameter of strata's materials.
    pub(super) fn param(&self) -> ColorParam {
        match self {
            Value::Rgb(c) => Textured::Value(Numbers(*c)),
            Value::Tex(name) => Textured::Texture(name.clone()),
        }
    }
    pub(super) fn constant(&self) -> Option<[f64; 3]> {
        match self {
            Value::Rgb(c) => Some(*c),
            Value::Tex(_) => None,
        }
    }
}

impl Builder<'_> {
    /// A colour parameter `name` (rgb, spectrum, a grey float, or a texture), or `default`; a
    /// constant reflectance outside [0, 1] clamped into it, as pbrt-v4 clamps at every lookup
    /// (warned).
    pub(super) fn color(
        &mut self,
        p: &Params,
        name: &str,
        default: [f64; 3],
        kind: SpectrumKind,
    ) -> Result<Value, SceneError> {
        let value = self.color_unclamped(p, name, default, kind)?;
        match value {
            Value::Rgb(c)
                if kind == SpectrumKind::Reflectance
                    && c.iter().any(|x| !(0.0..=1.0).contains(x)) =>
            {
                let clamped = c.map(|x| x.clamp(0.0, 1.0));
                self.report.warnings.push(p.warning(format!(
                    "{name} {c:?} clamped to {clamped:?}, as pbrt clamps a reflectance"
                )));
                Ok(Value::Rgb(clamped))
            }
            v => Ok(v),
        }
    }

    /// A reflectance parameter `name` that pbrt-v4 clamps to [0, 1] at every lookup: a colour
    /// clamped as [`Builder::color`] clamps it, or a texture that clamps its lookups when they
    /// can exceed 1 ([`Builder::clamped_texture`]).
    pub(super) fn reflectance(
        &mut self,
        p: &Params,
        name: &str,
        default: [f64; 3],
    ) -> Result<Value, SceneError> {
        let value = self.color(p, name, default, SpectrumKind::Reflectance)?;
        Ok(match value {
            Value::Tex(t) => Value::Tex(self.clamped_texture(p, name, t)),
            rgb => rgb,
        })
    }

    fn color_unclamped(
        &mut self,
        p: &Params,
        name: &str,
        default: [f64; 3],
        kind: SpectrumKind,
    ) -> Result<Value, SceneError> {
        if let Some(param) = p.find(ParamType::Rgb, name) {
            let n = numbers(&param.values);
            if n.len() != 3 {
                return Err(p.err(param, format!("rgb {name} takes three numbers")));
            }
            return Ok(Value::Rgb([n[0], n[1], n[2]]));
        }
        if let Some(param) = p.find(ParamType::Spectrum, name) {
            return match &param.values {
                Values::Strings(s) => match named_rgb(&s[0]) {
                    Some(rgb) => Ok(Value::Rgb(rgb)),
                    None => {
                        let pairs = read_spd(&self.resolve(&s[0])).map_err(|reason| {
                            p.err(
                                param,
                                format!(
                                    "`{}` is no spectrum pbrt-v4 names, nor a spectrum file: {reason}",
                                    s[0]
                                ),
                            )
                        })?;
                        Ok(Value::Rgb(sampled_rgb(&pairs, kind)))
                    }
                },
                Values::Numbers(pairs) => Ok(Value::Rgb(sampled_rgb(pairs, kind))),
                Values::Bools(_) => unreachable!("the parser reads spectra as numbers or names"),
            };
        }
        if let Some(param) = p.find(ParamType::Float, name) {
            return Ok(Value::Rgb([one_number(p, param, name)?; 3]));
        }
        if let Some(param) = p.find(ParamType::Texture, name) {
            return self.texture_value(p, param, false, default);
        }
        Ok(Value::Rgb(default))
    }

    /// A float parameter `name` (a number or a float texture), or `default`.
    pub(super) fn float_value(
        &mut self,
        p: &Params,
        name: &str,
        default: f64,
    ) -> Result<Value, SceneError> {
        if let Some(param) = p.find(ParamType::Float, name) {
            return Ok(Value::Rgb([one_number(p, param, name)?; 3]));
        }
        if let Some(param) = p.find(ParamType::Texture, name) {
            return self.texture_value(p, param, true, [default; 3]);
        }
        Ok(Value::Rgb([default; 3]))
    }

    /// A float parameter `name` given as a number or a float texture, as strata's one-number
    /// parameter (`None` where it is not given; `missing` for a texture strata cannot draw).
    pub(super) fn float_param(
        &mut self,
        p: &Params,
        name: &str,
        missing: f64,
    ) -> Result<Option<crate::desc::AmountParam>, SceneError> {
        let given =
            p.find(ParamType::Float, name).is_some() || p.find(ParamType::Texture, name).is_some();
        if !given {
            return Ok(None);
        }
        Ok(Some(match self.float_value(p, name, missing)? {
            Value::Rgb([v, ..]) => Textured::Value(Numbers([v])),
            Value::Tex(name) => Textured::Texture(name),
        }))
    }

    /// What a `"texture NAME"` parameter names: a float texture (`float`) or a spectrum one;
    /// `default` where the texture is one strata cannot draw (warned where it is defined).
    fn texture_value(
        &self,
        p: &Params,
        param: &super::parse::Param,
        float: bool,
        default: [f64; 3],
    ) -> Result<Value, SceneError> {
        let Values::Strings(s) = &param.values else {
            unreachable!("textures are named by strings")
        };
        match self.textures.get(&(float, s[0].clone())) {
            Some(Texture::Named(t)) => Ok(Value::Tex(t.clone())),
            Some(Texture::Const(c)) => Ok(Value::Rgb(*c)),
            Some(Texture::Missing) => Ok(Value::Rgb(default)),
            None => Err(p.err(
                param,
                format!(
                    "no {} texture named `{}`",
                    if float { "float" } else { "spectrum" },
                    s[0]
                ),
            )),
        }
    }

    /// The GGX α of a rough material (`roughness`, or `uroughness` and `vroughness`, remapped by
    /// `remaproughness` as pbrt's `RoughnessToAlpha`, √x): `None` when smooth.
    fn roughness(&mut self, p: &Params) -> Result<Option<RoughnessParam>, SceneError> {
        let r = self.float_value(p, "roughness", 0.0)?;
        let u = self.float_value(p, "uroughness", f64::NAN)?;
        let v = self.float_value(p, "vroughness", f64::NAN)?;
        let remap = p.bool("remaproughness", true)?;
        let pick = |x: Value| match x {
            Value::Rgb(c) if c[0].is_nan() => r.clone(),
            x => x,
        };
        let (u, v) = (pick(u), pick(v));
        let alpha = |x: f64| if remap { x.max(0.0).sqrt() } else { x.max(0.0) };
        match (&u, &v) {
            (Value::Rgb(a), Value::Rgb(b)) => {
                let (a, b) = (alpha(a[0]), alpha(b[0]));
                Ok(match (a, b) {
                    (a, b) if a == 0.0 && b == 0.0 => None,
                    (a, b) => Some(Textured::Value(Numbers([a, b]))),
                })
            }
            (Value::Tex(t), _) | (_, Value::Tex(t)) => {
                if u != v {
                    self.report.warnings.push(p.warning(format!(
                        "one roughness texture, `{t}`, drawn for both directions"
                    )));
                }
                if remap {
                    self.report.warnings.push(p.warning(format!(
                        "roughness texture `{t}` read as GGX α, not remapped (√) as pbrt does"
                    )));
                }
                Ok(Some(Textured::Texture(t.clone())))
            }
        }
    }
}

/// The one number of `param` (a float that pbrt reads as one value).
fn one_number(p: &Params, param: &super::parse::Param, name: &str) -> Result<f64, SceneError> {
    match numbers(&param.values) {
        [x] => Ok(*x),
        n => Err(p.err(param, format!("`{name}` takes one number, not {}", n.len()))),
    }
}

/// The name of strata's material for pbrt's `material` emitting `area` (`None`: pbrt's
/// `interface`, no surface, and no light on it), written on first use.
pub(super) fn material_name(
    b: &mut Builder,
    material: &MaterialRef,
    area: Option<&AreaLight>,
) -> Result<Option<String>, SceneError> {
    material_name_at(b, material, area, 0)
}

/// [`material_name`] reached through `depth` mixes (a mix that names itself, directly or not, is
/// an error, not a loop).
fn material_name_at(
    b: &mut Builder,
    material: &MaterialRef,
    area: Option<&AreaLight>,
    depth: usize,
) -> Result<Option<String>, SceneError> {
    // A light of zero radiance is no light: its shapes share the material's plain name.
    let emitting = area.filter(|a| a.radiance.iter().any(|&x| x > 0.0));
    let key = (material.key(), emitting.map(|a| a.index));
    if let Some(name) = b.materials_written.get(&key) {
        return Ok(name.clone());
    }
    let body = match b.material_bodies.get(&material.key()) {
        Some(body) => body.clone(),
        None => {
            let body = material_body(b, material, depth)?;
            b.material_bodies.insert(material.key(), body.clone());
            body
        }
    };
    let base = match material {
        MaterialRef::Default => "pbrt's default (diffuse 0.5)".to_string(),
        MaterialRef::Named(name, _, _) => name.clone(),
        MaterialRef::Anonymous(i) => format!("Material #{}", i + 1),
    };
    let (name, body) = match (body, emitting) {
        (None, None) => {
            b.materials_written.insert(key, None);
            return Ok(None);
        }
        (Some(body), None) => (base, body),
        (body, Some(a)) => {
            let mut body = body.unwrap_or_else(|| {
                MaterialDesc::Diffuse(DiffuseDesc {
                    albedo: Spanned::new(a.span.clone(), Textured::Value(Numbers([0.0; 3]))),
                    ..DiffuseDesc::default()
                })
            });
            *body.emission_mut() = Some(Spanned::new(a.span.clone(), Numbers(a.radiance)));
            (format!("{base} + AreaLightSource #{}", a.index + 1), body)
        }
    };
    if body.reads_texture() {
        b.textured_materials.insert(name.clone());
    }
    let span = material_span(b, material);
    b.desc
        .materials
        .push((Spanned::new(span, name.clone()), body));
    b.materials_written.insert(key, Some(name.clone()));
    Ok(Some(name))
}

/// Where pbrt's material is defined (its `MakeNamedMaterial` or `Material`; the file's start
/// for pbrt's default).
fn material_span(b: &Builder, material: &MaterialRef) -> Range<usize> {
    match material {
        MaterialRef::Default => b.parsed.span(0, 0),
        MaterialRef::Named(name, source, at) => match b.named_materials.get(name) {
            Some(&(s, d)) => b.parsed.span(s, d.at),
            None => b.parsed.span(*source, *at),
        },
        MaterialRef::Anonymous(i) => {
            let (s, d) = b.anonymous_materials[*i];
            b.parsed.span(s, d.at)
        }
    }
}

/// strata's material body for pbrt's (`None`: `interface`); `depth` counts the `mix` materials
/// followed to get here (a mix that names itself, directly or not, is an error, not a loop).
fn material_body(
    b: &mut Builder,
    material: &MaterialRef,
    depth: usize,
) -> Result<Option<MaterialDesc>, SceneError> {
    let (source, d) = match material {
        MaterialRef::Default => {
            return Ok(Some(MaterialDesc::Diffuse(DiffuseDesc {
                albedo: Spanned::new(b.parsed.span(0, 0), Textured::Value(Numbers([0.5; 3]))),
                ..DiffuseDesc::default()
            })))
        }
        MaterialRef::Named(name, source, at) => match b.named_materials.get(name) {
            Some(&(s, d)) => (s, d),
            None => {
                return Err(b
                    .parsed
                    .err(*source, *at, format!("no material named `{name}`")))
            }
        },
        MaterialRef::Anonymous(i) => b.anonymous_materials[*i],
    };
    let p = Params::new(b.parsed, source, d);
    let kind = match d.name.as_str() {
        "MakeNamedMaterial" => match p.string("type")? {
            Some(t) => t.to_string(),
            None => return Err(p.directive_err("MakeNamedMaterial needs \"string type\"")),
        },
        _ => p.kind().to_string(),
    };
    let mut body = convert::convert(b, &p, &kind, depth)?;
    if let Some(body) = &mut body {
        detail(b, &p, body)?;
    }
    b.report.warnings.extend(p.unused());
    Ok(body)
}

/// A material's `normalmap` (an image file, read linear, repeating, at pbrt's `(u, 1 − v)` as
/// its image textures are) or else its `displacement` (a float texture or a number), pbrt-v4's
/// bump map; pbrt ignores the displacement of a material with a normal map, and so does this.
fn detail(b: &mut Builder, p: &Params, body: &mut MaterialDesc) -> Result<(), SceneError> {
    let (displacement, normal_map) = body.detail_mut();
    if let Some(file) = p.string("normalmap")? {
        b.existing_file(p, "normalmap", file)?;
        let span = p.span_of("normalmap");
        let name = format!("normalmap {file}");
        if !b.desc.textures.iter().any(|(n, _)| n.get_ref() == &name) {
            let image = ImageTextureDesc {
                file: Spanned::new(span.clone(), b.file_path(file)),
                raw: Some(true),
                ..ImageTextureDesc::default()
            };
            b.desc.textures.push((
                Spanned::new(span.clone(), name.clone()),
                TextureDesc::Image(image),
            ));
        }
        *normal_map = Some(Spanned::new(span, name));
        let _ = p.find(ParamType::Float, "displacement");
        let _ = p.find(ParamType::Texture, "displacement");
        return Ok(());
    }
    if let Some(height) = b.float_param(p, "displacement", 0.0)? {
        *displacement = Some(Spanned::new(p.span_of("displacement"), height));
    }
    Ok(())
}
