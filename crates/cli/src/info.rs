//! `strata info`: what a scene calls for, without rendering.

use clap::Args;
use std::path::PathBuf;
use stratapt_scene::effects::{kind_names, LIGHT_KIND_NAMES, MATERIAL_KIND_NAMES};
use stratapt_scene::gpu::light_kind;
use stratapt_scene::{DimLayout, Effects};

#[derive(Args)]
pub struct InfoArgs {
    /// Scene file (TOML).
    scene: PathBuf,
}

pub fn run(args: InfoArgs) -> anyhow::Result<()> {
    let scene = stratapt_scene::load::load(&args.scene)?;
    let settings = scene.settings;
    let effects = Effects::of(&scene, &settings);
    let layout = DimLayout::new(&effects);
    let cam = &scene.camera;
    out!("scene      {}", args.scene.display());
    out!("film       {}×{}", cam.width, cam.height);
    out!(
        "render     {} spp, {} sampler, {} strategy, max depth {}, seed {}",
        settings.spp,
        settings.sampler,
        settings.strategy,
        settings.max_depth,
        settings.seed
    );
    out!(
        "geometry   {} primitives, {} BVH nodes, {} moving",
        scene.prims.len(),
        scene.bvh.nodes.len(),
        scene.motions.iter().filter(|m| m.is_moving()).count()
    );
    out!(
        "materials  {}",
        kinds(effects.material_kinds, &MATERIAL_KIND_NAMES)
    );
    out!(
        "lights     {} ({})",
        scene.lights.len(),
        kinds(
            effects.light_kinds & !(1 << light_kind::SKY),
            &LIGHT_KIND_NAMES
        )
    );
    out!(
        "sky        {}",
        if effects.has_sky() { "yes" } else { "no" }
    );
    out!(
        "effects    lens {}, time {}, next-event estimation {}, path {}, lobe choice {}, roulette {}",
        yes(effects.lens),
        yes(effects.time),
        yes(effects.nee),
        yes(effects.path),
        yes(effects.lobe),
        yes(effects.roulette)
    );
    out!(
        "dimensions pixel {}, lens {}, time {}, {} per vertex from {} ({} for a full path)",
        layout.pixel,
        opt(layout.lens),
        opt(layout.time),
        layout.per_vertex,
        layout.first_vertex,
        layout.total(settings.max_depth)
    );
    Ok(())
}

fn kinds(mask: u32, names: &[&str]) -> String {
    kind_names(mask, names, ", ")
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

fn opt(d: Option<u32>) -> String {
    d.map_or("—".into(), |d| d.to_string())
}
