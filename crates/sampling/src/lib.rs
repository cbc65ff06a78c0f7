//! strata sampling: the samplers that produce sample values and the warps that turn them into
//! points and directions with consistent densities.
//!
//! Owns: the sampler contract `value(pixel, index, dim, seed) → [0,1)` (pure 32-bit integer
//! arithmetic, mirrored bit for bit in `shaders/sampler.wgsl`), and every warp with its pdf;
//! for the workspace's tests, [`testing::TestRng`], the one generator of random test inputs.
//! Must not know: scenes, materials, lights, images or devices. Everything here is f32 so that
//! the WGSL mirror computes the same numbers.

pub mod atan;
pub mod frame;
pub mod hash;
pub mod mis;
pub mod replica;
pub mod sampler;
pub mod testing;
pub mod warp;

pub use frame::Frame;
pub use sampler::{PathSampler, Sampler, SamplerKind};
