//! Loop's weights and pbrt-v4's limit tangents, on a vertex and its ring.

use glam::DVec3;
use std::f64::consts::PI;

/// Warren's β for `n` neighbours (pbrt's `beta`): 3/16 for 3, else 3 / 8n (1/16 for the
/// regular 6, pbrt's special case for regular vertices).
pub(super) fn beta(n: usize) -> f64 {
    match n {
        3 => 3.0 / 16.0,
        n => 3.0 / (8.0 * n as f64),
    }
}

/// The limit weight of each of `n` neighbours (pbrt's `loopGamma`): 1 / (n + 3 / 8β).
pub(super) fn loop_gamma(n: usize) -> f64 {
    1.0 / (n as f64 + 3.0 / (8.0 * beta(n)))
}

/// (1 − nβ) p\[v\] + β Σ p\[ring\] (pbrt's `weightOneRing`).
pub(super) fn weigh_ring(p: &[DVec3], v: u32, ring: &[u32], beta: f64) -> DVec3 {
    let sum: DVec3 = ring.iter().map(|&r| p[r as usize]).sum();
    (1.0 - ring.len() as f64 * beta) * p[v as usize] + beta * sum
}

/// (1 − 2β) p\[v\] + β of each end of the ring, its boundary neighbours (pbrt's
/// `weightBoundary`).
pub(super) fn weigh_boundary(p: &[DVec3], v: u32, ring: &[u32], beta: f64) -> DVec3 {
    let ends = p[ring[0] as usize] + p[ring[ring.len() - 1] as usize];
    (1.0 - 2.0 * beta) * p[v as usize] + beta * ends
}

/// Tangents at an interior vertex from its ring `d` (relative to it): Σ cos(2πj/n) d_j and
/// Σ sin(2πj/n) d_j.
pub(super) fn interior_tangents(d: &[DVec3]) -> (DVec3, DVec3) {
    let n = d.len() as f64;
    d.iter()
        .enumerate()
        .fold((DVec3::ZERO, DVec3::ZERO), |(s, t), (j, &dj)| {
            let (sin, cos) = (2.0 * PI * j as f64 / n).sin_cos();
            (s + cos * dj, t + sin * dj)
        })
}

/// Tangents at a boundary vertex from its ring `d` (relative to it): along the boundary, from
/// one end of the ring to the other; across it, pbrt's rule for the valence (the ring's length:
/// 2, 3, the regular 4, or more).
pub(super) fn boundary_tangents(d: &[DVec3]) -> (DVec3, DVec3) {
    let n = d.len();
    let s = d[n - 1] - d[0];
    let t = match n {
        2 => d[0] + d[1],
        3 => d[1],
        4 => -d[0] + 2.0 * d[1] + 2.0 * d[2] - d[3],
        _ => {
            let theta = PI / (n - 1) as f64;
            let inner: DVec3 = (1..n - 1)
                .map(|k| (2.0 * theta.cos() - 2.0) * (k as f64 * theta).sin() * d[k])
                .sum();
            -(theta.sin() * (d[0] + d[n - 1]) + inner)
        }
    };
    (s, t)
}
