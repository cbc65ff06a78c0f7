//! pbrt-v4's lights as strata's: `AreaLightSource "diffuse"` as the emission of the shapes that
//! follow it, and `LightSource` `point`, `spot`, `distant` and `infinite` (a constant colour, or an
//! equal-area octahedral image, oriented by the CTM).
//!
//! Radiance: pbrt-v4 divides a light's `scale` by its spectrum's luminance, where the spectrum
//! of an `rgb` value is that colour under the colour space's illuminant (D65), whose luminance
//! is 1 here. So `rgb` values are strata's as they are, and `blackbody`, named and sampled
//! spectra are their colour at luminance 1 ([`super::spectrum`], [`super::named`]), each
//! times `scale`.

use super::import::{numbers, AreaLight, Builder};
use super::params::Params;
use super::parse::{Directive, ParamType, Values};
use super::spectrum::{sampled_rgb, SpectrumKind};
use crate::desc::Spanned;
use crate::desc::{DistantDesc, LightDesc, Numbers, PointDesc, SkyDesc, SpotDesc};
use glam::{DMat3, DVec3};
use stratapt_scene::error::SceneError;

/// A light's spectrum parameter `name` as RGB (pbrt's default, the illuminant: white).
fn light_rgb(b: &Builder, p: &Params, name: &str) -> Result<[f64; 3], SceneError> {
    if let Some(param) = p.find(ParamType::Rgb, name) {
        let n = numbers(&param.values);
        if n.len() != 3 {
            return Err(p.err(param, format!("rgb {name} takes three numbers")));
        }
        return Ok([n[0], n[1], n[2]]);
    }
    if let Some(param) = p.find(ParamType::Blackbody, name) {
        let kelvin = match numbers(&param.values) {
            [k] => *k,
            n => {
                return Err(p.err(
                    param,
                    format!("blackbody {name} takes one temperature, not {}", n.len()),
                ))
            }
        };
        return super::spectrum::blackbody_rgb(kelvin).ok_or_else(|| {
            p.err(
                param,
                format!("blackbody {kelvin}: a temperature above 0 K"),
            )
        });
    }
    if let Some(param) = p.find(ParamType::Spectrum, name) {
        return match &param.values {
            Values::Strings(s) => match super::spectrum::named_rgb(&s[0]) {
                Some(rgb) => Ok(rgb),
                None => super::spectrum::read_spd(&b.resolve(&s[0]))
                    .map(|pairs| sampled_rgb(&pairs, SpectrumKind::Illuminant))
                    .map_err(|reason| {
                        p.err(
                            param,
                            format!(
                                "`{}` is no spectrum pbrt-v4 names, nor a spectrum file: {reason}",
                                s[0]
                            ),
                        )
                    }),
            },
            Values::Numbers(pairs) => Ok(sampled_rgb(pairs, SpectrumKind::Illuminant)),
            Values::Bools(_) => unreachable!("spectra are numbers or names"),
        };
    }
    Ok([1.0; 3])
}

fn scaled(c: [f64; 3], s: f64) -> [f64; 3] {
    c.map(|x| x * s)
}

/// A non-negative, finite radiance or intensity, or an error at the directive.
fn check(p: &Params, what: &str, c: [f64; 3]) -> Result<[f64; 3], SceneError> {
    match c.iter().all(|x| x.is_finite() && *x >= 0.0) {
        true => Ok(c),
        false => Err(p.directive_err(format!("{what} {c:?}: finite and not negative"))),
    }
}

/// A light's position, checked to be finite and within f32's range.
fn placed(p: &Params, v: DVec3) -> Result<DVec3, SceneError> {
    match super::import::fits_f32(&v.to_array()) {
        true => Ok(v),
        false => Err(p.directive_err(format!("placed at {v}: outside f32's range"))),
    }
}

/// The error for a `kind` light whose `from` and `to` are one point once placed: they are one
/// in the file, or a singular transform flattens them together (pbrt-v4's light would have no
/// direction either).
fn from_is_to(b: &Builder, p: &Params, kind: &str) -> SceneError {
    match b.state.attributes.flattened_at {
        Some(at) => p.directive_err(format!(
            "a {kind} light with no direction: the transform, singular since {}, takes its \
             from and to onto one point",
            b.parsed.location(at.0, at.1)
        )),
        None => p.directive_err(format!("a {kind} light with from = to")),
    }
}

/// `AreaLightSource`: the emission of the shapes that follow (`None`: not one strata draws).
pub(super) fn area_light(
    b: &mut Builder,
    source: usize,
    d: &Directive,
) -> Result<Option<AreaLight>, SceneError> {
    let p = Params::new(b.parsed, source, d);
    if p.kind() != "diffuse" {
        b.report
            .warnings
            .push(p.warning("not drawn: strata's area lights are diffuse"));
        b.report.warnings.extend(p.unused());
        return Ok(None);
    }
    let radiance = scaled(light_rgb(b, &p, "L")?, p.float("scale", 1.0)?);
    let radiance = check(&p, "radiance", radiance)?;
    let two_sided = p.bool("twosided", false)?;
    if p.float("power", -1.0)? > 0.0 {
        b.report
            .warnings
            .push(p.warning("power ignored: the radiance is L × scale"));
    }
    if p.string("filename")?.is_some() {
        b.report
            .warnings
            .push(p.warning("an emission image ignored: the radiance is L × scale"));
    }
    b.report.warnings.extend(p.unused());
    b.area_lights += 1;
    Ok(Some(AreaLight {
        radiance,
        index: b.area_lights - 1,
        two_sided,
        span: p.span_of("L"),
    }))
}

/// `LightSource`.
pub(super) fn light(b: &mut Builder, source: usize, d: &Directive) -> Result<(), SceneError> {
    let p = Params::new(b.parsed, source, d);
    let ctm = b.state.attributes.ctm;
    let point3 = |name: &str, default: DVec3| -> DVec3 {
        match p.find(ParamType::Point3, name) {
            Some(param) => {
                let n = numbers(&param.values);
                DVec3::new(n[0], n[1], n[2])
            }
            None => default,
        }
    };
    match p.kind() {
        "point" => {
            let from = point3("from", DVec3::ZERO);
            let mut scale = p.float("scale", 1.0)?;
            let power = p.float("power", -1.0)?;
            if power > 0.0 {
                scale *= power / (4.0 * std::f64::consts::PI);
            }
            let intensity = check(&p, "intensity", scaled(light_rgb(b, &p, "I")?, scale))?;
            let position = placed(&p, b.world_point(ctm.transform_point3(from)))?;
            let light = LightDesc::Point(PointDesc {
                position: Spanned::new(p.span_of("from"), position.to_array()),
                intensity: Spanned::new(p.span_of("I"), Numbers(intensity)),
                ..PointDesc::default()
            });
            b.desc.lights.push(Spanned::new(p.directive_span(), light));
        }
        "spot" => {
            let from = point3("from", DVec3::ZERO);
            let to = point3("to", DVec3::Z);
            let cone = p.float("coneangle", 30.0)?;
            let delta = p.float("conedeltaangle", 5.0)?;
            let (cos_end, cos_start) = (cone.to_radians().cos(), (cone - delta).to_radians().cos());
            let mut scale = p.float("scale", 1.0)?;
            let power = p.float("power", -1.0)?;
            if power > 0.0 {
                let k =
                    2.0 * std::f64::consts::PI * ((1.0 - cos_start) + 0.5 * (cos_start - cos_end));
                scale *= power / k;
            }
            let intensity = check(&p, "intensity", scaled(light_rgb(b, &p, "I")?, scale))?;
            if !((0.0..=180.0).contains(&cone) && (0.0..=180.0).contains(&delta)) {
                return Err(p.directive_err(format!(
                    "coneangle {cone}, conedeltaangle {delta}: each 0 to 180 degrees"
                )));
            }
            let position = placed(&p, b.world_point(ctm.transform_point3(from)))?;
            let look_at = placed(&p, b.world_point(ctm.transform_point3(to)))?;
            if (look_at - position).length_squared() == 0.0 {
                return Err(from_is_to(b, &p, "spot"));
            }
            let light = LightDesc::Spot(SpotDesc {
                position: Spanned::new(p.span_of("from"), position.to_array()),
                look_at: Spanned::new(p.span_of("to"), look_at.to_array()),
                intensity: Spanned::new(p.span_of("I"), Numbers(intensity)),
                cone_angle: Some(Spanned::new(p.span_of("coneangle"), cone)),
                cone_delta: Some(Spanned::new(p.span_of("conedeltaangle"), delta)),
                ..SpotDesc::default()
            });
            b.desc.lights.push(Spanned::new(p.directive_span(), light));
        }
        "distant" => {
            let from = point3("from", DVec3::ZERO);
            let to = point3("to", DVec3::Z);
            let scale = p.float("scale", 1.0)?;
            if p.float("illuminance", -1.0)? > 0.0 {
                b.report
                    .warnings
                    .push(p.warning("illuminance ignored: the irradiance is L × scale"));
            }
            let irradiance = check(&p, "irradiance", scaled(light_rgb(b, &p, "L")?, scale))?;
            let towards = b.world_vector(ctm.transform_vector3(from - to));
            if towards.length_squared() == 0.0 || !towards.is_finite() {
                return Err(from_is_to(b, &p, "distant"));
            }
            let light = LightDesc::Distant(DistantDesc {
                direction: Spanned::new(p.span_of("to"), towards.normalize().to_array()),
                irradiance: Spanned::new(p.span_of("L"), Numbers(irradiance)),
                ..DistantDesc::default()
            });
            b.desc.lights.push(Spanned::new(p.directive_span(), light));
        }
        "infinite" => infinite(b, &p, DMat3::from_mat4(ctm))?,
        other => {
            b.report
                .warnings
                .push(p.warning(format!("not drawn: strata has no {other} light")));
        }
    }
    b.report.warnings.extend(p.unused());
    Ok(())
}

/// `LightSource "infinite"`: strata's sky (one per scene).
fn infinite(b: &mut Builder, p: &Params, world_from_light: DMat3) -> Result<(), SceneError> {
    if b.desc.scene.sky.is_some() {
        b.report
            .warnings
            .push(p.warning("not drawn: strata has one environment, the first infinite light"));
        let _ = (
            p.string("filename")?,
            light_rgb(b, p, "L")?,
            p.float("scale", 1.0)?,
        );
        return Ok(());
    }
    let scale = p.float("scale", 1.0)?;
    if p.float("illuminance", -1.0)? > 0.0 {
        b.report
            .warnings
            .push(p.warning("illuminance ignored: the radiance is the image (or L) × scale"));
    }
    if p.find(ParamType::Point3, "portal").is_some() {
        b.report
            .warnings
            .push(p.warning("portal ignored (it only changes the noise)"));
    }
    let Some(file) = p.string("filename")? else {
        let color = check(p, "radiance", scaled(light_rgb(b, p, "L")?, scale))?;
        let sky = SkyDesc {
            color: Some(Spanned::new(p.span_of("L"), Numbers(color))),
            ..SkyDesc::default()
        };
        b.desc.scene.sky = Some(Spanned::new(p.directive_span(), sky));
        return Ok(());
    };
    b.existing_file(p, "filename", file)?;
    if p.find(ParamType::Rgb, "L").is_some() || p.find(ParamType::Spectrum, "L").is_some() {
        b.report
            .warnings
            .push(p.warning("L ignored: the image gives the radiance"));
    }
    // pbrt's light space → strata's world: its rotation (columns made orthonormal), then the
    // camera's mirror. An improper result is a proper rotation of the map mirrored in x.
    let r = orthonormal(world_from_light);
    let largest = |m: DMat3| m.to_cols_array().iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if largest(r - world_from_light) > 1e-6 * largest(world_from_light) {
        b.report.warnings.push(
            p.warning("the transform's scale and shear dropped: an environment map is only turned"),
        );
    }
    if !r.is_finite() {
        return Err(p.directive_err(
            "the transform turns no direction (it is singular): the map cannot be oriented",
        ));
    }
    let mut w = DMat3::from_mat4(b.mirror) * r;
    let mirrored = w.determinant() < 0.0;
    if mirrored {
        w *= DMat3::from_diagonal(DVec3::new(-1.0, 1.0, 1.0));
    }
    let at = p.directive_span();
    let mut sky = SkyDesc {
        map: Some(Spanned::new(p.span_of("filename"), b.file_path(file))),
        mapping: Some(Spanned::new(at.clone(), "octahedral".to_string())),
        rotate: Some(Spanned::new(at.clone(), euler_xyz_of(w).to_array())),
        mirror: mirrored.then(|| Spanned::new(at.clone(), true)),
        ..SkyDesc::default()
    };
    if scale != 1.0 {
        let scale = check(p, "scale", [scale; 3])?;
        sky.scale = Some(Spanned::new(p.span_of("scale"), Numbers(scale)));
    }
    b.desc.scene.sky = Some(Spanned::new(at, sky));
    Ok(())
}

/// The nearest rotation to `m`'s columns (Gram–Schmidt), keeping its handedness.
fn orthonormal(m: DMat3) -> DMat3 {
    let x = m.x_axis.normalize();
    let y = (m.y_axis - x * x.dot(m.y_axis)).normalize();
    let z = x.cross(y);
    let z = if z.dot(m.z_axis) < 0.0 { -z } else { z };
    DMat3::from_cols(x, y, z)
}

/// Euler angles in degrees `(x, y, z)` with `Rz · Ry · Rx = r` (strata's `rotate`) of a proper
/// rotation.
pub fn euler_xyz_of(r: DMat3) -> DVec3 {
    // Rz·Ry·Rx: row 2 is (−sin y, cos y sin x, cos y cos x).
    let (r00, r10, r20) = (r.x_axis.x, r.x_axis.y, r.x_axis.z);
    let (r21, r22) = (r.y_axis.z, r.z_axis.z);
    let y = (-r20).clamp(-1.0, 1.0).asin();
    let (x, z) = if r20.abs() < 1.0 - 1e-12 {
        (r21.atan2(r22), r10.atan2(r00))
    } else {
        // Gimbal lock: x and z turn about one axis; put it all in z.
        let (r01, r11) = (r.y_axis.x, r.y_axis.y);
        (0.0, (-r01).atan2(r11))
    };
    DVec3::new(x, y, z) * (180.0 / std::f64::consts::PI)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_angles_rebuild_the_rotation() {
        let rotations = [
            DMat3::IDENTITY,
            DMat3::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 1.1),
            DMat3::from_axis_angle(DVec3::Y, std::f64::consts::FRAC_PI_2),
            DMat3::from_axis_angle(DVec3::Y, -std::f64::consts::FRAC_PI_2)
                * DMat3::from_axis_angle(DVec3::X, 0.3),
            DMat3::from_axis_angle(DVec3::new(-0.3, 0.1, 0.9).normalize(), 3.0),
        ];
        for r in rotations {
            let e = euler_xyz_of(r);
            let q = crate::load::euler_xyz(e.as_vec3());
            let back = glam::DMat3::from_quat(q.as_dquat());
            assert!(
                (back - r).to_cols_array().iter().all(|x| x.abs() < 1e-5),
                "{r} → {e} → {back}"
            );
        }
    }
}
