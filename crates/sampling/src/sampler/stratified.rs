//! Stratified sampler for any sample count `N = spp`: jittered strata in 1D and correlated
//! multi-jittered sampling in 2D (Kensler 2013, "Correlated Multi-Jittered Sampling", Pixar
//! TM 13-01), each domain's pattern keyed by `(seed, pixel, dim, pass)` and its sample order
//! shuffled, so strata of different domains are decorrelated.
//!
//! Exact formulas (the WGSL mirror copies them):
//! ```text
//! N    = min(spp, 2^24)                  (strata finer than 2^-24 cannot be told apart)
//! pass = index / N,  s = index % N       (each pass of N samples is a fresh pattern)
//! base = hash_combine(pattern_seed(seed, pixel, dim), pass)   // pattern_seed = hash_combine(key, dim)
//! t    = permute(s, N, hash_combine(base, 1))                 // shuffled sample order
//! 1D:  x = stratum_bits(t, hash_combine(hash_combine(base, 4), s), N)
//! 2D:  (m, n) = grid(N); col = t % m; row = t / m
//!      sx = permute(col, m, hash_combine(base, 2)); sy = permute(row, n, hash_combine(base, 3))
//!      x = stratum_bits(col·n + sy, hash_combine(hash_combine(base, 4), s), N)
//!      y = stratum_bits(row·m + sx, hash_combine(hash_combine(base, 5), s), N)
//! value = to_unit_float(x), to_unit_float(y)
//! ```
//! In 2D sample `t` lies in cell `(col, row)` of the `m × n` grid and in x-stratum `col·n + sy`,
//! y-stratum `row·m + sx` of the `N` fine strata of each axis: one sample per cell and one per
//! fine stratum on each axis (N-rooks), whatever `N`.
//!
//! Kensler's correlation (one `sx`, `sy` permutation per pattern, so all samples of a row share
//! their x sub-stratum): lower RMS error than per-row/per-column keys on edges (disk, step), the
//! common case in images, but a slower rate than N^-1 on smooth non-periodic integrands
//! (measured: docs/measurements/samplers.md#convergence-rates).

use glam::Vec2;

use super::to_unit_float;
use crate::hash::{div_rem, hash_combine, mul_hi, permute};

/// Largest stratum count: with 24-bit output every stratum of `2^24` still holds one value.
pub const MAX_STRATA: u32 = 1 << 24;

/// The stratum count actually used for `spp` samples per pixel: `clamp(spp, 1, 2^24)`.
#[inline]
pub fn strata(spp: u32) -> u32 {
    spp.clamp(1, MAX_STRATA)
}

/// The 2D grid `(m, n)`, `m · n = count`, `m` columns (along x) and `n` rows: `m` is the largest
/// divisor of `count` not above `√count` (a prime count gives `1 × count`).
pub fn grid(count: u32) -> (u32, u32) {
    let count = count.max(1);
    if count.is_power_of_two() {
        // 2^j: the largest power of two not above its root, 2^⌊j/2⌋, divides it.
        let half = count.trailing_zeros() / 2;
        return (1 << half, count >> half);
    }
    // Integer square root: f32 estimate, corrected exactly.
    let mut m = (count as f32).sqrt() as u32;
    m = m.max(1);
    while m > count / m {
        m -= 1;
    }
    while m < count / (m + 1) {
        m += 1;
    }
    while !count.is_multiple_of(m) {
        m -= 1;
    }
    (m, count / m)
}

/// `ceil(k · 2^24 / n)` for `k ≤ n ≤ 2^24`, without an integer division: a shift when `n` is a
/// power of two; else an f32 estimate of the quotient, a few units off at most, corrected to the
/// exact value by its remainder `k · 2^24 − q · n`, which wrapping u32 arithmetic gives exactly
/// while it lies within ±2^31 (a quotient off by fewer than 128 units). The estimate's rounding
/// (which may differ between CPU and GPU) never reaches the result.
#[inline]
pub fn scaled_ceil(k: u32, n: u32) -> u32 {
    if n.is_power_of_two() {
        return k << (24 - n.trailing_zeros());
    }
    let mut q = (k as f32 * (16_777_216.0 / n as f32)) as u32;
    let mut r = (k << 24).wrapping_sub(q.wrapping_mul(n)) as i32;
    let ni = n as i32;
    while r < 0 {
        q -= 1;
        r += ni;
    }
    while r >= ni {
        q += 1;
        r -= ni;
    }
    q + u32::from(r != 0)
}

/// 32-bit fixed-point value jittered inside stratum `k` of `n`: the 24-bit values `v` with
/// `v / 2^24 ∈ [k/n, (k+1)/n)` are `[lo, hi)`, `lo = scaled_ceil(k, n)`,
/// `hi = scaled_ceil(k + 1, n)`; the jitter bits pick `lo + mul_hi(jitter, hi − lo)`, returned
/// shifted left by 8 (so [`to_unit_float`] gives exactly `v / 2^24`).
#[inline]
pub fn stratum_bits(k: u32, jitter: u32, n: u32) -> u32 {
    if n.is_power_of_two() {
        // n = 2^j: the stratum is 2^(24 − j) values from k · 2^(24 − j), and the jitter's top
        // 24 − j bits pick one (`mul_hi` by a power of two).
        let j = n.trailing_zeros();
        return ((k << (24 - j)) + ((jitter >> 8) >> j)) << 8;
    }
    let lo = scaled_ceil(k, n);
    let hi = scaled_ceil(k + 1, n);
    (lo + mul_hi(jitter, hi - lo)) << 8
}

/// Pattern seed of this pass, sample position inside the pass, and the shuffled position
/// (`key`: the pixel's [`pixel_seed`](crate::hash::pixel_seed)).
#[inline]
fn locate(key: u32, index: u32, dim: u32, n: u32) -> (u32, u32, u32) {
    let (pass, s) = div_rem(index, n);
    let base = hash_combine(hash_combine(key, dim), pass);
    let t = permute(s, n, hash_combine(base, 1));
    (base, s, t)
}

/// 32-bit fixed-point value of the 1D domain at `dim` (`spp` samples per pattern).
pub fn bits_1d(key: u32, index: u32, dim: u32, spp: u32) -> u32 {
    let n = strata(spp);
    let (base, s, t) = locate(key, index, dim, n);
    stratum_bits(t, hash_combine(hash_combine(base, 4), s), n)
}

/// 32-bit fixed-point point of the 2D domain at `dim`, `dim + 1` (`spp` samples per pattern).
pub fn bits_2d(key: u32, index: u32, dim: u32, spp: u32) -> [u32; 2] {
    let n = strata(spp);
    let (base, s, t) = locate(key, index, dim, n);
    let (cols, rows) = grid(n);
    let (row, col) = div_rem(t, cols);
    // Correlated multi-jitter: one permutation per axis shared by the whole pattern.
    let sx = permute(col, cols, hash_combine(base, 2));
    let sy = permute(row, rows, hash_combine(base, 3));
    [
        stratum_bits(col * rows + sy, hash_combine(hash_combine(base, 4), s), n),
        stratum_bits(row * cols + sx, hash_combine(hash_combine(base, 5), s), n),
    ]
}

/// Value in `[0, 1)` of the 1D domain at `dim`.
#[inline]
pub fn sample_1d(key: u32, index: u32, dim: u32, spp: u32) -> f32 {
    to_unit_float(bits_1d(key, index, dim, spp))
}

/// Point in `[0, 1)²` of the 2D domain at `dim`, `dim + 1`.
#[inline]
pub fn sample_2d(key: u32, index: u32, dim: u32, spp: u32) -> Vec2 {
    let [x, y] = bits_2d(key, index, dim, spp);
    Vec2::new(to_unit_float(x), to_unit_float(y))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaled_ceil_matches_u64() {
        for n in [
            1u32,
            2,
            3,
            7,
            12,
            50,
            255,
            256,
            257,
            65_537,
            1_000_003,
            1 << 20,
            MAX_STRATA - 1,
            MAX_STRATA,
        ] {
            let ks = [0, 1, n / 3, n / 2, n.saturating_sub(1), n];
            for k in ks {
                let exact = ((k as u64) << 24).div_ceil(n as u64) as u32;
                assert_eq!(scaled_ceil(k, n), exact, "k={k} n={n}");
            }
        }
        // Every k for small counts, and random (k, n) up to 2^24.
        let exact = |k: u32, n: u32| ((k as u64) << 24).div_ceil(n as u64) as u32;
        for n in 1..=300 {
            for k in 0..=n {
                assert_eq!(scaled_ceil(k, n), exact(k, n), "k={k} n={n}");
            }
        }
        let mut x = 7u32;
        for _ in 0..200_000 {
            x = crate::hash::lowbias32(x);
            let n = 1 + x % MAX_STRATA;
            x = crate::hash::lowbias32(x);
            let k = x % (n + 1);
            assert_eq!(scaled_ceil(k, n), exact(k, n), "k={k} n={n}");
        }
    }

    /// For a power-of-two count the shortcut picks the value the general formula does.
    #[test]
    fn stratum_bits_shortcut_matches_the_formula() {
        let general = |k: u32, jitter: u32, n: u32| {
            let (lo, hi) = (scaled_ceil(k, n), scaled_ceil(k + 1, n));
            (lo + mul_hi(jitter, hi - lo)) << 8
        };
        let mut jitter = 1u32;
        for j in 0..=24 {
            let n = 1u32 << j;
            for k in [0, 1, n / 2, n - 1] {
                for _ in 0..200 {
                    jitter = crate::hash::lowbias32(jitter);
                    assert_eq!(stratum_bits(k, jitter, n), general(k, jitter, n), "{k} {n}");
                }
                for edge in [0, u32::MAX] {
                    assert_eq!(stratum_bits(k, edge, n), general(k, edge, n), "{k} {n}");
                }
            }
        }
    }

    #[test]
    fn grid_is_largest_divisor_below_sqrt() {
        assert_eq!(grid(1), (1, 1));
        assert_eq!(grid(7), (1, 7));
        assert_eq!(grid(12), (3, 4));
        assert_eq!(grid(16), (4, 4));
        assert_eq!(grid(50), (5, 10));
        assert_eq!(grid(64), (8, 8));
        assert_eq!(grid(MAX_STRATA), (4096, 4096));
        assert_eq!(grid(u32::MAX), (65535, 65537));
        let powers = (11..=24).map(|j| 1u32 << j);
        for n in (1..2000u32).chain(powers) {
            let (m, r) = grid(n);
            assert_eq!(m * r, n);
            assert!(m * m <= n);
            assert!((m + 1..=r).all(|d| d * d > n || n % d != 0), "n={n}");
        }
    }
}
