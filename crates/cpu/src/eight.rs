//! A prototype of the eight-lane CPU renderer (issue 48; as a `Render`er:
//! [`crate::Cpu8Renderer`]): the path loop of
//! [`crate::integrator`] for eight paths at once, one per lane of an AVX2 vector (`wide`), a
//! lane refilled from the pixel queue when its path ends (a wavefront of eight paths per thread).
//!
//! It covers what Mitsuba 3's Cornell box calls for, and refuses any other scene
//! ([`supports`]): static triangles, diffuse materials without textures, one one-sided
//! rectangle light, a pinhole camera with the box filter, the Sobol sampler and MIS. Within that
//! it computes the one-lane reference's estimator from the same sample values (the sampler's
//! integer arithmetic and the ray-origin offsets are the reference's bit for bit; `sin_cos`
//! of the concentric disk is `wide`'s polynomial rather than libm's), so its films agree with
//! the reference's statistically, not bit for bit. Ray queries are the reference's, lane by
//! lane. Where the time goes and what it gains: `docs/measurements/eight-lanes.md`.

mod path;
mod rectangle;
mod sobol;

pub use path::Paths;

use stratapt_sampling::SamplerKind;
use stratapt_scene::records::{filter_kind, light_flag, light_kind, material_kind, NONE};
use stratapt_scene::{Effects, FlatScene, RenderSettings, Strategy};

/// What the prototype found in a scene it covers.
#[derive(Clone, Debug)]
pub struct Support {
    pub(crate) effects: Effects,
    /// The light next-event estimation samples (none: the scene has no light).
    pub(crate) nee_light: Option<usize>,
}

/// Whether the prototype covers `scene` under `settings`; if not, the first thing it lacks.
pub fn supports(scene: &FlatScene, settings: &RenderSettings) -> Result<Support, String> {
    let effects = Effects::of(scene, settings);
    let refuse = |what: &str| Err(format!("the eight-lane prototype does not cover {what}"));
    if settings.sampler != SamplerKind::Sobol {
        return refuse(&format!("the {} sampler (only sobol)", settings.sampler));
    }
    if settings.strategy != Strategy::Mis {
        return refuse(&format!("the {} strategy (only mis)", settings.strategy));
    }
    if effects.lens || effects.time {
        return refuse("a thin lens or motion blur");
    }
    if scene.camera.filter != filter_kind::BOX {
        return refuse("pixel filters other than the box");
    }
    if effects.textures || effects.alpha || effects.lobe {
        return refuse("textures, alpha or materials that choose lobes");
    }
    if scene
        .materials
        .iter()
        .any(|m| m.tag != material_kind::DIFFUSE)
    {
        return refuse("materials other than plain diffuse");
    }
    if (0..scene.geometry.len() as u32).any(|id| !scene.geometry.is_static_triangle(id)) {
        return refuse("primitives other than static triangles");
    }
    if !scene.environment_lights().is_empty() || scene.light_table.len() > 1 {
        return refuse("environment lights or more than one light");
    }
    let nee_light = match scene.light_table.is_empty() {
        true => None,
        false => {
            let (index, _) = stratapt_scene::light_table::select(&scene.light_table, 0.0);
            let l = &scene.lights[index];
            if l.kind != light_kind::RECTANGLE || l.has(light_flag::TWO_SIDED) || l.motion != NONE {
                return refuse("lights other than one static one-sided rectangle");
            }
            Some(index)
        }
    };
    Ok(Support { effects, nee_light })
}
