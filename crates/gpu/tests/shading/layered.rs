//! The coated materials' layered BSDF (`bsdf_layered.wgsl`, placed by `shading_point_new` with
//! its base record) against `stratapt_cpu::bsdf::ShadingPoint::with_base`: eval, and pdf and
//! sample (valid, wi, weight, pdf, delta) under every strategy, on random coated materials.
//!
//! Both sides run the same random walks from the same counter-based stream, keyed by the f32
//! bits of the directions. The built-ins `exp`, `log`, `sin` and `cos` (transmittance, free
//! flights, phase-function directions) round differently from Rust's, so values agree to a
//! tolerance rather than to the bit, and a walk whose branch (inside the slab or not, roulette)
//! hangs on such a last bit goes another way. A value *agrees* when it is within [`TOLERANCE`]
//! of its largest component (no absolute floor above 10⁻³⁰; widened for sample weights and pdfs
//! at grazing cos θi as in `bsdf.rs`), a flag when it is equal. Measured on lavapipe (20 000
//! cases): 66 % of evals and 90 % of pdfs identical to the bit, the largest agreeing difference
//! 9e-5 relative, 0.01 % of cases and of samples diverged, 12 % of samples re-keyed.
//!
//! - At the given directions (is_delta, eval, pdf under every strategy) the cases that do not
//!   agree, diverged walks, stay under [`DIVERGED_BAR`].
//! - A sample's direction comes from warps whose `sin` / `cos` differ in the last bit now and
//!   then; a direction of other bits keys another stream, and the estimate made there (the
//!   weight under the hemisphere strategies, which is `eval / pdf`; the pdf of the BSDF's own
//!   sample, pbrt's estimate at the direction) is an independent one: a re-keyed sample, counted
//!   but not held to agree. The other samples (valid, wi, delta, and weight and pdf where the
//!   directions have the same bits) stay under [`DIVERGED_BAR`] too.
//!
//! Planted: a Henyey–Greenstein of the wrong sign, and the walk's base sample drawing its
//! directions before its lobe dimension; each diverges at the given directions far above the bar.

use super::*;
use stratapt_scene::records::{material_flag, material_kind, Material};

/// The largest fraction of cases whose walks may diverge on a last-bit difference.
const DIVERGED_BAR: f64 = 0.02;

/// Relative tolerance of a value (to its largest component).
const TOLERANCE: f32 = 1e-4;

/// Per case: hit point, geometric and shading normals, wo, wi (15 words), u, u_lobe (3), the
/// coated record (16), its base's record (16), 2 unused.
const IN_STRIDE: usize = 52;
/// Per case: is_delta, eval (3), then per strategy pdf, valid, wi, weight, pdf, eta, delta, and
/// the sample's direction in the shading frame (14), 2 unused.
const OUT_STRIDE: usize = 76;

const LAYERED_PROBE: &str = r#"
fn probe_material(k: u32) -> Material {
    return Material(probe_v3(k), probe_in[k + 3u], probe_v3(k + 4u), probe_f(k + 7u),
        probe_v3(k + 8u), probe_f(k + 11u), probe_v3(k + 12u), probe_f(k + 15u));
}

fn probe(i: u32) {
    let k = i * 52u;
    let o = i * 76u;
    let hit = Hit(1.0, 0u, probe_v3(k), vec3f(0.0), probe_v3(k + 3u), probe_v3(k + 6u), vec2f(0.0));
    let wo = probe_v3(k + 9u);
    let wi = probe_v3(k + 12u);
    let u = probe_v2(k + 15u);
    let u_lobe = probe_f(k + 17u);
    let sp = shading_point_new(hit, probe_material(k + 18u), probe_material(k + 34u), wo);
    probe_put_bool(o, bsdf_is_delta(sp));
    probe_put3(o + 1u, shading_point_eval(sp, wo, wi));
    for (var strategy = 0u; strategy < 5u; strategy++) {
        let q = o + 4u + strategy * 14u;
        probe_put(q, shading_point_pdf(sp, wo, wi, strategy));
        let s = shading_point_sample(sp, wo, u, u_lobe, strategy);
        probe_put_bool(q + 1u, s.valid);
        probe_put3(q + 2u, s.wi);
        probe_put3(q + 5u, s.weight);
        probe_put(q + 8u, s.pdf);
        probe_put(q + 9u, s.eta);
        probe_put_bool(q + 10u, s.delta);
        let local = bsdf_sample(sp.bsdf, frame_to_local(sp.frame, wo), u, u_lobe, strategy);
        probe_put3(q + 11u, local.wi);
    }
}
"#;

/// The record's 16 words in `Material`'s layout.
fn push_material(input: &mut Vec<f32>, m: &Material) {
    push3(input, Vec3::from_array(m.color));
    input.push(f32::from_bits(m.tag));
    push3(input, Vec3::from_array(m.emission));
    input.push(m.ior);
    push3(input, Vec3::from_array(m.eta));
    input.push(m.alpha_u);
    push3(input, Vec3::from_array(m.k));
    input.push(m.alpha_v);
}

fn material_at(input: &[f32]) -> Material {
    Material {
        color: v3(input, 0).to_array(),
        tag: input[3].to_bits(),
        emission: v3(input, 4).to_array(),
        ior: input[7],
        eta: v3(input, 8).to_array(),
        alpha_u: input[11],
        k: v3(input, 12).to_array(),
        alpha_v: input[15],
    }
}

/// GGX roughness: smooth (0, or below the mirror threshold) a third of the time, else up to 1,
/// now and then anisotropic.
fn roughness(rng: &mut Rng) -> (f32, f32) {
    match rng.below(6) {
        0 => (0.0, 0.0),
        1 => {
            let a = rng.range(0.0, 1e-3);
            (a, a)
        }
        2 => (rng.log_range(2e-3, 1.0), rng.log_range(1e-4, 1.0)),
        _ => {
            let a = rng.log_range(2e-3, 1.0);
            (a, a)
        }
    }
}

/// A random coated record over a random base record: (coated, base).
fn coated_case(rng: &mut Rng) -> (Material, Material) {
    let separable = |rng: &mut Rng| match rng.below(3) {
        0 => material_flag::SEPARABLE_MASKING,
        _ => 0,
    };
    let colour = |rng: &mut Rng| Vec3::new(rng.f32(), rng.f32(), rng.f32()).to_array();
    // The base: diffuse, Schlick or complex conductor, smooth or rough.
    let (alpha_u, alpha_v) = roughness(rng);
    let base = match rng.below(3) {
        0 => Material {
            tag: material_kind::DIFFUSE,
            color: colour(rng),
            ..Material::default()
        },
        1 => Material {
            tag: material_kind::CONDUCTOR | separable(rng),
            color: colour(rng),
            alpha_u,
            alpha_v,
            ..Material::default()
        },
        _ => Material {
            tag: material_kind::COMPLEX_CONDUCTOR | separable(rng),
            color: Vec3::new(rng.range(0.5, 1.0), rng.range(0.5, 1.0), 1.0).to_array(),
            eta: Vec3::new(rng.log_range(0.1, 3.0), rng.log_range(0.1, 3.0), 1.5).to_array(),
            k: Vec3::new(rng.range(0.0, 5.0), rng.range(0.0, 5.0), 2.0).to_array(),
            alpha_u,
            alpha_v,
            ..Material::default()
        },
    };
    let kind = match base.kind() {
        material_kind::DIFFUSE => material_kind::COATED_DIFFUSE,
        _ => material_kind::COATED_CONDUCTOR,
    };
    // The coat and the slab: a clear slab a quarter of the time, g near 0 now and then.
    let (alpha_u, alpha_v) = roughness(rng);
    let ior = if rng.below(20) == 0 {
        1.0
    } else {
        rng.range(1.05, 2.5)
    };
    let albedo = match rng.below(4) {
        0 => [0.0; 3],
        _ => colour(rng),
    };
    let g = match rng.below(8) {
        0 => rng.range(-1e-3, 1e-3),
        _ => rng.range(-0.9, 0.9),
    };
    let thickness = rng.log_range(1e-3, 1.0);
    let max_depth = 1 + rng.below(20) as u32;
    let samples = 1 + rng.below(3) as u32;
    let coated = Material {
        tag: kind | separable(rng),
        color: albedo,
        ior,
        alpha_u,
        alpha_v,
        eta: [thickness, g, max_depth as f32],
        k: [samples as f32, 1.0, 0.0],
        ..Material::default()
    };
    (coated, base)
}

/// `count` random cases: shading geometry, directions, sample dimensions and materials.
fn cases(count: usize, seed: u64) -> Vec<f32> {
    let mut rng = Rng(seed);
    let mut input = Vec::with_capacity(count * IN_STRIDE);
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
        let wi = match i % 3 {
            // Near the mirror direction, where the coat's lobe peaks.
            0 => (2.0 * wo.dot(ns) * ns - wo + 0.05 * rng.sphere()).normalize(),
            _ => rng.sphere(),
        };
        for v in [p, ng, ns, wo, wi] {
            push3(&mut input, v);
        }
        input.extend_from_slice(&[rng.f32(), rng.f32(), rng.f32()]);
        let (coated, base) = coated_case(&mut rng);
        push_material(&mut input, &coated);
        push_material(&mut input, &base);
        input.extend_from_slice(&[0.0, 0.0]);
    }
    input
}

/// How the values of one kind (eval, pdf under a strategy, …) compare.
#[derive(Clone, Copy, Default, Debug)]
struct Counts {
    identical: usize,
    close: usize,
    beyond: usize,
}

/// How the GPU's cases compare with the CPU's.
#[derive(Default)]
struct Tally {
    cases: usize,
    /// Cases whose every value is the same number on both sides.
    identical: usize,
    /// Cases with a value at the given directions beyond the tolerance.
    diverged: usize,
    /// Samples (case × strategy), those whose direction has other bits than the CPU's, and those
    /// that do not agree without that excuse.
    samples: usize,
    rekeyed: usize,
    rekeyed_beyond: usize,
    samples_diverged: usize,
    examples: Vec<String>,
    /// The largest relative difference of a value within the tolerance, and where.
    largest: (f32, String),
    by_what: std::collections::BTreeMap<String, Counts>,
}

impl Tally {
    /// Compare `gpu` with `cpu` (its tolerance widened by `widen`): whether they agree, and
    /// whether they are the same numbers. Relative to the largest of the CPU's components, with
    /// no absolute floor but for values below 10⁻³⁰ (the estimates span many decades, and the
    /// other probes' floor of 10⁻⁶ would pass any two small estimates).
    fn value(
        &mut self,
        what: &str,
        i: usize,
        gpu: &[f32],
        cpu: &[f32],
        widen: f32,
    ) -> (bool, bool) {
        let counts = self.by_what.entry(what.to_string()).or_default();
        let same = gpu
            .iter()
            .zip(cpu)
            .all(|(g, c)| g == c || g.is_nan() && c.is_nan());
        if same {
            counts.identical += 1;
            return (true, true);
        }
        let scale = cpu.iter().fold(0.0f32, |m, c| m.max(c.abs()));
        let diff = gpu
            .iter()
            .zip(cpu)
            .map(|(g, c)| (g - c).abs())
            .fold(0.0, f32::max);
        let close = diff <= (TOLERANCE * widen * scale).max(1e-30);
        if !close {
            counts.beyond += 1;
            return (false, false);
        }
        counts.close += 1;
        let rel = diff / scale;
        // An estimate made from another stream is no rounding difference.
        if rel > self.largest.0 && !what.contains("re-keyed") {
            self.largest = (rel, format!("{what} #{i}: gpu {gpu:?} cpu {cpu:?}"));
        }
        (true, false)
    }

    fn flag(&mut self, what: &str, i: usize, gpu: f32, cpu: bool) -> bool {
        let g = [f32::from(u8::from(gpu != 0.0))];
        self.value(what, i, &g, &[f32::from(u8::from(cpu))], 0.0).1
    }

    fn example(&mut self, text: String) {
        if self.examples.len() < 12 {
            self.examples.push(text);
        }
    }

    fn fraction(&self, n: usize, of: usize) -> f64 {
        n as f64 / of.max(1) as f64
    }

    fn report(&self, name: &str) {
        eprintln!(
            "{name}: {} cases, {:.2} % identical in every value, {:.2} % diverged at the given \
             directions; {} samples, {:.2} % re-keyed (of which {:.2} % beyond the tolerance), \
             {:.2} % diverged otherwise; largest difference within the tolerance {:.2e} ({})",
            self.cases,
            100.0 * self.fraction(self.identical, self.cases),
            100.0 * self.fraction(self.diverged, self.cases),
            self.samples,
            100.0 * self.fraction(self.rekeyed, self.samples),
            100.0 * self.fraction(self.rekeyed_beyond, self.rekeyed),
            100.0 * self.fraction(self.samples_diverged, self.samples),
            self.largest.0,
            self.largest.1,
        );
        for (what, c) in &self.by_what {
            let n = c.identical + c.close + c.beyond;
            eprintln!(
                "  {what:>24}: {n:>5} compared, {:6.2} % identical, {:6.2} % beyond",
                100.0 * self.fraction(c.identical, n),
                100.0 * self.fraction(c.beyond, n)
            );
        }
        for e in &self.examples {
            eprintln!("  diverged {e}");
        }
    }
}

/// Run `probe` (the layered probe, after whatever WGSL it brings) over `count` cases from
/// `seed` with `modules`, and compare every case with the CPU.
fn compare(modules: &[&str], probe: &str, count: usize, seed: u64) -> Tally {
    use stratapt_cpu::bsdf::ShadingPoint;
    use stratapt_cpu::intersect::Hit;
    use stratapt_scene::Strategy;
    let scene = load_scene("coated.toml");
    let input = cases(count, seed);
    let settings = RenderSettings::default();
    let out = run(&scene, &settings, modules, probe, &input, OUT_STRIDE, count);
    let mut t = Tally::default();
    for i in 0..count {
        let inp = &input[i * IN_STRIDE..];
        let o = &out[i * OUT_STRIDE..];
        let hit = Hit {
            t: 1.0,
            prim: 0,
            p: v3(inp, 0),
            err: Vec3::ZERO,
            ng: v3(inp, 3),
            ns: v3(inp, 6),
            uv: Vec2::ZERO,
        };
        let (wo, wi) = (v3(inp, 9), v3(inp, 12));
        let (u, u_lobe) = (Vec2::new(inp[15], inp[16]), inp[17]);
        let (coated, base) = (material_at(&inp[18..]), material_at(&inp[34..]));
        let sp = ShadingPoint::with_base(&hit, &coated, Some(&base), &scene.tables, wo);
        // At the given directions.
        let mut same = t.flag("is_delta", i, o[0], sp.bsdf.is_delta());
        let mut agree = same;
        let f = sp.eval(wo, wi);
        let (a, s) = t.value("eval", i, &o[1..4], &f.to_array(), 1.0);
        (agree, same) = (agree && a, same && s);
        if !a {
            t.example(format!("#{i} eval: gpu {:?} cpu {f}", &o[1..4]));
        }
        for (si, strategy) in Strategy::ALL.into_iter().enumerate() {
            let pdf = sp.pdf(wo, wi, strategy);
            let q = &o[4 + si * 14..];
            let (a, s) = t.value(&format!("pdf {strategy}"), i, &q[..1], &[pdf], 1.0);
            (agree, same) = (agree && a, same && s);
            if !a {
                t.example(format!("#{i} pdf {strategy}: gpu {} cpu {pdf}", q[0]));
            }
        }
        t.diverged += usize::from(!agree);
        // The samples.
        for (si, strategy) in Strategy::ALL.into_iter().enumerate() {
            let q = &o[4 + si * 14..];
            let s = sp.sample(wo, u, u_lobe, strategy);
            t.samples += 1;
            let valid = t.flag(&format!("sample {strategy} valid"), i, q[1], s.is_some());
            same &= valid;
            let Some(s) = s.filter(|_| valid && q[1] != 0.0) else {
                t.samples_diverged += usize::from(!valid);
                continue;
            };
            let wi = s.wi.to_array();
            // The direction the estimate at it is keyed by: in the shading frame.
            let local = sp.bsdf.sample(sp.frame.to_local(wo), u, u_lobe, strategy);
            let local = local.map_or(Vec3::NAN, |l| l.wi).to_array();
            let rekeyed = q[11..14]
                .iter()
                .zip(&local)
                .any(|(g, c)| g.to_bits() != c.to_bits());
            let (wi_agrees, wi_same) =
                t.value(&format!("sample {strategy} wi"), i, &q[2..5], &wi, 1.0);
            let delta_same = t.flag(&format!("sample {strategy} delta"), i, q[10], s.delta);
            // As bsdf.rs: weights and pdfs at grazing cos θi carry a larger relative error.
            let cos_i = sp.frame.to_local(s.wi).z.abs();
            let widen = (1e-2 / cos_i).max(1e-3 / (cos_i * cos_i)).max(1.0);
            let key = |v: &str| match rekeyed {
                true => format!("sample {strategy} {v} (re-keyed)"),
                false => format!("sample {strategy} {v}"),
            };
            let weight = s.weight.to_array();
            let w = t.value(&key("weight"), i, &q[5..8], &weight, widen);
            let p = t.value(&key("pdf"), i, &q[8..9], &[s.pdf], widen);
            let e = t.value(&key("eta"), i, &q[9..10], &[s.eta], 1.0);
            same &= wi_same && delta_same && w.1 && p.1 && e.1;
            if rekeyed {
                t.rekeyed += 1;
                t.rekeyed_beyond += usize::from(!(w.0 && p.0));
            }
            let ok = wi_agrees && delta_same && e.0 && (rekeyed || w.0 && p.0);
            if !ok {
                t.samples_diverged += 1;
                t.example(format!(
                    "#{i} sample {strategy} (cos θi {cos_i}): gpu wi {:?} weight {:?} pdf {} \
                     delta {}, cpu {s:?}",
                    &q[2..5],
                    &q[5..8],
                    q[8],
                    q[10]
                ));
            }
        }
        t.cases += 1;
        t.identical += usize::from(same);
    }
    t
}

const MODULES: [&str; 5] = ["frame", "warp", "motion", "intersect", "bsdf"];

#[test]
fn layered_bsdfs_match_cpu() {
    let t = compare(&MODULES, LAYERED_PROBE, 20_000, 11);
    t.report("layered");
    let list = t.examples.join("\n");
    assert!(
        t.fraction(t.diverged, t.cases) < DIVERGED_BAR,
        "{} of {} cases diverge at the given directions:\n{list}",
        t.diverged,
        t.cases,
    );
    assert!(
        t.fraction(t.samples_diverged, t.samples) < DIVERGED_BAR,
        "{} of {} samples diverge:\n{list}",
        t.samples_diverged,
        t.samples,
    );
}

/// The `bsdf` module with `from` replaced by `to` in its source, composed from its needs.
fn planted(from: &str, to: &str) -> (Vec<&'static str>, String) {
    let module = stratapt_gpu::testing::MODULES
        .iter()
        .find(|m| m.stem == "bsdf")
        .expect("bsdf module");
    assert_eq!(module.source.matches(from).count(), 1, "plant `{from}`");
    let mut needs = module.needs().expect("needs");
    needs.push("motion");
    let source = module.source.replace(from, to);
    (needs, format!("{source}\n{LAYERED_PROBE}"))
}

/// The comparison catches a sign error in the phase function and a walk that draws its
/// numbers in another order: either diverges in far more cases than the bar allows.
#[test]
fn a_planted_layered_error_diverges() {
    let plants = [
        (
            "let denom = 1.0 + g * g + 2.0 * g * cos_theta;",
            "let denom = 1.0 + g * g - 2.0 * g * cos_theta;",
        ),
        (
            "_ = bsdf_layered_next(rng);\n        let u = bsdf_layered_u2(rng);",
            "let u = bsdf_layered_u2(rng);\n        _ = bsdf_layered_next(rng);",
        ),
    ];
    for (from, to) in plants {
        let (modules, probe) = planted(from, to);
        let t = compare(&modules, &probe, 3000, 12);
        t.report(&format!("planted `{to}`"));
        assert!(
            t.fraction(t.diverged, t.cases) > 5.0 * DIVERGED_BAR,
            "planted `{to}`: only {} of {} cases diverge",
            t.diverged,
            t.cases
        );
    }
}
