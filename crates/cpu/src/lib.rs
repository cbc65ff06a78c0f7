//! strata CPU reference renderer.
//!
//! Owns: ray–primitive intersection (watertight triangles), the 4-wide BVH collapsed from the
//! scene crate's BVH2 and its traversal, BSDFs, light sampling, the path integrator for every
//! strategy, and the multi-threaded render loop; and a second renderer of the same estimator
//! that traces eight paths per AVX2 vector (`eight`, a prototype covering Mitsuba's Cornell
//! box: [`Cpu8Renderer`]), with the eight-ray traversal it uses (`accel`) and its vector lanes
//! (`lanes`).
//! It is the ground truth: correct first, then fast. Must not know: file formats, wgpu.
//!
//! Everything per sample is f32 and consumes the sample dimensions of
//! [`stratapt_scene::DimLayout`] in its fixed order, so that the WGSL integrator can mirror it;
//! only the [`stratapt_film::Film`] accumulates in f64.
//!
//! Path depth: a path has at most `max_depth` *scattering* vertices (vertex `k = 0` is the first
//! hit). Emission is gathered at vertices `0 ..= max_depth`: the ray leaving the last scattering
//! vertex `max_depth − 1` still collects the emission it finds. So `max_depth = 1` is direct
//! lighting, and in a closed furnace of albedo `a` and emission `Le` the expected radiance is
//! `Le · Σ_{k=0}^{max_depth} a^k`.

pub mod accel;
pub mod bsdf;
pub mod camera;
pub mod detail;
pub mod eight;
pub mod integrator;
pub mod intersect;
pub(crate) mod lanes;
pub mod light;
pub mod offset;
pub mod render;

pub use integrator::Integrator;
pub use render::{render, render_peak_twins, Cpu8Renderer, CpuRenderer};
pub use stratapt_film::RenderStats;
