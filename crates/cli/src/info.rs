//! `strata info`: what a scene calls for, without rendering.

use clap::Args;
use std::path::PathBuf;
use stratapt_gpu::{BvhLayout, Kernel, Renderer, Specialization};
use stratapt_scene::effects::{kind_names, LIGHT_KIND_NAMES, MATERIAL_KIND_NAMES};
use stratapt_scene::records::light_kind;
use stratapt_scene::{DimLayout, Effects};

#[derive(Args)]
pub struct InfoArgs {
    /// Scene file: strata's TOML, or pbrt-v4 (.pbrt, .pbrt.gz).
    scene: PathBuf,
    #[command(flatten)]
    import: crate::scene::ImportArgs,
}

pub fn run(args: InfoArgs) -> anyhow::Result<()> {
    let started = std::time::Instant::now();
    let scene = crate::scene::load(&args.scene, args.import, false)?;
    let load_seconds = started.elapsed().as_secs_f64();
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
        "geometry   {} primitives ({} triangles), {} BVH nodes, {} moving",
        scene.geometry.len(),
        (0..scene.geometry.len() as u32)
            .filter(|&id| scene.geometry.surface(id).kind
                == stratapt_scene::records::prim_kind::TRIANGLE)
            .count(),
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
    let environment = scene
        .lights
        .iter()
        .find(|l| l.kind == light_kind::ENVIRONMENT || l.kind == light_kind::OCTAHEDRAL);
    match environment {
        Some(l) => {
            let [w, h] = [l.p2[0] as usize, l.p2[1] as usize];
            let bytes = 4 * stratapt_scene::environment::data_len(w, h) as u64;
            let layout = match l.kind {
                light_kind::OCTAHEDRAL => "octahedral",
                _ => "equirectangular",
            };
            out!(
                "sky        environment map {w}×{h} texels ({layout}), {} with its distribution",
                mib(bytes)
            );
        }
        None => out!(
            "sky        {}",
            if effects.has_sky() { "yes" } else { "no" }
        ),
    }
    if scene.textures > 0 {
        out!(
            "textures   {} ({} with their texels{})",
            scene.textures,
            mib(scene.texture_bytes),
            match effects.textures {
                true => "",
                false => "; no material in use reads them",
            }
        );
    }
    if !scene.tables.is_empty() {
        out!(
            "tables     {} (textures, rough plastics' coatings, environment map)",
            mib(4 * scene.tables.len() as u64)
        );
    }
    out!(
        "effects    lens {}, time {}, textures {}, next-event estimation {}, path {}, lobe choice {}, roulette {}",
        yes(effects.lens),
        yes(effects.time),
        yes(effects.textures),
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
    let bvh = BvhLayout::default();
    let memory = Renderer::device_bytes(&scene, &settings, bvh).and_then(|(arrays, film)| {
        let nodes = stratapt_gpu::scene_bytes(&scene, bvh)?
            .iter()
            .find(|(name, _)| *name == "BVH nodes")
            .map_or(0, |(_, b)| *b);
        Ok((arrays, film, nodes))
    });
    match memory {
        Ok((arrays, film, nodes)) => out!(
            "gpu memory {} (scene {} of which {bvh} BVH {}, film accumulator and readback {})",
            mib(arrays + film),
            mib(arrays),
            mib(nodes),
            mib(film)
        ),
        Err(e) => out!("gpu memory — (the GPU cannot render it: {e})"),
    }
    let spec = Specialization {
        bvh,
        ..Renderer::specialization(&scene, &settings)
    };
    let specialized = spec.kernel_size()?;
    let generic = spec.for_kernel(Kernel::Generic).kernel_size()?;
    out!(
        "kernel     specialized {} IR operations in {} functions, generic {} in {} ({:.0} %); \
         SPIR-V {} vs {} words",
        specialized.operations,
        specialized.functions,
        generic.operations,
        generic.functions,
        100.0 * specialized.operations as f64 / generic.operations as f64,
        specialized.spirv_words,
        generic.spirv_words
    );
    out!("           (IR operations reachable once the driver inlines every call and drops the");
    out!("           branches the scene's constants decide; SPIR-V keeps the dead branches)");
    if let Some(r) = &scene.import {
        out!(
            "imported   pbrt-v4: {} shapes, {} more from {} object instances flattened, {} PLY \
             files, {} triangles; loaded in {:.2} s, peak memory {}",
            r.shapes,
            r.instanced_shapes,
            r.instances,
            r.ply_files,
            r.triangles,
            load_seconds,
            peak_memory().unwrap_or_else(|| "unknown".into())
        );
        let lines = crate::scene::warning_lines(&scene);
        out!("warnings   {}", lines.len());
        for line in lines {
            out!("  {line}");
        }
    }
    Ok(())
}

/// This process's peak resident memory (Linux: `VmHWM` in `/proc/self/status`).
fn peak_memory() -> Option<String> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let kib: u64 = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))?
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(mib(kib * 1024))
}

fn mib(bytes: u64) -> String {
    if bytes < 1 << 20 {
        format!("{:.1} KiB", bytes as f64 / 1024.0)
    } else {
        format!("{:.1} MiB", bytes as f64 / (1 << 20) as f64)
    }
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
