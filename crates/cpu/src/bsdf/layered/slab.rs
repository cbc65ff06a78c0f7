//! The slab of [`Layered`](super::Layered): its transmittance, the Henyey–Greenstein phase
//! function, and the counter-based random stream of the parent module's documentation.

use super::*;

// ---------------------------------------------------------------------------------------------
// The slab: transmittance, the Henyey–Greenstein phase function, the random stream.
// ---------------------------------------------------------------------------------------------

/// pbrt's `Tr(dz, w) = exp(−|dz / w.z|)` (1 for |dz| at most the smallest normal f32).
pub(super) fn transmittance(dz: f32, w: Vec3) -> f32 {
    if dz.abs() <= f32::MIN_POSITIVE {
        1.0
    } else {
        (-(dz / w.z).abs()).exp()
    }
}

/// Henyey–Greenstein in pbrt-v4's convention: `cos` is `wo · wi` with both pointing away, so
/// `g > 0` peaks at `cos = −1` (forward): `(1 − g²) / (4π (1 + g² + 2g cos)^{3/2})`.
pub(super) fn hg(cos: f32, g: f32) -> f32 {
    let g = g.clamp(-0.99, 0.99);
    let denom = 1.0 + g * g + 2.0 * g * cos;
    0.25 * FRAC_1_PI * (1.0 - g * g) / (denom * denom.max(0.0).sqrt())
}

/// A direction from [`hg`] around `wo` and its density (pbrt's `SampleHenyeyGreenstein`:
/// `cos = −(1 + g² − ((1 − g²) / (1 + g − 2g u.x))²) / (2g)`, `1 − 2 u.x` for |g| < 10⁻³).
pub(super) fn sample_hg(wo: Vec3, g: f32, u: Vec2) -> Option<(Vec3, f32)> {
    let g = g.clamp(-0.99, 0.99);
    let cos = if g.abs() < 1e-3 {
        1.0 - 2.0 * u.x
    } else {
        let s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u.x);
        -(1.0 + g * g - s * s) / (2.0 * g)
    };
    let cos = cos.clamp(-1.0, 1.0);
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = TAU * u.y;
    let local = Vec3::new(sin * phi.cos(), sin * phi.sin(), cos);
    let wi = Frame::from_normal(wo).to_world(local);
    let pdf = hg(cos, g);
    (pdf > 0.0 && wi.z != 0.0).then_some((wi, pdf))
}

/// The counter-based stream of the module doc.
pub(super) struct Rng(u32);

impl Rng {
    pub(super) fn new(domain: u32, seed: u32, values: &[f32]) -> Self {
        let start = hash_combine(lowbias32(domain), seed);
        Self(
            values
                .iter()
                .fold(start, |h, v| hash_combine(h, v.to_bits())),
        )
    }

    pub(super) fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9);
        (lowbias32(self.0) >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    pub(super) fn u2(&mut self) -> Vec2 {
        let x = self.next();
        Vec2::new(x, self.next())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stratapt_sampling::testing::chi2::Refusals;
    use stratapt_sampling::testing::chi2::{accept, density_bins, fit, reject, Family, Plant};
    use stratapt_sampling::testing::TestRng;

    /// Henyey–Greenstein sampling draws what [`hg`] says around an oblique `wo`, from backward
    /// to forward scattering (histogrammed in `(φ / 2π, (1 − cos) / 2)` about `wo`, where the
    /// density is `4π hg`), and returns that density; planted: the density of a g 0.03 off is
    /// rejected.
    #[test]
    fn henyey_greenstein_sampling_matches_its_density() {
        const FAMILY: Family = Family {
            alpha: 0.01,
            tests: 5,
        };
        let (nx, ny, n) = (8, 40, 100_000);
        let wo = Vec3::new(0.3, -0.5, 0.81).normalize();
        let frame = Frame::from_normal(wo);
        let (mut fits, mut planted) = (Vec::new(), Vec::new());
        for (i, g) in [-0.9f32, -0.3, 0.0, 0.5, 0.9].into_iter().enumerate() {
            let mut rng = TestRng(40 + i as u64);
            let samples: Vec<_> = (0..n)
                .map(|_| {
                    let (wi, pdf) = sample_hg(wo, g, rng.u2())?;
                    let expected = hg(wo.dot(wi), g);
                    assert!(
                        (pdf - expected).abs() <= 2e-3 * expected,
                        "{pdf} vs {expected}"
                    );
                    let l = frame.to_local(wi);
                    let phi = f64::from(l.y)
                        .atan2(f64::from(l.x))
                        .rem_euclid(std::f64::consts::TAU);
                    Some([
                        phi / std::f64::consts::TAU,
                        0.5 * (1.0 - f64::from(l.z.clamp(-1.0, 1.0))),
                    ])
                })
                .collect();
            let bins = |g: f32| {
                let density = |_: f64, y: f64| {
                    4.0 * std::f64::consts::PI * f64::from(hg(1.0 - 2.0 * y as f32, g))
                };
                density_bins(&density, nx, ny)
            };
            let name = format!("HG g {g}");
            let (right, wrong) = (bins(g), bins(g + 0.03));
            let samples = || samples.iter().copied();
            let refusals = Refusals::Allowed;
            fits.push(fit(
                &FAMILY,
                &name,
                samples(),
                &right,
                nx,
                ny,
                refusals,
                Plant::None,
            ));
            let label = format!("{name}, density of g + 0.03");
            planted.push(fit(
                &FAMILY,
                &label,
                samples(),
                &wrong,
                nx,
                ny,
                refusals,
                Plant::None,
            ));
        }
        accept(fits);
        reject(planted, "");
    }
}
