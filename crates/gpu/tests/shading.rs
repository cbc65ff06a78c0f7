//! WGSL frame, warps, MIS weights, BSDFs and lights (`shaders/{frame,warp,mis,bsdf,light}.wgsl`)
//! against their Rust counterparts, value by value on random inputs, on the software adapter.
//!
//! Tolerance: relative 1e-4, absolute 1e-6 near zero; vectors relative to their length.
//! `valid` / `delta` flags must agree exactly.

use std::path::Path;

use glam::{Vec2, Vec3};
use stratapt_gpu::testing;
use stratapt_sampling::testing::TestRng as Rng;
use stratapt_sampling::{warp, Frame};
use stratapt_scene::{FlatScene, RenderSettings};

#[path = "shading/bsdf.rs"]
mod bsdf;
#[path = "shading/detail.rs"]
mod detail;
#[path = "shading/layered.rs"]
mod layered;
#[path = "shading/lights.rs"]
mod lights;
#[path = "shading/mis.rs"]
mod mis;
#[path = "shading/placed.rs"]
mod placed;
#[path = "shading/textures.rs"]
mod textures;
#[path = "shading/warps.rs"]
mod warps;

// ---- Harness helpers -------------------------------------------------------------------------

/// WGSL helpers for probes: read floats from `probe_in`, write floats to `probe_out`.
const IO: &str = r#"
fn probe_f(k: u32) -> f32 { return bitcast<f32>(probe_in[k]); }
fn probe_v2(k: u32) -> vec2f { return vec2f(probe_f(k), probe_f(k + 1u)); }
fn probe_v3(k: u32) -> vec3f { return vec3f(probe_f(k), probe_f(k + 1u), probe_f(k + 2u)); }
fn probe_put(k: u32, x: f32) { probe_out[k] = bitcast<u32>(x); }
fn probe_put2(k: u32, v: vec2f) { probe_put(k, v.x); probe_put(k + 1u, v.y); }
fn probe_put3(k: u32, v: vec3f) { probe_put(k, v.x); probe_put(k + 1u, v.y); probe_put(k + 2u, v.z); }
fn probe_put_bool(k: u32, b: bool) { probe_put(k, select(0.0, 1.0, b)); }
"#;

fn scene_path(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name)
}

fn load_scene(name: &str) -> FlatScene {
    stratapt_import::scene_file::load(&scene_path(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Run `probe` (with [`IO`]) on `scene` over `count` records of floats; returns the outputs.
fn run(
    scene: &FlatScene,
    settings: &RenderSettings,
    modules: &[&str],
    probe: &str,
    input: &[f32],
    out_stride: usize,
    count: usize,
) -> Vec<f32> {
    let (device, queue) = testing::software_device().expect("software adapter");
    let words: Vec<u32> = input.iter().map(|x| x.to_bits()).collect();
    let src = format!("{IO}\n{probe}");
    let out = testing::run_probe(
        &device,
        &queue,
        scene,
        settings,
        modules,
        &src,
        &words,
        out_stride * count,
        count as u32,
    );
    out.into_iter().map(f32::from_bits).collect()
}

/// Collects mismatches between GPU and CPU values; panics listing them at the end.
struct Check {
    name: &'static str,
    compared: usize,
    failures: Vec<String>,
}

impl Check {
    fn new(name: &'static str) -> Self {
        Self {
            name,
            compared: 0,
            failures: Vec::new(),
        }
    }
    fn close(gpu: f32, cpu: f32, scale: f32) -> bool {
        if gpu.is_nan() && cpu.is_nan() || gpu == cpu {
            return true;
        }
        (gpu - cpu).abs() <= (1e-4 * scale).max(1e-6)
    }
    fn fail(&mut self, what: &str, i: usize, gpu: String, cpu: String) {
        self.failures
            .push(format!("{what} #{i}: gpu {gpu} cpu {cpu}"));
    }
    fn f(&mut self, what: &str, i: usize, gpu: f32, cpu: f32) {
        self.f_rel(what, i, gpu, cpu, 1.0);
    }
    /// Relative tolerance `1e-4 · widen`, for quantities whose conditioning is known to be worse.
    fn f_rel(&mut self, what: &str, i: usize, gpu: f32, cpu: f32, widen: f32) {
        self.compared += 1;
        if !Self::close(gpu, cpu, cpu.abs() * widen) {
            self.fail(what, i, format!("{gpu:e}"), format!("{cpu:e}"));
        }
    }
    fn v3(&mut self, what: &str, i: usize, gpu: Vec3, cpu: Vec3) {
        self.compared += 1;
        let scale = cpu.length();
        if !(0..3).all(|k| Self::close(gpu[k], cpu[k], scale)) {
            self.fail(what, i, format!("{gpu}"), format!("{cpu}"));
        }
    }
    fn v2(&mut self, what: &str, i: usize, gpu: Vec2, cpu: Vec2) {
        self.v3(what, i, gpu.extend(0.0), cpu.extend(0.0));
    }
    fn flag(&mut self, what: &str, i: usize, gpu: f32, cpu: bool) -> bool {
        self.compared += 1;
        let g = gpu != 0.0;
        if g != cpu {
            self.fail(what, i, format!("{g}"), format!("{cpu}"));
        }
        g && cpu
    }
    fn finish(self) {
        let n = self.failures.len();
        let list: Vec<_> = self.failures.iter().take(30).cloned().collect();
        assert!(
            n == 0,
            "{}: {n} of {} comparisons differ:\n{}",
            self.name,
            self.compared,
            list.join("\n")
        );
        eprintln!("{}: {} comparisons agree", self.name, self.compared);
    }
}

fn v3(o: &[f32], k: usize) -> Vec3 {
    Vec3::new(o[k], o[k + 1], o[k + 2])
}

fn push3(v: &mut Vec<f32>, x: Vec3) {
    v.extend_from_slice(&x.to_array());
}

// ---- Naga validation (no device) ---------------------------------------------------------------

#[test]
fn shading_modules_validate() {
    // Each with what its `// needs:` line brings in.
    for modules in [
        &["frame"][..],
        &["warp"],
        &["mis"],
        &["bsdf"],
        &["light"],
        &["mis", "bsdf", "light"],
    ] {
        testing::compose(modules, "").unwrap_or_else(|e| panic!("{modules:?}: {e}"));
    }
}
