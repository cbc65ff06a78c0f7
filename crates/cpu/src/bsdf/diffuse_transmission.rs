//! Diffuse reflection and transmission (pbrt-v4's `DiffuseTransmissionBxDF`): `R / π` towards
//! `wo`'s side of the surface and `T / π` through it, for leaves, paper, lamp shades and blinds.
//!
//! The lobe dimension picks the side: under the BSDF's own sampling with probability
//! `max(R) / (max(R) + max(T))` for reflection, as pbrt-v4 does, and a cosine-weighted direction
//! there; under the `uniform` and `cosine` strategies each side with probability ½ (as the rough
//! dielectric's), and a uniform or cosine-weighted direction there.

use super::{hemisphere_pdf, sample_hemisphere, BsdfSample, Lobe};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseTransmission {
    pub reflectance: Vec3,
    pub transmittance: Vec3,
}

impl DiffuseTransmission {
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z == 0.0 {
            return Vec3::ZERO;
        }
        let colour = if wi.z > 0.0 {
            self.reflectance
        } else {
            self.transmittance
        };
        colour * (FRAC_1_PI * wi.z.abs())
    }

    /// The probability of sampling the reflection side.
    fn reflect_probability(&self, lobe: Lobe) -> f32 {
        if lobe != Lobe::Bsdf {
            return 0.5;
        }
        let (r, t) = (
            self.reflectance.max_element().max(0.0),
            self.transmittance.max_element().max(0.0),
        );
        if r + t > 0.0 {
            r / (r + t)
        } else {
            0.5
        }
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3, lobe: Lobe) -> f32 {
        if wo.z <= 0.0 || wi.z == 0.0 {
            return 0.0;
        }
        let p_reflect = self.reflect_probability(lobe);
        let side = if wi.z > 0.0 {
            p_reflect
        } else {
            1.0 - p_reflect
        };
        side * hemisphere_pdf(Vec3::new(wi.x, wi.y, wi.z.abs()), lobe == Lobe::Uniform)
    }

    pub fn sample(&self, wo: Vec3, u: Vec2, u_lobe: f32, lobe: Lobe) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let p_reflect = self.reflect_probability(lobe);
        let reflect = u_lobe < p_reflect;
        let (side, colour) = if reflect {
            (p_reflect, self.reflectance)
        } else {
            (1.0 - p_reflect, self.transmittance)
        };
        let uniform = lobe == Lobe::Uniform;
        let (wi, pdf) = sample_hemisphere(u, uniform);
        if wi.z <= 0.0 || pdf <= 0.0 || side <= 0.0 {
            return None;
        }
        // f·cos / pdf: the colour over the side's probability, times 2 cos θ for uniform
        // directions (cosine-weighted ones cancel the cosine exactly).
        let cosine = if uniform { 2.0 * wi.z } else { 1.0 };
        let weight = colour * (cosine / side);
        let wi = if reflect {
            wi
        } else {
            Vec3::new(wi.x, wi.y, -wi.z)
        };
        Some(BsdfSample::reflection(wi, weight, side * pdf))
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::super::Bsdf;
    use super::*;
    use stratapt_scene::Strategy;

    #[test]
    fn consistent_reciprocal_and_energy_conserving() {
        let bsdf = Bsdf::DiffuseTransmission(DiffuseTransmission {
            reflectance: Vec3::new(0.3, 0.6, 0.0),
            transmittance: Vec3::new(0.7, 0.2, 0.0),
        });
        check_reciprocity(&bsdf, 1);
        for (i, strategy) in Strategy::ALL.into_iter().enumerate() {
            check_sample_consistency(&bsdf, strategy, 10 + i as u64);
            let wo = Vec3::new(0.3, 0.1, 0.9).normalize();
            let (mean, stderr) = weight_mean(&bsdf, wo, strategy, 40_000, 3);
            // ∫ f |cos| over the sphere = R + T: 1 in red, 0.8 in green, exactly.
            for (c, expected) in [(0, 1.0), (1, 0.8)] {
                assert!(
                    (mean[c] - expected).abs() <= 4.5 * stderr[c] + 1e-4,
                    "{strategy}: {mean} ± {stderr}"
                );
            }
            assert_eq!(mean.z, 0.0);
        }
    }

    #[test]
    fn reciprocal_through_the_surface() {
        // f(wo, wi) = f(wi', wo') for wi below: T / π either way round.
        let b = DiffuseTransmission {
            reflectance: Vec3::splat(0.2),
            transmittance: Vec3::new(0.5, 0.4, 0.3),
        };
        let (wo, wi) = (
            Vec3::new(0.3, 0.2, 0.9).normalize(),
            Vec3::new(-0.1, 0.5, -0.6).normalize(),
        );
        let a = b.eval(wo, wi) / wi.z.abs();
        let back = b.eval(-wi, -wo) / wo.z.abs();
        assert!((a - back).abs().max_element() < 1e-6, "{a} {back}");
        assert!((a - b.transmittance * FRAC_1_PI).abs().max_element() < 1e-6);
    }
}
