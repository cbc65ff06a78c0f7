//! Rough conductor: GGX microfacets (Walter et al. 2007) with Schlick's Fresnel from F0 = the
//! material colour and height-correlated Smith masking-shadowing (Heitz 2014), sampled by
//! visible normals (Heitz 2018). At α ≤ [`MIRROR_ALPHA`] it is a perfect mirror.

use super::{hemisphere_pdf, sample_hemisphere, BsdfSample, Lobe};
use glam::{Vec2, Vec3};
use stratapt_sampling::warp::ggx;
use stratapt_scene::records::MIRROR_ALPHA;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    /// Normal-incidence reflectance.
    pub f0: Vec3,
    /// GGX roughness α.
    pub alpha: f32,
}

/// Schlick's approximation F0 + (1 − F0)(1 − cos)⁵.
pub fn schlick(f0: Vec3, cos: f32) -> Vec3 {
    let m = (1.0 - cos).clamp(0.0, 1.0);
    let m2 = m * m;
    f0 + (Vec3::ONE - f0) * (m2 * m2 * m)
}

impl Conductor {
    pub fn is_mirror(&self) -> bool {
        self.alpha <= MIRROR_ALPHA
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if self.is_mirror() || wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let h = (wo + wi).normalize();
        let d = ggx::d(h, self.alpha);
        let g = ggx::g2(wo, wi, self.alpha);
        // f · cos θi = F D G / (4 cos θo cos θi) · cos θi.
        schlick(self.f0, wo.dot(h)) * (d * g / (4.0 * wo.z))
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3, lobe: Lobe) -> f32 {
        if self.is_mirror() || wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        match lobe {
            Lobe::Uniform | Lobe::Cosine => hemisphere_pdf(wi, lobe == Lobe::Uniform),
            Lobe::Bsdf => {
                let h = (wo + wi).normalize();
                // Reflection Jacobian dh/dωi = 1 / (4 wo·h).
                ggx::vndf_pdf(wo, h, self.alpha) / (4.0 * wo.dot(h))
            }
        }
    }

    pub fn sample(&self, wo: Vec3, u: Vec2, lobe: Lobe) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        if self.is_mirror() {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            let weight = schlick(self.f0, wo.z);
            return Some(BsdfSample {
                wi,
                weight,
                pdf: 1.0,
                delta: true,
                eta: 1.0,
            });
        }
        let (wi, pdf, weight) = match lobe {
            Lobe::Uniform | Lobe::Cosine => {
                let (wi, pdf) = sample_hemisphere(u, lobe == Lobe::Uniform);
                (wi, pdf, self.eval(wo, wi) / pdf)
            }
            Lobe::Bsdf => {
                let h = ggx::sample_vndf(wo, self.alpha, u);
                let wi = 2.0 * wo.dot(h) * h - wo;
                if wi.z <= 0.0 {
                    return None;
                }
                let pdf = ggx::vndf_pdf(wo, h, self.alpha) / (4.0 * wo.dot(h));
                // F D G2 / (4 cos θo) over G1(wo) D / (4 cos θo) = F G2 / G1.
                let g = ggx::g2(wo, wi, self.alpha) / ggx::g1(wo, self.alpha);
                (wi, pdf, schlick(self.f0, wo.dot(h)) * g)
            }
        };
        (wi.z > 0.0 && pdf > 0.0 && weight.is_finite()).then_some(BsdfSample {
            wi,
            weight,
            pdf,
            delta: false,
            eta: 1.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::super::Bsdf;
    use super::*;
    use stratapt_scene::Strategy;

    fn conductor(alpha: f32) -> Bsdf {
        Bsdf::Conductor(Conductor {
            f0: Vec3::new(1.0, 0.8, 0.1),
            alpha,
        })
    }

    #[test]
    fn consistent_and_reciprocal() {
        for (k, alpha) in [0.05f32, 0.2, 0.6, 1.0].into_iter().enumerate() {
            let bsdf = conductor(alpha);
            check_reciprocity(&bsdf, 7 + k as u64);
            for (i, strategy) in Strategy::ALL.into_iter().enumerate() {
                check_sample_consistency(&bsdf, strategy, 100 * k as u64 + i as u64);
            }
        }
    }

    #[test]
    fn energy_never_exceeds_one_and_white_furnace_albedo_is_high_for_smooth_ggx() {
        for alpha in [0.02f32, 0.1, 0.5, 1.0] {
            let bsdf = conductor(alpha);
            for cos in [0.2f32, 0.6, 1.0] {
                let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
                let (mean, stderr) = weight_mean(&bsdf, wo, Strategy::Mis, 20_000, 5);
                // F0 = 1 in red: the directional albedo is the fraction not lost to masking.
                assert!(
                    mean.x <= 1.0 + 3.0 * stderr.x + 1e-6,
                    "α {alpha} cos {cos}: {mean} ± {stderr}"
                );
                assert!(mean.x > 0.0);
                if alpha <= 0.1 {
                    assert!(mean.x > 0.8, "α {alpha} cos {cos}: albedo {mean}");
                }
                // Uniform sampling estimates the same integral.
                let (mu, su) = weight_mean(&bsdf, wo, Strategy::Uniform, 50_000, 9);
                if alpha >= 0.5 {
                    let tol = 4.5 * (su.x * su.x + stderr.x * stderr.x).sqrt() + 1e-4;
                    assert!(
                        (mu.x - mean.x).abs() < tol,
                        "α {alpha}: uniform {mu} vs vndf {mean}"
                    );
                }
            }
        }
    }

    #[test]
    fn mirror_is_delta_and_reflects() {
        let bsdf = conductor(0.0);
        assert!(bsdf.is_delta());
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let s = bsdf
            .sample(wo, Vec2::new(0.3, 0.7), 0.5, Strategy::Uniform)
            .unwrap();
        assert!(s.delta && (s.wi - Vec3::new(-0.6, 0.0, 0.8)).length() < 1e-6);
        assert_eq!(bsdf.eval(wo, s.wi), Vec3::ZERO);
        assert_eq!(bsdf.pdf(wo, s.wi, Strategy::Mis), 0.0);
    }
}
