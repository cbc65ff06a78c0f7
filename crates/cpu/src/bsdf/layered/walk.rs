//! The random walks of [`Layered`](super::Layered): `eval`'s walk with next-event estimates
//! through the coat (pbrt's `f`), `pdf`'s estimate, `sample`'s walk, and the hemisphere
//! strategies.

use super::slab::{hg, sample_hg, transmittance};
use super::*;

impl Layered {
    // -----------------------------------------------------------------------------------------
    // eval: one random walk with next-event estimates through the coat (pbrt's `f`).
    // -----------------------------------------------------------------------------------------

    pub(super) fn walk_eval(&self, top: Top, wo: Vec3, wi: Vec3, rng: &mut Rng) -> Vec3 {
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
    pub(super) fn mirror_chains(&self, top: Top, light: &Light, back: Vec3, zp: f32) -> Vec3 {
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

    pub(super) fn pdf_estimate(&self, top: Top, wo: Vec3, wi: Vec3, seed: u32) -> f32 {
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

    pub(super) fn sample_walk(
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
    pub(super) fn walk(
        &self,
        top: Top,
        entry: Scatter,
        rng: &mut Rng,
    ) -> Option<(Vec3, Vec3, f32, bool)> {
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
    pub(super) fn finish(
        &self,
        wo: Vec3,
        wi: Vec3,
        weight: Vec3,
        pdf: f32,
        delta: bool,
    ) -> BsdfSample {
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
    pub(super) fn delta_split(&self, top: Top, wo: Vec3) -> (f32, f32) {
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

    pub(super) fn sample_hemisphere(
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
pub(super) struct Light {
    wi: Vec3,
    wis: Scatter,
    exit: Vec3,
}

impl Light {
    pub(super) fn new(top: Top, wi: Vec3, wis: Scatter) -> Option<Self> {
        // Importance mode: the radiance weight without the 1/η² of entering.
        let eta = top.eta();
        let exit = wis.weight * (eta * eta * wi.z / wis.wi.z.abs());
        exit.is_finite().then_some(Self { wi, wis, exit })
    }

    /// The next event along `wis` from a vertex `dz` below the coat that scatters into it with
    /// `value` (`f · cos`, or albedo × phase) and samples it with density `pdf`; weighted by the
    /// power heuristic against `wis` unless the coat is smooth.
    pub(super) fn along_wis(&self, top: Top, value: Vec3, pdf: f32, dz: f32) -> Vec3 {
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
    pub(super) fn along(&self, top: Top, w: Vec3, pdf: f32, delta: bool, dz: f32) -> Vec3 {
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
