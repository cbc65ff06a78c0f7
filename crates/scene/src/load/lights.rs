//! `[[lights]]` (point, line, distant) and `[sky]` → lights.

use super::desc::{LightDesc, SkyDesc};
use super::materials::emits;
use super::validate::{Ctx, Result};
use crate::records::{light_kind, Light, NONE};
use glam::Vec3;
use toml::Spanned;

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

/// `[sky]` → a `SKY` light; `None` when black.
pub fn sky(ctx: &Ctx, desc: &Spanned<SkyDesc>) -> Result<Option<Light>> {
    let d = desc.get_ref();
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

fn base() -> Light {
    Light {
        motion: NONE,
        ..Default::default()
    }
}
