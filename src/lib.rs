//! strata: a Monte Carlo path tracer whose integrators run as WGSL compute shaders, checked
//! against a CPU reference renderer.
//!
//! This facade re-exports the workspace crates for embedding:
//! - [`scene`]: scene files, validation, effects, flattening, BVH, film and image output;
//! - [`sampling`]: samplers and warps;
//! - [`cpu`]: the CPU reference renderer.

pub use stratapt_cpu as cpu;
pub use stratapt_sampling as sampling;
pub use stratapt_scene as scene;
