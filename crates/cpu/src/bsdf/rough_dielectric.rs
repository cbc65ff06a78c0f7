//! Rough dielectric: GGX microfacet reflection and transmission (Walter et al. 2007) with
//! anisotropic roughness and Smith masking-shadowing (height-correlated or separable), sampled by visible
//! normals (Heitz 2018) with reflection or refraction about the sampled normal chosen with
//! probability F by the lobe dimension, as Mitsuba 3's `roughdielectric` does. Refracted radiance
//! is scaled by 1/η² and tinted, as the smooth [`super::dielectric::Dielectric`] (its α → 0 limit).
//!
//! Local frame as every BSDF (`wo.z ≥ 0`); `eta = η_t / η_i` for light crossing from `wo`'s side.
//! Under the `uniform` and `cosine` strategies the lobe dimension picks the side (½ each) and
//! the direction is drawn on that hemisphere.

use super::dielectric::fresnel;
use super::{hemisphere_pdf, sample_hemisphere, BsdfSample, Lobe};
use glam::{Vec2, Vec3};
use stratapt_sampling::warp::ggx::{self, Masking};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughDielectric {
    /// Relative index of refraction η_t / η_i for light arriving from the `wo` side.
    pub eta: f32,
    /// Transmission tint.
    pub tint: Vec3,
    /// GGX roughness (αu, αv), each at least [`stratapt_scene::records::MIRROR_ALPHA`].
    pub alpha: Vec2,
    pub masking: Masking,
}

/// The microfacet normal that takes `wo` to `wi` (reflection when `wi.z > 0`, else refraction
/// with relative index `eta`), on the `+z` side, and `wi · h`; `None` when no microfacet
/// facing both directions the right way does (`wo · h > 0`, and `wi · h` of the sign of `wi.z`).
fn half_vector(wo: Vec3, wi: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let reflect = wi.z > 0.0;
    let h = if reflect { wo + wi } else { wo + eta * wi };
    let h = h.normalize_or_zero();
    let h = if h.z < 0.0 { -h } else { h };
    let (o, i) = (wo.dot(h), wi.dot(h));
    (h.z > 0.0 && o > 0.0 && (i > 0.0) == reflect && i != 0.0).then_some((h, i))
}

impl RoughDielectric {
    /// `f · |cos θi|`: `F D G2 / (4 cos θo)` for reflection and
    /// `tint (1 − F) D G2 |wo·h| |wi·h| / (cos θo (wo·h + η wi·h)²)` for transmission (the
    /// radiance form, with the 1/η² of Veach §5.2 folded in).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z == 0.0 {
            return Vec3::ZERO;
        }
        let Some((h, wi_h)) = half_vector(wo, wi, self.eta) else {
            return Vec3::ZERO;
        };
        let wo_h = wo.dot(h);
        let d = ggx::d(h, self.alpha);
        let g = ggx::g2(wo, wi, self.alpha, self.masking);
        let f = fresnel(wo_h, self.eta);
        if wi.z > 0.0 {
            return Vec3::splat(f * d * g / (4.0 * wo.z));
        }
        let denom = wo_h + self.eta * wi_h;
        let value = (1.0 - f) * d * g * (wo_h * wi_h).abs() / (wo.z * denom * denom);
        // Near index matching (η → 1) the transmission lobe tends to a delta: 0 where it overflows.
        if value.is_finite() {
            self.tint * value
        } else {
            Vec3::ZERO
        }
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3, lobe: Lobe) -> f32 {
        if wo.z <= 0.0 || wi.z == 0.0 {
            return 0.0;
        }
        match lobe {
            Lobe::Uniform | Lobe::Cosine => {
                0.5 * hemisphere_pdf(Vec3::new(wi.x, wi.y, wi.z.abs()), lobe == Lobe::Uniform)
            }
            Lobe::Bsdf => {
                let Some((h, wi_h)) = half_vector(wo, wi, self.eta) else {
                    return 0.0;
                };
                let wo_h = wo.dot(h);
                let vndf = ggx::vndf_pdf(wo, h, self.alpha);
                let f = fresnel(wo_h, self.eta);
                if wi.z > 0.0 {
                    // Reflection Jacobian dh/dωi = 1 / (4 wo·h).
                    f * vndf / (4.0 * wo_h)
                } else {
                    // Refraction Jacobian dh/dωi = η² |wi·h| / (wo·h + η wi·h)².
                    let denom = wo_h + self.eta * wi_h;
                    let pdf = (1.0 - f) * vndf * self.eta * self.eta * wi_h.abs() / (denom * denom);
                    if pdf.is_finite() {
                        pdf
                    } else {
                        0.0
                    }
                }
            }
        }
    }

    pub fn sample(&self, wo: Vec3, u: Vec2, u_lobe: f32, lobe: Lobe) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let (wi, pdf, weight) = match lobe {
            Lobe::Uniform | Lobe::Cosine => {
                let (wi, pdf) = sample_hemisphere(u, lobe == Lobe::Uniform);
                let wi = if u_lobe < 0.5 {
                    wi
                } else {
                    Vec3::new(wi.x, wi.y, -wi.z)
                };
                let pdf = 0.5 * pdf;
                (wi, pdf, self.eval(wo, wi) / pdf)
            }
            Lobe::Bsdf => {
                let h = ggx::sample_vndf(wo, self.alpha, u);
                let wo_h = wo.dot(h);
                if wo_h <= 0.0 {
                    return None;
                }
                let vndf = ggx::vndf_pdf(wo, h, self.alpha);
                let f = fresnel(wo_h, self.eta);
                if u_lobe < f {
                    let wi = 2.0 * wo_h * h - wo;
                    if wi.z <= 0.0 {
                        return None;
                    }
                    let pdf = f * vndf / (4.0 * wo_h);
                    // F D G2 / (4 cos θo) over F G1(wo) D / (4 cos θo).
                    let g = ggx::g2(wo, wi, self.alpha, self.masking) / ggx::g1(wo, self.alpha);
                    (wi, pdf, Vec3::splat(g))
                } else {
                    // Refraction about h (Snell); u_lobe ≥ F excludes total internal reflection.
                    let eta = self.eta;
                    let sin2_t = (1.0 - wo_h * wo_h) / (eta * eta);
                    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
                    // Normalized: at extreme η the rounding of 1 − (wo·h)² is amplified by 1/η².
                    let wi = ((wo_h / eta - cos_t) * h - wo / eta).normalize_or_zero();
                    if wi.z >= 0.0 {
                        return None;
                    }
                    let wi_h = wi.dot(h);
                    let denom = wo_h + eta * wi_h;
                    let pdf = (1.0 - f) * vndf * eta * eta * wi_h.abs() / (denom * denom);
                    // The eval over the pdf: tint G2 / (G1(wo) η²).
                    let g = ggx::g2(wo, wi, self.alpha, self.masking) / ggx::g1(wo, self.alpha);
                    (wi, pdf, self.tint * (g / (eta * eta)))
                }
            }
        };
        let valid = wi.z != 0.0 && pdf > 0.0 && pdf.is_finite() && weight.is_finite();
        valid.then_some(BsdfSample {
            wi,
            weight,
            pdf,
            delta: false,
            eta: if wi.z > 0.0 { 1.0 } else { self.eta },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::super::Bsdf;
    use super::*;
    use stratapt_scene::Strategy;

    fn glass(eta: f32, alpha: Vec2, masking: Masking) -> Bsdf<'static> {
        Bsdf::RoughDielectric(RoughDielectric {
            eta,
            tint: Vec3::new(1.0, 0.9, 0.7),
            alpha,
            masking,
        })
    }

    /// (η, α, masking): every roughness correlated, the rough ones also separable.
    fn configurations() -> Vec<(f32, Vec2, Masking)> {
        let mut out = Vec::new();
        for eta in [1.5f32, 1.0 / 1.5, 1.33] {
            for alpha in [
                Vec2::splat(0.05),
                Vec2::splat(0.3),
                Vec2::splat(1.0),
                Vec2::new(0.05, 0.5),
            ] {
                out.push((eta, alpha, Masking::Correlated));
                if alpha.max_element() >= 0.3 && eta != 1.33 {
                    out.push((eta, alpha, Masking::Separable));
                }
            }
        }
        out
    }

    #[test]
    fn consistent() {
        for (k, (eta, alpha, masking)) in configurations().into_iter().enumerate() {
            let bsdf = glass(eta, alpha, masking);
            for (i, strategy) in Strategy::ALL.into_iter().enumerate() {
                check_sample_consistency(&bsdf, strategy, 300 * k as u64 + i as u64);
            }
        }
    }

    /// Reflection is reciprocal as any BRDF; transmission with the 1/η² radiance scaling obeys
    /// the generalized reciprocity `f(wo, wi) / η_o² = f(wi, wo) / η_i²` (Veach 1997, §5.2): seen
    /// from `wi`'s side the relative index is 1/η.
    #[test]
    fn reciprocal_with_the_eta_squared_scaling() {
        let mut rng = stratapt_sampling::testing::TestRng(12);
        for (eta, alpha, masking) in configurations() {
            let (front, back) = (glass(eta, alpha, masking), glass(1.0 / eta, alpha, masking));
            for _ in 0..500 {
                let wo = random_upper(&mut rng);
                let wi = random_upper(&mut rng);
                let a = front.eval(wo, wi) / wi.z;
                let b = front.eval(wi, wo) / wo.z;
                assert!(rel_close(a.x, b.x, 1e-3), "reflection {a} vs {b}");
                // Transmission: wi below; seen from it, wo is below and the index is 1/η.
                let wt = Vec3::new(wi.x, wi.y, -wi.z);
                let a = front.eval(wo, wt).x / wt.z.abs();
                let b = back.eval(-wt, -wo).x / wo.z;
                // Near total internal reflection 1 − F ∝ cos θt, whose square 1 − sin²θi / η²
                // cancels: an f32 rounding of the directions moves it by ~1e-7 absolute.
                let cos2_t = half_vector(wo, wt, eta).map_or(1.0, |(h, _)| {
                    let cos = wo.dot(h);
                    1.0 - (1.0 - cos * cos) / (eta * eta)
                });
                let tol = (1e-6 / cos2_t.max(1e-9)).max(2e-3);
                assert!(
                    rel_close(a * eta * eta, b, tol) || (a - 0.0).abs() + b.abs() < 1e-6,
                    "η {eta} α {alpha} {masking:?}: f(wo,wi) η² {} vs f(wi,wo) {b}",
                    a * eta * eta
                );
            }
        }
    }

    /// Mean and standard error of the sampled energy, `weight · η²` (what leaves as flux).
    fn energy(bsdf: &Bsdf, wo: Vec3, strategy: Strategy, n: usize) -> (f64, f64) {
        let mut rng = stratapt_sampling::testing::TestRng(77);
        let (mut sum, mut sum_sq) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let u = rng.u2();
            if let Some(s) = bsdf.sample(wo, u, rng.f32(), strategy) {
                let energy = f64::from(s.weight.x * s.eta * s.eta);
                sum += energy;
                sum_sq += energy * energy;
            }
        }
        let mean = sum / n as f64;
        let err = ((sum_sq / n as f64 - mean * mean).max(0.0) / n as f64).sqrt();
        (mean, err)
    }

    /// A white furnace: untinted rough glass returns at most the light that falls on it; the
    /// radiance-scaled transmission carries 1/η², so the sum weighted back by η² per refraction
    /// (what leaves the other side as energy) is compared with 1.
    #[test]
    fn a_white_furnace_never_gains_energy() {
        for (eta, alpha, masking) in configurations() {
            let bsdf = Bsdf::RoughDielectric(RoughDielectric {
                eta,
                tint: Vec3::ONE,
                alpha,
                masking,
            });
            for cos in [0.2f32, 0.6, 1.0] {
                let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
                let (mean, err) = energy(&bsdf, wo, Strategy::Mis, 40_000);
                println!(
                    "η {eta} α ({}, {}) {masking:?} cos θo {cos}: albedo {mean:.4} ± {err:.4}",
                    alpha.x, alpha.y
                );
                assert!(
                    mean <= 1.0 + 4.0 * err + 1e-6,
                    "η {eta} α {alpha} cos {cos}: {mean}"
                );
                // Separable masking shadows more (down to 0.35 inside at α = 1, grazing).
                let floor = match masking {
                    Masking::Correlated => 0.4,
                    Masking::Separable => 0.3,
                };
                assert!(mean > floor, "η {eta} α {alpha} cos {cos}: {mean}");
                if alpha.max_element() <= 0.05 {
                    assert!(mean > 0.95, "η {eta} α {alpha} cos {cos}: {mean}");
                }
                // Sampling both hemispheres uniformly estimates the same integral from `eval`
                // alone (where the lobe is wide enough for it to converge).
                if alpha.min_element() >= 0.3 {
                    let (mu, eu) = energy(&bsdf, wo, Strategy::Uniform, 200_000);
                    let tol = 4.5 * (eu * eu + err * err).sqrt() + 1e-4;
                    assert!(
                        (mu - mean).abs() < tol,
                        "η {eta} α {alpha} cos {cos}: uniform {mu} ± {eu} vs vndf {mean} ± {err}"
                    );
                }
            }
        }
    }
}
