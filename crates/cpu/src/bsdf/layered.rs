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

    // -----------------------------------------------------------------------------------------
    // eval: one random walk with next-event estimates through the coat (pbrt's `f`).
    // -----------------------------------------------------------------------------------------

    fn walk_eval(&self, top: Top, wo: Vec3, wi: Vec3, rng: &mut Rng) -> Vec3 {
        let (base, thickness) = (self.base, self.thickness());
        // Into the coat from wo (radiance), and the virtual light from wi (importance).
        let Some(wos) = top.sample(wo, rng.next(), rng.u2(), Only::Transmission) else {
            return Vec3::ZERO;
        };
        let Some(wis) = top.sample(wi, rng.next(), rng.u2(), Only::Transmission) else {
            return Vec3::ZERO;
        };
        let Some(light) = Light::new(top, wi, wis) else {
            return Vec3::ZERO;
        };
        let mut f = Vec3::ZERO;
        let (mut beta, mut z, mut w) = (wos.weight, thickness, wos.wi);
        for depth in 0..self.max_depth {
            // Russian roulette on a low throughput.
            if depth > 3 && beta.max_element() < 0.25 {
                let q = (1.0 - beta.max_element()).max(0.0);
                if rng.next() < q {
                    break;
                }
                beta /= 1.0 - q;
            }
            if !self.scatters() {
                // Straight across the clear slab.
                z = if z == thickness { 0.0 } else { thickness };
                beta *= transmittance(thickness, w);
            } else {
                // Free flight; a medium event inside the slab.
                let dz = -(1.0 - rng.next()).ln() * w.z.abs();
                let zp = if w.z > 0.0 { z + dz } else { z - dz };
                if zp == z {
                    continue;
                }
                if 0.0 < zp && zp < thickness {
                    // Next event along wis (and the mirror's chains), then scatter and the next
                    // event along the phase function's direction.
                    let p = hg((-w).dot(-light.wis.wi), self.g);
                    let value = self.albedo * p;
                    f += beta * light.along_wis(top, value, p, zp - thickness);
                    if top.specular() && base.specular() {
                        f += beta
                            * self.albedo
                            * light.exit
                            * self.mirror_chains(top, &light, -w, zp);
                    }
                    let Some((wp, pdf)) = sample_hg(-w, self.g, rng.u2()) else {
                        continue;
                    };
                    beta *= self.albedo;
                    (w, z) = (wp, zp);
                    if w.z > 0.0 {
                        f += beta * light.along(top, w, pdf, false, zp - thickness);
                    }
                    continue;
                }
                z = zp.clamp(0.0, thickness);
            }
            if z == thickness {
                // At the coat's inside: reflection only (leaving is the next events' part).
                let Some(bs) = top.sample(-w, rng.next(), rng.u2(), Only::Reflection) else {
                    break;
                };
                beta *= bs.weight;
                w = bs.wi;
                continue;
            }
            // At the base: next event along wis, then a sampled reflection and its next event.
            if !base.specular() {
                let (value, pdf) = (base.eval(-w, -light.wis.wi), base.pdf(-w, -light.wis.wi));
                f += beta * light.along_wis(top, value, pdf, thickness);
            }
            let uc = rng.next();
            let Some(bs) = base.sample(-w, uc, rng.u2()) else {
                break;
            };
            beta *= bs.weight;
            w = bs.wi;
            f += beta * light.along(top, w, bs.pdf, bs.delta, thickness);
        }
        f
    }

    /// Under a smooth coat over a mirror, the specular chains from a medium event at `zp` (seen
    /// from `back`) to the exit along `wis` that pbrt's `f` leaves out (it connects the event
    /// to the coat directly; nothing else there is non-specular): up, reflected inside the coat
    /// and by the mirror `k ≥ 1` times, or down to the mirror first and then `k ≥ 0` round
    /// trips, each of `R(θ) · F_mirror(θ) · Tr(thickness)²` at the one angle θ of `wis`.
    fn mirror_chains(&self, top: Top, light: &Light, back: Vec3, zp: f32) -> Vec3 {
        let wis = light.wis.wi;
        let thickness = self.thickness();
        let (up, down) = (-wis, Vec3::new(-wis.x, -wis.y, wis.z));
        let Some(mirror) = self.base.sample(-down, 0.0, Vec2::ZERO) else {
            return Vec3::ZERO;
        };
        let inside = top.sample(wis, 0.0, Vec2::ZERO, Only::Reflection);
        let r = inside.map_or(Vec3::ZERO, |s| s.weight);
        let tr = transmittance(thickness, up);
        let round = r * mirror.weight * (tr * tr);
        let rest = Vec3::ONE - round;
        let up_part = round / rest * (hg(back.dot(up), self.g) * transmittance(zp - thickness, up));
        let down_part =
            mirror.weight / rest * (hg(back.dot(down), self.g) * transmittance(zp, up) * tr);
        let chains = up_part + down_part;
        if chains.is_finite() {
            chains
        } else {
            Vec3::ZERO
        }
    }

    // -----------------------------------------------------------------------------------------
    // pdf: pbrt's estimate of the reflection and transmit–base–transmit densities.
    // -----------------------------------------------------------------------------------------

    fn pdf_estimate(&self, top: Top, wo: Vec3, wi: Vec3, seed: u32) -> f32 {
        let base = self.base;
        let n = self.samples.max(1);
        let mut rng = Rng::new(PDF, seed, &[wi.x, wi.y, wi.z, wo.x, wo.y, wo.z]);
        let mut sum = n as f32 * top.pdf(wo, wi, Only::Reflection);
        for _ in 0..n {
            let wos = top.sample(wo, rng.next(), rng.u2(), Only::Transmission);
            let wis = top.sample(wi, rng.next(), rng.u2(), Only::Transmission);
            let (Some(wos), Some(wis)) = (wos, wis) else {
                continue;
            };
            if top.specular() {
                sum += base.pdf(-wos.wi, -wis.wi);
                continue;
            }
            // Both the base's and the coat's sampling, combined by the power heuristic.
            let uc = rng.next();
            let Some(rs) = base.sample(-wos.wi, uc, rng.u2()) else {
                continue;
            };
            if base.specular() {
                sum += top.pdf(-rs.wi, wi, Only::All);
                continue;
            }
            let r_pdf = base.pdf(-wos.wi, -wis.wi);
            sum += power_heuristic(wis.pdf, r_pdf) * r_pdf;
            let t_pdf = top.pdf(-rs.wi, wi, Only::All);
            sum += power_heuristic(rs.pdf, t_pdf) * t_pdf;
        }
        // Mixed with the uniform sphere, as pbrt does: 0.1 / (4π) + 0.9 · estimate.
        let uniform = 0.25 * FRAC_1_PI;
        let pdf = 0.1 * uniform + 0.9 * (sum / n as f32);
        if pdf.is_finite() {
            pdf
        } else {
            uniform
        }
    }

    // -----------------------------------------------------------------------------------------
    // sample: the coat, then the walk until it leaves (pbrt's `Sample_f`).
    // -----------------------------------------------------------------------------------------

    fn sample_walk(
        &self,
        top: Top,
        wo: Vec3,
        u: Vec2,
        u_lobe: f32,
        rng: &mut Rng,
    ) -> Option<BsdfSample> {
        let bs = top.sample(wo, u_lobe, u, Only::All)?;
        let (wi, weight, pdf, delta) = if bs.wi.z > 0.0 {
            (bs.wi, bs.weight, bs.pdf, bs.delta)
        } else {
            self.walk(top, bs, rng)?
        };
        Some(self.finish(wo, wi, weight, pdf, delta))
    }

    /// A walk that refracted in with `entry` until it leaves through the coat: the direction,
    /// the path's weight and pdf (a product of densities and probabilities), and whether every
    /// event was specular.
    fn walk(&self, top: Top, entry: Scatter, rng: &mut Rng) -> Option<(Vec3, Vec3, f32, bool)> {
        let thickness = self.thickness();
        let (mut weight, mut pdf, mut specular) = (entry.weight, entry.pdf, entry.delta);
        let (mut z, mut w) = (thickness, entry.wi);
        for depth in 0..self.max_depth {
            // Russian roulette on a low weight.
            let rr = weight.max_element();
            if depth > 3 && rr < 0.25 {
                let q = (1.0 - rr).max(0.0);
                if rng.next() < q {
                    return None;
                }
                weight /= 1.0 - q;
                pdf *= 1.0 - q;
            }
            if w.z == 0.0 {
                return None;
            }
            if self.scatters() {
                // Free flight; a medium event inside the slab scatters by the phase function.
                let dz = -(1.0 - rng.next()).ln() * w.z.abs();
                let zp = if w.z > 0.0 { z + dz } else { z - dz };
                if zp == z {
                    return None;
                }
                if 0.0 < zp && zp < thickness {
                    let (wp, p) = sample_hg(-w, self.g, rng.u2())?;
                    weight *= self.albedo;
                    pdf *= p;
                    specular = false;
                    (w, z) = (wp, zp);
                    continue;
                }
                z = zp.clamp(0.0, thickness);
            } else {
                z = if z == thickness { 0.0 } else { thickness };
                weight *= transmittance(thickness, w);
            }
            // Scatter at the interface reached; leaving through the coat ends the walk.
            let uc = rng.next();
            let bs = match z == 0.0 {
                true => self.base.sample(-w, uc, rng.u2())?,
                false => top.sample(-w, uc, rng.u2(), Only::All)?,
            };
            weight *= bs.weight;
            pdf *= bs.pdf;
            specular &= bs.delta;
            w = bs.wi;
            if z != 0.0 && w.z > 0.0 {
                return Some((w, weight, pdf, specular));
            }
        }
        None
    }

    /// The sample as strata returns it: a non-delta one with [`Layered::pdf`] as its density.
    fn finish(&self, wo: Vec3, wi: Vec3, weight: Vec3, pdf: f32, delta: bool) -> BsdfSample {
        let pdf = match delta {
            true => pdf.max(f32::MIN_POSITIVE),
            false => self.pdf_estimate(self.top(), wo, wi, 0),
        };
        BsdfSample {
            wi,
            weight,
            pdf,
            delta,
            eta: 1.0,
        }
    }

    /// Probabilities, under the hemisphere strategies, of a smooth coat's mirror, and (of the
    /// rest) of the specular walks over a mirror base.
    fn delta_split(&self, top: Top, wo: Vec3) -> (f32, f32) {
        let Top::Smooth(d) = top else {
            return (0.0, 0.0);
        };
        let p_mirror = fresnel(wo.z, d.eta);
        let p_walk = match (self.base.specular(), self.scatters()) {
            (false, _) => 0.0,
            (true, true) => 0.5,
            (true, false) => 1.0,
        };
        (p_mirror, p_walk)
    }

    fn sample_hemisphere(
        &self,
        top: Top,
        wo: Vec3,
        u: Vec2,
        u_lobe: f32,
        uniform: bool,
        rng: &mut Rng,
    ) -> Option<BsdfSample> {
        let (p_mirror, p_walk) = self.delta_split(top, wo);
        if u_lobe < p_mirror {
            return Some(BsdfSample::mirror(wo, Vec3::ONE, p_mirror));
        }
        let u_walk = (u_lobe - p_mirror) / (1.0 - p_mirror);
        if u_walk < p_walk {
            // A specular walk: refract in, keep the walk only if it stays specular.
            let p = (1.0 - p_mirror) * p_walk;
            let entry = top.sample(wo, 0.0, u, Only::Transmission)?;
            let (wi, weight, pdf, delta) = self.walk(top, entry, rng)?;
            return delta.then(|| self.finish(wo, wi, weight / p, pdf * p, true));
        }
        let (wi, hemisphere) = sample_hemisphere(u, uniform);
        let pdf = (1.0 - p_mirror) * (1.0 - p_walk) * hemisphere;
        let weight = self.eval(wo, wi) / pdf;
        Some(BsdfSample::reflection(wi, weight, pdf))
    }
}

/// The virtual light of `eval`'s walk: `wi`, and `wis`, a transmission into the coat sampled from
/// `wi`, with `exit`, pbrt's `wis.f / wis.pdf` in importance mode times the `|cos θi|` strata's
/// `eval` carries.
struct Light {
    wi: Vec3,
    wis: Scatter,
    exit: Vec3,
}

impl Light {
    fn new(top: Top, wi: Vec3, wis: Scatter) -> Option<Self> {
        // Importance mode: the radiance weight without the 1/η² of entering.
        let eta = top.eta();
        let exit = wis.weight * (eta * eta * wi.z / wis.wi.z.abs());
        exit.is_finite().then_some(Self { wi, wis, exit })
    }

    /// The next event along `wis` from a vertex `dz` below the coat that scatters into it with
    /// `value` (`f · cos`, or albedo × phase) and samples it with density `pdf`; weighted by the
    /// power heuristic against `wis` unless the coat is smooth.
    fn along_wis(&self, top: Top, value: Vec3, pdf: f32, dz: f32) -> Vec3 {
        let wt = match top.specular() {
            true => 1.0,
            false => power_heuristic(self.wis.pdf, pdf),
        };
        value * self.exit * (wt * transmittance(dz, self.wis.wi))
    }

    /// The next event through a rough coat along `w`, sampled at a vertex `dz` below it with
    /// density `pdf` (`delta`: a mirror's): weighted against the density with which `wis`
    /// reaches `w`, `pdf(wi → −w)`. pbrt weights with `PDF(−w → wi)`, the density of the reverse
    /// transmission, so that its two weights do not sum to one.
    fn along(&self, top: Top, w: Vec3, pdf: f32, delta: bool, dz: f32) -> Vec3 {
        if top.specular() {
            return Vec3::ZERO;
        }
        let f_exit = top.eval(-w, self.wi);
        if f_exit == Vec3::ZERO {
            return Vec3::ZERO;
        }
        let wt = match delta {
            true => 1.0,
            false => power_heuristic(pdf, top.pdf(self.wi, -w, Only::Transmission)),
        };
        f_exit * (transmittance(dz, w) * wt)
    }
}

// ---------------------------------------------------------------------------------------------
// The two interfaces as the walk calls them: from either side, sampling restricted to
// reflection or transmission as pbrt's `BxDFReflTransFlags`.
// ---------------------------------------------------------------------------------------------

#[derive(Clone, Copy, PartialEq)]
enum Only {
    All,
    Reflection,
    Transmission,
}

/// An interface's sample: `weight` is `f · |cos| / pdf` (radiance).
#[derive(Clone, Copy)]
struct Scatter {
    wi: Vec3,
    weight: Vec3,
    pdf: f32,
    delta: bool,
}

impl Scatter {
    /// pbrt's test of a usable sample: a density, a direction off the plane, some throughput.
    fn usable(self) -> Option<Self> {
        let ok = self.pdf > 0.0 && self.wi.z != 0.0 && self.weight != Vec3::ZERO;
        ok.then_some(self)
    }
}

#[derive(Clone, Copy)]
enum Top {
    Smooth(Dielectric),
    Rough(RoughDielectric),
}

impl Top {
    fn eta(self) -> f32 {
        match self {
            Self::Smooth(d) => d.eta,
            Self::Rough(r) => r.eta,
        }
    }

    fn specular(self) -> bool {
        matches!(self, Self::Smooth(_))
    }

    /// The interface seen from `wo`'s side, and the sign that takes directions there (from
    /// inside, the relative index is 1/η and directions are mirrored through the origin).
    fn facing(self, wo: Vec3) -> (Self, f32) {
        if wo.z >= 0.0 {
            return (self, 1.0);
        }
        let top = match self {
            Self::Smooth(d) => Self::Smooth(Dielectric {
                eta: 1.0 / d.eta,
                ..d
            }),
            Self::Rough(r) => Self::Rough(RoughDielectric {
                eta: 1.0 / r.eta,
                ..r
            }),
        };
        (top, -1.0)
    }

    fn eval(self, wo: Vec3, wi: Vec3) -> Vec3 {
        match self.facing(wo) {
            (Self::Rough(r), s) => r.eval(s * wo, s * wi),
            (Self::Smooth(_), _) => Vec3::ZERO,
        }
    }

    fn pdf(self, wo: Vec3, wi: Vec3, only: Only) -> f32 {
        let (Self::Rough(r), s) = self.facing(wo) else {
            return 0.0;
        };
        let (wo, wi) = (s * wo, s * wi);
        let full = r.pdf(wo, wi, Lobe::Bsdf);
        let reflect = wi.z > 0.0;
        match (only, reflect) {
            (Only::All, _) => return full,
            (Only::Reflection, false) | (Only::Transmission, true) => return 0.0,
            _ => {}
        }
        // The lobe's probability F or 1 − F at the half vector, divided out.
        let h = if reflect { wo + wi } else { wo + r.eta * wi };
        let h = h.normalize_or_zero();
        let h = if h.z < 0.0 { -h } else { h };
        let f = fresnel(wo.dot(h), r.eta);
        let prob = if reflect { f } else { 1.0 - f };
        let pdf = full / prob;
        if full > 0.0 && pdf.is_finite() {
            pdf
        } else {
            0.0
        }
    }

    fn sample(self, wo: Vec3, uc: f32, u: Vec2, only: Only) -> Option<Scatter> {
        let (top, s) = self.facing(wo);
        let wo = s * wo;
        if wo.z.is_nan() || wo.z <= 0.0 {
            return None;
        }
        let out = match top {
            Self::Smooth(d) => sample_smooth(d, wo, uc, only)?,
            Self::Rough(r) => sample_rough(r, wo, uc, u, only)?,
        };
        Scatter {
            wi: s * out.wi,
            ..out
        }
        .usable()
    }
}

/// A smooth interface's sample from above: both lobes by F (as [`Dielectric::sample`]), or one.
fn sample_smooth(d: Dielectric, wo: Vec3, uc: f32, only: Only) -> Option<Scatter> {
    let f = fresnel(wo.z, d.eta);
    let (wi, weight, pdf) = match only {
        Only::All => {
            let b = d.sample(wo, uc)?;
            (b.wi, b.weight, b.pdf)
        }
        Only::Reflection if f > 0.0 => (Vec3::new(-wo.x, -wo.y, wo.z), Vec3::splat(f), 1.0),
        // The refraction (lobe dimension 1 ≥ F < 1), its weight times its probability 1 − F.
        Only::Transmission if f < 1.0 => {
            let b = d.sample(wo, 1.0)?;
            (b.wi, b.weight * (1.0 - f), 1.0)
        }
        _ => return None,
    };
    Some(Scatter {
        wi,
        weight,
        pdf,
        delta: true,
    })
}

/// A GGX interface's sample from above: both lobes by F at the visible normal (as
/// [`RoughDielectric::sample`]), or one, with the lobe's probability moved from the pdf into the
/// weight.
fn sample_rough(r: RoughDielectric, wo: Vec3, uc: f32, u: Vec2, only: Only) -> Option<Scatter> {
    let (prob, u_lobe) = match only {
        Only::All => (1.0, uc),
        _ => {
            // The normal RoughDielectric::sample draws with `u`, and its F.
            let f = fresnel(wo.dot(ggx::sample_vndf(wo, r.alpha, u)), r.eta);
            match only {
                Only::Reflection => (f, 0.0),
                _ => (1.0 - f, 1.0),
            }
        }
    };
    if prob.is_nan() || prob <= 0.0 {
        return None;
    }
    let b = r.sample(wo, u, u_lobe, Lobe::Bsdf)?;
    Some(Scatter {
        wi: b.wi,
        weight: b.weight * prob,
        pdf: b.pdf / prob,
        delta: false,
    })
}

impl Base {
    fn specular(&self) -> bool {
        match self {
            Self::Diffuse(_) => false,
            Self::Conductor(c) => c.is_mirror(),
        }
    }

    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        match self {
            Self::Diffuse(b) => b.eval(wo, wi),
            Self::Conductor(b) => b.eval(wo, wi),
        }
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            Self::Diffuse(b) => b.pdf(wo, wi, Lobe::Bsdf),
            Self::Conductor(b) => b.pdf(wo, wi, Lobe::Bsdf),
        }
    }

    /// The base's own sampling (`_uc`: pbrt draws a lobe dimension it does not use).
    fn sample(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<Scatter> {
        let b = match self {
            Self::Diffuse(b) => b.sample(wo, u, Lobe::Bsdf)?,
            Self::Conductor(b) => b.sample(wo, u, Lobe::Bsdf)?,
        };
        Scatter {
            wi: b.wi,
            weight: b.weight,
            pdf: b.pdf,
            delta: b.delta,
        }
        .usable()
    }
}

// ---------------------------------------------------------------------------------------------
// The slab: transmittance, the Henyey–Greenstein phase function, the random stream.
// ---------------------------------------------------------------------------------------------

/// pbrt's `Tr(dz, w) = exp(−|dz / w.z|)` (1 for |dz| at most the smallest normal f32).
fn transmittance(dz: f32, w: Vec3) -> f32 {
    if dz.abs() <= f32::MIN_POSITIVE {
        1.0
    } else {
        (-(dz / w.z).abs()).exp()
    }
}

/// Henyey–Greenstein in pbrt-v4's convention: `cos` is `wo · wi` with both pointing away, so
/// `g > 0` peaks at `cos = −1` (forward): `(1 − g²) / (4π (1 + g² + 2g cos)^{3/2})`.
fn hg(cos: f32, g: f32) -> f32 {
    let g = g.clamp(-0.99, 0.99);
    let denom = 1.0 + g * g + 2.0 * g * cos;
    0.25 * FRAC_1_PI * (1.0 - g * g) / (denom * denom.max(0.0).sqrt())
}

/// A direction from [`hg`] around `wo` and its density (pbrt's `SampleHenyeyGreenstein`:
/// `cos = −(1 + g² − ((1 − g²) / (1 + g − 2g u.x))²) / (2g)`, `1 − 2 u.x` for |g| < 10⁻³).
fn sample_hg(wo: Vec3, g: f32, u: Vec2) -> Option<(Vec3, f32)> {
    let g = g.clamp(-0.99, 0.99);
    let cos = if g.abs() < 1e-3 {
        1.0 - 2.0 * u.x
    } else {
        let s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u.x);
        -(1.0 + g * g - s * s) / (2.0 * g)
    };
    let cos = cos.clamp(-1.0, 1.0);
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = TAU * u.y;
    let local = Vec3::new(sin * phi.cos(), sin * phi.sin(), cos);
    let wi = Frame::from_normal(wo).to_world(local);
    let pdf = hg(cos, g);
    (pdf > 0.0 && wi.z != 0.0).then_some((wi, pdf))
}

/// The counter-based stream of the module doc.
struct Rng(u32);

impl Rng {
    fn new(domain: u32, seed: u32, values: &[f32]) -> Self {
        let start = hash_combine(lowbias32(domain), seed);
        Self(
            values
                .iter()
                .fold(start, |h, v| hash_combine(h, v.to_bits())),
        )
    }

    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9);
        (lowbias32(self.0) >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    fn u2(&mut self) -> Vec2 {
        let x = self.next();
        Vec2::new(x, self.next())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stratapt_sampling::testing::chi2::Refusals;
    use stratapt_sampling::testing::chi2::{accept, density_bins, fit, reject, Family, Plant};
    use stratapt_sampling::testing::TestRng;

    /// Henyey–Greenstein sampling draws what [`hg`] says around an oblique `wo`, from backward
    /// to forward scattering (histogrammed in `(φ / 2π, (1 − cos) / 2)` about `wo`, where the
    /// density is `4π hg`), and returns that density; planted: the density of a g 0.03 off is
    /// rejected.
    #[test]
    fn henyey_greenstein_sampling_matches_its_density() {
        const FAMILY: Family = Family {
            alpha: 0.01,
            tests: 5,
        };
        let (nx, ny, n) = (8, 40, 100_000);
        let wo = Vec3::new(0.3, -0.5, 0.81).normalize();
        let frame = Frame::from_normal(wo);
        let (mut fits, mut planted) = (Vec::new(), Vec::new());
        for (i, g) in [-0.9f32, -0.3, 0.0, 0.5, 0.9].into_iter().enumerate() {
            let mut rng = TestRng(40 + i as u64);
            let samples: Vec<_> = (0..n)
                .map(|_| {
                    let (wi, pdf) = sample_hg(wo, g, rng.u2())?;
                    let expected = hg(wo.dot(wi), g);
                    assert!(
                        (pdf - expected).abs() <= 2e-3 * expected,
                        "{pdf} vs {expected}"
                    );
                    let l = frame.to_local(wi);
                    let phi = f64::from(l.y)
                        .atan2(f64::from(l.x))
                        .rem_euclid(std::f64::consts::TAU);
                    Some([
                        phi / std::f64::consts::TAU,
                        0.5 * (1.0 - f64::from(l.z.clamp(-1.0, 1.0))),
                    ])
                })
                .collect();
            let bins = |g: f32| {
                let density = |_: f64, y: f64| {
                    4.0 * std::f64::consts::PI * f64::from(hg(1.0 - 2.0 * y as f32, g))
                };
                density_bins(&density, nx, ny)
            };
            let name = format!("HG g {g}");
            let (right, wrong) = (bins(g), bins(g + 0.03));
            let samples = || samples.iter().copied();
            let refusals = Refusals::Allowed;
            fits.push(fit(
                &FAMILY,
                &name,
                samples(),
                &right,
                nx,
                ny,
                refusals,
                Plant::None,
            ));
            let label = format!("{name}, density of g + 0.03");
            planted.push(fit(
                &FAMILY,
                &label,
                samples(),
                &wrong,
                nx,
                ny,
                refusals,
                Plant::None,
            ));
        }
        accept(fits);
        reject(planted, "");
    }
}
