//! The layered BSDF (pbrt-v4's `LayeredBxDF`, [`stratapt_cpu::bsdf::layered`]) against what it
//! estimates: a brute-force simulation of the physical slab, energy conservation, reciprocity,
//! the agreement of its three estimators with each other, its closed-form limits, and its
//! numerical edges. Each statistical comparison is a z-test with both standard errors and has
//! a planted error it must reject; every test prints its figures (`--nocapture`).
//!
//! The quantity compared is mostly the directional albedo `∫ f cos θi dωi` from `wo`, in red:
//! the mean `sample` weight under [`Lobe::Bsdf`] (delta lobes included), or `2π · eval` at
//! uniform directions (delta lobes excluded; a smooth coat's mirror adds `F(θo)`).

use glam::{DVec3, Vec2, Vec3};
use std::f64::consts::TAU;
use stratapt_cpu::bsdf::conductor::{Conductor, Fresnel};
use stratapt_cpu::bsdf::dielectric::fresnel;
use stratapt_cpu::bsdf::diffuse::Diffuse;
use stratapt_cpu::bsdf::layered::{Base, Coat, Layered};
use stratapt_cpu::bsdf::plastic::Plastic;
use stratapt_cpu::bsdf::rough_dielectric::RoughDielectric;
use stratapt_cpu::bsdf::Lobe;
use stratapt_sampling::testing::chi2::{
    accept, density_bins, fit, reject, Family, Plant, Refusals,
};
use stratapt_sampling::testing::TestRng;
use stratapt_sampling::warp;
use stratapt_sampling::warp::ggx::Masking;

// ---------------------------------------------------------------------------------------------
// Estimates and the configurations they are taken of.
// ---------------------------------------------------------------------------------------------

/// Running sums of a Monte Carlo estimate.
#[derive(Default)]
struct Sums {
    sum: f64,
    sum_sq: f64,
    n: usize,
}

impl Sums {
    fn add(&mut self, v: f64) {
        self.sum += v;
        self.sum_sq += v * v;
        self.n += 1;
    }

    fn estimate(&self) -> Estimate {
        let n = self.n as f64;
        let mean = self.sum / n;
        let se = ((self.sum_sq / n - mean * mean).max(0.0) / n).sqrt();
        Estimate { mean, se }
    }
}

/// A Monte Carlo mean and its standard error.
#[derive(Clone, Copy, Debug)]
struct Estimate {
    mean: f64,
    se: f64,
}

impl Estimate {
    fn of(n: usize, mut value: impl FnMut() -> f64) -> Self {
        let mut sums = Sums::default();
        (0..n).for_each(|_| sums.add(value()));
        sums.estimate()
    }

    fn exact(mean: f64) -> Self {
        Self { mean, se: 0.0 }
    }

    /// The z statistic of `self − other`.
    fn z(self, other: Self) -> f64 {
        let se = (self.se * self.se + other.se * other.se).sqrt();
        (self.mean - other.mean) / se.max(1e-12)
    }

    fn scaled(self, k: f64) -> Self {
        Self {
            mean: self.mean * k,
            se: self.se * k.abs(),
        }
    }

    fn plus(self, x: f64) -> Self {
        Self {
            mean: self.mean + x,
            ..self
        }
    }
}

impl std::fmt::Display for Estimate {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "{:.5} ± {:.5}", self.mean, self.se)
    }
}

/// The critical |z| of every comparison here (two-sided 6·10⁻⁵ each; ~60 comparisons).
const Z: f64 = 4.0;

fn wo_at(cos: f32, phi: f32) -> Vec3 {
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    Vec3::new(sin * phi.cos(), sin * phi.sin(), cos)
}

fn lambert(albedo: f32) -> Base {
    Base::Diffuse(Diffuse {
        albedo: Vec3::new(albedo, 0.5 * albedo, 0.25),
    })
}

fn rough_conductor(alpha: f32) -> Base {
    Base::Conductor(Conductor::new(
        Fresnel::Schlick(Vec3::new(0.9, 0.6, 0.3)),
        alpha,
        alpha,
    ))
}

fn rough_coat(eta: f32, alpha: Vec2) -> Coat {
    Coat::Rough(RoughDielectric {
        eta,
        tint: Vec3::ONE,
        alpha,
        masking: Masking::Correlated,
    })
}

/// A layered BSDF with a slab of `thickness`, `albedo` (grey) and `g`, walks of `max_depth`.
fn layered(coat: Coat, base: Base, thickness: f32, albedo: f32, g: f32, depth: u32) -> Layered {
    Layered {
        thickness,
        albedo: Vec3::splat(albedo),
        g,
        max_depth: depth,
        ..Layered::new(coat, base)
    }
}

/// The smooth coat's mirror reflectance from `wo` (what `eval` leaves out), 0 for a rough coat.
fn mirror(l: &Layered, wo: Vec3) -> f64 {
    match l.coat {
        Coat::Smooth { eta } => f64::from(fresnel(wo.z, eta)),
        Coat::Rough(_) => 0.0,
    }
}

/// The directional albedo as the mean `sample` weight under `lobe`.
fn sampled_albedo(l: &Layered, wo: Vec3, lobe: Lobe, n: usize, seed: u64) -> Estimate {
    let mut rng = TestRng(seed);
    Estimate::of(n, || {
        let u = rng.u2();
        l.sample(wo, u, rng.f32(), lobe)
            .map_or(0.0, |s| f64::from(s.weight.x))
    })
}

/// The directional albedo without delta lobes, `∫ eval dωi` by uniform directions.
fn evaluated_albedo(l: &Layered, wo: Vec3, n: usize, seed: u64) -> Estimate {
    let mut rng = TestRng(seed);
    Estimate::of(n, || {
        let wi = warp::uniform_hemisphere(rng.u2());
        f64::from(l.eval(wo, wi).x) * TAU
    })
}

// ---------------------------------------------------------------------------------------------
// The physical slab, photon by photon.
// ---------------------------------------------------------------------------------------------

fn uniform(rng: &mut TestRng) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Snell's law into a smooth coat of relative index `eta` from `wo` above it.
fn refract_down(wo: DVec3, eta: f64) -> DVec3 {
    let sin2_t = (1.0 - wo.z * wo.z) / (eta * eta);
    DVec3::new(-wo.x / eta, -wo.y / eta, -(1.0 - sin2_t).max(0.0).sqrt()).normalize()
}

/// A Henyey–Greenstein deflection of the travel direction `d`: the cosine between the old and
/// the new direction by the textbook inversion (g > 0 forward).
fn henyey_greenstein(d: DVec3, g: f64, rng: &mut TestRng) -> DVec3 {
    let xi = uniform(rng);
    let mu = if g.abs() < 1e-3 {
        1.0 - 2.0 * xi
    } else {
        let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * xi);
        (1.0 + g * g - s * s) / (2.0 * g)
    };
    let phi = TAU * uniform(rng);
    let a = if d.x.abs() > 0.9 { DVec3::Y } else { DVec3::X };
    let t = d.cross(a).normalize();
    let b = d.cross(t);
    let sin = (1.0 - mu * mu).max(0.0).sqrt();
    (t * (sin * phi.cos()) + b * (sin * phi.sin()) + d * mu).normalize()
}

/// One photon of light arriving from `wo`: the flux that leaves, and whether it left by delta
/// events only (the smooth coat's mirror; a smooth coat over a mirror without a medium event),
/// which `eval` leaves out. The walk, Snell's law, the free flights (σt = 1) and the scattering
/// are written here; the Fresnel factor, the rough interfaces and the conductor are strata's
/// components (a refraction's flux is the radiance weight times η²).
fn photon(l: &Layered, wo: DVec3, rng: &mut TestRng) -> (f64, bool) {
    let (flux, d) = match l.coat {
        Coat::Smooth { eta } => {
            let f = f64::from(fresnel(wo.z as f32, eta));
            if uniform(rng) < f {
                return (1.0, true);
            }
            (1.0, refract_down(wo, f64::from(eta)))
        }
        Coat::Rough(r) => {
            let Some(s) = r.sample(wo.as_vec3(), rng.u2(), rng.f32(), Lobe::Bsdf) else {
                return (0.0, false);
            };
            if s.wi.z > 0.0 {
                return (f64::from(s.weight.x), false);
            }
            let flux = f64::from(s.weight.x * s.eta * s.eta);
            (flux, s.wi.as_dvec3().normalize())
        }
    };
    let (left, delta) = inside(l, d, rng);
    (flux * left, delta && matches!(l.coat, Coat::Smooth { .. }))
}

/// The fraction of a photon travelling `d` just below the coat that leaves through it, and
/// whether it met only the smooth coat and a mirror base.
fn inside(l: &Layered, mut d: DVec3, rng: &mut TestRng) -> (f64, bool) {
    let thickness = f64::from(l.thickness);
    let (albedo, g) = (f64::from(l.albedo.x), f64::from(l.g));
    let (mut z, mut flux, mut delta) = (thickness, 1.0, true);
    for _ in 0..100_000 {
        // Free flight to a collision or to the interface ahead.
        let to_boundary = if d.z < 0.0 {
            z / -d.z
        } else {
            (thickness - z) / d.z
        };
        let s = -(1.0 - uniform(rng)).ln();
        if s < to_boundary {
            flux *= albedo;
            if flux == 0.0 {
                return (0.0, false);
            }
            z += s * d.z;
            d = henyey_greenstein(d, g, rng);
            delta = false;
        } else if d.z < 0.0 {
            z = 0.0;
            match l.base {
                Base::Diffuse(b) => {
                    flux *= f64::from(b.albedo.x);
                    // Cosine-weighted: √u for the sine, uniform azimuth.
                    let (r, phi) = (uniform(rng).sqrt(), TAU * uniform(rng));
                    d = DVec3::new(r * phi.cos(), r * phi.sin(), (1.0 - r * r).max(0.0).sqrt());
                    delta = false;
                }
                Base::Conductor(c) => {
                    let Some(s) = c.sample((-d).as_vec3(), rng.u2(), Lobe::Bsdf) else {
                        return (0.0, false);
                    };
                    flux *= f64::from(s.weight.x);
                    d = s.wi.as_dvec3().normalize();
                    delta &= s.delta;
                }
            }
        } else {
            z = thickness;
            match l.coat {
                Coat::Smooth { eta } => {
                    let f = f64::from(fresnel(d.z as f32, 1.0 / eta));
                    if uniform(rng) >= f {
                        return (flux, delta);
                    }
                    d.z = -d.z;
                }
                Coat::Rough(r) => {
                    // Seen from inside: the index inverted, directions through the origin.
                    let inner = RoughDielectric {
                        eta: 1.0 / r.eta,
                        ..r
                    };
                    let Some(s) = inner.sample(d.as_vec3(), rng.u2(), rng.f32(), Lobe::Bsdf) else {
                        return (0.0, false);
                    };
                    if s.wi.z < 0.0 {
                        return (flux * f64::from(s.weight.x * s.eta * s.eta), false);
                    }
                    flux *= f64::from(s.weight.x);
                    d = -s.wi.as_dvec3().normalize();
                }
            }
        }
        // Russian roulette on a faint photon.
        if flux < 0.1 {
            if uniform(rng) < 0.5 {
                return (0.0, false);
            }
            flux *= 2.0;
        }
    }
    (0.0, false)
}

/// The simulation's albedo from `wo`, all of it and the part without delta paths.
fn simulated_albedo(l: &Layered, wo: Vec3, n: usize, seed: u64) -> (Estimate, Estimate) {
    let mut rng = TestRng(seed);
    let wo = wo.as_dvec3().normalize();
    let (mut all, mut non_delta) = (Sums::default(), Sums::default());
    for _ in 0..n {
        let (flux, delta) = photon(l, wo, &mut rng);
        all.add(flux);
        non_delta.add(if delta { 0.0 } else { flux });
    }
    (all.estimate(), non_delta.estimate())
}

// ---------------------------------------------------------------------------------------------
// 1. Unbiased against the physical slab.
// ---------------------------------------------------------------------------------------------

/// The slabs of the brute-force comparison (walks of 200 events), each with the error planted in
/// it: the slab's albedo 1 % high (2 % where the slab matters less), a clear slab 10 % thicker.
fn slabs() -> Vec<(&'static str, Layered, Layered)> {
    let (smooth, rough) = (|eta| Coat::Smooth { eta }, rough_coat);
    let cases = [
        (
            "smooth η 1.5 / Lambert 0.8, slab 0.5 albedo 0.9 g 0.5",
            layered(smooth(1.5), lambert(0.8), 0.5, 0.9, 0.5, 200),
            1.01,
        ),
        (
            "smooth η 1.33 / conductor α 0.3, slab 1 albedo 0.95 g −0.3",
            layered(smooth(1.33), rough_conductor(0.3), 1.0, 0.95, -0.3, 200),
            1.01,
        ),
        (
            "smooth η 1.5 / mirror, slab 0.5 albedo 0.9 g 0.5",
            layered(smooth(1.5), rough_conductor(0.0), 0.5, 0.9, 0.5, 200),
            1.01,
        ),
        (
            "rough η 1.5 α 0.3 / Lambert 0.8, clear slab 0.2",
            layered(
                rough(1.5, Vec2::splat(0.3)),
                lambert(0.8),
                0.2,
                0.0,
                0.0,
                200,
            ),
            1.1,
        ),
        (
            "rough η 1.4 α 0.5 / conductor α 0.2, slab 1 albedo 0.8 g 0.8",
            layered(
                rough(1.4, Vec2::splat(0.5)),
                rough_conductor(0.2),
                1.0,
                0.8,
                0.8,
                200,
            ),
            1.02,
        ),
    ];
    cases
        .into_iter()
        .map(|(name, l, k)| {
            let planted = match l.albedo == Vec3::ZERO {
                true => Layered {
                    thickness: l.thickness * k,
                    ..l
                },
                false => Layered {
                    albedo: l.albedo * k,
                    ..l
                },
            };
            (name, l, planted)
        })
        .collect()
}

/// `sample` estimates the albedo the photons measure, `eval` the part of it without delta paths;
/// the same layered BSDF with the planted error is rejected by both.
#[test]
fn the_estimators_agree_with_a_brute_force_simulation_of_the_slab() {
    let n = 400_000;
    for (k, (name, l, planted)) in slabs().into_iter().enumerate() {
        for (j, cos) in [0.35f32, 0.9].into_iter().enumerate() {
            let wo = wo_at(cos, 0.7);
            let seed = 100 * k as u64 + 10 * j as u64;
            let (all, non_delta) = simulated_albedo(&l, wo, n, seed);
            let sampled = sampled_albedo(&l, wo, Lobe::Bsdf, n, seed + 1);
            let evaluated = evaluated_albedo(&l, wo, n, seed + 2);
            let wrong_sampled = sampled_albedo(&planted, wo, Lobe::Bsdf, n, seed + 1);
            let wrong_evaluated = evaluated_albedo(&planted, wo, n, seed + 2);
            let (zs, ze) = (sampled.z(all), evaluated.z(non_delta));
            let (ps, pe) = (wrong_sampled.z(all), wrong_evaluated.z(non_delta));
            println!(
                "{name}, cos θo {cos}: photons {all}, sample {sampled} (z {zs:.2}); photons \
                 without delta paths {non_delta}, eval {evaluated} (z {ze:.2}); planted: sample \
                 z {ps:.1}, eval z {pe:.1}"
            );
            assert!(zs.abs() < Z && ze.abs() < Z, "{name} cos {cos}");
            let rejected = ps.abs() > Z && pe.abs() > Z;
            assert!(rejected, "{name} cos {cos}: planted error accepted");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 2. Energy.
// ---------------------------------------------------------------------------------------------

/// A white furnace: a coat that absorbs nothing over a white Lambertian base, the slab clear
/// (thickness 10⁻⁶) or scattering without absorption (albedo 1), returns at most the light that
/// falls on it, and with walks of 1000 events all of it; what pbrt's default of 10 events loses
/// is printed. A rough coat loses what its microfacets scatter more than once (single-scattering
/// GGX), so it is only bounded. Planted: a base of albedo 1.02 is caught gaining energy.
#[test]
fn a_white_furnace_returns_the_light_that_falls_when_the_walk_is_long() {
    let white = Base::Diffuse(Diffuse { albedo: Vec3::ONE });
    let rough = rough_coat(1.5, Vec2::splat(0.3));
    let n = 100_000;
    for (name, coat, thickness, albedo, g) in [
        (
            "smooth η 1.5, clear slab",
            Coat::Smooth { eta: 1.5 },
            1e-6,
            0.0,
            0.0,
        ),
        (
            "smooth η 1.5, white slab 0.5 g 0.3",
            Coat::Smooth { eta: 1.5 },
            0.5,
            1.0,
            0.3,
        ),
        (
            "smooth η 2.5, clear slab",
            Coat::Smooth { eta: 2.5 },
            1e-6,
            0.0,
            0.0,
        ),
        ("rough η 1.5 α 0.3, clear slab", rough, 1e-6, 0.0, 0.0),
    ] {
        for (j, cos) in [0.1f32, 0.5, 1.0].into_iter().enumerate() {
            let wo = wo_at(cos, 0.0);
            let (mut long, mut short) = (Vec::new(), Vec::new());
            for (depth, out) in [(1000, &mut long), (10, &mut short)] {
                let l = layered(coat, white, thickness, albedo, g, depth);
                let sampled = sampled_albedo(&l, wo, Lobe::Bsdf, n, j as u64);
                let evaluated = evaluated_albedo(&l, wo, n, 10 + j as u64).plus(mirror(&l, wo));
                for e in [sampled, evaluated] {
                    assert!(e.mean <= 1.0 + 3.0 * e.se + 1e-6, "{name} cos {cos}: {e}");
                }
                out.extend([sampled, evaluated]);
            }
            println!(
                "{name}, cos θo {cos}: 1000 events: sample {}, eval {}; 10 events: sample {} \
                 (loses {:.1} %), eval {} (loses {:.1} %)",
                long[0],
                long[1],
                short[0],
                100.0 * (1.0 - short[0].mean),
                short[1],
                100.0 * (1.0 - short[1].mean)
            );
            if let Coat::Smooth { .. } = coat {
                for e in &long {
                    assert!(
                        (e.mean - 1.0).abs() < Z * e.se + 1e-3,
                        "{name} cos {cos}: {e}"
                    );
                }
            }
        }
    }
    // Planted: a base that reflects 2 % more than it receives.
    let gaining = Base::Diffuse(Diffuse {
        albedo: Vec3::splat(1.02),
    });
    let l = layered(Coat::Smooth { eta: 1.5 }, gaining, 1e-6, 0.0, 0.0, 1000);
    let e = sampled_albedo(&l, wo_at(0.5, 0.0), Lobe::Bsdf, n, 3);
    println!(
        "planted base albedo 1.02: {e} ({:.1} σ above 1)",
        (e.mean - 1.0) / e.se
    );
    assert!(e.mean > 1.0 + 3.0 * e.se, "a gaining base passes: {e}");
}

// ---------------------------------------------------------------------------------------------
// 3. Reciprocity.
// ---------------------------------------------------------------------------------------------

/// `f(wo, wi) = f(wi, wo)` in expectation: `eval` is deterministic in its directions, so the
/// estimates are averaged over its seed ([`Layered::eval_seeded`]); the two means agree, and a
/// 3 % asymmetry planted in one of them is rejected.
#[test]
fn eval_is_reciprocal_in_expectation() {
    let m = 120_000;
    let configurations = [
        (
            "rough η 1.5 α 0.3 / Lambert, slab 0.5 albedo 0.8 g 0.6",
            layered(
                rough_coat(1.5, Vec2::splat(0.3)),
                lambert(0.8),
                0.5,
                0.8,
                0.6,
                100,
            ),
        ),
        (
            "smooth η 1.5 / conductor α 0.3, slab 0.3 albedo 0.9 g −0.5",
            layered(
                Coat::Smooth { eta: 1.5 },
                rough_conductor(0.3),
                0.3,
                0.9,
                -0.5,
                100,
            ),
        ),
        (
            "rough η 1.3 α (0.1, 0.4) / conductor α 0.4, clear slab 0.1",
            layered(
                rough_coat(1.3, Vec2::new(0.1, 0.4)),
                rough_conductor(0.4),
                0.1,
                0.0,
                0.0,
                100,
            ),
        ),
    ];
    let pairs = [
        (wo_at(0.9, 0.3), wo_at(0.4, 2.5)),
        (wo_at(0.6, 0.0), wo_at(0.25, 1.0)),
    ];
    for (name, l) in configurations {
        for (wo, wi) in pairs {
            let mut seed = 0;
            let forward = Estimate::of(m, || {
                seed += 1;
                f64::from(l.eval_seeded(wo, wi, seed).x / wi.z)
            });
            let backward = Estimate::of(m, || {
                seed += 1;
                f64::from(l.eval_seeded(wi, wo, seed).x / wo.z)
            });
            let (z, planted) = (forward.z(backward), forward.z(backward.scaled(1.03)));
            println!(
                "{name}, cos θ {:.2} ↔ {:.2}: f(wo, wi) {forward}, f(wi, wo) {backward} (z {z:.2}; \
                 3 % planted: z {planted:.1})",
                wo.z, wi.z
            );
            assert!(z.abs() < Z, "{name}: {forward} vs {backward}");
            assert!(planted.abs() > Z, "{name}: a 3 % asymmetry passes");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 4. sample, eval and pdf agree.
// ---------------------------------------------------------------------------------------------

/// The mean `sample` weight under each strategy equals `∫ eval dωi` plus the smooth coat's
/// mirror (over a mirror base, whose specular walks `eval` leaves out, the strategies are
/// compared with each other); `eval` 2.5 % high is rejected. A non-delta sample's `pdf` is
/// exactly [`Layered::pdf`] at its direction (the integrator's MIS weights need both to be the
/// same number), a delta one's is positive.
#[test]
fn sample_eval_and_pdf_agree() {
    let n = 200_000;
    let configurations = [
        (
            "rough η 1.5 α 0.3 / Lambert 0.7, slab 0.3 albedo 0.8 g 0.4",
            layered(
                rough_coat(1.5, Vec2::splat(0.3)),
                lambert(0.7),
                0.3,
                0.8,
                0.4,
                100,
            ),
        ),
        (
            "rough η 1.5 α (0.1, 0.4) / conductor α 0.2, clear slab 0.05",
            layered(
                rough_coat(1.5, Vec2::new(0.1, 0.4)),
                rough_conductor(0.2),
                0.05,
                0.0,
                0.0,
                100,
            ),
        ),
        (
            "smooth η 1.5 / Lambert 0.7, slab 0.3 albedo 0.5 g −0.2",
            layered(Coat::Smooth { eta: 1.5 }, lambert(0.7), 0.3, 0.5, -0.2, 100),
        ),
        (
            "smooth η 1.5 / mirror conductor, slab 0.5 albedo 0.9 g 0.5",
            layered(
                Coat::Smooth { eta: 1.5 },
                rough_conductor(0.0),
                0.5,
                0.9,
                0.5,
                100,
            ),
        ),
    ];
    for (k, (name, l)) in configurations.into_iter().enumerate() {
        for (j, cos) in [0.3f32, 0.8].into_iter().enumerate() {
            let wo = wo_at(cos, 1.1);
            let seed = 1000 * k as u64 + 100 * j as u64;
            let bsdf = sampled_albedo(&l, wo, Lobe::Bsdf, n, seed);
            let uniform = sampled_albedo(&l, wo, Lobe::Uniform, n, seed + 1);
            let cosine = sampled_albedo(&l, wo, Lobe::Cosine, n, seed + 2);
            let (zu, zc) = (uniform.z(bsdf), cosine.z(bsdf));
            let mut line = format!(
                "{name}, cos θo {cos}: bsdf {bsdf}, uniform {uniform} (z {zu:.2}), cosine \
                 {cosine} (z {zc:.2})"
            );
            assert!(zu.abs() < Z && zc.abs() < Z, "{line}");
            if !matches!(l.base, Base::Conductor(c) if c.is_mirror()) {
                let evaluated = evaluated_albedo(&l, wo, n, seed + 3).plus(mirror(&l, wo));
                let (z, planted) = (evaluated.z(bsdf), evaluated.scaled(1.025).z(bsdf));
                line += &format!(", ∫ eval {evaluated} (z {z:.2}; 2.5 % planted: z {planted:.1})");
                assert!(z.abs() < Z, "{line}");
                assert!(planted.abs() > Z, "{line}: planted error accepted");
            }
            println!("{line}");
            // The sample's density is the pdf the integrator asks for.
            let mut rng = TestRng(seed + 4);
            for _ in 0..2000 {
                let u = rng.u2();
                let Some(s) = l.sample(wo, u, rng.f32(), Lobe::Bsdf) else {
                    continue;
                };
                match s.delta {
                    true => assert!(s.pdf > 0.0, "{s:?}"),
                    false => assert_eq!(s.pdf, l.pdf(wo, s.wi, Lobe::Bsdf), "{s:?}"),
                }
            }
        }
    }
}

/// This file's chi-square tests: family-wise significance 0.01 over at most 8 fits.
const FAMILY: Family = Family {
    alpha: 0.01,
    tests: 8,
};

/// The uniform and cosine strategies draw what their `pdf` says (delta samples, and walks
/// that did not stay specular, in the refusal cell), histogrammed over the sphere in
/// `(φ / 2π, √((1 − cos θ) / 2))` as `bsdf_chi2.rs` does. Planted wrong pdfs are rejected: the
/// smooth coat's with a 5 % wrong index (its mirror probability), the other strategy's. Under
/// [`Lobe::Bsdf`] `pdf` is pbrt's estimate, not the density of `sample` (see the module doc),
/// so no chi-square is run there.
#[test]
fn hemisphere_strategies_sample_their_pdf() {
    const NX: usize = 16;
    const NY: usize = 32;
    const N: usize = 200_000;
    let smooth = layered(Coat::Smooth { eta: 1.5 }, lambert(0.7), 0.1, 0.0, 0.0, 20);
    let rough = layered(
        rough_coat(1.5, Vec2::splat(0.3)),
        lambert(0.7),
        0.1,
        0.5,
        0.0,
        20,
    );
    let mirror = layered(
        Coat::Smooth { eta: 1.5 },
        rough_conductor(0.0),
        0.3,
        0.9,
        0.3,
        20,
    );
    let wrong_index = |l: Layered| Layered {
        coat: Coat::Smooth { eta: 1.575 },
        ..l
    };
    let cases = [
        (
            "smooth / Lambert, uniform",
            smooth,
            Lobe::Uniform,
            wrong_index(smooth),
            Lobe::Uniform,
        ),
        (
            "smooth / Lambert, cosine",
            smooth,
            Lobe::Cosine,
            smooth,
            Lobe::Uniform,
        ),
        (
            "rough / Lambert, cosine",
            rough,
            Lobe::Cosine,
            rough,
            Lobe::Uniform,
        ),
        (
            "smooth / mirror, uniform",
            mirror,
            Lobe::Uniform,
            wrong_index(mirror),
            Lobe::Uniform,
        ),
    ];
    let wo = wo_at(0.5, 0.4);
    let coordinates = |wi: Vec3| {
        let (z, sin2) = (f64::from(wi.z), f64::from(wi.x * wi.x + wi.y * wi.y));
        let one_minus_cos = if z > 0.0 { sin2 / (1.0 + z) } else { 1.0 - z };
        let phi = f64::from(wi.y).atan2(f64::from(wi.x)).rem_euclid(TAU) / TAU;
        [phi, (0.5 * one_minus_cos).sqrt()]
    };
    let probabilities = |l: &Layered, lobe: Lobe| {
        let density = |x: f64, y: f64| {
            let cos = 1.0 - 2.0 * y * y;
            let sin = (1.0 - cos * cos).max(0.0).sqrt();
            let wi = DVec3::new(sin * (TAU * x).cos(), sin * (TAU * x).sin(), cos).as_vec3();
            f64::from(l.pdf(wo, wi, lobe)) * 4.0 * TAU * y
        };
        density_bins(&density, NX, NY)
    };
    let (mut fits, mut planted) = (Vec::new(), Vec::new());
    for (i, (name, l, lobe, wrong, wrong_lobe)) in cases.into_iter().enumerate() {
        let mut rng = TestRng(500 + i as u64);
        let samples: Vec<_> = (0..N)
            .map(|_| {
                let u = rng.u2();
                l.sample(wo, u, rng.f32(), lobe)
                    .filter(|s| !s.delta)
                    .map(|s| coordinates(s.wi))
            })
            .collect();
        let right = probabilities(&l, lobe);
        let wrong = probabilities(&wrong, wrong_lobe);
        let samples = || samples.iter().copied();
        let refusals = Refusals::Allowed;
        fits.push(fit(
            &FAMILY,
            name,
            samples(),
            &right,
            NX,
            NY,
            refusals,
            Plant::None,
        ));
        let label = format!("{name}, planted wrong pdf");
        planted.push(fit(
            &FAMILY,
            &label,
            samples(),
            &wrong,
            NX,
            NY,
            refusals,
            Plant::None,
        ));
    }
    accept(fits);
    reject(planted, "");
}

// ---------------------------------------------------------------------------------------------
// 5. Limits with closed forms.
// ---------------------------------------------------------------------------------------------

/// The hemispherical reflectance of a smooth coat's inside, `2 ∫₀¹ F(μ, 1/η) μ dμ` (midpoint
/// rule, 10⁵ nodes).
fn internal_reflectance(eta: f32) -> f64 {
    let n = 100_000;
    let sum: f64 = (0..n)
        .map(|i| {
            let mu = (i as f64 + 0.5) / n as f64;
            f64::from(fresnel(mu as f32, 1.0 / eta)) * mu
        })
        .sum();
    2.0 * sum / n as f64
}

/// A smooth coat over a Lambertian base with nothing between them (thickness 10⁻⁶, albedo 0) is
/// Mitsuba's `plastic` with `nonlinear` and the exact internal reflectance F̄:
/// `f cos θi = T(θo) T(θi) ρ cos θi / (π η² (1 − ρ F̄))`, here strata's [`Plastic`] given F̄ by
/// quadrature. The mean of `eval` over seeds agrees at 100 events; the closed form 1 % high is
/// rejected. What 10 events (pbrt's default) lose is printed: the internal bounces past the
/// fifth, `(ρ F̄)⁵` of the base's light.
#[test]
fn a_thin_clear_smooth_coat_over_lambert_is_the_nonlinear_plastic() {
    let m = 1_000_000;
    let pairs = [
        (wo_at(0.9, 0.2), wo_at(0.5, 2.0)),
        (wo_at(0.3, 0.0), wo_at(0.7, 3.0)),
    ];
    for (eta, rho) in [(1.5f32, 0.8f32), (1.2, 0.5), (2.0, 0.6)] {
        let internal = internal_reflectance(eta);
        let plastic = Plastic {
            diffuse: Vec3::splat(rho),
            specular: Vec3::ONE,
            eta,
            internal: internal as f32,
            specular_weight: 0.5,
            nonlinear: true,
            rough: None,
        };
        let base = Base::Diffuse(Diffuse {
            albedo: Vec3::splat(rho),
        });
        for (wo, wi) in pairs {
            // The closed form by hand, and as the plastic computes it.
            let t = |cos: f32| 1.0 - f64::from(fresnel(cos, eta));
            let rho = f64::from(rho);
            let by_hand = t(wo.z) * t(wi.z) * rho * f64::from(wi.z)
                / (std::f64::consts::PI * f64::from(eta * eta) * (1.0 - rho * internal));
            let exact = f64::from(plastic.eval(wo, wi).x);
            assert!((exact / by_hand - 1.0).abs() < 1e-5, "{exact} vs {by_hand}");
            let mut figures = Vec::new();
            for (depth, m) in [(100, m), (10, m / 4)] {
                let l = layered(Coat::Smooth { eta }, base, 1e-6, 0.0, 0.0, depth);
                let mut seed = 0;
                let e = Estimate::of(m, || {
                    seed += 1;
                    f64::from(l.eval_seeded(wo, wi, seed).x)
                });
                figures.push(e);
            }
            let (e, short) = (figures[0], figures[1]);
            let exact = Estimate::exact(exact);
            let (z, planted) = (e.z(exact), e.z(exact.scaled(1.01)));
            println!(
                "η {eta} ρ {rho:.2} F̄ {internal:.5}, cos θ {:.2} → {:.2}: plastic {:.6}, eval \
                 {e} ({:+.3} %, z {z:.2}; closed form 1 % high: z {planted:.1}); 10 events: \
                 {short} ({:+.2} %)",
                wo.z,
                wi.z,
                exact.mean,
                100.0 * (e.mean / exact.mean - 1.0),
                100.0 * (short.mean / exact.mean - 1.0)
            );
            assert!(z.abs() < Z, "η {eta} ρ {rho:.2}: {e} vs {}", exact.mean);
            assert!(planted.abs() > Z, "η {eta} ρ {rho:.2}: 1 % high passes");
        }
    }
}

/// An index-matched coat (η = 1, also a rough one, which pbrt and strata then treat as smooth)
/// over a Lambertian base, with nothing between them, is the base: every walk refracts straight
/// in, connects to `wi` and ends (no internal reflection), so `eval` is the base to rounding and
/// the thin slab's transmittance. At η = 1.0001 it is the base in expectation (a walk whose
/// diffuse bounce is caught by total internal reflection, below cos 0.014, adds a rare second
/// bounce): the mean over seeds is within 10⁻³ at cosines above 0.05.
#[test]
fn an_index_matched_coat_over_lambert_is_the_base() {
    let base = Diffuse {
        albedo: Vec3::new(0.8, 0.4, 0.2),
    };
    let matched = |coat| layered(coat, Base::Diffuse(base), 1e-6, 0.0, 0.0, 100);
    let mut rng = TestRng(8);
    for coat in [Coat::Smooth { eta: 1.0 }, rough_coat(1.0, Vec2::splat(0.3))] {
        let l = matched(coat);
        let mut worst = 0.0f32;
        for _ in 0..2000 {
            let (wo, wi) = (rng.upper(), rng.upper());
            if wo.z > 1e-3 && wi.z > 1e-3 {
                // The base, dimmed by the slab's transmittance down and up.
                let tr = (-1e-6 / wo.z).exp() * (-1e-6 / wi.z).exp();
                let (f, expected) = (l.eval(wo, wi), base.eval(wo, wi) * tr);
                worst = worst.max(((f - expected) / expected).abs().max_element());
            }
        }
        println!("{coat:?}: largest relative difference from the base {worst:.2e}");
        assert!(worst < 1e-5, "{coat:?}: {worst}");
    }
    let l = matched(Coat::Smooth { eta: 1.0001 });
    for _ in 0..8 {
        let (wo, wi) = (rng.upper(), rng.upper());
        if wo.z < 0.05 || wi.z < 0.05 {
            continue;
        }
        let mut seed = 0;
        let e = Estimate::of(20_000, || {
            seed += 1;
            f64::from(l.eval_seeded(wo, wi, seed).x)
        });
        let expected = f64::from(base.eval(wo, wi).x);
        let relative = e.mean / expected - 1.0;
        println!(
            "η 1.0001, cos θ {:.2} → {:.2}: eval {e}, base {expected:.5} ({relative:+.1e})",
            wo.z, wi.z
        );
        assert!(relative.abs() < 1e-3, "{e} vs {expected}");
    }
}

// ---------------------------------------------------------------------------------------------
// 6. Numerical edges.
// ---------------------------------------------------------------------------------------------

/// Every estimate at the edges of its parameters: `wo` from normal to grazing (cos down to
/// 10⁻³⁰, 0, and below the surface: two-sided), `u` and the lobe dimension at 0 and 1 − 2⁻²⁴,
/// thickness 10⁻⁶ … 10³, slab albedo 0 … 1, g ±0.99, η 1.0001 … 3, α 10⁻⁴ … 1, walks of 1 and
/// 10 events (and 0 samples, which count as 1). A sample is refused or finite with a positive
/// pdf on `wo`'s side; `eval` and `pdf` are finite and non-negative.
#[test]
fn every_estimate_is_finite_at_the_edges() {
    let below_one = f32::from_bits(1.0f32.to_bits() - 1);
    let mut coats = Vec::new();
    for eta in [1.0001f32, 1.5, 3.0] {
        coats.push(Coat::Smooth { eta });
        for alpha in [1e-4f32, 0.05, 1.0] {
            coats.push(rough_coat(eta, Vec2::splat(alpha)));
        }
    }
    coats.push(Coat::Rough(RoughDielectric {
        eta: 1.5,
        tint: Vec3::new(1.0, 0.5, 0.0),
        alpha: Vec2::new(0.02, 1.0),
        masking: Masking::Separable,
    }));
    let complex = Fresnel::Complex {
        eta: Vec3::new(0.2, 0.9, 1.1),
        k: Vec3::new(3.9, 2.4, 1.6),
        tint: Vec3::ONE,
    };
    let bases = [
        Base::Diffuse(Diffuse { albedo: Vec3::ONE }),
        Base::Diffuse(Diffuse { albedo: Vec3::ZERO }),
        Base::Conductor(Conductor::new(Fresnel::Schlick(Vec3::ONE), 0.0, 0.0)),
        Base::Conductor(Conductor::new(complex, 1e-4, 0.3)),
        Base::Conductor(Conductor::new(complex, 1.0, 1.0)),
    ];
    let slabs = [
        (0.0, 0.0),
        (0.5, -0.99),
        (0.5, 0.99),
        (1.0, -0.99),
        (1.0, 0.99),
    ];
    let directions = |cos: f32| {
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        Vec3::new(sin * 0.6, sin * 0.8, cos)
    };
    let cosines = [1.0, 0.5, 1e-3, 1e-7, 1e-30, 0.0, -0.5];
    let (us, u_lobes) = ([0.0, below_one], [0.0, 0.5, below_one]);
    let (mut samples, mut refused) = (0u64, 0u64);
    for (c, &coat) in coats.iter().enumerate() {
        for base in bases {
            for thickness in [1e-6, 0.01, 1e3] {
                for (albedo, g) in slabs {
                    for depth in [1, 10] {
                        let l = Layered {
                            samples: (c % 3) as u32,
                            ..layered(coat, base, thickness, albedo, g, depth)
                        };
                        for cos in cosines {
                            let wo = directions(cos);
                            for wi in cosines.map(|c| Vec3::new(0.3, -0.1, 0.0) + directions(c)) {
                                let wi = wi.normalize();
                                let f = l.eval(wo, wi);
                                let ok = f.is_finite() && f.min_element() >= 0.0;
                                assert!(ok, "{l:?} wo {wo} wi {wi}: eval {f}");
                                for lobe in [Lobe::Bsdf, Lobe::Uniform, Lobe::Cosine] {
                                    let p = l.pdf(wo, wi, lobe);
                                    let ok = p.is_finite() && p >= 0.0;
                                    assert!(ok, "{l:?} wo {wo} wi {wi} {lobe:?}: pdf {p}");
                                }
                            }
                            for lobe in [Lobe::Bsdf, Lobe::Uniform, Lobe::Cosine] {
                                for (ux, uy, u_lobe) in us
                                    .iter()
                                    .flat_map(|&x| us.map(|y| (x, y)))
                                    .flat_map(|(x, y)| u_lobes.map(|l| (x, y, l)))
                                {
                                    samples += 1;
                                    let u = Vec2::new(ux, uy);
                                    let Some(s) = l.sample(wo, u, u_lobe, lobe) else {
                                        refused += 1;
                                        continue;
                                    };
                                    let ok = s.pdf > 0.0
                                        && !s.pdf.is_nan()
                                        && (s.delta || s.pdf.is_finite())
                                        && s.weight.is_finite()
                                        && s.weight.min_element() >= 0.0
                                        && s.wi.is_finite()
                                        && (s.wi.length() - 1.0).abs() < 1e-3
                                        && s.wi.z * wo.z.signum() > 0.0;
                                    assert!(ok, "{l:?} wo {wo} u {u} {u_lobe} {lobe:?}: {s:?}");
                                    let (f, p) = (l.eval(wo, s.wi), l.pdf(wo, s.wi, lobe));
                                    let ok = f.is_finite() && p.is_finite() && p >= 0.0;
                                    assert!(ok, "{l:?} wo {wo}: eval {f} pdf {p} at {s:?}");
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    println!("{refused} of {samples} edge samples refused");
    assert!(refused > 0 && refused < samples, "{refused} of {samples}");
}
