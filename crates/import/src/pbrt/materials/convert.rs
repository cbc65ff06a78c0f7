//! Each pbrt-v4 material type as strata's material description (the table in
//! [`super`](mod@super)): one function per type, [`convert`] choosing among them.

use super::super::import::{Builder, MaterialRef};
use super::super::params::Params;
use super::super::parse::{ParamType, Values};
use super::super::spectrum::{luminance_mean, named_rgb, read_spd, SpectrumKind};
use super::{material_name_at, Value};
use crate::desc::Spanned;
use crate::desc::{
    CoatedDesc, ColorParam, ConductorDesc, DielectricDesc, DiffuseDesc, MaterialDesc, MixDesc,
    Numbers, RoughnessParam, Textured,
};
use std::ops::Range;
use stratapt_scene::error::SceneError;

/// One material of pbrt type `kind` as strata's (`None`: `interface`, no surface); `depth`
/// counts the `mix` materials followed to get here.
pub(super) fn convert(
    b: &mut Builder,
    p: &Params,
    kind: &str,
    depth: usize,
) -> Result<Option<MaterialDesc>, SceneError> {
    // Read but drawn alike: bump maps are warned by `unused` (strata has none).
    let body = match kind {
        "diffuse" => diffuse(b, p)?,
        "conductor" => conductor(b, p, kind)?,
        "coatedconductor" => coated_conductor(b, p)?,
        "dielectric" | "thindielectric" => dielectric(b, p, kind)?,
        "diffusetransmission" => diffuse_transmission(b, p)?,
        "coateddiffuse" => coated_diffuse(b, p)?,
        "interface" | "none" | "" => return Ok(None),
        "mix" => return mix(b, p, depth),
        other => fallback(b, p, other)?,
    };
    Ok(Some(body))
}

/// pbrt's `diffuse` as strata's: its `reflectance` the albedo (clamped to [0, 1] at every
/// lookup, as pbrt clamps it).
fn diffuse(b: &mut Builder, p: &Params) -> Result<MaterialDesc, SceneError> {
    let r = b.reflectance(p, "reflectance", [0.5; 3])?;
    Ok(MaterialDesc::Diffuse(DiffuseDesc {
        albedo: Spanned::new(p.span_of("reflectance"), r.param()),
        ..DiffuseDesc::default()
    }))
}

/// pbrt's `conductor` as strata's, from its `reflectance` or its `eta` and `k`; a
/// `coatedconductor`'s base (its parameters named `conductor.…`).
fn conductor(b: &mut Builder, p: &Params, kind: &str) -> Result<MaterialDesc, SceneError> {
    let prefix = if kind == "coatedconductor" {
        "conductor."
    } else {
        ""
    };
    let reflectance = p
        .find(ParamType::Rgb, "reflectance")
        .or_else(|| p.find(ParamType::Spectrum, "reflectance"))
        .or_else(|| p.find(ParamType::Texture, "reflectance"))
        .is_some();
    let mut m = ConductorDesc::default();
    if reflectance {
        conductor_reflectance(b, p, &mut m)?;
    } else {
        conductor_eta_k(b, p, prefix, &mut m)?;
    }
    if let Some(alpha) = roughness_with_prefix(b, p, prefix)? {
        m.roughness = Some(Spanned::new(roughness_span(p, prefix), alpha));
    }
    Ok(MaterialDesc::Conductor(m))
}

/// A conductor's Fresnel from its `reflectance`: pbrt's η and k for a colour, Schlick's for a
/// texture (warned); either clamped to [0, 1] as pbrt clamps it (to [0, 0.9999]).
fn conductor_reflectance(
    b: &mut Builder,
    p: &Params,
    m: &mut ConductorDesc,
) -> Result<(), SceneError> {
    let at = p.span_of("reflectance");
    match b.reflectance(p, "reflectance", [1.0; 3])? {
        Value::Rgb(r) => {
            // pbrt-v4: η = 1 and k = 2√r / √(1 − r) reflect exactly r at normal incidence.
            let k = r.map(|r| {
                let r = r.clamp(0.0, 0.9999);
                2.0 * r.sqrt() / (1.0 - r).sqrt()
            });
            m.eta = Some(Spanned::new(at.clone(), Textured::Value(Numbers([1.0; 3]))));
            m.k = Some(Spanned::new(at, Textured::Value(Numbers(k))));
        }
        Value::Tex(t) => {
            b.report.warnings.push(p.warning(format!(
                "reflectance texture `{t}` drawn with Schlick's Fresnel, not pbrt's \
                 η = 1, k = 2√r/√(1 − r)"
            )));
            m.reflectance = Some(Spanned::new(at, Textured::Texture(t)));
        }
    }
    Ok(())
}

/// A conductor's Fresnel from its `eta` and `k` (named with `prefix`), copper's by default.
fn conductor_eta_k(
    b: &mut Builder,
    p: &Params,
    prefix: &str,
    m: &mut ConductorDesc,
) -> Result<(), SceneError> {
    let eta = b.color(
        p,
        &format!("{prefix}eta"),
        named_rgb("metal-Cu-eta").expect("a named spectrum"),
        SpectrumKind::Unbounded,
    )?;
    let k = b.color(
        p,
        &format!("{prefix}k"),
        named_rgb("metal-Cu-k").expect("a named spectrum"),
        SpectrumKind::Unbounded,
    )?;
    // Not clamped: where a reflectance reads the same texture clamped, it reads its own copy.
    let mut unclamped = |v: Value| match v {
        Value::Tex(t) => Value::Tex(b.unclamped_texture(t)),
        rgb => rgb,
    };
    let (eta, k) = (unclamped(eta), unclamped(k));
    m.eta = Some(Spanned::new(
        p.span_of(&format!("{prefix}eta")),
        eta.param(),
    ));
    m.k = Some(Spanned::new(p.span_of(&format!("{prefix}k")), k.param()));
    Ok(())
}

/// pbrt's `diffusetransmission` as strata's diffuse with a `transmittance`: `reflectance` and
/// `transmittance` (0.25 each by default) times `scale`, clamped to [0, 1] at every lookup as
/// pbrt-v4 clamps them.
fn diffuse_transmission(b: &mut Builder, p: &Params) -> Result<MaterialDesc, SceneError> {
    let scale = p.float("scale", 1.0)?;
    if !(scale >= 0.0 && scale.is_finite()) {
        return Err(p.directive_err(format!("scale {scale}: finite and not negative")));
    }
    let mut part = |name: &str| -> Result<ColorParam, SceneError> {
        let value = b.color_unclamped(p, name, [0.25; 3], SpectrumKind::Reflectance)?;
        Ok(match value {
            Value::Rgb(c) => Textured::Value(Numbers(c.map(|x| (x * scale).clamp(0.0, 1.0)))),
            Value::Tex(t) => {
                let scaled = match b.scaled_texture(p, t.clone(), scale) {
                    Some(scaled) => scaled,
                    None => {
                        b.report.warnings.push(p.warning(format!(
                            "{name} texture `{t}` drawn unscaled (strata scales image textures \
                             only)"
                        )));
                        t
                    }
                };
                Textured::Texture(b.clamped_texture(p, name, scaled))
            }
        })
    };
    let (mut r, mut t) = (part("reflectance")?, part("transmittance")?);
    // pbrt-v4 draws a surface that reflects and transmits more than 1 as it is, creating energy;
    // strata refuses one, so constants are scaled down to a sum of 1 where it is exceeded.
    if let (Textured::Value(Numbers(rc)), Textured::Value(Numbers(tc))) = (&mut r, &mut t) {
        let sum = (0..3).map(|c| rc[c] + tc[c]).fold(0.0, f64::max);
        if sum > 1.0 {
            b.report.warnings.push(p.warning(format!(
                "reflectance {rc:?} and transmittance {tc:?} sum to {sum} (pbrt would create \
                 energy): both scaled by 1/{sum}"
            )));
            for c in 0..3 {
                (rc[c], tc[c]) = (rc[c] / sum, tc[c] / sum);
            }
        }
    }
    Ok(MaterialDesc::Diffuse(DiffuseDesc {
        albedo: Spanned::new(p.span_of("reflectance"), r),
        transmittance: Some(Spanned::new(p.span_of("transmittance"), t)),
        ..DiffuseDesc::default()
    }))
}

/// pbrt's `dielectric` as strata's, and `thindielectric` as strata's thin one.
fn dielectric(b: &mut Builder, p: &Params, kind: &str) -> Result<MaterialDesc, SceneError> {
    let thin = kind == "thindielectric";
    let eta = match p.find(ParamType::Spectrum, "eta") {
        Some(param) => dispersive_eta(b, p, param)?,
        None => p.float("eta", 1.5)?,
    };
    positive_eta(p, eta)?;
    // pbrt-v4's thin dielectric is smooth: it reads no roughness (and warns of none).
    let roughness = if thin { None } else { b.roughness(p)? };
    Ok(MaterialDesc::Dielectric(DielectricDesc {
        ior: Some(Spanned::new(p.span_of("eta"), eta)),
        roughness: roughness.map(|alpha| Spanned::new(roughness_span(p, ""), alpha)),
        thin: thin.then(|| Spanned::new(p.directive_span(), true)),
        ..DielectricDesc::default()
    }))
}

/// A dielectric's index given as a spectrum (named, a file, or pairs) as one number, its mean
/// weighted by ȳ (warned: strata does not disperse).
fn dispersive_eta(
    b: &mut Builder,
    p: &Params,
    param: &super::super::parse::Param,
) -> Result<f64, SceneError> {
    let eta = match &param.values {
        Values::Strings(s) => match super::super::named::named_spectrum(&s[0]) {
            Some(n) => n.rgb()[1],
            None => {
                let pairs = read_spd(&b.resolve(&s[0])).map_err(|reason| {
                    p.err(
                        param,
                        format!(
                            "`{}` is no spectrum pbrt-v4 names, nor a spectrum \
                             file: {reason}",
                            s[0]
                        ),
                    )
                })?;
                luminance_mean(&pairs)
            }
        },
        Values::Numbers(pairs) => luminance_mean(pairs),
        Values::Bools(_) => unreachable!("spectra are numbers or names"),
    };
    b.report.warnings.push(p.warning(format!(
        "a dispersive index drawn as one number, its mean weighted by the luminance \
         curve ȳ, {eta:.4} (strata does not disperse)"
    )));
    Ok(eta)
}

/// An error unless the index of refraction `eta` is finite and above 0.
fn positive_eta(p: &Params, eta: f64) -> Result<(), SceneError> {
    if !(eta > 0.0 && eta.is_finite()) {
        return Err(p.directive_err(format!("eta {eta}: above 0")));
    }
    Ok(())
}

/// pbrt's `coateddiffuse` as strata's coated material over a diffuse base (`reflectance`, 0.5
/// by default, clamped as pbrt clamps it), written as a material of its own beside it.
fn coated_diffuse(b: &mut Builder, p: &Params) -> Result<MaterialDesc, SceneError> {
    let r = b.reflectance(p, "reflectance", [0.5; 3])?;
    let base = MaterialDesc::Diffuse(DiffuseDesc {
        albedo: Spanned::new(p.span_of("reflectance"), r.param()),
        ..DiffuseDesc::default()
    });
    let roughness = b.roughness(p)?;
    let coat = coat(b, p, "eta", base, "coateddiffuse")?;
    Ok(MaterialDesc::Coated(CoatedDesc {
        roughness: roughness.map(|alpha| Spanned::new(roughness_span(p, ""), alpha)),
        ..coat
    }))
}

/// pbrt's `coatedconductor` as strata's coated material over its conductor (`conductor.eta`,
/// `conductor.k` or `reflectance`, `conductor.roughness`), the coat's roughness and index
/// named `interface.…`.
fn coated_conductor(b: &mut Builder, p: &Params) -> Result<MaterialDesc, SceneError> {
    let base = conductor(b, p, "coatedconductor")?;
    let roughness = roughness_with_prefix(b, p, "interface.")?;
    let coat = coat(b, p, "interface.eta", base, "coatedconductor")?;
    Ok(MaterialDesc::Coated(CoatedDesc {
        roughness: roughness.map(|alpha| Spanned::new(roughness_span(p, "interface."), alpha)),
        ..coat
    }))
}

/// The parameters every pbrt-v4 coat takes (its index `eta_name`, `thickness`, `albedo`, `g`,
/// `maxdepth`, `nsamples`), over `base`, which is written as a material of its own named after
/// the directive's place.
fn coat(
    b: &mut Builder,
    p: &Params,
    eta_name: &str,
    base: MaterialDesc,
    kind: &str,
) -> Result<CoatedDesc, SceneError> {
    let eta = match p.find(ParamType::Spectrum, eta_name) {
        Some(param) => dispersive_eta(b, p, param)?,
        None => p.float(eta_name, 1.5)?,
    };
    positive_eta(p, eta)?;
    let thickness = p.float("thickness", 0.01)?;
    if !(thickness > 0.0 && thickness.is_finite()) {
        return Err(p.directive_err(format!("thickness {thickness}: above 0")));
    }
    let albedo = b.reflectance(p, "albedo", [0.0; 3])?;
    let g = p.float("g", 0.0)?;
    let max_depth = p.integer("maxdepth", 10)?;
    let samples = p.integer("nsamples", 1)?;
    let (source, at) = p.location();
    let base_name = format!("{kind} base at {}", b.parsed.location(source, at));
    if b.desc
        .materials
        .iter()
        .all(|(n, _)| n.get_ref() != &base_name)
    {
        b.desc
            .materials
            .push((Spanned::new(p.directive_span(), base_name.clone()), base));
    }
    Ok(CoatedDesc {
        base: Spanned::new(p.directive_span(), base_name),
        ior: Some(Spanned::new(p.span_of(eta_name), eta)),
        thickness: Some(Spanned::new(p.span_of("thickness"), thickness)),
        albedo: Some(Spanned::new(p.span_of("albedo"), albedo.param())),
        g: Some(Spanned::new(p.span_of("g"), g.clamp(-0.99, 0.99))),
        max_depth: Some(Spanned::new(p.span_of("maxdepth"), max_depth.clamp(1, 100))),
        samples: Some(Spanned::new(p.span_of("nsamples"), samples.clamp(1, 16))),
        ..CoatedDesc::default()
    })
}

/// pbrt's `mix` as strata's: its two `materials` (strata's materials for them, written first)
/// and its `amount` (a number or a float texture, 0.5 by default; a number outside [0, 1] chooses
/// one of them everywhere, as pbrt's does); an error where mixes lead back through 16 of them.
fn mix(b: &mut Builder, p: &Params, depth: usize) -> Result<Option<MaterialDesc>, SceneError> {
    let names = match p.find(ParamType::String, "materials") {
        Some(param) => match &param.values {
            Values::Strings(s) => s.clone(),
            _ => Vec::new(),
        },
        None => Vec::new(),
    };
    if names.len() != 2 {
        return Err(p.directive_err(format!(
            "Material \"mix\" needs \"string materials\" naming two materials, not {}",
            names.len()
        )));
    }
    if depth >= 16 {
        return Err(p.directive_err(format!(
            "Material \"mix\": `{}` leads back through 16 mixes (a mix that names itself)",
            names[0]
        )));
    }
    let amount = match b.float_value(p, "amount", 0.5)? {
        Value::Rgb(c) => Textured::Value(Numbers([c[0].clamp(0.0, 1.0)])),
        Value::Tex(t) => Textured::Texture(t),
    };
    let (source, at) = p.location();
    let span = p.span_of("materials");
    let mut materials = Vec::new();
    for name in &names {
        let material = MaterialRef::Named(name.clone(), source, at);
        let Some(strata) = material_name_at(b, &material, None, depth + 1)? else {
            return Err(p.directive_err(format!(
                "Material \"mix\": `{name}` is an interface, which has no surface to mix"
            )));
        };
        materials.push(Spanned::new(span.clone(), strata));
    }
    Ok(Some(MaterialDesc::Mix(MixDesc {
        materials: Spanned::new(span, materials),
        amount: Some(Spanned::new(p.span_of("amount"), amount)),
        ..MixDesc::default()
    })))
}

/// A material type strata has no counterpart for as diffuse, its reflectance or 0.5 (warned).
fn fallback(b: &mut Builder, p: &Params, kind: &str) -> Result<MaterialDesc, SceneError> {
    b.report.warnings.push(p.warning(format!(
        "strata has no {kind} material: drawn as diffuse, its reflectance or 0.5"
    )));
    diffuse(b, p)
}

/// [`Builder::roughness`] of parameters named with `prefix` (`conductor.` in a coated
/// conductor).
fn roughness_with_prefix(
    b: &mut Builder,
    p: &Params,
    prefix: &str,
) -> Result<Option<RoughnessParam>, SceneError> {
    if prefix.is_empty() {
        return b.roughness(p);
    }
    let _ = b.roughness(p)?;
    let r = b.float_value(p, &format!("{prefix}roughness"), 0.0)?;
    let remap = p.bool("remaproughness", true)?;
    Ok(match r {
        Value::Rgb(c) if c[0] > 0.0 => {
            let alpha = if remap { c[0].sqrt() } else { c[0] };
            Some(Textured::Value(Numbers([alpha; 2])))
        }
        Value::Rgb(_) => None,
        Value::Tex(t) => Some(Textured::Texture(t)),
    })
}

/// Where the roughness of a material is written (its `roughness`, `uroughness`, or the
/// directive).
fn roughness_span(p: &Params, prefix: &str) -> Range<usize> {
    match p.has(&format!("{prefix}uroughness")) {
        true => p.span_of(&format!("{prefix}uroughness")),
        false => p.span_of(&format!("{prefix}roughness")),
    }
}
