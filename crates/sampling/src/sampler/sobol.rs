//! Owen-scrambled Sobol sampler: Burley 2020, "Practical Hash-based Owen Scrambling" (JCGT 9(4)),
//! with Vegdahl's LK-hash constants (see [`crate::hash::lk_hash`]).
//!
//! Every domain is its own low-dimensional Sobol pattern, decorrelated from the others by seeds:
//! ```text
//! base = pattern_seed(seed, pixel, dim)              // hash_combine(key, dim), key = pixel_seed
//! i    = owen_scramble(index, base)                       // nested uniform index shuffle
//! 1D:  x = owen_scramble(reverse_bits(i), hash_combine(base, 1))
//! 2D:  x = owen_scramble(reverse_bits(i), hash_combine(base, 1))
//!      y = owen_scramble(sobol_dim1(i),   hash_combine(base, 2))
//! 1D with 2D (c; x, y), base and i of the 2D domain's dim:
//!      x, y as 2D;  c = owen_scramble(sobol_dim2(i), hash_combine(base, 3))
//! value = to_unit_float(x), to_unit_float(y)
//! ```
//! The index shuffle maps every aligned block `[k·2^m, (k+1)·2^m)` onto an aligned block of the
//! same size, and every such block of the Sobol (0,2)-sequence is a (0,m,2)-net; Owen scrambling
//! preserves nets. So every power-of-two prefix of every pixel's pattern is a (0,m,2)-net.
//!
//! A 1D domain drawn with a 2D one (the light choice with the point on the light, the shutter
//! instant with the position in the pixel) is one 3D pattern: the 1D value is Sobol dimension 2
//! of the 2D domain's own index, so each power-of-two prefix of (c, x, y) is a (1,m,3)-net
//! (Sobol's first three dimensions): the samples that choose one light (one stretch of the
//! shutter) are stratified over the 2D domain, where an independent 1D value would leave each a
//! random subset of its strata. The 2D point is exactly the 2D pattern of its dimension.

use glam::Vec2;

use super::to_unit_float;
use crate::hash::{hash_combine, owen_scramble};

/// Sobol dimension 0: the base-2 van der Corput radical inverse, as 32-bit fixed point.
#[inline]
pub fn sobol_dim0(i: u32) -> u32 {
    i.reverse_bits()
}

/// Sobol dimension 1 (with dimension 0, a (0,2)-sequence), as 32-bit fixed point. Its
/// generator matrix is Pascal's triangle mod 2: output bit `31 − p` is the parity of the index
/// bits `j` with `C(j, p)` odd, i.e. (Lucas) with `p ⊆ j` bitwise. That superset-parity
/// transform of the 32 index bits takes five shift-xor steps, one per bit of `j`, then a bit
/// reversal: no loop over the index bits (which costs a masked 32-step loop per lane on SIMD
/// GPUs). [`sobol_dim1_columns`] builds the same matrix column by column, for the tests.
#[inline]
pub fn sobol_dim1(i: u32) -> u32 {
    let mut a = i;
    a ^= (a >> 1) & 0x5555_5555;
    a ^= (a >> 2) & 0x3333_3333;
    a ^= (a >> 4) & 0x0f0f_0f0f;
    a ^= (a >> 8) & 0x00ff_00ff;
    a ^= (a >> 16) & 0x0000_ffff;
    a.reverse_bits()
}

/// [`sobol_dim1`] the textbook way: column `j` of the generator matrix is `v_j`, with
/// `v_0 = 2³¹` and `v_{j+1} = v_j ^ (v_j >> 1)`.
pub fn sobol_dim1_columns(mut i: u32) -> u32 {
    let mut r = 0;
    let mut v = 1u32 << 31;
    while i != 0 {
        if i & 1 != 0 {
            r ^= v;
        }
        i >>= 1;
        v ^= v >> 1;
    }
    r
}

/// Sobol dimension 2 (Joe & Kuo's direction numbers: primitive polynomial x² + x + 1,
/// m = 1, 3), as 32-bit fixed point: the XOR of the columns [`SOBOL_DIM2`] of the index bits
/// set, taken a byte of the index at a time from `SOBOL_DIM2_BYTES`.
#[inline]
pub fn sobol_dim2(i: u32) -> u32 {
    let t = &SOBOL_DIM2_BYTES;
    t[0][(i & 0xff) as usize]
        ^ t[1][((i >> 8) & 0xff) as usize]
        ^ t[2][((i >> 16) & 0xff) as usize]
        ^ t[3][(i >> 24) as usize]
}

/// The generator columns of [`sobol_dim2`], column `j` for index bit `j`. They follow the
/// polynomial's recurrence `m_k = 2m_{k−1} ⊕ 4m_{k−2} ⊕ m_{k−2}`, in fixed point
/// (`v_j = m_j · 2^{31−j}`) `v_k = v_{k−1} ⊕ v_{k−2} ⊕ (v_{k−2} >> 2)`; the WGSL mirror runs
/// the same recurrence.
pub const SOBOL_DIM2: [u32; 32] = {
    let mut v = [0u32; 32];
    v[0] = 1 << 31;
    v[1] = 3 << 30;
    let mut k = 2;
    while k < 32 {
        v[k] = v[k - 1] ^ v[k - 2] ^ (v[k - 2] >> 2);
        k += 1;
    }
    v
};

/// [`SOBOL_DIM2`] by bytes: entry `[b][x]` is the XOR of the columns `8b + j` of the bits `j`
/// set in `x`.
const SOBOL_DIM2_BYTES: [[u32; 256]; 4] = {
    let mut t = [[0u32; 256]; 4];
    let mut b = 0;
    while b < 4 {
        let mut x = 0;
        while x < 256 {
            let mut j = 0;
            while j < 8 {
                if x >> j & 1 == 1 {
                    t[b][x] ^= SOBOL_DIM2[8 * b + j];
                }
                j += 1;
            }
            x += 1;
        }
        b += 1;
    }
    t
};

/// The scrambled index and the pattern's base seed (`key`: the pixel's
/// [`pixel_seed`](crate::hash::pixel_seed)).
#[inline]
fn shuffled(key: u32, index: u32, dim: u32) -> (u32, u32) {
    let base = hash_combine(key, dim);
    (owen_scramble(index, base), base)
}

/// 32-bit fixed-point value of the 1D domain at `dim`.
#[inline]
pub fn bits_1d(key: u32, index: u32, dim: u32) -> u32 {
    let (i, base) = shuffled(key, index, dim);
    owen_scramble(sobol_dim0(i), hash_combine(base, 1))
}

/// 32-bit fixed-point point of the 2D domain at `dim`, `dim + 1`.
#[inline]
pub fn bits_2d(key: u32, index: u32, dim: u32) -> [u32; 2] {
    let (i, base) = shuffled(key, index, dim);
    point(i, base)
}

/// The scrambled Sobol (0,2) point of shuffled index `i` in the pattern with seed `base`.
#[inline]
fn point(i: u32, base: u32) -> [u32; 2] {
    [
        owen_scramble(sobol_dim0(i), hash_combine(base, 1)),
        owen_scramble(sobol_dim1(i), hash_combine(base, 2)),
    ]
}

/// 32-bit fixed-point 1D value and 2D point drawn together: the point is [`bits_2d`] at
/// `dim_2d`, the value Sobol dimension 2 of the same shuffled index.
#[inline]
pub fn bits_1d_2d(key: u32, index: u32, dim_2d: u32) -> (u32, [u32; 2]) {
    let (i, base) = shuffled(key, index, dim_2d);
    (
        owen_scramble(sobol_dim2(i), hash_combine(base, 3)),
        point(i, base),
    )
}

/// Value in `[0, 1)` of the 1D domain at `dim`.
#[inline]
pub fn sample_1d(key: u32, index: u32, dim: u32) -> f32 {
    to_unit_float(bits_1d(key, index, dim))
}

/// Point in `[0, 1)²` of the 2D domain at `dim`, `dim + 1`.
#[inline]
pub fn sample_2d(key: u32, index: u32, dim: u32) -> Vec2 {
    let [x, y] = bits_2d(key, index, dim);
    Vec2::new(to_unit_float(x), to_unit_float(y))
}
