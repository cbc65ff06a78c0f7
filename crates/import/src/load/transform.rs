//! `transform` / `transform_close` → where a shape lives: baked into world space, or in object
//! space with a [`Motion`].

use super::validate::{Ctx, Result};
use crate::desc::Spanned;
use crate::desc::{ShapeCommon, TransformDesc};
use glam::{Quat, Vec3};
use std::ops::Range;
use stratapt_scene::records::{Motion, Pose};

/// Where a shape's geometry is stored.
pub enum Placement {
    /// Baked into world space with this pose (often the identity).
    Static(Pose),
    /// Stored in object space, moved by this motion.
    Moving(Motion),
}

/// A shape's placement, and the span to blame for scale problems.
pub struct Placed {
    pub placement: Placement,
    pub scale_span: Range<usize>,
}

impl Placed {
    /// The poses at shutter open and close (equal when static).
    pub fn poses(&self) -> [Pose; 2] {
        match &self.placement {
            Placement::Static(p) => [*p, *p],
            Placement::Moving(m) => [m.open, m.close],
        }
    }

    /// Whether every pose scales all axes alike (spheres and disks need it).
    pub fn uniform_scale(&self) -> bool {
        self.poses()
            .iter()
            .all(|p| p.scale[0] == p.scale[1] && p.scale[1] == p.scale[2])
    }

    /// Error unless uniform: `what` names the shape.
    pub fn require_uniform_scale(&self, ctx: &Ctx, what: &str) -> Result<()> {
        if self.uniform_scale() {
            Ok(())
        } else {
            Err(ctx.err(
                self.scale_span.clone(),
                format!("a {what} needs a uniform `scale` (one number), not a per-axis one"),
            ))
        }
    }
}

/// Resolve a shape's `transform` and `transform_close`.
pub fn place(
    ctx: &Ctx,
    common: &ShapeCommon,
    table_span: Range<usize>,
    shutter_open: bool,
) -> Result<Placed> {
    let open = match &common.transform {
        Some(t) => pose(ctx, t.get_ref(), None)?,
        None => Pose::IDENTITY,
    };
    let mut scale_span = common
        .transform
        .as_ref()
        .map(|t| t.get_ref().scale.as_ref().map_or(t.span(), |s| s.span()))
        .unwrap_or(table_span);
    let Some(close_desc) = &common.transform_close else {
        return Ok(Placed {
            placement: Placement::Static(open),
            scale_span,
        });
    };
    let close = pose(
        ctx,
        close_desc.get_ref(),
        common.transform.as_ref().map(|t| t.get_ref()),
    )?;
    if close == open {
        return Ok(Placed {
            placement: Placement::Static(open),
            scale_span,
        });
    }
    if !shutter_open {
        return Err(ctx.err(
            close_desc.span(),
            "`transform_close` moves the shape but the shutter is closed: set \
             `shutter = [0, 1]` in [camera]",
        ));
    }
    if close.scale != open.scale {
        if let Some(s) = &close_desc.get_ref().scale {
            scale_span = s.span();
        }
    }
    Ok(Placed {
        placement: Placement::Moving(Motion { open, close }),
        scale_span,
    })
}

/// One pose; keys absent from `desc` come from `base` (the open pose's table), else identity.
fn pose(ctx: &Ctx, desc: &TransformDesc, base: Option<&TransformDesc>) -> Result<Pose> {
    let pick = |own: &Option<Spanned<[f64; 3]>>, base_key: Option<&Option<Spanned<[f64; 3]>>>| {
        own.clone().or_else(|| base_key.and_then(|b| b.clone()))
    };
    let translate = pick(&desc.translate, base.map(|b| &b.translate));
    let rotate = pick(&desc.rotate, base.map(|b| &b.rotate));
    let scale = desc
        .scale
        .clone()
        .or_else(|| base.and_then(|b| b.scale.clone()));

    let translation = match &translate {
        Some(t) => ctx.point(t, "translate")?,
        None => Vec3::ZERO,
    };
    let rotation = match &rotate {
        Some(r) => euler_xyz(ctx.point(r, "rotate")?),
        None => Quat::IDENTITY,
    };
    let scale = match &scale {
        Some(s) => {
            let v = ctx.finite3(s.get_ref().0, s.span(), "scale")?;
            if v.min_element() <= 0.0 {
                return Err(ctx.err(
                    s.span(),
                    format!("`scale` must be positive on every axis (mirroring is not supported), got {:?}", s.get_ref().0),
                ));
            }
            v
        }
        None => Vec3::ONE,
    };
    Ok(Pose::new(translation, rotation, scale))
}

/// Rotation by Euler angles in degrees, applied about X, then Y, then Z (world axes):
/// `R = Rz · Ry · Rx`.
pub fn euler_xyz(degrees: Vec3) -> Quat {
    let r = degrees * (std::f32::consts::PI / 180.0);
    Quat::from_rotation_z(r.z) * Quat::from_rotation_y(r.y) * Quat::from_rotation_x(r.x)
}
