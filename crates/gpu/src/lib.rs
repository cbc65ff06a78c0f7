//! strata's GPU renderer: the wgpu host of the WGSL path-tracing kernels in `shaders/`.
//!
//! Owns adapter choice (for the binary and tests), scene upload, per-scene specialization of
//! the kernel (`override` constants from the scene's effects), batched dispatch and readback
//! into the same [`Film`](stratapt_film::Film) as the CPU reference. It must not know about
//! scene files or the command line; a library user passes in their own `wgpu::Device` and
//! `wgpu::Queue` ([`Renderer::new`]).

pub mod adapter;
mod checks;
/// The compressed wide BVH the kernel may traverse (built from the scene's BVH2 at upload).
pub mod cwbvh;
mod error;
pub(crate) mod params;
pub(crate) mod rays;
pub(crate) mod readback;
mod renderer;
pub(crate) mod shader;
pub(crate) mod shared;
pub(crate) mod specialize;
/// Implementation details the tests reach (WGSL probes, kernel composition, parameter codes).
#[doc(hidden)]
pub mod testing;
/// Scene upload: the flattened scene's arrays as the kernel's storage buffers.
pub(crate) mod upload;

pub use checks::KernelChecks;
pub use error::GpuError;
pub use renderer::split::{SampleSplit, MAX_SPLIT};
pub use renderer::Renderer;
pub use shared::{
    effect_bit, uniform_scene_words, MAX_UNIFORM_SCENE_WORDS, MIN_UNIFORM_SCENE_WORDS,
};
pub use specialize::{
    BvhLayout, Kernel, KernelSize, Runtime, SceneBinding, Specialization, Traversal,
};
pub use stratapt_film::RenderStats;
pub use upload::scene_bytes;
