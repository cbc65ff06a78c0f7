//! `[[lights]]` (point, line, distant) and `[sky]` → lights.

use super::materials::emits;
use super::transform::euler_xyz;
use super::validate::{Ctx, Result};
use crate::desc::Spanned;
use crate::desc::{LightDesc, SkyDesc};
use glam::{Mat3, Quat, Vec3};
use stratapt_scene::environment::{self, EnvironmentMap};
use stratapt_scene::records::{light_kind, Light, NONE};

/// Largest accepted angular diameter of a distant light, in degrees (a hemisphere).
pub const MAX_ANGULAR_DIAMETER: f32 = 180.0;

/// Convert one `[[lights]]` entry; `None` for a black light (it is dropped).
pub fn light(ctx: &Ctx, desc: &LightDesc) -> Result<Option<Light>> {
    let light = match desc {
        LightDesc::Point(d) => Light {
            p0: ctx.point(&d.position, "position")?.to_array(),
            kind: light_kind::POINT,
            radiance: ctx.emitted(&d.intensity, "intensity")?,
            ..base()
        },
        LightDesc::Line(d) => {
            let from = ctx.point(&d.from, "from")?;
            let to = ctx.point(&d.to, "to")?;
            if from == to {
                return Err(ctx.err(d.to.span(), "a line light needs `from` ≠ `to`"));
            }
            Light {
                p0: from.to_array(),
                kind: light_kind::LINE,
                p1: to.to_array(),
                radiance: ctx.emitted(&d.intensity, "intensity")?,
                ..base()
            }
        }
        LightDesc::Distant(d) => {
            let direction = ctx.direction(&d.direction, "direction")?;
            let irradiance = ctx.emitted(&d.irradiance, "irradiance")?;
            let diameter = match &d.angular_diameter {
                Some(a) => {
                    let x = ctx.non_negative(a, "angular_diameter")?;
                    if x >= MAX_ANGULAR_DIAMETER {
                        return Err(ctx.err(a.span(), format!("`angular_diameter` must be below {MAX_ANGULAR_DIAMETER} degrees, got {x}")));
                    }
                    x
                }
                None => 0.0,
            };
            let (cos_max, radiance) = distant_cone(diameter, irradiance);
            Light {
                p0: direction.to_array(),
                kind: light_kind::DISTANT,
                p2: [cos_max, 0.0, 0.0],
                radiance,
                ..base()
            }
        }
        LightDesc::Spot(d) => {
            let position = ctx.point(&d.position, "position")?;
            let look_at = ctx.point(&d.look_at, "look_at")?;
            let axis = (look_at - position).normalize_or_zero();
            if axis == Vec3::ZERO || !axis.is_finite() {
                return Err(ctx.err(
                    d.look_at.span(),
                    "a spot light needs `look_at` ≠ `position`",
                ));
            }
            let angle = |v: &Option<Spanned<f64>>, key: &str, default: f32| match v {
                Some(a) => {
                    let x = ctx.non_negative(a, key)?;
                    match x <= 180.0 {
                        true => Ok(x),
                        false => Err(ctx.err(
                            a.span(),
                            format!("`{key}` must be at most 180 degrees, got {x}"),
                        )),
                    }
                }
                None => Ok(default),
            };
            let cone = angle(&d.cone_angle, "cone_angle", 30.0)?;
            let delta = angle(&d.cone_delta, "cone_delta", 5.0)?.min(cone);
            let cos = |deg: f32| (deg as f64).to_radians().cos() as f32;
            Light {
                p0: position.to_array(),
                kind: light_kind::SPOT,
                p1: axis.to_array(),
                p2: [cos(cone), cos(cone - delta), 0.0],
                radiance: ctx.emitted(&d.intensity, "intensity")?,
                ..base()
            }
        }
    };
    Ok(emits(light.radiance).then_some(light))
}

/// Cone cosine and radiance of a distant light of angular diameter `degrees` delivering
/// `irradiance` at normal incidence: `L = E / (π sin²θmax)` inside the cone. A cone so narrow
/// that its cosine rounds to 1 in `f32` is a delta direction (cosine 1, "radiance" = E).
pub fn distant_cone(degrees: f32, irradiance: [f32; 3]) -> (f32, [f32; 3]) {
    let half = (degrees as f64 * 0.5).to_radians();
    let cos_max = half.cos() as f32;
    if cos_max >= 1.0 {
        return (1.0, irradiance);
    }
    // sin² from the f32 cosine, so that the cone the renderers sample gets exactly E.
    let c = cos_max as f64;
    let sin2 = 1.0 - c * c;
    let scale = 1.0 / (std::f64::consts::PI * sin2);
    (cos_max, irradiance.map(|e| (e as f64 * scale) as f32))
}

/// `[sky]` → a `SKY` light, or an `ENVIRONMENT` or `OCTAHEDRAL` light whose map is appended to
/// `tables`; `None` when black.
pub fn sky(
    ctx: &Ctx,
    desc: &Spanned<SkyDesc>,
    base_dir: &std::path::Path,
    tables: &mut Vec<f32>,
) -> Result<Option<Light>> {
    let d = desc.get_ref();
    if let Some(map) = &d.map {
        return environment(ctx, d, map, base_dir, tables);
    }
    for (key, span) in [
        ("scale", d.scale.as_ref().map(|s| s.span())),
        ("rotate", d.rotate.as_ref().map(|s| s.span())),
        ("mapping", d.mapping.as_ref().map(|s| s.span())),
        ("mirror", d.mirror.as_ref().map(|s| s.span())),
    ] {
        if let Some(span) = span {
            return Err(ctx.err(span, format!("`{key}` applies to an environment `map`")));
        }
    }
    let (bottom, top) = match (&d.color, &d.top, &d.bottom) {
        (Some(c), None, None) => {
            let c = ctx.emitted(c, "color")?;
            (c, c)
        }
        (None, Some(top), Some(bottom)) => {
            (ctx.emitted(bottom, "bottom")?, ctx.emitted(top, "top")?)
        }
        (Some(c), _, _) => {
            return Err(ctx.err(
                c.span(),
                "give either `color` or `top` and `bottom`, not both",
            ))
        }
        (None, Some(t), None) => return Err(ctx.err(t.span(), "`top` needs `bottom` too")),
        (None, None, Some(b)) => return Err(ctx.err(b.span(), "`bottom` needs `top` too")),
        (None, None, None) => {
            return Err(ctx.err(desc.span(), "[sky] needs `color`, or `top` and `bottom`"))
        }
    };
    let up = match &d.up {
        Some(up) => ctx.direction(up, "up")?,
        None => Vec3::Y,
    };
    let light = Light {
        p0: up.to_array(),
        kind: light_kind::SKY,
        p1: top,
        radiance: bottom,
        ..base()
    };
    Ok((emits(bottom) || emits(top)).then_some(light))
}

/// `[sky] map = "…"`: the environment map, its texels scaled and its distribution built, in
/// `tables`; the light holds its frame, size, offset and mean radiance
/// ([`light_kind::ENVIRONMENT`], or [`light_kind::OCTAHEDRAL`] for `mapping = "octahedral"`).
fn environment(
    ctx: &Ctx,
    d: &SkyDesc,
    map: &Spanned<String>,
    base_dir: &std::path::Path,
    tables: &mut Vec<f32>,
) -> Result<Option<Light>> {
    for (key, span) in [
        ("color", d.color.as_ref().map(|s| s.span())),
        ("top", d.top.as_ref().map(|s| s.span())),
        ("bottom", d.bottom.as_ref().map(|s| s.span())),
        ("up", d.up.as_ref().map(|s| s.span())),
    ] {
        if let Some(span) = span {
            return Err(ctx.err(
                span,
                format!("`{key}` and `map` exclude each other (orient a map with `rotate`)"),
            ));
        }
    }
    let kind = match &d.mapping {
        Some(m) => ctx.one_of(
            m,
            "mapping",
            &["equirectangular", "octahedral"],
            |s| match s {
                "equirectangular" => Some(light_kind::ENVIRONMENT),
                "octahedral" => Some(light_kind::OCTAHEDRAL),
                _ => None,
            },
        )?,
        None => light_kind::ENVIRONMENT,
    };
    let path = base_dir.join(map.get_ref());
    let (mut texels, w, h) = environment::read_image(&path).map_err(|reason| {
        ctx.err(
            map.span(),
            format!(
                "environment map `{}` ({}): {reason}",
                map.get_ref(),
                path.display()
            ),
        )
    })?;
    let scale = match &d.scale {
        Some(s) => ctx.emitted(s, "scale")?,
        None => [1.0; 3],
    };
    for texel in texels.chunks_mut(3) {
        for c in 0..3 {
            texel[c] *= scale[c];
        }
    }
    // Reversing the map's x is reversing its columns, in either layout: the latitude–longitude
    // map's φ ↦ −φ is u ↦ 1 − u, and so is the octahedral map's x ↦ −x (its right edge is +x,
    // and the square's folds are symmetric about its vertical centre line).
    if d.mirror.as_ref().is_some_and(|m| *m.get_ref()) {
        for row in texels.chunks_mut(3 * w) {
            let columns = row.len() / 3;
            for i in 0..columns / 2 {
                for c in 0..3 {
                    row.swap(3 * i + c, 3 * (columns - 1 - i) + c);
                }
            }
        }
    }
    let rotation = match &d.rotate {
        Some(r) => euler_xyz(ctx.point(r, "rotate")?),
        None => Quat::IDENTITY,
    };
    let env = if kind == light_kind::OCTAHEDRAL {
        if w != h {
            return Err(ctx.err(
                d.mapping.as_ref().map_or(map.span(), |m| m.span()),
                format!(
                    "environment map `{}` is {w}×{h} texels: an octahedral map (pbrt-v4's \
                     equal-area layout) is square",
                    map.get_ref()
                ),
            ));
        }
        EnvironmentMap::octahedral(texels, w)
    } else {
        EnvironmentMap::new(texels, w, h)
    };
    let Some(env) = env else {
        return Ok(None);
    };
    // The offset travels as an f32 (exact below 2^24); what precedes the map is the rough
    // plastics' tables, 64 floats each.
    let offset = tables.len();
    if offset >= 1 << 24 {
        return Err(ctx.err(
            map.span(),
            "the materials' tables leave no room for the map",
        ));
    }
    tables.extend_from_slice(&env.data);
    // World → map: the inverse (transpose) of the map's rotation.
    let to_map = Mat3::from_quat(rotation).transpose();
    Ok(Some(Light {
        p0: to_map.row(0).to_array(),
        kind,
        p1: to_map.row(1).to_array(),
        p2: [w as f32, h as f32, offset as f32],
        radiance: env.mean_radiance,
        ..base()
    }))
}

fn base() -> Light {
    Light {
        motion: NONE,
        ..Default::default()
    }
}
