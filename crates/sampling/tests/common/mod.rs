//! Shared test harness: input uniforms, and the chi-square test of
//! [`stratapt_sampling::testing::chi2`] with this crate's family of tests.
#![allow(dead_code, unused_imports)]

use glam::Vec2;
use stratapt_sampling::testing::chi2::{self, Family, Refusals};
pub use stratapt_sampling::testing::chi2::{
    accept, density_bins, reject, simpson, simpson_2d, Chi2, Fit, Plant,
};
use stratapt_sampling::{Sampler, SamplerKind};

/// This crate's chi-square tests: family-wise significance 0.01 over at most 48 tests.
pub const FAMILY: Family = Family {
    alpha: 0.01,
    tests: 48,
};

/// Per-test significance level after the Šidák correction.
pub fn significance() -> f64 {
    FAMILY.significance()
}

/// `n` uniform points from the independent sampler (deterministic for a given `seed`).
pub fn uniforms(n: u32, seed: u32) -> impl Iterator<Item = Vec2> {
    let sampler = Sampler::new(SamplerKind::Independent, 1, seed);
    (0..n).map(move |i| sampler.sample_2d([i & 0xff, i >> 8], 0, 0))
}

/// The corners and middle of `[0,1)²`, including the largest sampler value `1 − 2⁻²⁴`.
pub fn edge_uniforms() -> Vec<Vec2> {
    let edges = [0.0, 2f32.powi(-24), 0.25, 0.5, 1.0 - 2f32.powi(-24)];
    edges
        .iter()
        .flat_map(|&x| edges.iter().map(move |&y| Vec2::new(x, y)))
        .collect()
}

/// [`chi2::fit`] in this crate's family.
pub fn fit(
    name: &str,
    samples: impl Iterator<Item = Option<[f64; 2]>>,
    probs: &[f64],
    nx: usize,
    ny: usize,
    plant: Plant,
) -> Fit {
    chi2::fit(
        &FAMILY,
        name,
        samples,
        probs,
        nx,
        ny,
        Refusals::Never,
        plant,
    )
}

/// [`chi2::detectable_bend`] in this crate's family.
pub fn detectable_bend(probs: &[f64], n: usize, nx: usize, ny: usize) -> f64 {
    chi2::detectable_bend(&FAMILY, probs, n, nx, ny)
}

/// Run [`fit`] with nothing planted and assert that it passes.
pub fn assert_chi2(
    name: &str,
    samples: impl Iterator<Item = Option<[f64; 2]>>,
    probs: &[f64],
    nx: usize,
    ny: usize,
) {
    accept(vec![fit(name, samples, probs, nx, ny, Plant::None)]);
}
