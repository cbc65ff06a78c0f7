//! Lambertian reflection: f = albedo / π.

use super::{hemisphere_pdf, sample_hemisphere, BsdfSample, Lobe};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diffuse {
    pub albedo: Vec3,
}

impl Diffuse {
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.albedo * (FRAC_1_PI * wi.z)
    }

    /// Uniform hemisphere for [`Lobe::Uniform`], cosine-weighted otherwise.
    pub fn pdf(&self, wo: Vec3, wi: Vec3, lobe: Lobe) -> f32 {
        if wo.z <= 0.0 {
            return 0.0;
        }
        hemisphere_pdf(wi, lobe == Lobe::Uniform)
    }

    pub fn sample(&self, wo: Vec3, u: Vec2, lobe: Lobe) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let uniform = lobe == Lobe::Uniform;
        let (wi, pdf) = sample_hemisphere(u, uniform);
        if wi.z <= 0.0 || pdf <= 0.0 {
            return None;
        }
        // Cosine sampling cancels f·cos exactly; uniform leaves 2·cos θ.
        let weight = if uniform {
            self.albedo * (2.0 * wi.z)
        } else {
            self.albedo
        };
        Some(BsdfSample::reflection(wi, weight, pdf))
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
        let bsdf = Bsdf::Diffuse(Diffuse {
            albedo: Vec3::new(1.0, 0.5, 0.0),
        });
        check_reciprocity(&bsdf, 1);
        for (i, strategy) in Strategy::ALL.into_iter().enumerate() {
            check_sample_consistency(&bsdf, strategy, 10 + i as u64);
            let wo = Vec3::new(0.3, 0.1, 0.9).normalize();
            let (mean, stderr) = weight_mean(&bsdf, wo, strategy, 20_000, 3);
            // Albedo 1 in red: ∫ f cos = 1 exactly.
            assert!(
                (mean.x - 1.0).abs() <= 4.5 * stderr.x + 1e-4,
                "{strategy}: {mean} ± {stderr}"
            );
            assert!(mean.x <= 1.0 + 3.0 * stderr.x + 1e-6);
        }
    }
}
