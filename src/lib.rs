//! strata: a Monte Carlo path tracer whose integrators run as WGSL compute shaders, checked
//! against a CPU reference renderer.
//!
//! This facade re-exports the workspace crates for embedding:
//! - [`import`]: scene files (strata's TOML, pbrt-v4) read into one description and validated,
//!   with errors at the file, line and column the user wrote;
//! - [`scene`]: the validated scene, its effects, BVH and records;
//! - [`film`]: the film with its calibrated error, parts, EXR/PNG, the `Render` interface and the
//!   progressive driver;
//! - [`sampling`]: samplers and warps;
//! - [`cpu`]: the CPU reference renderer;
//! - [`gpu`]: the GPU renderer (WGSL compute on wgpu), on your device; [`gpu_renderer`] gives
//!   it the CPU reference's peak twins, as the `strata` command does.
//!
//! Render a scene file on the CPU and write the image (linear EXR with variance channels):
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! use stratapt::scene::RenderSettings;
//!
//! let scene = stratapt::import::load("scenes/cornell-box.toml".as_ref())?;
//! let settings = RenderSettings { pattern_spp: 16, ..scene.settings };
//! let (film, _stats) = stratapt::cpu::render(&scene, &settings, &|_samples_done| {}, None);
//! let [r, g, b] = film.image_mean().0;
//! println!("mean radiance {r:.3} {g:.3} {b:.3}");
//! film.write("cornell-box.exr".as_ref())?;
//! # Ok(())
//! # }
//! ```

pub use stratapt_cpu as cpu;
pub use stratapt_film as film;
pub use stratapt_gpu as gpu;
pub use stratapt_import as import;
pub use stratapt_sampling as sampling;
pub use stratapt_scene as scene;

/// The GPU renderer on your `device` and `queue`, its films' peak twins rendered by the CPU
/// reference (what the error estimate's brightest pixels rest on; [`gpu::Renderer::new`] alone
/// renders none).
pub fn gpu_renderer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
) -> Result<gpu::Renderer, gpu::GpuError> {
    Ok(gpu::Renderer::new(device, queue)?
        .with_peak_twins(std::sync::Arc::new(cpu::render_peak_twins)))
}
