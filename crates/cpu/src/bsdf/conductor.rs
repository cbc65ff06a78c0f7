//! Rough conductor: GGX microfacets (Walter et al. 2007) with anisotropic roughness (αu, αv)
//! along the shading frame's tangents and Smith masking-shadowing, height-correlated (Heitz
//! 2014) or separable ([`Masking`]), sampled by visible normals (Heitz 2018). The Fresnel reflectance is Schlick's from F0,
//! or the exact one of a complex index of refraction η + ik. With both α ≤ [`MIRROR_ALPHA`] it is
//! a perfect mirror.

use super::{hemisphere_pdf, sample_hemisphere, BsdfSample, Lobe};
use glam::{Vec2, Vec3};
use stratapt_sampling::warp::ggx::{self, Masking};
use stratapt_scene::records::MIRROR_ALPHA;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    pub fresnel: Fresnel,
    /// GGX roughness (αu, αv) along the shading frame's x and y axes.
    pub alpha: Vec2,
    pub masking: Masking,
}

/// How a conductor reflects as a function of the angle to the microfacet normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fresnel {
    /// Schlick's approximation from the normal-incidence reflectance F0.
    Schlick(Vec3),
    /// The exact unpolarized reflectance of a conductor with complex index of refraction
    /// `eta + i k` per RGB channel, times `tint`.
    Complex { eta: Vec3, k: Vec3, tint: Vec3 },
}

impl Fresnel {
    /// Reflectance for the cosine `cos` between the incident direction and the (micro)normal.
    pub fn eval(&self, cos: f32) -> Vec3 {
        match *self {
            Self::Schlick(f0) => schlick(f0, cos),
            Self::Complex { eta, k, tint } => tint * fresnel_complex(cos, eta, k),
        }
    }
}

/// Schlick's approximation F0 + (1 − F0)(1 − cos)⁵.
pub fn schlick(f0: Vec3, cos: f32) -> Vec3 {
    let m = (1.0 - cos).clamp(0.0, 1.0);
    let m2 = m * m;
    f0 + (Vec3::ONE - f0) * (m2 * m2 * m)
}

/// Unpolarized Fresnel reflectance of a conductor with complex index of refraction `eta + i k`
/// (relative to the outside medium), per channel, for `cos` the cosine of incidence.
///
/// The closed form of the s- and p-polarized amplitudes in real arithmetic (e.g. pbrt-v3's
/// `FrConductor`): with `t = η² − k² − sin²θ`, `a² + b² = √(t² + 4η²k²)`, `a = √((a² + b² + t)/2)`,
/// `Rs = (a² + b² + cos²θ − 2a cosθ) / (a² + b² + cos²θ + 2a cosθ)` and
/// `Rp = Rs (cos²θ (a² + b²) + sin⁴θ − 2a cosθ sin²θ) / (cos²θ (a² + b²) + sin⁴θ + 2a cosθ sin²θ)`,
/// `F = (Rs + Rp) / 2`. With `k = 0` it is the dielectric reflectance of `eta`; at grazing
/// incidence it is 1 (also for the index-matched `eta = 1, k = 0`, where the form is 0/0);
/// clamped to [0, 1] against rounding.
pub fn fresnel_complex(cos: f32, eta: Vec3, k: Vec3) -> Vec3 {
    let cos = cos.clamp(0.0, 1.0);
    let cos2 = cos * cos;
    let sin2 = 1.0 - cos2;
    let sin4 = sin2 * sin2;
    let t = eta * eta - k * k - Vec3::splat(sin2);
    let a2_b2 = (t * t + 4.0 * eta * eta * k * k).max(Vec3::ZERO);
    let a2_b2 = Vec3::new(a2_b2.x.sqrt(), a2_b2.y.sqrt(), a2_b2.z.sqrt());
    let a = (0.5 * (a2_b2 + t)).max(Vec3::ZERO);
    let a = Vec3::new(a.x.sqrt(), a.y.sqrt(), a.z.sqrt());
    let term1 = a2_b2 + Vec3::splat(cos2);
    let term2 = 2.0 * cos * a;
    let term3 = a2_b2 * cos2 + Vec3::splat(sin4);
    let term4 = term2 * sin2;
    let mut f = Vec3::ONE;
    for c in 0..3 {
        let (d_s, d_p) = (term1[c] + term2[c], term3[c] + term4[c]);
        if d_s > 0.0 && d_p > 0.0 {
            let rs = (term1[c] - term2[c]) / d_s;
            let rp = rs * (term3[c] - term4[c]) / d_p;
            f[c] = 0.5 * (rs + rp);
        }
    }
    // Rs's numerator (a − cos θ)² + b² rounds below 0 near the index-matched case.
    f.clamp(Vec3::ZERO, Vec3::ONE)
}

impl Conductor {
    /// A conductor with roughness `(alpha_u, alpha_v)`: a mirror when both are at most
    /// [`MIRROR_ALPHA`], otherwise each is raised to at least that (a GGX pdf with a smaller α
    /// overflows f32).
    pub fn new(fresnel: Fresnel, alpha_u: f32, alpha_v: f32) -> Self {
        let alpha = Vec2::new(alpha_u, alpha_v);
        let alpha = if alpha.max_element() <= MIRROR_ALPHA {
            Vec2::ZERO
        } else {
            alpha.max(Vec2::splat(MIRROR_ALPHA))
        };
        Self {
            fresnel,
            alpha,
            masking: Masking::Correlated,
        }
    }

    /// The same conductor with masking-shadowing of the form `masking`.
    /// The same conductor under a medium of index `eta` (a coat): a complex index divided by it,
    /// as pbrt-v4's `coatedconductor` does; Schlick's reflectance as it is.
    pub fn relative_to(self, eta: f32) -> Self {
        let fresnel = match self.fresnel {
            Fresnel::Complex { eta: e, k, tint } => Fresnel::Complex {
                eta: e / eta,
                k: k / eta,
                tint,
            },
            schlick => schlick,
        };
        Self { fresnel, ..self }
    }

    pub fn with_masking(self, masking: Masking) -> Self {
        Self { masking, ..self }
    }

    pub fn is_mirror(&self) -> bool {
        self.alpha.max_element() <= MIRROR_ALPHA
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if self.is_mirror() || wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let h = (wo + wi).normalize();
        let d = ggx::d(h, self.alpha);
        let g = ggx::g2(wo, wi, self.alpha, self.masking);
        // f · cos θi = F D G / (4 cos θo cos θi) · cos θi.
        self.fresnel.eval(wo.dot(h)) * (d * g / (4.0 * wo.z))
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
            return Some(BsdfSample::mirror(wo, self.fresnel.eval(wo.z), 1.0));
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
                let g = ggx::g2(wo, wi, self.alpha, self.masking) / ggx::g1(wo, self.alpha);
                (wi, pdf, self.fresnel.eval(wo.dot(h)) * g)
            }
        };
        (wi.z > 0.0 && pdf > 0.0 && weight.is_finite())
            .then_some(BsdfSample::reflection(wi, weight, pdf))
    }
}

#[cfg(test)]
mod tests {
    use super::super::dielectric;
    use super::super::test_util::*;
    use super::super::Bsdf;
    use super::*;
    use stratapt_scene::Strategy;

    /// Gold-like η and k (RGB), as the bundled scenes use.
    const GOLD_ETA: Vec3 = Vec3::new(0.143, 0.375, 1.442);
    const GOLD_K: Vec3 = Vec3::new(3.983, 2.386, 1.603);

    fn conductor(alpha: f32) -> Bsdf<'static> {
        Bsdf::Conductor(Conductor::new(
            Fresnel::Schlick(Vec3::new(1.0, 0.8, 0.1)),
            alpha,
            alpha,
        ))
    }

    /// The configurations every test runs: Schlick and complex Fresnel, isotropic and
    /// anisotropic roughness.
    fn conductors() -> Vec<(String, Bsdf<'static>)> {
        let mut out = Vec::new();
        let complex = Fresnel::Complex {
            eta: GOLD_ETA,
            k: GOLD_K,
            tint: Vec3::ONE,
        };
        for (au, av) in [
            (0.05, 0.05),
            (0.2, 0.2),
            (0.6, 0.6),
            (1.0, 1.0),
            (0.05, 0.5),
            (0.8, 0.1),
        ] {
            out.push((
                format!("schlick α ({au}, {av})"),
                Bsdf::Conductor(Conductor::new(
                    Fresnel::Schlick(Vec3::new(1.0, 0.8, 0.1)),
                    au,
                    av,
                )),
            ));
            out.push((
                format!("complex α ({au}, {av})"),
                Bsdf::Conductor(Conductor::new(complex, au, av)),
            ));
            out.push((
                format!("complex α ({au}, {av}) separable"),
                Bsdf::Conductor(Conductor::new(complex, au, av).with_masking(Masking::Separable)),
            ));
        }
        out
    }

    #[test]
    fn consistent_and_reciprocal() {
        for (k, (name, bsdf)) in conductors().into_iter().enumerate() {
            println!("{name}");
            check_reciprocity(&bsdf, 7 + k as u64);
            for (i, strategy) in Strategy::ALL.into_iter().enumerate() {
                check_sample_consistency(&bsdf, strategy, 100 * k as u64 + i as u64);
            }
        }
    }

    #[test]
    fn complex_fresnel_is_the_dielectric_one_without_absorption_and_exact_at_its_ends() {
        for eta in [1.0001f32, 1.33, 1.5, 2.4] {
            for i in 0..=100 {
                let cos = i as f32 / 100.0;
                let f = fresnel_complex(cos, Vec3::splat(eta), Vec3::ZERO);
                let d = dielectric::fresnel(cos, eta);
                assert!((f.x - d).abs() < 2e-6, "η {eta} cos {cos}: {f} vs {d}");
            }
        }
        // Normal incidence: ((η − 1)² + k²) / ((η + 1)² + k²); grazing: 1; index-matched: 0 at
        // normal incidence and 1 at grazing (not 0/0).
        let f = fresnel_complex(1.0, GOLD_ETA, GOLD_K);
        let n = (GOLD_ETA - Vec3::ONE) * (GOLD_ETA - Vec3::ONE) + GOLD_K * GOLD_K;
        let d = (GOLD_ETA + Vec3::ONE) * (GOLD_ETA + Vec3::ONE) + GOLD_K * GOLD_K;
        assert!((f - n / d).abs().max_element() < 1e-6, "{f} vs {}", n / d);
        assert_eq!(fresnel_complex(0.0, GOLD_ETA, GOLD_K), Vec3::ONE);
        assert_eq!(fresnel_complex(0.0, Vec3::ONE, Vec3::ZERO), Vec3::ONE);
        assert_eq!(fresnel_complex(1.0, Vec3::ONE, Vec3::ZERO), Vec3::ZERO);
        // A conductor's reflectance dips (slightly) before grazing and never leaves [0, 1].
        for i in 0..=1000 {
            let f = fresnel_complex(i as f32 / 1000.0, GOLD_ETA, GOLD_K);
            assert!(f.min_element() >= 0.0 && f.max_element() <= 1.0, "{f}");
        }
    }

    /// A white furnace: every conductor at F = 1 (η = 1, k → ∞ is unphysical; Schlick F0 = 1 is
    /// exactly 1) reflects at most the light that falls on it. What it loses is the energy of
    /// paths that hit a second microfacet: single-scattering GGX drops them (up to ~40 % at α = 1
    /// near grazing, Heitz et al. 2016).
    #[test]
    fn a_white_furnace_never_gains_energy_and_loses_little_when_smooth() {
        for (au, av) in [
            (0.02f32, 0.02f32),
            (0.1, 0.1),
            (0.5, 0.5),
            (1.0, 1.0),
            (0.05, 0.6),
            (0.6, 0.05),
        ] {
            for masking in [Masking::Correlated, Masking::Separable] {
                let bsdf = Bsdf::Conductor(
                    Conductor::new(Fresnel::Schlick(Vec3::ONE), au, av).with_masking(masking),
                );
                for cos in [0.2f32, 0.6, 1.0] {
                    for phi in [0.0f32, 1.0] {
                        let sin = (1.0 - cos * cos).sqrt();
                        let wo = Vec3::new(sin * phi.cos(), sin * phi.sin(), cos);
                        let (mean, stderr) = weight_mean(&bsdf, wo, Strategy::Mis, 20_000, 5);
                        assert!(
                            mean.x <= 1.0 + 3.0 * stderr.x + 1e-6,
                            "α ({au}, {av}) cos {cos}: {mean} ± {stderr}"
                        );
                        println!(
                            "α ({au}, {av}) {masking:?} cos θo {cos} φo {phi}: albedo {:.4}",
                            mean.x
                        );
                        assert!(mean.x > 0.3, "α ({au}, {av}) cos {cos}: albedo {mean}");
                        if au.max(av) <= 0.1 {
                            assert!(mean.x > 0.85, "α ({au}, {av}) cos {cos}: albedo {mean}");
                        }
                        // Uniform sampling estimates the same integral.
                        let (mu, su) = weight_mean(&bsdf, wo, Strategy::Uniform, 50_000, 9);
                        if au.min(av) >= 0.5 {
                            let tol = 4.5 * (su.x * su.x + stderr.x * stderr.x).sqrt() + 1e-4;
                            assert!(
                                (mu.x - mean.x).abs() < tol,
                                "α ({au}, {av}): uniform {mu} vs vndf {mean}"
                            );
                        }
                    }
                }
            }
        }
    }

    /// At α = 1 and normal incidence D = 1/π and Λ(wi) = (1/cos θi − 1)/2, so the albedo of a
    /// white single-scattering conductor has a closed form: ∫₀^{π/4} 2 sin θh cos θh ·
    /// 2 cos 2θh / (1 + cos 2θh) dθh = 1 − ln 2 (the half vectors beyond 45° reflect below the
    /// horizon). Both masking forms agree there (G1(wo) = 1 at normal incidence). Planted: the
    /// same estimate against a value 1.5 % off is rejected (an error of that size in D, G or the
    /// weight is more than 7 standard errors here).
    #[test]
    fn white_albedo_at_alpha_one_and_normal_incidence_is_one_minus_ln_2() {
        let exact = 1.0 - std::f32::consts::LN_2;
        let white = Conductor::new(Fresnel::Schlick(Vec3::ONE), 1.0, 1.0);
        for (bsdf, strategy) in [
            (white, Strategy::Mis),
            (white, Strategy::Uniform),
            (white.with_masking(Masking::Separable), Strategy::Mis),
        ] {
            let bsdf = Bsdf::Conductor(bsdf);
            let (mean, stderr) = weight_mean(&bsdf, Vec3::Z, strategy, 400_000, 21);
            let z = (mean.x - exact) / stderr.x;
            println!(
                "{strategy}: {} ± {} (exact {exact}, z {z:.2})",
                mean.x, stderr.x
            );
            assert!(z.abs() < 4.0, "{strategy}: {mean} ± {stderr} vs {exact}");
            for planted in [exact * 1.015, exact / 1.015] {
                let z = (mean.x - planted) / stderr.x;
                assert!(
                    z.abs() > 4.0,
                    "{strategy}: {planted} not rejected (z {z:.2})"
                );
            }
        }
    }

    #[test]
    fn anisotropy_stretches_the_highlight_along_the_rougher_axis() {
        // wo at normal incidence: the reflected lobe spreads αu / αv as far along x as along y.
        let bsdf = Bsdf::Conductor(Conductor::new(Fresnel::Schlick(Vec3::ONE), 0.4, 0.05));
        let mut rng = stratapt_sampling::testing::TestRng(11);
        let (mut sx, mut sy) = (0.0f64, 0.0f64);
        for _ in 0..20_000 {
            if let Some(s) = bsdf.sample(Vec3::Z, rng.u2(), rng.f32(), Strategy::Bsdf) {
                sx += (s.wi.x as f64).abs();
                sy += (s.wi.y as f64).abs();
            }
        }
        assert!(sx > 5.0 * sy, "spread x {sx} y {sy}");
    }

    #[test]
    fn alphas_at_most_the_mirror_threshold_make_a_mirror_and_others_are_raised_to_it() {
        let f = Fresnel::Schlick(Vec3::ONE);
        assert!(Conductor::new(f, 0.0, MIRROR_ALPHA).is_mirror());
        let c = Conductor::new(f, 0.5, 0.0);
        assert!(!c.is_mirror());
        assert_eq!(c.alpha, Vec2::new(0.5, MIRROR_ALPHA));
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
