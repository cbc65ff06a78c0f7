//! strata CPU reference renderer.
//!
//! Owns: ray–primitive intersection (watertight triangles), BVH2 traversal, BSDFs, light
//! sampling, the path integrator for every strategy, and the multi-threaded render loop.
//! It is the ground truth: correct first, then fast. Must not know: file formats, wgpu.
