//! Plastic and rough plastic exactly as Mitsuba 3's `plastic` and `roughplastic` define them: a
//! diffuse base under a dielectric coating of relative index η. The coating reflects `F`
//! (smooth: a mirror; rough: GGX microfacets, `F D G2 / (4 cos θo)`, isotropic), scaled by the
//! specular reflectance. Light the coating lets in scatters diffusely in the base and between the
//! base and the coating's inside, and leaves as
//!
//! `f · cos θi = diffuse / (1 − R_int) · (cos θi / π) · (1 / η²) · T(θo) T(θi)`,
//!
//! with `T = 1 − F` and `R_int` the diffuse Fresnel reflectance of the inside (Mitsuba's fit)
//! for the smooth coating, the tabulated rough transmittance and Mitsuba's internal reflectance
//! for the rough one ([`stratapt_scene::coating`]). With `nonlinear`, `R_int` is multiplied by
//! the diffuse colour in the denominator. Sampling picks the coating with probability
//! `(1 − T(θo)) w / ((1 − T(θo)) w + T(θo) (1 − w))`, `w` the specular sampling weight, else a
//! cosine-weighted direction. Like every strata BSDF it is two-sided: seen from behind it is the
//! same plastic (Mitsuba's is black there; the comparison scenes are closed objects).
//!
//! Under the `uniform` / `cosine` strategies the rough plastic samples its whole lobe on the
//! hemisphere; the smooth one still takes its mirror (a delta) with the lobe probability.

use super::{hemisphere_pdf, sample_hemisphere, BsdfSample, Lobe};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;
use stratapt_sampling::warp::{self, ggx, ggx::Masking};
use stratapt_scene::coating::{fresnel, transmittance};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plastic<'a> {
    /// The base's diffuse reflectance.
    pub diffuse: Vec3,
    /// Scales the coating's reflection.
    pub specular: Vec3,
    /// The coating's relative index of refraction (inside / outside).
    pub eta: f32,
    /// The coating's internal reflectance `R_int`.
    pub internal: f32,
    /// Mitsuba's specular sampling weight `w`.
    pub specular_weight: f32,
    pub nonlinear: bool,
    /// `None` for the smooth coating.
    pub rough: Option<RoughCoat<'a>>,
}

/// A rough coating: its GGX α, masking and transmittance table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughCoat<'a> {
    pub alpha: f32,
    pub masking: Masking,
    /// [`stratapt_scene::coating::TRANSMITTANCE_RES`] entries.
    pub transmittance: &'a [f32],
}

impl Plastic<'_> {
    /// The coating's transmittance at cosine `cos` (from outside).
    fn transmittance(&self, cos: f32) -> f32 {
        match &self.rough {
            None => 1.0 - fresnel(cos, self.eta),
            Some(r) => transmittance(r.transmittance, cos),
        }
    }

    /// Probability of sampling the coating rather than the base, seen from `wo`.
    fn specular_probability(&self, wo: Vec3) -> f32 {
        let t = self.transmittance(wo.z);
        let specular = (1.0 - t) * self.specular_weight;
        let diffuse = t * (1.0 - self.specular_weight);
        if specular + diffuse > 0.0 {
            specular / (specular + diffuse)
        } else {
            0.0
        }
    }

    /// The base's contribution `f · cos θi`.
    fn base(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let scatter = if self.nonlinear {
            self.diffuse * self.internal
        } else {
            Vec3::splat(self.internal)
        };
        let diffuse = self.diffuse / (Vec3::ONE - scatter);
        let t = self.transmittance(wo.z) * self.transmittance(wi.z);
        diffuse * (FRAC_1_PI * wi.z * t / (self.eta * self.eta))
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let mut f = self.base(wo, wi);
        if let Some(r) = &self.rough {
            let alpha = Vec2::splat(r.alpha);
            let h = (wo + wi).normalize();
            let d = ggx::d(h, alpha);
            let g = ggx::g2(wo, wi, alpha, r.masking);
            f += self.specular * (fresnel(wo.dot(h), self.eta) * d * g / (4.0 * wo.z));
        }
        f
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3, lobe: Lobe) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        self.pdf_with(wo, wi, lobe, self.specular_probability(wo))
    }

    /// [`Self::pdf`] for `wo`, `wi` above the surface, with the coating's probability seen
    /// from `wo` (which [`Self::sample`] has computed already).
    fn pdf_with(&self, wo: Vec3, wi: Vec3, lobe: Lobe, p_specular: f32) -> f32 {
        match (lobe, &self.rough) {
            (Lobe::Uniform | Lobe::Cosine, Some(_)) => hemisphere_pdf(wi, lobe == Lobe::Uniform),
            (Lobe::Uniform | Lobe::Cosine, None) => {
                (1.0 - p_specular) * hemisphere_pdf(wi, lobe == Lobe::Uniform)
            }
            (Lobe::Bsdf, None) => (1.0 - p_specular) * warp::cosine_hemisphere_pdf(wi.z),
            (Lobe::Bsdf, Some(r)) => {
                let glossy = ggx::reflection_pdf(wo, wi, Vec2::splat(r.alpha));
                p_specular * glossy + (1.0 - p_specular) * warp::cosine_hemisphere_pdf(wi.z)
            }
        }
    }

    pub fn sample(&self, wo: Vec3, u: Vec2, u_lobe: f32, lobe: Lobe) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let p_specular = self.specular_probability(wo);
        let wi = match (&self.rough, lobe) {
            (None, _) if u_lobe < p_specular => {
                // The coating's mirror: weight F · specular / P(specular).
                let f = fresnel(wo.z, self.eta);
                let weight = self.specular * (f / p_specular);
                return Some(BsdfSample::mirror(wo, weight, p_specular));
            }
            (_, Lobe::Uniform | Lobe::Cosine) => sample_hemisphere(u, lobe == Lobe::Uniform).0,
            (Some(r), Lobe::Bsdf) if u_lobe < p_specular => {
                ggx::reflect(wo, ggx::sample_vndf(wo, Vec2::splat(r.alpha), u))
            }
            (_, Lobe::Bsdf) => warp::cosine_hemisphere(u),
        };
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf_with(wo, wi, lobe, p_specular);
        let weight = self.eval(wo, wi) / pdf;
        (pdf > 0.0 && weight.is_finite()).then_some(BsdfSample::reflection(wi, weight, pdf))
    }
}

#[cfg(test)]
mod tests {
    use super::super::rough_dielectric::RoughDielectric;
    use super::super::test_util::*;
    use super::super::Bsdf;
    use super::*;
    use stratapt_scene::coating::{fresnel_diffuse_reflectance, RoughCoating};
    use stratapt_scene::Strategy;

    /// Plastics as the loader makes them: `(name, plastic, its table)`.
    fn plastics() -> Vec<(String, Plastic<'static>)> {
        let mut out = Vec::new();
        for (eta, alpha, masking, nonlinear) in [
            (1.49f32, 0.0f32, Masking::Separable, false),
            (1.49, 0.0, Masking::Separable, true),
            (1.8, 0.0, Masking::Separable, false),
            (1.49, 0.05, Masking::Separable, false),
            (1.49, 0.3, Masking::Correlated, true),
            (1.49, 0.3, Masking::Separable, false),
            (1.3, 1.0, Masking::Separable, false),
        ] {
            let (internal, rough) = if alpha > 0.0 {
                let coating = RoughCoating::new(eta, alpha, masking);
                let table: &'static [f32] = Box::leak(Box::new(coating.transmittance));
                let coat = RoughCoat {
                    alpha,
                    masking,
                    transmittance: table,
                };
                (coating.internal_reflectance, Some(coat))
            } else {
                (fresnel_diffuse_reflectance(1.0 / eta), None)
            };
            let diffuse = Vec3::new(0.8, 0.5, 0.1);
            out.push((
                format!("η {eta} α {alpha} {masking:?} nonlinear {nonlinear}"),
                Plastic {
                    diffuse,
                    specular: Vec3::new(1.0, 0.9, 0.8),
                    eta,
                    internal,
                    specular_weight: 0.9 / (0.9 + diffuse.element_sum() / 3.0),
                    nonlinear,
                    rough,
                },
            ));
        }
        out
    }

    #[test]
    fn consistent_and_reciprocal() {
        for (k, (name, plastic)) in plastics().into_iter().enumerate() {
            println!("{name}");
            let bsdf = Bsdf::Plastic(plastic);
            check_reciprocity(&bsdf, 40 + k as u64);
            for (i, strategy) in Strategy::ALL.into_iter().enumerate() {
                check_sample_consistency(&bsdf, strategy, 500 * k as u64 + i as u64);
            }
        }
    }

    /// A white smooth plastic in a white furnace returns exactly the light that falls on it
    /// when `R_int` is the exact diffuse reflectance of the coating's inside (the coating's
    /// reflection F plus, by the Stokes relation `1 − F̄(η) = η² (1 − F̄(1/η))`, all of the
    /// rest); Mitsuba's fit for `R_int` is within 0.1 % of it at η = 1.49, so the estimate is 1
    /// to within that and its noise. Rough coatings lose the light that scatters between
    /// microfacets and what Mitsuba's rule for `R_int` leaves out (a few per cent of the base's
    /// light even at small α), and most of all the light the coating reflects back inside at
    /// rough microfacets into directions they mask: `R_int` falls steeply with α, as in Mitsuba
    /// (`coating::tests`), so a white rough plastic keeps less the rougher it is. They never
    /// gain (measured: docs/measurements/materials.md#plastics-energy-and-speed).
    #[test]
    fn a_white_furnace_returns_at_most_the_light_that_falls() {
        for (name, mut plastic) in plastics() {
            if plastic.nonlinear {
                continue;
            }
            plastic.diffuse = Vec3::ONE;
            plastic.specular = Vec3::ONE;
            plastic.specular_weight = 0.5;
            let bsdf = Bsdf::Plastic(plastic);
            for cos in [0.1f32, 0.5, 1.0] {
                let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
                let (mean, err) = weight_mean(&bsdf, wo, Strategy::Mis, 100_000, 31);
                println!("{name} cos θo {cos}: albedo {:.4} ± {:.4}", mean.x, err.x);
                match plastic.rough {
                    None if plastic.eta == 1.49 => assert!(
                        (mean.x - 1.0).abs() < 4.0 * err.x + 1.5e-3,
                        "{name}: {mean} ± {err}"
                    ),
                    None => assert!(mean.x < 1.0 + 4.0 * err.x + 5e-3, "{name}: {mean}"),
                    Some(_) => {
                        assert!(mean.x < 1.0 + 4.0 * err.x, "{name}: {mean} ± {err}");
                        assert!(mean.x > 0.1, "{name}: {mean}");
                    }
                }
            }
        }
    }

    /// The rough coating's table against a Monte Carlo estimate of the same transmittance
    /// through the rough dielectric (its refracted energy `weight · η²`), at five angles; a
    /// planted 1 % error in the table is rejected.
    #[test]
    fn coating_tables_are_the_rough_dielectrics_transmittance() {
        for (eta, alpha, masking) in [
            (1.49f32, 0.3f32, Masking::Separable),
            (1.49, 0.3, Masking::Correlated),
            (1.3, 0.8, Masking::Separable),
        ] {
            let coating = RoughCoating::new(eta, alpha, masking);
            let glass = Bsdf::RoughDielectric(RoughDielectric {
                eta,
                tint: Vec3::ONE,
                alpha: Vec2::splat(alpha),
                masking,
            });
            for i in [3usize, 16, 32, 50, 63] {
                let cos = i as f32 / 63.0;
                let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
                let mut rng = stratapt_sampling::testing::TestRng(9 + i as u64);
                let n = 200_000;
                let (mut sum, mut sum_sq) = (0.0f64, 0.0f64);
                for _ in 0..n {
                    if let Some(s) = glass.sample(wo, rng.u2(), rng.f32(), Strategy::Mis) {
                        if s.wi.z < 0.0 {
                            let e = f64::from(s.weight.x * eta * eta);
                            sum += e;
                            sum_sq += e * e;
                        }
                    }
                }
                let mean = sum / n as f64;
                let err = ((sum_sq / n as f64 - mean * mean) / n as f64).sqrt();
                let table = f64::from(coating.transmittance[i]);
                let z = (table - mean) / err;
                println!("η {eta} α {alpha} {masking:?} cos {cos:.3}: table {table:.5} MC {mean:.5} ± {err:.5} (z {z:.2})");
                assert!(z.abs() < 4.5, "cos {cos}: table {table} vs {mean} ± {err}");
                let planted = (table * 1.01 - mean) / err;
                assert!(planted.abs() > 4.5, "a 1 % error passes: z {planted}");
            }
        }
    }

    #[test]
    fn nonlinear_saturates_the_colour() {
        let (_, linear) = plastics().remove(0);
        let nonlinear = Plastic {
            nonlinear: true,
            ..linear
        };
        let (wo, wi) = (
            Vec3::new(0.0, 0.6, 0.8),
            Vec3::new(0.3, 0.0, 0.95).normalize(),
        );
        let (a, b) = (linear.eval(wo, wi), nonlinear.eval(wo, wi));
        // Same where the colour is white-ish, darker where it is dim: the ratio falls with it.
        assert!(
            b.x < a.x && b.z < a.z && (b.z / a.z) < (b.x / a.x),
            "{a} vs {b}"
        );
    }
}
