//! A plastic's dielectric coating, as Mitsuba 3's `plastic` and `roughplastic` define it: the
//! exact dielectric Fresnel reflectance, the diffuse Fresnel reflectance of the smooth coating's
//! inside (Mitsuba's fit), and the rough coating's tables (its transmittance per incident angle
//! and its internal reflectance), computed once at load for both renderers.
//!
//! The rough coating's quantities are integrals over GGX microfacets sampled by visible normals,
//! by Gauss–Legendre quadrature as Mitsuba computes them (`eval_transmittance`,
//! `eval_reflectance` in its `microfacet.h`): 32² nodes for the transmittance from outside, 128²
//! for the reflectance from inside (total internal reflection makes that integrand kinked). The
//! transmittance is tabulated at [`TRANSMITTANCE_RES`] cosines `max(10⁻⁶, i / 63)` and looked up
//! linearly ([`transmittance`]); the internal reflectance is Mitsuba's `2 · mean_i(R(μᵢ) μᵢ)` over
//! the same cosines, a coarse rule that reads a few per cent below the integral `2 ∫ R(μ) μ dμ`
//! and is kept because it is the definition the images are checked against.

use glam::{Vec2, Vec3};
use stratapt_sampling::warp::ggx::{self, Masking};

/// Entries of a rough coating's transmittance table (Mitsuba's `MI_ROUGH_TRANSMITTANCE_RES`).
pub const TRANSMITTANCE_RES: usize = 64;

/// Unpolarized Fresnel reflectance of a dielectric interface for `cos_i ≥ 0` on the incident
/// side and relative index `eta = η_t / η_i`; 1 under total internal reflection.
pub fn fresnel(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_parallel * r_parallel + r_perpendicular * r_perpendicular)
}

/// The hemispherical average of the Fresnel reflectance, `2 ∫ F(μ, eta) μ dμ`, by Mitsuba 3's
/// `fresnel_diffuse_reflectance`: Egan and Hilgeman's (1973) fit for `eta < 1`, d'Eon and
/// Irving's (2011) above. A smooth plastic's coating reflects this much of the diffuse light
/// back from inside, at `eta = 1 / η`.
pub fn fresnel_diffuse_reflectance(eta: f32) -> f32 {
    let inv = 1.0 / eta;
    if eta < 1.0 {
        0.0636 * inv + eta * (eta * -1.4399 + 0.7099) + 0.6681
    } else {
        let c = [0.919317f32, -3.4793, 6.75335, -7.80989, 4.98554, -1.36881];
        c.iter().rev().fold(0.0, |acc, &c| acc * inv + c)
    }
}

/// What the renderers look up for a rough coating.
#[derive(Clone, Debug, PartialEq)]
pub struct RoughCoating {
    /// Transmittance from outside through the rough interface at the cosines
    /// `max(10⁻⁶, i / 63)`: `∫ (1 − F) G2 / G1(wo)` under the visible normals of `wo`.
    pub transmittance: [f32; TRANSMITTANCE_RES],
    /// Mitsuba's internal reflectance: `2 · mean_i(R(μᵢ) μᵢ)`, R the rough interface's
    /// reflectance seen from inside (relative index 1/η, total internal reflection included).
    pub internal_reflectance: f32,
}

impl RoughCoating {
    /// The tables of a coating of relative index `eta` (inside / outside, ≠ 1) and GGX `alpha`.
    pub fn new(eta: f32, alpha: f32, masking: Masking) -> Self {
        let alpha = Vec2::splat(alpha);
        let cosines =
            (0..TRANSMITTANCE_RES).map(|i| (i as f32 / (TRANSMITTANCE_RES - 1) as f32).max(1e-6));
        let mut transmittance = [0.0; TRANSMITTANCE_RES];
        let mut internal = 0.0f64;
        for (i, mu) in cosines.enumerate() {
            let wi = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
            transmittance[i] = interface(wi, eta, alpha, masking, Side::Transmitted) as f32;
            internal += interface(wi, 1.0 / eta, alpha, masking, Side::Reflected) * f64::from(mu);
        }
        Self {
            transmittance,
            internal_reflectance: (2.0 * internal / TRANSMITTANCE_RES as f64) as f32,
        }
    }
}

/// A rough coating's transmittance at `cos` from `table`, linearly between its entries (as
/// Mitsuba's `lerp_gather`), `cos` clamped to [0, 1]. The GPU kernel computes the same
/// (`bsdf_plastic_transmittance` in `shaders/bsdf.wgsl`).
pub fn transmittance(table: &[f32], cos: f32) -> f32 {
    let x = cos.clamp(0.0, 1.0) * (TRANSMITTANCE_RES - 1) as f32;
    let i = (x as usize).min(TRANSMITTANCE_RES - 2);
    let f = x - i as f32;
    table[i] * (1.0 - f) + table[i + 1] * f
}

#[derive(Clone, Copy, PartialEq)]
enum Side {
    Reflected,
    Transmitted,
}

/// The fraction of light arriving along `-wi` that one GGX interface of relative index `eta`
/// sends to `side`, single scattering: the mean of `F` (reflected) or `1 − F` (transmitted)
/// times the masking of the outgoing direction given `wi`'s, under `wi`'s visible normals.
fn interface(wi: Vec3, eta: f32, alpha: Vec2, masking: Masking, side: Side) -> f64 {
    let n = if eta > 1.0 { 32 } else { 128 };
    let (nodes, weights) = gauss_legendre(n);
    let mut sum = 0.0f64;
    for (x, wx) in nodes.iter().zip(&weights) {
        for (y, wy) in nodes.iter().zip(&weights) {
            let u = Vec2::new((0.5 * x + 0.5) as f32, (0.5 * y + 0.5) as f32);
            let m = ggx::sample_vndf(wi, alpha, u);
            let cos = wi.dot(m);
            let f = fresnel(cos, eta);
            let (wo, weight) = match side {
                Side::Reflected => (ggx::reflect(wi, m), f),
                Side::Transmitted => {
                    let sin2_t = (1.0 - cos * cos) / (eta * eta);
                    if sin2_t >= 1.0 {
                        continue;
                    }
                    let cos_t = (1.0 - sin2_t).sqrt();
                    ((cos / eta - cos_t) * m - wi / eta, 1.0 - f)
                }
            };
            let leaves = match side {
                Side::Reflected => wo.z > 0.0,
                Side::Transmitted => wo.z < 0.0,
            };
            // Masking of the outgoing direction given the incident one's: G2 / G1(wi).
            if !leaves || wo.dot(m) * wo.z <= 0.0 {
                continue;
            }
            let shadow = ggx::g2(wi, wo, alpha, masking) / ggx::g1(wi, alpha);
            sum += wx * wy * 0.25 * f64::from(weight * shadow);
        }
    }
    sum
}

/// Nodes and weights of the `n`-point Gauss–Legendre rule on [−1, 1] (Newton's method on the
/// Legendre polynomial from Chebyshev starting points).
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = vec![0.0; n];
    let mut weights = vec![0.0; n];
    for i in 0..n.div_ceil(2) {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut derivative = 0.0;
        for _ in 0..100 {
            // P_n(x) and P_n'(x) by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                (p0, p1) = (p1, p2);
            }
            let p = if n == 0 { 1.0 } else { p1 };
            derivative = n as f64 * (x * p - p0) / (x * x - 1.0);
            let step = p / derivative;
            x -= step;
            if step.abs() < 1e-15 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * derivative * derivative);
        nodes[i] = -x;
        nodes[n - 1 - i] = x;
        weights[i] = w;
        weights[n - 1 - i] = w;
    }
    (nodes, weights)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials_of_degree_2n_minus_1_exactly() {
        for n in [1usize, 2, 5, 32, 128] {
            let (x, w) = gauss_legendre(n);
            for degree in 0..2 * n {
                let q: f64 = x
                    .iter()
                    .zip(&w)
                    .map(|(x, w)| w * x.powi(degree as i32))
                    .sum();
                let exact = if degree % 2 == 1 {
                    0.0
                } else {
                    2.0 / (degree + 1) as f64
                };
                assert!(
                    (q - exact).abs() < 1e-11,
                    "n {n} degree {degree}: {q} vs {exact}"
                );
            }
        }
    }

    /// The fit against the integral it approximates, `2 ∫ F(μ) μ dμ` by a fine midpoint rule:
    /// within 0.3 % for the indices plastics use, inside (η < 1) and out.
    #[test]
    fn diffuse_fresnel_reflectance_is_close_to_its_integral() {
        for eta in [1.3f32, 1.49, 1.6, 2.0, 1.0 / 1.3, 1.0 / 1.49, 1.0 / 1.6] {
            let n = 200_000;
            let integral: f64 = (0..n)
                .map(|i| {
                    let mu = (i as f64 + 0.5) / n as f64;
                    2.0 * f64::from(fresnel(mu as f32, eta)) * mu / n as f64
                })
                .sum();
            let fit = f64::from(fresnel_diffuse_reflectance(eta));
            assert!(
                (fit / integral - 1.0).abs() < 3e-3,
                "η {eta}: fit {fit} vs {integral}"
            );
        }
    }

    /// A smooth coating is the α → 0 limit: the transmittance tends to 1 − F(μ) and the internal
    /// reflectance to Mitsuba's rule applied to F(μ, 1/η).
    #[test]
    fn a_nearly_smooth_coating_transmits_one_minus_fresnel() {
        let eta = 1.5;
        let coating = RoughCoating::new(eta, 1e-3, Masking::Separable);
        for (i, t) in coating.transmittance.iter().enumerate().skip(2) {
            let mu = i as f32 / 63.0;
            let smooth = 1.0 - fresnel(mu, eta);
            assert!((t - smooth).abs() < 2e-3, "μ {mu}: {t} vs {smooth}");
        }
        let rule: f32 = (0..64)
            .map(|i| {
                let mu = (i as f32 / 63.0).max(1e-6);
                fresnel(mu, 1.0 / eta) * mu
            })
            .sum::<f32>()
            * 2.0
            / 64.0;
        assert!(
            (coating.internal_reflectance - rule).abs() < 2e-3,
            "{} vs {rule}",
            coating.internal_reflectance
        );
    }

    /// The separable masking, which shadows more, transmits less than the correlated one; both
    /// lie in [0, 1]. (The tables against a Monte Carlo estimate through the rough dielectric:
    /// `stratapt_cpu`'s plastic tests.)
    #[test]
    fn separable_coatings_transmit_less_than_correlated_ones() {
        let rough = RoughCoating::new(1.5, 0.5, Masking::Correlated);
        let separable = RoughCoating::new(1.5, 0.5, Masking::Separable);
        for i in 1..TRANSMITTANCE_RES {
            assert!(separable.transmittance[i] <= rough.transmittance[i] + 1e-6);
            assert!((0.0..=1.0).contains(&rough.transmittance[i]));
        }
        assert!((0.0..1.0).contains(&rough.internal_reflectance));
    }

    /// Against Mitsuba 3.9.1's own `roughplastic` (η 1.49, GGX, separable masking), whose
    /// internal reflectance and transmittance were read back from its diffuse lobe's `eval` at
    /// normal incidence with `nonlinear` off and on (`scripts/compare-mitsuba-coating.py`):
    /// the same to within the difference of two quadratures of the same integral (Mitsuba's
    /// nodes go through its own visible-normal map; measured: docs/measurements/materials.md,
    /// "Against Mitsuba 3: pixel by pixel"). A 0.1 % error in either is rejected.
    #[test]
    fn tables_match_mitsubas_roughplastic() {
        // (α, R_int, T(1), T(0.5), T(0.1)) as Mitsuba computes them.
        let mitsuba = [
            (0.001f32, 0.579351f32, 0.961275f32, 0.912421f32, 0.429269f32),
            (0.05, 0.570043, 0.961232, 0.910959, 0.512609),
            (0.3, 0.409008, 0.954486, 0.887811, 0.714967),
            (1.0, 0.114777, 0.882837, 0.652428, 0.359993),
        ];
        for (alpha, r, t1, t05, t01) in mitsuba {
            let c = RoughCoating::new(1.49, alpha, Masking::Separable);
            let close = |a: f32, b: f32, tol: f32| (a / b - 1.0).abs() < tol;
            let ours = [
                c.internal_reflectance,
                transmittance(&c.transmittance, 1.0),
                transmittance(&c.transmittance, 0.5),
                transmittance(&c.transmittance, 0.1),
            ];
            println!("α {alpha}: ours {ours:?}, Mitsuba {:?}", [r, t1, t05, t01]);
            for (what, a, b) in [
                ("R_int", ours[0], r),
                ("T(1)", ours[1], t1),
                ("T(0.5)", ours[2], t05),
                ("T(0.1)", ours[3], t01),
            ] {
                assert!(close(a, b, 5e-4), "α {alpha} {what}: {a} vs Mitsuba's {b}");
                assert!(!close(a * 1.001, b, 5e-4) || !close(a / 1.001, b, 5e-4));
            }
        }
    }

    #[test]
    fn lookup_interpolates_linearly_and_clamps() {
        let table: Vec<f32> = (0..TRANSMITTANCE_RES).map(|i| i as f32).collect();
        assert_eq!(transmittance(&table, 0.0), 0.0);
        assert_eq!(transmittance(&table, 1.0), 63.0);
        assert_eq!(transmittance(&table, 2.0), 63.0);
        assert_eq!(transmittance(&table, -1.0), 0.0);
        assert!((transmittance(&table, 0.5) - 31.5).abs() < 1e-5);
    }
}
