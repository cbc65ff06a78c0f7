//! strata: a Monte Carlo path tracer whose integrators run as WGSL compute shaders, checked
//! against a CPU reference renderer.
//!
//! This facade re-exports the workspace crates for embedding:
//! - [`scene`]: scene files, validation, effects, flattening, BVH, film and image output;
//! - [`sampling`]: samplers and warps;
//! - [`cpu`]: the CPU reference renderer;
//! - [`gpu`]: the GPU renderer (WGSL compute on wgpu), on your device or one it opens.
//!
//! Render a scene file on the CPU and write the image (linear EXR with variance channels):
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! use stratapt::scene::{scene_file, RenderSettings};
//!
//! let scene = scene_file::load("scenes/cornell-box.toml".as_ref())?;
//! let settings = RenderSettings { spp: 16, ..scene.settings };
//! let film = stratapt::cpu::render(&scene, &settings, &|_samples_done| {});
//! let [r, g, b] = film.image_mean().0;
//! println!("mean radiance {r:.3} {g:.3} {b:.3}");
//! film.write("cornell-box.exr".as_ref())?;
//! # Ok(())
//! # }
//! ```

pub use stratapt_cpu as cpu;
pub use stratapt_gpu as gpu;
pub use stratapt_sampling as sampling;
pub use stratapt_scene as scene;
