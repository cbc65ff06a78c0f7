//! pbrt-v4's `LayeredBxDF` (Pharr, Jakob and Humphreys, *Physically Based Rendering* 4th ed.,
//! §14.3, after Guo et al. 2018, "Position-Free Monte Carlo Simulation for Arbitrary Layered
//! BSDFs"), the BSDF of `coateddiffuse` and `coatedconductor`: a dielectric coat over an opaque
//! base (Lambertian or GGX conductor), between them a homogeneous slab of `thickness` mean free
//! paths (σt = 1) that scatters with `albedo` by a Henyey–Greenstein phase function of
//! asymmetry `g`. `eval`, `pdf` and `sample` are stochastic estimates, in strata's conventions
//! ([`super`]): `wo.z ≥ 0` (seen from below it is the same BSDF: pbrt's `twoSided`), `eval` is
//! `f · |cos θi|`, `sample` returns `f · |cos θi| / pdf`. Reflection only: the base is opaque.
//!
//! - `eval` is pbrt's `f`: the coat's reflection plus, per sample, a random walk between the
//!   coat's inside (`z = thickness`) and the base (`z = 0`) that leaves through the coat towards
//!   `wi` only by next-event estimates: along `wis`, a transmission into the coat sampled from
//!   `wi`, and (rough coat) along the direction the base or the phase function sampled, the two
//!   combined by the power heuristic. Unbiased for the slab, up to `max_depth` events.
//! - `sample` under [`Lobe::Bsdf`] is pbrt's `Sample_f`: the coat's sample, and if it refracted,
//!   the walk until it leaves through the coat; `weight` is the path's `f / pdf`. Its `pdf` is
//!   [`Layered::pdf`] at the direction (pbrt marks the sample `pdfIsProportional` and its
//!   integrator asks `PDF()` for MIS; an integrator that reads `pdf` here and calls
//!   [`Layered::pdf`] for light samples, as strata's does, sees the same number); `delta`
//!   where every event was specular (a smooth coat's reflection, with its probability F as
//!   `pdf`; a smooth coat over a mirror without a medium event, with the product of its
//!   events' probabilities).
//! - `pdf` under [`Lobe::Bsdf`] is pbrt's `PDF`: an estimate of the densities of "coat
//!   reflection" and "transmit, base, transmit" (the medium ignored) mixed with the sphere's
//!   uniform density, `0.1 / (4π) + 0.9 · estimate`. It is *not* the density of `sample`
//!   (measured: it integrates to 1.5–2.7 over the hemisphere, and normalized it is 0.12–0.25 in
//!   total variation from the density of `sample`); it is positive wherever `sample` goes and
//!   the same number for both MIS strategies, which is all their weights need.
//! - Under [`Lobe::Uniform`] / [`Lobe::Cosine`] the non-delta part is sampled on the hemisphere
//!   (weight `eval / pdf`); the delta parts keep their own sampling: a smooth coat's mirror with
//!   probability F, and over a mirror base the specular walks, taken half of the time (all of it
//!   without a medium), of which only those that stay specular are kept.
//!
//! **Transport mode and η².** strata's dielectrics return the radiance form, `f` with the 1/η²
//! of Veach 1997, §5.2, η the relative index crossed: pbrt's `TransportMode::Radiance`. From
//! outside that is 1/η² on entering; from inside (relative index 1/η) η² on leaving; with
//! `η² f(wo outside, wi inside) = f(wi, wo)` (generalized reciprocity) they cancel, so the
//! layered reflectance carries no net η² (its white furnace is 1, not 1/η²). pbrt's walk is in
//! radiance mode everywhere but for `wis`, sampled from `wi` in importance mode (`!mode`), whose
//! BTDF lacks the 1/η² (`f_importance = η² f_radiance` from outside): `wis`'s weight here is the
//! radiance one times η². That is all pbrt's `TransportMode` does in the walk; no helper in
//! `rough_dielectric.rs` is needed: a reflection- or transmission-only sample is
//! [`RoughDielectric::sample`] with the lobe dimension 0 or 1, its lobe probability F or 1 − F
//! moved from the pdf into the weight, and a side-only density its `pdf` divided by the same.
//!
//! **Randomness** (a contract with a WGSL port). `eval` and `pdf` are deterministic in their
//! directions, `sample` in its inputs; the directions are those after the two-sided flip. Each
//! call draws from a 32-bit counter-based stream built from [`lowbias32`] and [`hash_combine`]:
//! ```text
//! state = hash_combine(lowbias32(domain), seed), then state = hash_combine(state, bits(v))
//!         for v in: eval (domain 1): wo.x, wo.y, wo.z, wi.x, wi.y, wi.z
//!                   pdf  (domain 2): wi.x, wi.y, wi.z, wo.x, wo.y, wo.z   (pbrt's order)
//!                   sample (domain 3): wo.x, wo.y, wo.z, u.x, u.y, u_lobe
//! draw:  state = state + 0x9e3779b9 (wrapping);  u = f32(lowbias32(state) >> 8) · 2⁻²⁴
//! ```
//! `bits` is the f32 bit pattern, `seed` 0 unless given ([`Layered::eval_seeded`],
//! [`Layered::pdf_seeded`]). Draws are taken in the order the code reads them: an interface
//! sample takes its lobe dimension, then u.x, u.y (the base's too, unused); a free flight one,
//! `dz = −ln(1 − u) |w.z|`; a phase sample u.x, u.y; Russian roulette one, after the fourth
//! event when the throughput's largest channel is below ¼.
//!
//! **Departures from pbrt.** (1) The weight of the next event through a rough coat along a
//! direction `w` the base or the phase function sampled: pbrt weighs it against
//! `PDF(−w → wi)`, the reverse transmission's density, while the competing `wis` strategy has
//! density `PDF(wi → −w)`; the weights then do not sum to one and pbrt's `f` is biased (rough
//! η 1.5, α 0.3 over a white Lambertian base, clear slab 0.01: ∫ f cos 0.679 against 0.632
//! from `Sample_f` at cos θo 0.3, +7.4 %; +7.9 % at 0.9). Here the weight uses `PDF(wi → −w)`
//! and the two agree. (2) Under a smooth coat over a mirror, pbrt's `f` connects a medium event
//! to the coat directly only, and misses the specular chains through the mirror (16 % of the
//! albedo at cos θo 0.3 for a slab 0.5 of albedo 0.9); they are added here in closed form
//! (`mirror_chains`). (3) Transmission directions (`wi.z ≤ 0`) get 0 from `eval` and `pdf`
//! (pbrt's `PDF` returns its uniform floor there). (4) `samples = 0` counts as 1.
//! (5) pbrt's generator is its PCG32 seeded by `Hash`es of the inputs and the render seed.

use super::conductor::Conductor;
use super::dielectric::{fresnel, Dielectric};
use super::diffuse::Diffuse;
use super::rough_dielectric::RoughDielectric;
use super::{hemisphere_pdf, sample_hemisphere, BsdfSample, Lobe};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, TAU};
use stratapt_sampling::hash::{hash_combine, lowbias32};
use stratapt_sampling::mis::power_heuristic;
use stratapt_sampling::warp::ggx;
use stratapt_sampling::Frame;
use stratapt_scene::records::MIRROR_ALPHA;

mod interface;
mod slab;
mod walk;

use interface::{Only, Scatter, Top};
use slab::Rng;

/// The opaque base under the coat.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Base {
    Diffuse(Diffuse),
    /// pbrt's `coatedconductor` divides the conductor's η and k by the coat's index: the
    /// conductor sits in the coat's medium.
    Conductor(Conductor),
}

/// The dielectric coat; `eta` is relative, inside over outside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Coat {
    Smooth {
        eta: f32,
    },
    /// GGX; the tint (1 in pbrt) multiplies every crossing. At most [`MIRROR_ALPHA`] rough, or
    /// index-matched, it is smooth (pbrt's `EffectivelySmooth` and `eta == 1`).
    Rough(RoughDielectric),
}

/// A coat over a base with a scattering slab between them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layered {
    pub coat: Coat,
    pub base: Base,
    /// In mean free paths (σt = 1); at least the smallest normal f32.
    pub thickness: f32,
    /// Single-scattering albedo of the slab; 0 is a clear slab.
    pub albedo: Vec3,
    /// Henyey–Greenstein asymmetry, clamped to [−0.99, 0.99].
    pub g: f32,
    /// Events per walk (interface or medium); pbrt's default 10.
    pub max_depth: u32,
    /// Walks per estimate; pbrt's default 1.
    pub samples: u32,
}

const EVAL: u32 = 1;
const PDF: u32 = 2;
const SAMPLE: u32 = 3;

impl Layered {
    /// pbrt-v4's defaults: thickness 0.01, a clear slab (albedo 0, g 0), 10 events, 1 walk.
    pub fn new(coat: Coat, base: Base) -> Self {
        Self {
            coat,
            base,
            thickness: 0.01,
            albedo: Vec3::ZERO,
            g: 0.0,
            max_depth: 10,
            samples: 1,
        }
    }

    /// `f · |cos θi|`, estimated (deterministic in `wo`, `wi`).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        self.eval_seeded(wo, wi, 0)
    }

    /// Density of [`Layered::sample`] under `lobe` (pbrt's estimate under [`Lobe::Bsdf`]).
    pub fn pdf(&self, wo: Vec3, wi: Vec3, lobe: Lobe) -> f32 {
        self.pdf_seeded(wo, wi, lobe, 0)
    }

    /// [`Layered::eval`] with its random stream keyed also by `seed` (0 is `eval`): independent
    /// estimates at the same directions.
    pub fn eval_seeded(&self, wo: Vec3, wi: Vec3, seed: u32) -> Vec3 {
        // Two-sided: seen from below, the same BSDF.
        let (wo, wi) = if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) };
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return Vec3::ZERO;
        }
        let top = self.top();
        let n = self.samples.max(1);
        let bits = [wo.x, wo.y, wo.z, wi.x, wi.y, wi.z];
        let mut rng = Rng::new(EVAL, seed, &bits);
        // The coat's own reflection, then one walk per sample.
        let mut f = top.eval(wo, wi) * n as f32;
        for _ in 0..n {
            f += self.walk_eval(top, wo, wi, &mut rng);
        }
        let f = f / n as f32;
        if f.is_finite() {
            f.max(Vec3::ZERO)
        } else {
            Vec3::ZERO
        }
    }

    /// [`Layered::pdf`] with its random stream keyed also by `seed` (0 is `pdf`).
    pub fn pdf_seeded(&self, wo: Vec3, wi: Vec3, lobe: Lobe, seed: u32) -> f32 {
        let (wo, wi) = if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) };
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return 0.0;
        }
        let top = self.top();
        match lobe {
            Lobe::Uniform | Lobe::Cosine => {
                let (p_mirror, p_walk) = self.delta_split(top, wo);
                (1.0 - p_mirror) * (1.0 - p_walk) * hemisphere_pdf(wi, lobe == Lobe::Uniform)
            }
            Lobe::Bsdf => self.pdf_estimate(top, wo, wi, seed),
        }
    }

    /// A direction from `wo` with the direction dimensions `u` and the lobe dimension `u_lobe`
    /// (under [`Lobe::Bsdf`] the coat's sample; the walk draws from the stream these seed).
    pub fn sample(&self, wo: Vec3, u: Vec2, u_lobe: f32, lobe: Lobe) -> Option<BsdfSample> {
        let flip = wo.z < 0.0;
        let wo = if flip { -wo } else { wo };
        if wo.z.is_nan() || wo.z <= 0.0 {
            return None;
        }
        let top = self.top();
        let mut rng = Rng::new(SAMPLE, 0, &[wo.x, wo.y, wo.z, u.x, u.y, u_lobe]);
        let s = match lobe {
            Lobe::Bsdf => self.sample_walk(top, wo, u, u_lobe, &mut rng)?,
            Lobe::Uniform | Lobe::Cosine => {
                self.sample_hemisphere(top, wo, u, u_lobe, lobe == Lobe::Uniform, &mut rng)?
            }
        };
        let valid = s.pdf > 0.0 && s.weight.is_finite() && s.wi.z > 0.0;
        valid.then_some(BsdfSample {
            wi: if flip { -s.wi } else { s.wi },
            ..s
        })
    }

    /// The coat as the walk sees it.
    fn top(&self) -> Top {
        match self.coat {
            Coat::Smooth { eta } => Top::Smooth(Dielectric {
                eta,
                tint: Vec3::ONE,
            }),
            Coat::Rough(r) if r.eta == 1.0 || r.alpha.max_element() <= MIRROR_ALPHA => {
                Top::Smooth(Dielectric {
                    eta: r.eta,
                    tint: r.tint,
                })
            }
            Coat::Rough(r) => Top::Rough(r),
        }
    }

    fn thickness(&self) -> f32 {
        self.thickness.max(f32::MIN_POSITIVE)
    }

    fn scatters(&self) -> bool {
        self.albedo != Vec3::ZERO
    }
}
