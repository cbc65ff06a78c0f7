//! `[camera]`, `[film]` and `[render]` → [`Camera`] and [`RenderSettings`].

use super::validate::{Ctx, Result};
use crate::desc::Spanned;
use crate::desc::{CameraDesc, FilmDesc, RenderDesc};
use glam::Vec3;
use stratapt_scene::records::{filter_kind, Camera};
use stratapt_scene::{RenderSettings, SamplerKind, Strategy};

/// Largest accepted film side, in pixels.
pub const MAX_RESOLUTION: u32 = 16384;
/// Largest accepted `max_depth`.
pub const MAX_DEPTH: u32 = 1024;
/// Default film side, in pixels.
pub const DEFAULT_RESOLUTION: u32 = 256;

/// The camera (with film and filter), and whether the shutter is open (`close > open`).
pub fn camera(
    ctx: &Ctx,
    desc: &Spanned<CameraDesc>,
    film: Option<&Spanned<FilmDesc>>,
) -> Result<(Camera, bool)> {
    let d = desc.get_ref();
    // Pose at shutter open.
    let eye0 = ctx.point(&d.eye, "eye")?;
    let target0 = ctx.point(&d.look_at, "look_at")?;
    let up0 = match &d.up {
        Some(up) => ctx.direction(up, "up")?,
        None => Vec3::Y,
    };
    check_pose(ctx, d, eye0, target0, up0, &d.look_at, d.up.as_ref())?;

    // Pose at shutter close: each key defaults to the open one.
    let (mut eye1, mut target1, mut up1) = (eye0, target0, up0);
    if let Some(close) = &d.close {
        let c = close.get_ref();
        if let Some(eye) = &c.eye {
            eye1 = ctx.point(eye, "close.eye")?;
        }
        if let Some(look_at) = &c.look_at {
            target1 = ctx.point(look_at, "close.look_at")?;
        }
        if let Some(up) = &c.up {
            up1 = ctx.direction(up, "close.up")?;
        }
        let at = c.look_at.as_ref().unwrap_or(&d.look_at);
        check_pose(
            ctx,
            d,
            eye1,
            target1,
            up1,
            at,
            c.up.as_ref().or(d.up.as_ref()),
        )?;
    }

    // Lens, shutter.
    let fov = ctx.finite(&d.fov, "fov")?;
    if !(fov > 0.0 && fov < 180.0) {
        return Err(ctx.err(
            d.fov.span(),
            format!("`fov` must be in (0, 180) degrees, got {}", d.fov.get_ref()),
        ));
    }
    let lens_radius = match &d.aperture {
        Some(a) => ctx.non_negative(a, "aperture")?,
        None => 0.0,
    };
    let focus_distance = match &d.focus_distance {
        Some(f) => ctx.positive(f, "focus_distance")?,
        None => (target0 - eye0).length(),
    };
    let (shutter_open, shutter_close) = match &d.shutter {
        Some(s) => {
            let [open, close] = *s.get_ref();
            let open = ctx.finite(&Spanned::new(s.span(), open), "shutter")?;
            let close = ctx.finite(&Spanned::new(s.span(), close), "shutter")?;
            if close < open {
                return Err(ctx.err(
                    s.span(),
                    format!("`shutter` close ({close}) must not be before open ({open})"),
                ));
            }
            (open, close)
        }
        None => (0.0, 0.0),
    };
    let is_open = shutter_close > shutter_open;
    if let Some(close) = &d.close {
        let moves = (eye0, target0, up0) != (eye1, target1, up1);
        if moves && !is_open {
            return Err(ctx.err(
                close.span(),
                "`camera.close` moves the camera but the shutter is closed: set \
                 `shutter = [0, 1]` in [camera]",
            ));
        }
    }

    let film = film_settings(ctx, film)?;
    let camera = Camera {
        eye0: eye0.to_array(),
        tan_half_fov: (fov.to_radians() * 0.5).tan(),
        target0: target0.to_array(),
        lens_radius,
        up0: up0.to_array(),
        focus_distance,
        eye1: eye1.to_array(),
        shutter_open,
        target1: target1.to_array(),
        shutter_close,
        up1: up1.to_array(),
        filter: film.filter,
        width: film.width,
        height: film.height,
        filter_param: film.filter_param,
        ..Default::default()
    };
    Ok((camera, is_open))
}

/// The view direction must be non-zero and not parallel to `up`.
fn check_pose(
    ctx: &Ctx,
    d: &CameraDesc,
    eye: Vec3,
    target: Vec3,
    up: Vec3,
    look_at: &Spanned<[f64; 3]>,
    up_key: Option<&Spanned<[f64; 3]>>,
) -> Result<()> {
    let forward = (target - eye).normalize_or_zero();
    if forward == Vec3::ZERO {
        return Err(ctx.err(
            look_at.span(),
            "`look_at` must differ from `eye` (zero view direction)",
        ));
    }
    if forward.cross(up).length() < 1e-6 {
        let span = up_key.map_or(d.look_at.span(), |u| u.span());
        return Err(ctx.err(
            span,
            "`up` is parallel to the view direction (look_at − eye)",
        ));
    }
    Ok(())
}

struct Film {
    width: u32,
    height: u32,
    filter: u32,
    filter_param: f32,
}

fn film_settings(ctx: &Ctx, film: Option<&Spanned<FilmDesc>>) -> Result<Film> {
    let mut out = Film {
        width: DEFAULT_RESOLUTION,
        height: DEFAULT_RESOLUTION,
        filter: filter_kind::BOX,
        filter_param: 1.0,
    };
    let Some(film) = film else { return Ok(out) };
    let f = film.get_ref();
    if let Some(w) = &f.width {
        out.width = ctx.count(w, "width", MAX_RESOLUTION)?;
    }
    if let Some(h) = &f.height {
        out.height = ctx.count(h, "height", MAX_RESOLUTION)?;
    }
    if let Some(filter) = &f.filter {
        const FILTERS: [&str; 3] = ["box", "tent", "gaussian"];
        out.filter = ctx.one_of(filter, "filter", &FILTERS, |s| match s {
            "box" => Some(filter_kind::BOX),
            "tent" => Some(filter_kind::TENT),
            "gaussian" => Some(filter_kind::GAUSSIAN),
            _ => None,
        })?;
    }
    out.filter_param = match &f.filter_width {
        Some(w) => ctx.positive(w, "filter_width")?,
        None if out.filter == filter_kind::GAUSSIAN => 0.5,
        None => 1.0,
    };
    Ok(out)
}

/// `[render] exact`: every pixel's closed-form value, if the scene states one.
pub fn exact(ctx: &Ctx, render: Option<&Spanned<RenderDesc>>) -> Result<Option<[f64; 3]>> {
    let Some(exact) = render.and_then(|r| r.get_ref().exact.as_ref()) else {
        return Ok(None);
    };
    ctx.finite3(exact.get_ref().0, exact.span(), "exact")?;
    Ok(Some(exact.get_ref().0))
}

/// `[render]` → settings, defaults where absent.
pub fn settings(ctx: &Ctx, render: Option<&Spanned<RenderDesc>>) -> Result<RenderSettings> {
    let mut s = RenderSettings::default();
    let Some(render) = render else { return Ok(s) };
    let r = render.get_ref();
    if let Some(spp) = &r.spp {
        s.pattern_spp = ctx.count(spp, "spp", u32::MAX)?;
    }
    if let Some(depth) = &r.max_depth {
        s.max_depth = ctx.count(depth, "max_depth", MAX_DEPTH)?;
    }
    if let Some(sampler) = &r.sampler {
        let names: Vec<_> = SamplerKind::ALL.iter().map(|k| k.name()).collect();
        s.sampler = ctx.one_of(sampler, "sampler", &names, SamplerKind::from_name)?;
    }
    if let Some(strategy) = &r.strategy {
        let names: Vec<_> = Strategy::ALL.iter().map(|k| k.name()).collect();
        s.strategy = ctx.one_of(strategy, "strategy", &names, Strategy::from_name)?;
    }
    if let Some(seed) = &r.seed {
        let v = *seed.get_ref();
        if !(0..=u32::MAX as i64).contains(&v) {
            return Err(ctx.err(
                seed.span(),
                format!("`seed` must be in 0..={}, got {v}", u32::MAX),
            ));
        }
        s.seed = v as u32;
    }
    Ok(s)
}
