//! Embedding strata's GPU renderer in a program that owns its wgpu device.
//!
//! The host program creates the instance, adapter and device as it likes (here: the first
//! adapter wgpu offers, with that adapter's limits, since the kernel binds more storage buffers
//! than WebGPU's default limit), then hands `&Device` and `&Queue` to `Renderer::new`. The
//! renderer compiles one kernel per scene specialization and caches it, so rendering many frames
//! or scenes on one `Renderer` compiles each kind once.
//!
//! ```text
//! cargo run --release -p stratapt-gpu --example embed -- scenes/cornell-box.toml out.exr
//! ```

use std::path::PathBuf;
use stratapt_film::Render;
use stratapt_gpu::Renderer;
use stratapt_scene::RenderSettings;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args_os().skip(1).map(PathBuf::from);
    let (Some(scene_path), Some(out)) = (args.next(), args.next()) else {
        return Err("usage: embed SCENE.toml OUT.exr|OUT.png".into());
    };

    // ---- The host program's own device ----------------------------------------------------
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle());
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        ..Default::default()
    }))?;
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("host program"),
        // The WebGPU defaults allow 8 storage buffers per stage and 128 MiB bindings; ask for
        // what the adapter really has.
        required_limits: adapter.limits(),
        ..Default::default()
    }))?;
    println!(
        "adapter: {} ({:?})",
        adapter.get_info().name,
        adapter.get_info().backend
    );

    // ---- strata on that device ------------------------------------------------------------
    // The error estimate's peak twins from the CPU reference (without them the film's error
    // rests on the kernel's hashed twins alone).
    let renderer = Renderer::new(&device, &queue)?
        .with_peak_twins(std::sync::Arc::new(stratapt_cpu::render_peak_twins));
    let scene = stratapt_import::scene_file::load(&scene_path)?;
    let settings = RenderSettings {
        pattern_spp: 16,
        ..scene.settings
    };
    let total =
        scene.camera.width as u64 * scene.camera.height as u64 * settings.pattern_spp as u64;
    let done = std::sync::atomic::AtomicU64::new(0);
    let progress = |n| {
        let d = done.fetch_add(n, std::sync::atomic::Ordering::Relaxed) + n;
        eprint!("\r{:>3}%", d * 100 / total);
    };
    let (film, _) = renderer
        .render(&scene, &settings, &progress, None)
        .map_err(|e| e.to_string())?;
    eprintln!();

    let ([r, g, b], [sr, sg, sb]) = film.image_mean();
    println!("mean radiance {r:.4} {g:.4} {b:.4} (± {sr:.4} {sg:.4} {sb:.4})");
    film.write(&out)?;
    println!("wrote {} ({} spp)", out.display(), film.held_spp());
    Ok(())
}
