//! A thin dielectric sheet (pbrt-v4's `ThinDielectricBxDF`, Mitsuba 3's `thindielectric`): two
//! parallel smooth interfaces so close that the light bouncing between them leaves at the point
//! it entered. Summing the bounces, a sheet reflects `R' = R + T²R / (1 − R²)` (R the Fresnel
//! reflectance of one interface, T = 1 − R) and transmits the rest straight through, unbent.
//! Reflection or transmission is chosen with probability R' by the lobe dimension, so each
//! sample's weight is 1 (reflection) or the tint (transmission).

use super::dielectric::fresnel;
use super::BsdfSample;
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinDielectric {
    /// Index of refraction of the sheet relative to the medium around it (either way round:
    /// the sheet's reflectance does not depend on the side).
    pub eta: f32,
    /// Transmission tint.
    pub tint: Vec3,
}

impl ThinDielectric {
    /// The sheet's reflectance `R'` for light arriving at `cos_i` (≥ 0) from the normal.
    pub fn reflectance(&self, cos_i: f32) -> f32 {
        let r = fresnel(cos_i, self.eta);
        if r >= 1.0 {
            return 1.0;
        }
        let t = 1.0 - r;
        r + t * t * r / (1.0 - r * r)
    }

    pub fn sample(&self, wo: Vec3, u_lobe: f32) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let r = self.reflectance(wo.z);
        if u_lobe < r {
            // Mirror reflection, chosen with probability R': weight R' / R'.
            return Some(BsdfSample::mirror(wo, Vec3::ONE, r));
        }
        // Straight through, chosen with probability 1 − R': weight tint (1 − R') / (1 − R').
        Some(BsdfSample {
            wi: -wo,
            weight: self.tint,
            pdf: 1.0 - r,
            delta: true,
            eta: 1.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflectance_sums_the_bounces_between_the_interfaces() {
        let sheet = ThinDielectric {
            eta: 1.5,
            tint: Vec3::ONE,
        };
        // Normal incidence: R = 0.04, R' = 2R / (1 + R) (the closed form of the series).
        let r = 0.04f32;
        assert!((sheet.reflectance(1.0) - 2.0 * r / (1.0 + r)).abs() < 1e-6);
        // Index-matched: nothing reflects; grazing: everything does.
        let matched = ThinDielectric { eta: 1.0, ..sheet };
        assert!(matched.reflectance(0.7).abs() < 1e-7);
        assert!((sheet.reflectance(0.0) - 1.0).abs() < 1e-6);
        // The same sheet seen from its back: air on both sides, the same index.
        for entering in [true, false] {
            let material = stratapt_scene::records::Material {
                tag: stratapt_scene::records::material_kind::THIN_DIELECTRIC,
                ior: 1.5,
                color: [1.0; 3],
                ..Default::default()
            };
            let super::super::Bsdf::ThinDielectric(b) =
                super::super::Bsdf::new(&material, &[], entering)
            else {
                panic!("not a thin dielectric");
            };
            assert_eq!(b, sheet);
        }
    }

    #[test]
    fn transmission_passes_straight_through_with_the_tint() {
        let sheet = ThinDielectric {
            eta: 1.5,
            tint: Vec3::new(0.9, 0.5, 0.1),
        };
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let r = sheet.reflectance(0.8);
        let t = sheet.sample(wo, r + 1e-3).unwrap();
        assert!(t.delta && t.wi == -wo && t.weight == sheet.tint && t.eta == 1.0);
        assert!((t.pdf - (1.0 - r)).abs() < 1e-6);
        let m = sheet.sample(wo, r - 1e-3).unwrap();
        assert!(m.wi == Vec3::new(-0.6, 0.0, 0.8) && m.weight == Vec3::ONE);
        assert!(sheet.sample(Vec3::new(0.6, 0.0, -0.8), 0.5).is_none());
    }
}
