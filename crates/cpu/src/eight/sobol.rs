//! The Owen-scrambled Sobol sampler ([`stratapt_sampling::sampler::sobol`]) for eight paths at
//! once, each lane with its own pixel key, sample index and dimension: the same integer
//! arithmetic in `u32x8` lanes, so every lane's value is the one-lane sampler's, bit for bit.

use bytemuck::cast;
use wide::{f32x8, i32x8, u32x8};

/// Chris Wellons' `lowbias32` ([`stratapt_sampling::hash::lowbias32`]).
pub(super) fn lowbias32(mut x: u32x8) -> u32x8 {
    x = x ^ (x >> 16);
    x = x * u32x8::splat(0x7feb_352d);
    x = x ^ (x >> 15);
    x = x * u32x8::splat(0x846c_a68b);
    x ^ (x >> 16)
}

/// [`stratapt_sampling::hash::hash_combine`].
pub(super) fn hash_combine(h: u32x8, v: u32x8) -> u32x8 {
    let mixed = v + u32x8::splat(0x9e37_79b9) + (h << 6) + (h >> 2);
    lowbias32(h ^ mixed)
}

/// `u32::reverse_bits` per lane: AVX2 has no bit reversal, so five swaps of halves.
fn reverse_bits(mut x: u32x8) -> u32x8 {
    let swap = |x: u32x8, shift: u32, mask: u32| {
        let m = u32x8::splat(mask);
        ((x >> shift) & m) | ((x & m) << shift)
    };
    x = swap(x, 1, 0x5555_5555);
    x = swap(x, 2, 0x3333_3333);
    x = swap(x, 4, 0x0f0f_0f0f);
    x = swap(x, 8, 0x00ff_00ff);
    (x >> 16) | (x << 16)
}

/// [`stratapt_sampling::hash::lk_hash`].
fn lk_hash(mut x: u32x8, seed: u32x8) -> u32x8 {
    x = x ^ (x * u32x8::splat(0x3d20_adea));
    x += seed;
    x = x * ((seed >> 16) | u32x8::splat(1));
    x = x ^ (x * u32x8::splat(0x0552_6c56));
    x ^ (x * u32x8::splat(0x53a2_2864))
}

/// [`stratapt_sampling::hash::owen_scramble`].
fn owen_scramble(x: u32x8, seed: u32x8) -> u32x8 {
    reverse_bits(lk_hash(reverse_bits(x), seed))
}

/// Sobol dimension 1 ([`stratapt_sampling::sampler::sobol::sobol_dim1`]).
fn sobol_dim1(i: u32x8) -> u32x8 {
    let mut a = i;
    a = a ^ ((a >> 1) & u32x8::splat(0x5555_5555));
    a = a ^ ((a >> 2) & u32x8::splat(0x3333_3333));
    a = a ^ ((a >> 4) & u32x8::splat(0x0f0f_0f0f));
    a = a ^ ((a >> 8) & u32x8::splat(0x00ff_00ff));
    a = a ^ ((a >> 16) & u32x8::splat(0x0000_ffff));
    reverse_bits(a)
}

/// [`stratapt_sampling::sampler::to_unit_float`]: the top 24 bits times 2⁻²⁴.
fn to_unit_float(bits: u32x8) -> f32x8 {
    let top: i32x8 = cast(bits >> 8);
    top.round_float() * f32x8::splat(1.0 / 16_777_216.0)
}

/// The 1D domain at `dim` of path `index` of the pixel with key `key`, per lane.
pub fn sample_1d(key: u32x8, index: u32x8, dim: u32x8) -> f32x8 {
    let base = hash_combine(key, dim);
    let i = owen_scramble(index, base);
    to_unit_float(owen_scramble(
        reverse_bits(i),
        hash_combine(base, u32x8::splat(1)),
    ))
}

/// The 2D domain at `dim`, `dim + 1`, per lane.
pub fn sample_2d(key: u32x8, index: u32x8, dim: u32x8) -> (f32x8, f32x8) {
    let base = hash_combine(key, dim);
    let i = owen_scramble(index, base);
    let x = owen_scramble(reverse_bits(i), hash_combine(base, u32x8::splat(1)));
    let y = owen_scramble(sobol_dim1(i), hash_combine(base, u32x8::splat(2)));
    (to_unit_float(x), to_unit_float(y))
}

#[cfg(test)]
mod tests {
    use super::*;
    use stratapt_sampling::hash::lowbias32 as hash;
    use stratapt_sampling::sampler::sobol;

    /// Every lane draws the one-lane sampler's values, bit for bit.
    #[test]
    fn lanes_draw_the_reference_values() {
        for round in 0..4000u32 {
            let key: [u32; 8] = std::array::from_fn(|i| hash(round * 8 + i as u32));
            let index: [u32; 8] = std::array::from_fn(|i| match round % 3 {
                0 => round + i as u32,
                _ => hash(key[i] ^ 0xabcd),
            });
            let dim: [u32; 8] = std::array::from_fn(|i| (round + 3 * i as u32) % 40);
            let (k, n, d) = (u32x8::from(key), u32x8::from(index), u32x8::from(dim));
            let one = sample_1d(k, n, d).to_array();
            let (x, y) = sample_2d(k, n, d);
            let (x, y) = (x.to_array(), y.to_array());
            for i in 0..8 {
                assert_eq!(
                    one[i].to_bits(),
                    sobol::sample_1d(key[i], index[i], dim[i]).to_bits()
                );
                let p = sobol::sample_2d(key[i], index[i], dim[i]);
                assert_eq!(
                    (x[i].to_bits(), y[i].to_bits()),
                    (p.x.to_bits(), p.y.to_bits())
                );
            }
        }
    }
}
