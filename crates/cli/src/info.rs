//! `strata info`: what a scene calls for, without rendering.

use clap::Args;
use std::path::{Path, PathBuf};
use stratapt_gpu::{BvhLayout, Kernel, Renderer, Specialization};
use stratapt_scene::effects::{kind_names, LIGHT_KIND_NAMES, MATERIAL_KIND_NAMES};
use stratapt_scene::records::light_kind;
use stratapt_scene::{DimLayout, Effects, FlatScene, RenderSettings};

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
    print_scene(&args.scene, &scene)?;
    print_contents(&scene, &effects)?;
    print_effects(&effects, &layout, settings.max_depth)?;
    let bvh = BvhLayout::default();
    print_gpu_memory(&scene, &settings, bvh)?;
    print_kernel_size(&scene, &settings, bvh)?;
    print_import(&scene, load_seconds)?;
    Ok(())
}

/// The scene's file, film, render settings and geometry.
fn print_scene(path: &Path, scene: &FlatScene) -> anyhow::Result<()> {
    let (cam, settings) = (&scene.camera, &scene.settings);
    out!("scene      {}", path.display());
    out!("film       {}×{}", cam.width, cam.height);
    out!(
        "render     {} spp, {} sampler, {} strategy, max depth {}, seed {}",
        settings.pattern_spp,
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
    Ok(())
}

/// What the scene holds besides geometry: materials, lights, sky, textures and tables.
fn print_contents(scene: &FlatScene, effects: &Effects) -> anyhow::Result<()> {
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
    print_sky(scene, effects)?;
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
    Ok(())
}

/// The sky: an environment map's size, layout and memory, else whether there is one.
fn print_sky(scene: &FlatScene, effects: &Effects) -> anyhow::Result<()> {
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
    Ok(())
}

/// The effects the kernel carries and the sample dimensions a path draws.
fn print_effects(effects: &Effects, layout: &DimLayout, max_depth: u32) -> anyhow::Result<()> {
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
        layout.total(max_depth)
    );
    Ok(())
}

/// The GPU memory a render takes (scene arrays, BVH nodes among them, film), or why the GPU
/// cannot render it.
fn print_gpu_memory(
    scene: &FlatScene,
    settings: &RenderSettings,
    bvh: BvhLayout,
) -> anyhow::Result<()> {
    let memory = Renderer::device_bytes(scene, settings, bvh).and_then(|(arrays, film)| {
        let nodes = stratapt_gpu::scene_bytes(scene, bvh)?
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
    Ok(())
}

/// The specialized kernel's size against the generic one's.
fn print_kernel_size(
    scene: &FlatScene,
    settings: &RenderSettings,
    bvh: BvhLayout,
) -> anyhow::Result<()> {
    let spec = Specialization {
        bvh,
        ..Renderer::specialization(scene, settings)
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
    Ok(())
}

/// For a pbrt-v4 import: what it flattened, how long it took, and its warnings.
fn print_import(scene: &FlatScene, load_seconds: f64) -> anyhow::Result<()> {
    let Some(r) = &scene.import else {
        return Ok(());
    };
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
    let lines = crate::scene::warning_lines(scene.import.as_ref());
    out!("warnings   {}", lines.len());
    for line in lines {
        out!("  {line}");
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
