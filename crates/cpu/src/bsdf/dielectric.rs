//! Smooth dielectric: exact Fresnel reflectance, reflection or refraction chosen with
//! probability F by the lobe dimension; refracted radiance is scaled by 1/η² (camera paths:
//! Veach 1997, §5.2) and tinted by the material colour.

use super::BsdfSample;
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    /// Relative index of refraction η_t / η_i for light arriving from the `wo` side.
    pub eta: f32,
    /// Transmission tint.
    pub tint: Vec3,
}

/// The exact dielectric Fresnel reflectance (shared with the plastics' coating tables).
pub use stratapt_scene::coating::fresnel;

impl Dielectric {
    pub fn sample(&self, wo: Vec3, u_lobe: f32) -> Option<BsdfSample> {
        let cos_i = wo.z;
        if cos_i <= 0.0 {
            return None;
        }
        let f = fresnel(cos_i, self.eta);
        if u_lobe < f {
            // Specular reflection, chosen with probability F: weight F / F.
            return Some(BsdfSample::mirror(wo, Vec3::ONE, f));
        }
        // Refraction (Snell), chosen with probability 1 − F: weight (1 − F) / (1 − F) / η².
        let sin2_t = (1.0 - cos_i * cos_i) / (self.eta * self.eta);
        let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
        let wi = Vec3::new(-wo.x / self.eta, -wo.y / self.eta, -cos_t);
        let weight = self.tint / (self.eta * self.eta);
        Some(BsdfSample {
            wi,
            weight,
            pdf: 1.0 - f,
            delta: true,
            eta: self.eta,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_limits() {
        // Normal incidence: ((η − 1)/(η + 1))².
        assert!((fresnel(1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((fresnel(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert_eq!(fresnel(0.3, 1.0 / 1.5), 1.0); // beyond the critical angle
        assert!((fresnel(0.0, 1.5) - 1.0).abs() < 1e-6);
        assert!(fresnel(0.5, 1.0).abs() < 1e-7);
    }

    #[test]
    fn refraction_obeys_snell_and_is_unit() {
        let d = Dielectric {
            eta: 1.5,
            tint: Vec3::ONE,
        };
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let s = d.sample(wo, 0.99).unwrap();
        assert!(s.delta && s.wi.z < 0.0);
        assert!((s.wi.length() - 1.0).abs() < 1e-6);
        let sin_i = 0.6f32;
        let sin_t = (s.wi.x * s.wi.x + s.wi.y * s.wi.y).sqrt();
        assert!((sin_i - 1.5 * sin_t).abs() < 1e-6);
        assert!((s.weight - Vec3::splat(1.0 / 2.25)).abs().max_element() < 1e-6);
        // The reverse path refracts back to wo.
        let back = Dielectric {
            eta: 1.0 / 1.5,
            tint: Vec3::ONE,
        }
        .sample(-s.wi, 0.99)
        .unwrap();
        assert!((back.wi + wo).length() < 1e-5, "{back:?}");
    }

    #[test]
    fn lobe_probabilities_follow_fresnel_and_tir_always_reflects() {
        let d = Dielectric {
            eta: 1.5,
            tint: Vec3::ONE,
        };
        let wo = Vec3::new(0.0, 0.0, 1.0);
        assert!(d.sample(wo, 0.039).unwrap().wi.z > 0.0);
        assert!(d.sample(wo, 0.041).unwrap().wi.z < 0.0);
        let inside = Dielectric {
            eta: 1.0 / 1.5,
            tint: Vec3::ONE,
        };
        let grazing = Vec3::new(0.9, 0.0, (1.0f32 - 0.81).sqrt());
        let s = inside.sample(grazing, 0.999).unwrap();
        assert!(s.wi.z > 0.0 && s.weight == Vec3::ONE);
    }
}
