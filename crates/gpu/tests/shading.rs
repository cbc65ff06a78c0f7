//! WGSL warps, MIS weights, BSDFs and lights (`shaders/{warp,mis,bsdf,light}.wgsl`) against
//! their Rust counterparts, value by value on random inputs, on the software adapter.
//!
//! Tolerance: relative 1e-4, absolute 1e-6 near zero; vectors relative to their length.
//! `valid` / `delta` flags must agree exactly.

use std::path::Path;

use glam::{Vec2, Vec3};
use stratapt_gpu::testing;
use stratapt_sampling::{mis, warp, Frame};
use stratapt_scene::{FlatScene, RenderSettings};

// ---- Harness helpers -------------------------------------------------------------------------

/// Deterministic generator for test inputs (PCG-style LCG, top bits).
struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 40) as f32) / (1u64 << 24) as f32
    }
    fn range(&mut self, a: f32, b: f32) -> f32 {
        a + (b - a) * self.f()
    }
    fn log_range(&mut self, a: f32, b: f32) -> f32 {
        (a.ln() + (b.ln() - a.ln()) * self.f()).exp()
    }
    fn u2(&mut self) -> Vec2 {
        Vec2::new(self.f(), self.f())
    }
    fn sphere(&mut self) -> Vec3 {
        warp::uniform_sphere(self.u2())
    }
    fn upper(&mut self) -> Vec3 {
        let v = self.sphere();
        Vec3::new(v.x, v.y, v.z.abs())
    }
    fn point(&mut self, r: f32) -> Vec3 {
        Vec3::new(self.range(-r, r), self.range(-r, r), self.range(-r, r))
    }
}

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
    stratapt_scene::load::load(&scene_path(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
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
    for modules in [
        &["warp"][..],
        &["mis"],
        &["warp", "motion", "intersect", "bsdf"],
        &["warp", "motion", "light"],
        &["warp", "mis", "motion", "intersect", "bsdf", "light"],
    ] {
        testing::compose(modules, "").unwrap_or_else(|e| panic!("{modules:?}: {e}"));
    }
}

// ---- Warps -------------------------------------------------------------------------------------

const WARP_PROBE: &str = r#"
fn probe(i: u32) {
    let k = i * 16u;
    let o = i * 56u;
    let u = probe_v2(k);
    let cos_max = probe_f(k + 2u);
    let alpha = probe_f(k + 3u);
    let wo = probe_v3(k + 4u);
    let wi = probe_v3(k + 7u);
    let n = probe_v3(k + 10u);
    probe_put3(o, warp_uniform_hemisphere(u));
    probe_put(o + 3u, warp_uniform_hemisphere_pdf());
    probe_put3(o + 4u, warp_cosine_hemisphere(u));
    probe_put(o + 7u, warp_cosine_hemisphere_pdf(wi.z));
    probe_put3(o + 8u, warp_uniform_sphere(u));
    probe_put(o + 11u, warp_uniform_sphere_pdf());
    probe_put2(o + 12u, warp_concentric_disk(u));
    probe_put(o + 14u, warp_concentric_disk_pdf());
    probe_put3(o + 15u, warp_uniform_cone(u, cos_max));
    probe_put(o + 18u, warp_uniform_cone_pdf(cos_max));
    probe_put3(o + 19u, warp_uniform_triangle(u));
    probe_put3(o + 22u, warp_line_segment(wo, wi, probe_f(k + 13u)));
    let f = frame_from_normal(n);
    probe_put3(o + 25u, f.s);
    probe_put3(o + 28u, f.t);
    probe_put3(o + 31u, f.n);
    probe_put3(o + 34u, frame_to_local(f, wi));
    probe_put3(o + 37u, frame_to_world(f, wi));
    probe_put(o + 40u, warp_ggx_d(wi, alpha));
    probe_put(o + 41u, warp_ggx_lambda(wi, alpha));
    probe_put(o + 42u, warp_ggx_g1(wo, alpha));
    probe_put(o + 43u, warp_ggx_g2(wo, wi, alpha));
    let h = warp_ggx_sample_vndf(wo, alpha, u);
    probe_put3(o + 44u, h);
    probe_put(o + 47u, warp_ggx_vndf_pdf(wo, wi, alpha));
    probe_put3(o + 48u, warp_ggx_reflect(wo, wi));
    probe_put(o + 51u, warp_ggx_reflection_pdf(wo, wi, alpha));
    probe_put(o + 52u, warp_ggx_vndf_pdf(wo, h, alpha));
    probe_put(o + 53u, warp_ggx_reflection_pdf(wo, warp_ggx_reflect(wo, h), alpha));
}
"#;

#[test]
fn warps_match_cpu() {
    use warp::ggx;
    let mut rng = Rng(1);
    let count = 2000;
    let mut input = Vec::new();
    for i in 0..count {
        let mut u = rng.u2();
        // Edges: the disk's centre and axes, the unit square's corners.
        match i % 50 {
            0 => u = Vec2::splat(0.5),
            1 => u = Vec2::new(0.5, rng.f()),
            2 => u = Vec2::new(rng.f(), 0.5),
            3 => u = Vec2::ZERO,
            4 => u = Vec2::splat(rng.f()),
            _ => {}
        }
        let cos_max = match i % 7 {
            0 => 1.0,
            1 => -1.0,
            2 => 1.0 - rng.log_range(1e-7, 1e-2),
            _ => rng.range(-1.0, 1.0),
        };
        let alpha = rng.log_range(2e-3, 1.0);
        let wo = if i % 20 == 0 {
            rng.sphere()
        } else {
            rng.upper()
        };
        let wi = match i % 30 {
            0 => Vec3::X,
            1 => Vec3::Z,
            _ => rng.sphere(),
        };
        let n = match i % 40 {
            0 => -Vec3::Z,
            1 => Vec3::Z,
            _ => rng.sphere(),
        };
        input.extend_from_slice(&[u.x, u.y, cos_max, alpha]);
        push3(&mut input, wo);
        push3(&mut input, wi);
        push3(&mut input, n);
        input.extend_from_slice(&[rng.f(), 0.0, 0.0]);
    }
    let scene = load_scene("cornell-box.toml");
    let out = run(
        &scene,
        &RenderSettings::default(),
        &["warp"],
        WARP_PROBE,
        &input,
        56,
        count,
    );
    let mut c = Check::new("warps");
    for i in 0..count {
        let inp = &input[i * 16..];
        let o = &out[i * 56..];
        let u = Vec2::new(inp[0], inp[1]);
        let (cos_max, alpha) = (inp[2], inp[3]);
        let (wo, wi, n) = (v3(inp, 4), v3(inp, 7), v3(inp, 10));
        c.v3(
            "uniform_hemisphere",
            i,
            v3(o, 0),
            warp::uniform_hemisphere(u),
        );
        c.f(
            "uniform_hemisphere_pdf",
            i,
            o[3],
            warp::uniform_hemisphere_pdf(),
        );
        // At the square's corners the disk point has |d| = 1 and z = √(1 − |d|²) turns last-ulp
        // differences of cos/sin into ~1e-4: ill-conditioned, compared on x, y only.
        let cosine = warp::cosine_hemisphere(u);
        if u.x == 0.0 || u.y == 0.0 {
            c.v2(
                "cosine_hemisphere(corner).xy",
                i,
                v3(o, 4).truncate(),
                cosine.truncate(),
            );
        } else {
            c.v3("cosine_hemisphere", i, v3(o, 4), cosine);
        }
        c.f(
            "cosine_hemisphere_pdf",
            i,
            o[7],
            warp::cosine_hemisphere_pdf(wi.z),
        );
        c.v3("uniform_sphere", i, v3(o, 8), warp::uniform_sphere(u));
        c.f("uniform_sphere_pdf", i, o[11], warp::uniform_sphere_pdf());
        let disk = Vec2::new(o[12], o[13]);
        c.v2("concentric_disk", i, disk, warp::concentric_disk(u));
        c.f("concentric_disk_pdf", i, o[14], warp::concentric_disk_pdf());
        c.v3("uniform_cone", i, v3(o, 15), warp::uniform_cone(u, cos_max));
        c.f(
            "uniform_cone_pdf",
            i,
            o[18],
            warp::uniform_cone_pdf(cos_max),
        );
        c.v3("uniform_triangle", i, v3(o, 19), warp::uniform_triangle(u));
        let seg = warp::line::segment(wo, wi, inp[13]);
        c.v3("line::segment", i, v3(o, 22), seg);
        let f = Frame::from_normal(n);
        c.v3("frame.s", i, v3(o, 25), f.s);
        c.v3("frame.t", i, v3(o, 28), f.t);
        c.v3("frame.n", i, v3(o, 31), f.n);
        c.v3("frame.to_local", i, v3(o, 34), f.to_local(wi));
        c.v3("frame.to_world", i, v3(o, 37), f.to_world(wi));
        c.f("ggx::d", i, o[40], ggx::d(wi, alpha));
        c.f("ggx::lambda", i, o[41], ggx::lambda(wi, alpha));
        c.f("ggx::g1", i, o[42], ggx::g1(wo, alpha));
        c.f("ggx::g2", i, o[43], ggx::g2(wo, wi, alpha));
        let h = ggx::sample_vndf(wo, alpha, u);
        c.v3("ggx::sample_vndf", i, v3(o, 44), h);
        c.f("ggx::vndf_pdf", i, o[47], ggx::vndf_pdf(wo, wi, alpha));
        c.v3("ggx::reflect", i, v3(o, 48), ggx::reflect(wo, wi));
        c.f(
            "ggx::reflection_pdf",
            i,
            o[51],
            ggx::reflection_pdf(wo, wi, alpha),
        );
        c.f(
            "ggx::vndf_pdf(sampled)",
            i,
            o[52],
            ggx::vndf_pdf(wo, h, alpha),
        );
        // At the GPU's sampled normal. h = normalize(wo + reflect(wo, h)) recovers h.xy ~ α with
        // an absolute error of a few ulp of 1, and D ∝ 1/q² amplifies it by ~1/α: widen.
        let r = ggx::reflection_pdf(wo, ggx::reflect(wo, v3(o, 44)), alpha);
        let widen = (0.03 / alpha).max(1.0);
        c.f_rel("ggx::reflection_pdf(sampled)", i, o[53], r, widen);
    }
    c.finish();
}

const SPHERICAL_PROBE: &str = r#"
fn probe(i: u32) {
    let k = i * 24u;
    let o = i * 12u;
    let p = probe_v3(k);
    let a = probe_v3(k + 3u);
    let b = probe_v3(k + 6u);
    let c = probe_v3(k + 9u);
    let u = probe_v2(k + 12u);
    probe_put(o, warp_spherical_triangle_solid_angle(p, a, b, c));
    let t = warp_spherical_triangle_sample(p, a, b, c, u);
    probe_put_bool(o + 1u, t.valid);
    probe_put3(o + 2u, t.dir);
    probe_put(o + 5u, t.pdf);
    let corner = probe_v3(k + 14u);
    let ex = probe_v3(k + 17u);
    let ey = probe_v3(k + 20u);
    probe_put(o + 6u, warp_spherical_rectangle_solid_angle(p, corner, ex, ey));
    let r = warp_spherical_rectangle_sample(p, corner, ex, ey, u);
    probe_put_bool(o + 7u, r.valid);
    probe_put3(o + 8u, r.point);
    probe_put(o + 11u, r.pdf);
}
"#;

#[test]
fn spherical_warps_match_cpu() {
    use warp::{spherical_rectangle as rect, spherical_triangle as tri};
    let mut rng = Rng(2);
    let count = 2000;
    let mut input = Vec::new();
    for i in 0..count {
        // Shapes from tiny (far) to huge (near), and p on a vertex or in the plane.
        let scale = rng.log_range(1e-3, 10.0);
        let centre = rng.point(2.0);
        let (a, b, c) = (
            centre + scale * rng.sphere(),
            centre + scale * rng.sphere(),
            centre + scale * rng.sphere(),
        );
        let mut p = rng.point(2.0);
        match i % 25 {
            0 => p = a,
            1 => p = a + rng.f() * (b - a) + rng.f() * (c - a),
            _ => {}
        }
        let f = Frame::from_normal(rng.sphere());
        let (ex, ey) = (
            f.s * rng.log_range(1e-3, 5.0),
            f.t * rng.log_range(1e-3, 5.0),
        );
        let corner = if i % 25 == 2 {
            p - 0.3 * ex - 0.6 * ey
        } else {
            rng.point(2.0)
        };
        for v in [p, a, b, c] {
            push3(&mut input, v);
        }
        input.extend_from_slice(&[rng.f(), rng.f()]);
        for v in [corner, ex, ey] {
            push3(&mut input, v);
        }
        input.push(0.0);
    }
    let scene = load_scene("cornell-box.toml");
    let settings = RenderSettings::default();
    let out = run(
        &scene,
        &settings,
        &["warp"],
        SPHERICAL_PROBE,
        &input,
        12,
        count,
    );
    let mut c = Check::new("spherical warps");
    // Lights use the spherical maps only for Ω in (3e-4, 6.22) (`light::use_spherical`): outside,
    // tiny Ω (a difference of atan2s) and Ω near 2π are ill-conditioned, and only flags and Ω
    // are compared. Ω is compared absolutely near 0 (1e-6), and the pdf through Ω = 1/pdf.
    let in_range = |omega: f32| omega > 3e-4 && omega < 6.22;
    let mut compared = [0; 2];
    for i in 0..count {
        let inp = &input[i * 24..];
        let o = &out[i * 12..];
        let (p, a, b, cc) = (v3(inp, 0), v3(inp, 3), v3(inp, 6), v3(inp, 9));
        let u = Vec2::new(inp[12], inp[13]);
        let (corner, ex, ey) = (v3(inp, 14), v3(inp, 17), v3(inp, 20));
        c.f(
            "spherical_triangle::solid_angle",
            i,
            o[0],
            tri::solid_angle(p, a, b, cc),
        );
        let t = tri::sample(p, a, b, cc, u);
        if c.flag("spherical_triangle::sample valid", i, o[1], t.is_some()) {
            let (dir, pdf) = t.unwrap();
            c.f("spherical_triangle::sample 1/pdf", i, 1.0 / o[5], 1.0 / pdf);
            if in_range(1.0 / pdf) {
                c.v3("spherical_triangle::sample dir", i, v3(o, 2), dir);
                compared[0] += 1;
            }
        }
        let sa = rect::solid_angle(p, corner, ex, ey);
        c.f("spherical_rectangle::solid_angle", i, o[6], sa);
        let r = rect::sample(p, corner, ex, ey, u);
        if c.flag("spherical_rectangle::sample valid", i, o[7], r.is_some()) {
            let (x, pdf) = r.unwrap();
            c.f(
                "spherical_rectangle::sample 1/pdf",
                i,
                1.0 / o[11],
                1.0 / pdf,
            );
            if in_range(1.0 / pdf) {
                // The point relative to the rectangle's size and distance.
                let scale = ex.length().max(ey.length()).max((x - p).length());
                c.v3(
                    "spherical_rectangle::sample point",
                    i,
                    v3(o, 8) / scale,
                    x / scale,
                );
                compared[1] += 1;
            }
        }
    }
    eprintln!(
        "samples compared in the lights' range: triangle {}, rectangle {} of {count}",
        compared[0], compared[1]
    );
    c.finish();
}

// ---- MIS ---------------------------------------------------------------------------------------

const MIS_PROBE: &str = r#"
fn probe(i: u32) {
    let a = probe_f(2u * i);
    let b = probe_f(2u * i + 1u);
    probe_put(2u * i, mis_power_heuristic(a, b));
    probe_put(2u * i + 1u, mis_balance_heuristic(a, b));
}
"#;

#[test]
fn mis_weights_match_cpu() {
    let values = [
        0.0,
        -0.0,
        1e-30,
        1e-3,
        0.5,
        1.0,
        3.0,
        1e19,
        1e30,
        f32::MAX,
        f32::INFINITY,
        f32::NAN,
    ];
    let mut rng = Rng(3);
    let mut pairs: Vec<(f32, f32)> = values
        .iter()
        .flat_map(|&a| values.iter().map(move |&b| (a, b)))
        .collect();
    pairs.extend((0..500).map(|_| (rng.log_range(1e-6, 1e6), rng.log_range(1e-6, 1e6))));
    let input: Vec<f32> = pairs.iter().flat_map(|&(a, b)| [a, b]).collect();
    let scene = load_scene("cornell-box.toml");
    let settings = RenderSettings::default();
    let out = run(
        &scene,
        &settings,
        &["mis"],
        MIS_PROBE,
        &input,
        2,
        pairs.len(),
    );
    let mut c = Check::new("mis");
    for (i, &(a, b)) in pairs.iter().enumerate() {
        c.f("power_heuristic", i, out[2 * i], mis::power_heuristic(a, b));
        c.f(
            "balance_heuristic",
            i,
            out[2 * i + 1],
            mis::balance_heuristic(a, b),
        );
    }
    c.finish();
}

// ---- BSDFs -------------------------------------------------------------------------------------

const BSDF_PROBE: &str = r#"
fn probe(i: u32) {
    let k = i * 24u;
    let o = i * 60u;
    let hit = Hit(1.0, 0u, probe_v3(k), probe_v3(k + 3u), probe_v3(k + 6u));
    let wo = probe_v3(k + 9u);
    let wi = probe_v3(k + 12u);
    let u = probe_v2(k + 15u);
    let u_lobe = probe_f(k + 17u);
    let material = Material(probe_v3(k + 18u), probe_in[k + 21u], vec3f(0.0), probe_f(k + 22u));
    let sp = shading_point_new(hit, material, wo);
    probe_put_bool(o, bsdf_is_delta(sp));
    probe_put3(o + 1u, shading_point_eval(sp, wo, wi));
    for (var strategy = 0u; strategy < 5u; strategy++) {
        let q = o + 4u + strategy * 11u;
        probe_put(q, shading_point_pdf(sp, wo, wi, strategy));
        let s = shading_point_sample(sp, wo, u, u_lobe, strategy);
        probe_put_bool(q + 1u, s.valid);
        probe_put3(q + 2u, s.wi);
        probe_put3(q + 5u, s.weight);
        probe_put(q + 8u, s.pdf);
        probe_put(q + 9u, s.eta);
        probe_put_bool(q + 10u, s.delta);
    }
}
"#;

#[test]
fn bsdfs_match_cpu() {
    use stratapt_cpu::bsdf::ShadingPoint;
    use stratapt_cpu::intersect::Hit;
    use stratapt_scene::gpu::{material_kind, Material};
    use stratapt_scene::Strategy;
    let mut rng = Rng(4);
    let count = 3000;
    let mut input = Vec::new();
    for i in 0..count {
        let p = rng.point(3.0);
        let ng = rng.sphere();
        // Shading normals near the geometric one, sometimes on its other side.
        let ns = match i % 10 {
            0 => ng,
            1 => -ng,
            _ => (ng + 0.4 * rng.sphere()).normalize(),
        };
        let wo = rng.sphere();
        let wi = if i % 3 == 0 {
            // Near the mirror direction, where glossy lobes peak.
            (2.0 * wo.dot(ns) * ns - wo + 0.05 * rng.sphere()).normalize()
        } else {
            rng.sphere()
        };
        let (kind, param) = match i % 6 {
            0 | 1 => (material_kind::DIFFUSE, 0.0),
            2 => (material_kind::CONDUCTOR, rng.log_range(2e-3, 1.0)),
            3 => (material_kind::CONDUCTOR, rng.range(0.0, 1e-3)),
            _ => (material_kind::DIELECTRIC, rng.range(1.05, 2.4)),
        };
        for v in [p, ng, ns, wo, wi] {
            push3(&mut input, v);
        }
        input.extend_from_slice(&[rng.f(), rng.f(), rng.f()]);
        push3(&mut input, Vec3::new(rng.f(), rng.f(), rng.f()));
        input.extend_from_slice(&[f32::from_bits(kind), param, 0.0]);
    }
    let scene = load_scene("cornell-box.toml");
    let settings = RenderSettings::default();
    let modules = ["warp", "motion", "intersect", "bsdf"];
    let out = run(&scene, &settings, &modules, BSDF_PROBE, &input, 60, count);
    let mut c = Check::new("bsdfs");
    let mut valid = [0usize; 5];
    for i in 0..count {
        let inp = &input[i * 24..];
        let o = &out[i * 60..];
        let hit = Hit {
            t: 1.0,
            prim: 0,
            p: v3(inp, 0),
            ng: v3(inp, 3),
            ns: v3(inp, 6),
        };
        let (wo, wi) = (v3(inp, 9), v3(inp, 12));
        let (u, u_lobe) = (Vec2::new(inp[15], inp[16]), inp[17]);
        let material = Material {
            color: v3(inp, 18).to_array(),
            kind: inp[21].to_bits(),
            emission: [0.0; 3],
            param: inp[22],
        };
        let sp = ShadingPoint::new(&hit, &material, wo);
        c.flag("is_delta", i, o[0], sp.bsdf.is_delta());
        c.v3("eval", i, v3(o, 1), sp.eval(wo, wi));
        for (si, strategy) in Strategy::ALL.into_iter().enumerate() {
            let q = &o[4 + si * 11..];
            c.f(
                &format!("pdf {strategy}"),
                i,
                q[0],
                sp.pdf(wo, wi, strategy),
            );
            let s = sp.sample(wo, u, u_lobe, strategy);
            if c.flag(&format!("sample {strategy} valid"), i, q[1], s.is_some()) {
                let s = s.unwrap();
                c.v3(&format!("sample {strategy} wi"), i, v3(q, 2), s.wi);
                // G2 / G1 varies as 1 / cos θi at grazing wi, whose cosine carries an absolute
                // error of ~1e-7 from the reflection: widen the weight's tolerance there.
                let cos_i = sp.frame.to_local(s.wi).z.abs();
                let widen = (1e-2 / cos_i).max(1.0);
                for k in 0..3 {
                    let what = format!("sample {strategy} weight[{k}] (cos θi {cos_i})");
                    c.f_rel(&what, i, q[5 + k], s.weight[k], widen);
                }
                c.f(&format!("sample {strategy} pdf"), i, q[8], s.pdf);
                c.f(&format!("sample {strategy} eta"), i, q[9], s.eta);
                c.flag(&format!("sample {strategy} delta"), i, q[10], s.delta);
                valid[si] += 1;
            }
        }
    }
    eprintln!("valid samples per strategy: {valid:?} of {count}");
    c.finish();
}

// ---- Lights ------------------------------------------------------------------------------------

/// WGSL: the `Light` at word `k` of `probe_in` (the 16 words of `gpu::Light`).
const LIGHT_IN: &str = r#"
fn probe_light(k: u32) -> Light {
    return Light(probe_v3(k), probe_in[k + 3u], probe_v3(k + 4u), probe_in[k + 7u],
        probe_v3(k + 8u), probe_f(k + 11u), probe_v3(k + 12u), probe_f(k + 15u));
}
"#;

const LIGHT_PROBE: &str = r#"
fn probe(i: u32) {
    let k = i * 28u;
    let o = i * 18u;
    let light = probe_light(k);
    let p = probe_v3(k + 16u);
    let u = probe_v2(k + 19u);
    let dir = probe_v3(k + 21u);
    let dist = probe_f(k + 24u);
    let s = light_sample(light, p, u);
    probe_put_bool(o, s.valid);
    probe_put3(o + 1u, s.wi);
    probe_put3(o + 4u, s.radiance);
    probe_put(o + 7u, s.dist);
    probe_put(o + 8u, s.pdf);
    probe_put_bool(o + 9u, s.delta);
    probe_put(o + 10u, light_pdf(light, p, s.wi, s.dist));
    probe_put(o + 11u, light_pdf(light, p, dir, dist));
    probe_put3(o + 12u, light_escaped_radiance(light, dir));
    probe_put_bool(o + 15u, light_is_environment(light));
}
"#;

/// A random light of `kind` near the origin, and a shading point `p` that sometimes sits on it.
fn random_light(rng: &mut Rng, kind: u32, i: usize) -> (stratapt_scene::gpu::Light, Vec3) {
    use stratapt_scene::gpu::{light_kind, Light};
    let scale = rng.log_range(1e-2, 3.0);
    let centre = rng.point(1.0);
    let mut p = rng.point(3.0);
    let mut l = Light {
        kind,
        motion: stratapt_scene::gpu::NONE,
        radiance: [
            rng.range(0.1, 5.0),
            rng.range(0.1, 5.0),
            rng.range(0.1, 5.0),
        ],
        ..Default::default()
    };
    let (a, b, c) = match kind {
        light_kind::TRIANGLE => (
            centre + scale * rng.sphere(),
            centre + scale * rng.sphere(),
            centre + scale * rng.sphere(),
        ),
        light_kind::RECTANGLE => {
            let f = Frame::from_normal(rng.sphere());
            let (ex, ey) = (
                f.s * scale * rng.range(0.2, 2.0),
                f.t * scale * rng.range(0.2, 2.0),
            );
            // Every 8th a parallelogram (area sampling); every 9th p in its plane.
            let ey = if i.is_multiple_of(8) {
                ey + 0.3 * ex
            } else {
                ey
            };
            if i.is_multiple_of(9) {
                p = centre + rng.range(-1.0, 2.0) * ex + rng.range(-1.0, 2.0) * ey;
            }
            (centre, ex, ey)
        }
        light_kind::DISK => (centre, rng.sphere(), Vec3::new(scale, 0.0, 0.0)),
        light_kind::SPHERE => {
            // Inside, on, and outside the sphere, far and near.
            match i % 4 {
                0 => p = centre + scale * rng.f() * rng.sphere(),
                1 => p = centre + scale * rng.sphere(),
                _ => {}
            }
            (centre, Vec3::ZERO, Vec3::new(scale, 0.0, 0.0))
        }
        light_kind::LINE => (centre, centre + scale * rng.sphere(), Vec3::ZERO),
        light_kind::POINT => (centre, Vec3::ZERO, Vec3::ZERO),
        light_kind::DISTANT => {
            let cos_max = match i % 3 {
                0 => 1.0,
                1 => 1.0 - rng.log_range(1e-6, 1e-2),
                _ => rng.range(0.0, 1.0),
            };
            (rng.sphere(), Vec3::ZERO, Vec3::new(cos_max, 0.0, 0.0))
        }
        _ => (
            rng.sphere(),
            Vec3::new(rng.f(), rng.f(), rng.f()),
            Vec3::ZERO,
        ),
    };
    l.p0 = a.to_array();
    l.p1 = b.to_array();
    l.p2 = c.to_array();
    (l, p)
}

/// Compare `light::sample`, `pdf` (at the sample and along a random direction),
/// `escaped_radiance` and `is_environment` for each `(light, p)`.
fn compare_lights(name: &'static str, cases: &[(stratapt_scene::gpu::Light, Vec3)], rng: &mut Rng) {
    use stratapt_cpu::light;
    let mut input = Vec::new();
    for (l, p) in cases {
        input.extend(
            bytemuck::cast_slice::<_, u32>(&[*l])
                .iter()
                .map(|w| f32::from_bits(*w)),
        );
        push3(&mut input, *p);
        input.extend_from_slice(&[rng.f(), rng.f()]);
        // A direction towards the light (near its centre) or anywhere, and a distance.
        let towards = (Vec3::from_array(l.p0) - *p).normalize_or(Vec3::Z);
        let dir = if rng.f() < 0.5 {
            (towards + 0.2 * rng.sphere()).normalize()
        } else {
            rng.sphere()
        };
        push3(&mut input, dir);
        input.extend_from_slice(&[rng.log_range(1e-2, 10.0), 0.0, 0.0, 0.0]);
    }
    let scene = load_scene("cornell-box.toml");
    let settings = RenderSettings::default();
    let modules = ["warp", "motion", "light"];
    let probe = format!("{LIGHT_IN}\n{LIGHT_PROBE}");
    let out = run(&scene, &settings, &modules, &probe, &input, 18, cases.len());
    let mut c = Check::new(name);
    let mut valid = [(0usize, 0usize); 8];
    for (i, (l, p)) in cases.iter().enumerate() {
        let inp = &input[i * 28..];
        let o = &out[i * 18..];
        let kind = [
            "triangle",
            "rectangle",
            "disk",
            "sphere",
            "line",
            "point",
            "distant",
            "sky",
        ][l.kind as usize];
        let u = Vec2::new(inp[19], inp[20]);
        let (dir, dist) = (v3(inp, 21), inp[24]);
        let s = light::sample(l, *p, u);
        valid[l.kind as usize].1 += 1;
        if c.flag(&format!("{kind} sample valid"), i, o[0], s.is_some()) {
            let s = s.unwrap();
            c.v3(&format!("{kind} sample wi"), i, v3(o, 1), s.wi);
            c.v3(&format!("{kind} sample radiance"), i, v3(o, 4), s.radiance);
            c.f(&format!("{kind} sample dist"), i, o[7], s.dist);
            c.f(&format!("{kind} sample pdf"), i, o[8], s.pdf);
            c.flag(&format!("{kind} sample delta"), i, o[9], s.delta);
            c.f(
                &format!("{kind} pdf(sampled)"),
                i,
                o[10],
                light::pdf(l, *p, s.wi, s.dist),
            );
            valid[l.kind as usize].0 += 1;
        }
        c.f(
            &format!("{kind} pdf"),
            i,
            o[11],
            light::pdf(l, *p, dir, dist),
        );
        let e = light::escaped_radiance(l, dir);
        c.v3(&format!("{kind} escaped_radiance"), i, v3(o, 12), e);
        c.flag(
            &format!("{kind} is_environment"),
            i,
            o[15],
            light::is_environment(l),
        );
    }
    eprintln!("{name}: (valid samples, cases) per light kind: {valid:?}");
    c.finish();
}

#[test]
fn lights_match_cpu() {
    let mut rng = Rng(5);
    let cases: Vec<_> = (0..8 * 600)
        .map(|i| random_light(&mut rng, (i % 8) as u32, i / 8))
        .collect();
    compare_lights("random lights", &cases, &mut rng);
}

#[test]
fn scene_lights_match_cpu() {
    let mut rng = Rng(7);
    let mut cases = Vec::new();
    for name in [
        "cornell-box.toml",
        "soft-shadow-area.toml",
        "soft-shadow-line.toml",
        "soft-shadow-sun.toml",
        "veach-mis.toml",
        "glass.toml",
    ] {
        let scene = load_scene(name);
        // Shading points anywhere in (and a little around) the scene's bounds.
        let (lo, hi) = (scene.bounds_min, scene.bounds_max);
        for _ in 0..300 {
            for l in &scene.lights {
                let t = Vec3::new(
                    rng.range(-0.1, 1.1),
                    rng.range(-0.1, 1.1),
                    rng.range(-0.1, 1.1),
                );
                cases.push((*l, lo + (hi - lo) * t));
            }
        }
    }
    compare_lights("scene lights", &cases, &mut rng);
}

/// Moving emitters of every shape kind, the non-surface lights, and a sky.
const MOVING_LIGHTS: &str = r#"
[camera]
eye = [0, 1, -5]
look_at = [0, 1, 0]
fov = 40
shutter = [0, 1]

[film]
width = 8
height = 8

[materials.lamp]
type = "diffuse"
albedo = 0.5
emission = [3, 2, 1]

[[shapes]]
type = "rectangle"
corner = [-1, 3, -1]
edge_u = [2, 0, 0]
edge_v = [0, 0, 1.5]
material = "lamp"
transform = { translate = [0, 0, 0], rotate = [10, 0, 0] }
transform_close = { translate = [0.5, -0.2, 0.1], rotate = [10, 40, 5], scale = 1.3 }

[[shapes]]
type = "triangle"
vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0.2]]
material = "lamp"
transform = { translate = [1, 1, 1] }
transform_close = { translate = [1, 2, 1], rotate = [0, 90, 30], scale = 0.7 }

[[shapes]]
type = "disk"
center = [0, 0, 0]
normal = [0, -1, 0]
radius = 0.4
material = "lamp"
transform = { translate = [-2, 2, 0], rotate = [20, 0, 0] }
transform_close = { translate = [-2, 2.5, 0], rotate = [-30, 45, 0], scale = 1.5 }

[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 0.3
material = "lamp"
transform = { translate = [2, 0.5, 0] }
transform_close = { translate = [2, 1.5, -1], scale = 2 }

[[lights]]
type = "point"
position = [0, 4, 0]
intensity = 5

[[lights]]
type = "line"
from = [-1, 4, 1]
to = [1, 4, 1]
intensity = 2

[[lights]]
type = "distant"
direction = [0.3, 1, 0.2]
irradiance = 2
angular_diameter = 3

[sky]
top = [0.2, 0.3, 0.8]
bottom = [0.1, 0.1, 0.1]
"#;

const PLACED_PROBE: &str = r#"
fn probe(i: u32) {
    let index = probe_in[4u * i];
    let time = probe_f(4u * i + 1u);
    let u = probe_f(4u * i + 2u);
    let l = light_placed(index, time);
    let o = i * 20u;
    probe_put3(o, l.p0);
    probe_out[o + 3u] = l.kind;
    probe_put3(o + 4u, l.p1);
    probe_out[o + 7u] = l.motion;
    probe_put3(o + 8u, l.p2);
    probe_put(o + 11u, l.select_pdf);
    probe_put3(o + 12u, l.radiance);
    probe_put(o + 15u, l.unhittable_select_pdf);
    let full = light_select(true, u);
    probe_out[o + 16u] = full.index;
    probe_put(o + 17u, full.pdf);
    let unhittable = light_select(false, u);
    probe_out[o + 18u] = unhittable.index;
    probe_put(o + 19u, unhittable.pdf);
}
"#;

#[test]
fn placed_lights_and_selection_match_cpu() {
    use stratapt_cpu::light;
    use stratapt_scene::light_table;
    let scene = stratapt_scene::load::load_str(MOVING_LIGHTS, Path::new("moving-lights"))
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(!scene.unhittable_table.is_empty() && scene.lights.len() >= 8);
    let moving = scene
        .lights
        .iter()
        .filter(|l| l.motion != stratapt_scene::gpu::NONE)
        .count();
    assert!(moving >= 4, "{moving} moving lights");
    let mut rng = Rng(6);
    let count = 2000;
    let mut input = Vec::new();
    for i in 0..count {
        let u = if i < 64 { i as f32 / 64.0 } else { rng.f() };
        let time = if i % 10 == 0 {
            (i % 20 / 10) as f32
        } else {
            rng.f()
        };
        let index = (i % scene.lights.len()) as u32;
        input.extend_from_slice(&[f32::from_bits(index), time, u, 0.0]);
    }
    let settings = RenderSettings::default();
    let out = run(
        &scene,
        &settings,
        &["warp", "motion", "light"],
        PLACED_PROBE,
        &input,
        20,
        count,
    );
    let mut c = Check::new("placed lights, selection");
    for i in 0..count {
        let (index, time, u) = (
            input[4 * i].to_bits() as usize,
            input[4 * i + 1],
            input[4 * i + 2],
        );
        let o = &out[i * 20..];
        let l = light::placed(&scene.lights[index], &scene.motions, time);
        let words = |k: usize| Vec3::new(o[k], o[k + 1], o[k + 2]);
        c.v3("placed p0", i, words(0), Vec3::from_array(l.p0));
        c.v3("placed p1", i, words(4), Vec3::from_array(l.p1));
        c.v3("placed p2", i, words(8), Vec3::from_array(l.p2));
        c.v3(
            "placed radiance",
            i,
            words(12),
            Vec3::from_array(l.radiance),
        );
        c.f("placed select_pdf", i, o[11], l.select_pdf);
        c.f(
            "placed unhittable_select_pdf",
            i,
            o[15],
            l.unhittable_select_pdf,
        );
        c.flag(
            "placed kind/motion",
            i,
            1.0,
            o[3].to_bits() == l.kind && o[7].to_bits() == l.motion,
        );
        let (j, pdf) = light_table::select(&scene.light_table, u);
        c.flag("select index", i, 1.0, o[16].to_bits() as usize == j);
        c.f("select pdf", i, o[17], pdf);
        let (j, pdf) = light_table::select(&scene.unhittable_table, u);
        c.flag(
            "select unhittable index",
            i,
            1.0,
            o[18].to_bits() as usize == j,
        );
        c.f("select unhittable pdf", i, o[19], pdf);
    }
    c.finish();
}

// ---- warp_atan2 --------------------------------------------------------------------------------

const ATAN2_PROBE: &str = r#"
fn probe(i: u32) {
    let y = probe_f(2u * i);
    let x = probe_f(2u * i + 1u);
    probe_put(2u * i, warp_atan2(y, x));
    probe_put(2u * i + 1u, atan2(y, x));
}
"#;

/// The solid angles subtract atan2s, and Vulkan lets the built-in be off by 4096 ulp: the warps
/// use `warp_atan2`, which must stay within a few ulp of Rust's.
#[test]
fn warp_atan2_is_accurate() {
    let mut rng = Rng(9);
    let mut pairs: Vec<(f32, f32)> = (0..4000)
        .map(|i| match i % 3 {
            0 => (rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)),
            1 => (rng.log_range(1e-6, 1.0), 1.0),
            _ => (
                rng.range(-1e3, 1e3),
                rng.log_range(1e-3, 1e3) * rng.range(-1.0, 1.0),
            ),
        })
        .collect();
    for a in [0.0f32, -0.0, 1.0, -1.0] {
        for b in [0.0f32, -0.0, 1.0, -1.0] {
            pairs.push((a, b));
        }
    }
    let input: Vec<f32> = pairs.iter().flat_map(|&(y, x)| [y, x]).collect();
    let scene = load_scene("cornell-box.toml");
    let settings = RenderSettings::default();
    let out = run(
        &scene,
        &settings,
        &["warp"],
        ATAN2_PROBE,
        &input,
        2,
        pairs.len(),
    );
    let mut c = Check::new("warp_atan2");
    let (mut worst, mut builtin) = (0.0f32, 0.0f32);
    for (i, &(y, x)) in pairs.iter().enumerate() {
        let exact = y.atan2(x);
        let ulp = f32::EPSILON * exact.abs().max(f32::MIN_POSITIVE);
        worst = worst.max((out[2 * i] - exact).abs() / ulp);
        builtin = builtin.max((out[2 * i + 1] - exact).abs());
        c.f("warp_atan2", i, out[2 * i], exact);
    }
    eprintln!("atan2 error: warp_atan2 {worst} ulp; the built-in up to {builtin:e} absolute");
    assert!(worst <= 4.0, "warp_atan2 is {worst} ulp off");
    c.finish();
}
