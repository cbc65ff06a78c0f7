//! Piecewise-constant 2D distribution over `[0,1)²` on a `w × h` grid of cells, sampled by
//! inversion: a row by the marginal CDF, a column by that row's conditional CDF, then uniformly
//! inside the cell (pbrt's `PiecewiseConstant2D`). The tables are one flat `f32` array, so that
//! the GPU kernel reads the same numbers (`warp_piecewise_*` in `shaders/warp.wgsl`):
//!
//! `[marginal CDF: h + 1 entries][row 0's conditional CDF: w + 1] … [row h − 1's: w + 1]`,
//!
//! each CDF from 0 to exactly 1. A cell's probability is the difference of its CDF entries,
//! used alike by [`sample`] and [`pdf`], so the two agree to the bit whatever the rounding of
//! the CDFs. A cell of weight 0 is never sampled and has density 0.

use glam::Vec2;

/// Entries of the tables of a `w × h` distribution.
pub fn len(w: usize, h: usize) -> usize {
    (h + 1) + h * (w + 1)
}

/// The tables of the distribution proportional to `weights` (row-major, `w × h`, each finite and
/// `≥ 0`), accumulated in f64. `None` when every weight is 0.
pub fn build(weights: &[f32], w: usize, h: usize) -> Option<Vec<f32>> {
    assert_eq!(weights.len(), w * h, "{w} × {h} weights");
    let mut out = Vec::with_capacity(len(w, h));
    let row_sums: Vec<f64> = weights
        .chunks(w)
        .map(|row| row.iter().map(|&x| f64::from(x)).sum())
        .collect();
    out.extend(cdf(&row_sums)?);
    for row in weights.chunks(w) {
        let row: Vec<f64> = row.iter().map(|&x| f64::from(x)).collect();
        // A row of zeros is never chosen; any CDF will do (uniform).
        out.extend(cdf(&row).unwrap_or_else(|| cdf(&vec![1.0; w]).unwrap()));
    }
    Some(out)
}

/// `[0, c₁, …, 1]` of non-negative `values`; `None` when they sum to 0.
fn cdf(values: &[f64]) -> Option<Vec<f32>> {
    let total: f64 = values.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return None;
    }
    let mut acc = 0.0;
    let mut out = vec![0.0f32];
    for (i, v) in values.iter().enumerate() {
        acc += v;
        out.push(if i + 1 == values.len() {
            1.0
        } else {
            (acc / total) as f32
        });
    }
    Some(out)
}

/// The largest `i < n` with `cdf[i] ≤ u` (`cdf[0] = 0 ≤ u < 1 = cdf[n]`), skipping cells of
/// zero probability: binary search, as the kernel does it.
fn find(cdf: &[f32], n: usize, u: f32) -> usize {
    let (mut lo, mut hi) = (0usize, n);
    // Invariant: cdf[lo] ≤ u < cdf[hi].
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if cdf[mid] <= u {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// A point of the distribution in `tables` (of a `w × h` grid) for the uniform `u`, with its
/// density over `[0,1)²`; `None` where the chosen cell's density rounds to 0.
pub fn sample(tables: &[f32], w: usize, h: usize, u: Vec2) -> Option<(Vec2, f32)> {
    sample_cell(tables, w, h, u).map(|(p, density, _)| (p, density))
}

/// [`sample`], with the index (`row · w + column`) of the cell the point was drawn in (the
/// point's own coordinates may round onto the next cell's edge).
pub fn sample_cell(tables: &[f32], w: usize, h: usize, u: Vec2) -> Option<(Vec2, f32, usize)> {
    let marginal = &tables[..h + 1];
    let row = find(marginal, h, u.y);
    let (r0, r1) = (marginal[row], marginal[row + 1]);
    let conditional = &tables[h + 1 + row * (w + 1)..][..w + 1];
    let col = find(conditional, w, u.x);
    let (c0, c1) = (conditional[col], conditional[col + 1]);
    let (pr, pc) = (r1 - r0, c1 - c0);
    let density = pr * h as f32 * pc * w as f32;
    if !(density > 0.0) {
        return None;
    }
    // Where u falls inside the cell, reused as the position in it (clamped below 1).
    let below_one = 1.0 - f32::EPSILON / 2.0;
    let fx = ((u.x - c0) / pc).clamp(0.0, below_one);
    let fy = ((u.y - r0) / pr).clamp(0.0, below_one);
    let p = Vec2::new((col as f32 + fx) / w as f32, (row as f32 + fy) / h as f32);
    Some((p.min(Vec2::splat(below_one)), density, row * w + col))
}

/// Density of [`sample`] at `p ∈ [0,1)²` (clamped into the grid).
pub fn pdf(tables: &[f32], w: usize, h: usize, p: Vec2) -> f32 {
    let col = ((p.x * w as f32) as usize).min(w - 1);
    let row = ((p.y * h as f32) as usize).min(h - 1);
    let marginal = &tables[..h + 1];
    let conditional = &tables[h + 1 + row * (w + 1)..][..w + 1];
    let pr = marginal[row + 1] - marginal[row];
    let pc = conditional[col + 1] - conditional[col];
    pr * h as f32 * pc * w as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_get_their_share_and_zero_cells_none() {
        let weights = [1.0, 0.0, 3.0, 0.0, 0.0, 0.0, 2.0, 2.0];
        let t = build(&weights, 4, 2).unwrap();
        assert_eq!(t.len(), len(4, 2));
        // Cell (0, 0): probability 1/8 of the total, area 1/8: density 1.
        assert!((pdf(&t, 4, 2, Vec2::new(0.1, 0.2)) - 1.0).abs() < 1e-6);
        assert_eq!(pdf(&t, 4, 2, Vec2::new(0.3, 0.2)), 0.0);
        assert!((pdf(&t, 4, 2, Vec2::new(0.9, 0.9)) - 2.0).abs() < 1e-6);
        for i in 0..1000 {
            let u = Vec2::new(
                (i as f32 + 0.5) / 1000.0,
                ((i * 37 % 1000) as f32 + 0.5) / 1000.0,
            );
            let (p, d) = sample(&t, 4, 2, u).unwrap();
            assert!(
                d > 0.0 && (d - pdf(&t, 4, 2, p)).abs() < 1e-6,
                "{u} → {p} {d}"
            );
        }
        assert!(build(&[0.0; 4], 2, 2).is_none());
    }
}
