//! Integer hashes shared by the samplers (mirrored in WGSL: only u32 wrapping arithmetic,
//! shifts, xor and reverse_bits).
//!
//! Every function here is a bit-exact contract with `shaders/sampler.wgsl`: `wrapping_*` is
//! WGSL's `u32` arithmetic, `>>` / `<<` are logical shifts, `reverse_bits` is `reverseBits`,
//! `/` and `%` are WGSL's `u32` division and remainder.

/// Chris Wellons' `lowbias32` integer hash (a bijection on `u32`):
/// ```text
/// x ^= x >> 16; x *= 0x7feb352d; x ^= x >> 15; x *= 0x846ca68b; x ^= x >> 16
/// ```
#[inline]
pub fn lowbias32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// Fold the value `v` into the running hash `h` (boost's combine, finalized by [`lowbias32`]):
/// ```text
/// hash_combine(h, v) = lowbias32(h ^ (v + 0x9e3779b9 + (h << 6) + (h >> 2)))
/// ```
/// For a fixed `h` it is a bijection of `v`.
#[inline]
pub fn hash_combine(h: u32, v: u32) -> u32 {
    let mixed = v
        .wrapping_add(0x9e37_79b9)
        .wrapping_add(h << 6)
        .wrapping_add(h >> 2);
    lowbias32(h ^ mixed)
}

/// The pixel's part of every pattern seed: the render seed and the pixel, folded in that order.
/// A renderer hashes it once per path and derives each domain's [`pattern_seed`] from it.
/// ```text
/// pixel_seed(seed, pixel) = hash_combine(hash_combine(lowbias32(seed), pixel.x), pixel.y)
/// ```
#[inline]
pub fn pixel_seed(seed: u32, pixel: [u32; 2]) -> u32 {
    hash_combine(hash_combine(lowbias32(seed), pixel[0]), pixel[1])
}

/// The seed of one sample pattern: the render seed, the pixel and the (first) dimension of the
/// domain, folded in that order:
/// ```text
/// pattern_seed(seed, pixel, dim) = hash_combine(pixel_seed(seed, pixel), dim)
/// ```
#[inline]
pub fn pattern_seed(seed: u32, pixel: [u32; 2], dim: u32) -> u32 {
    hash_combine(pixel_seed(seed, pixel), dim)
}

/// `(a / d, a % d)` for `d ≥ 1`, by a shift and a mask when `d` is a power of two: the same
/// values, without the integer division that SIMD code (lavapipe's 8-lane kernel) performs lane
/// by lane. The sample counts people use are mostly powers of two.
#[inline]
pub fn div_rem(a: u32, d: u32) -> (u32, u32) {
    match d.is_power_of_two() {
        true => (a >> d.trailing_zeros(), a & (d - 1)),
        false => (a / d, a % d),
    }
}

/// Kensler 2013, "Correlated Multi-Jittered Sampling" (Pixar TM 13-01), `permute`: element `i`
/// of a pseudo-random permutation of `[0, l)` keyed by `p` (hash on the enclosing power of two,
/// then cycle-walking until the value lands below `l`), then a rotation by `p mod l`. Requires
/// `i < l`, `l ≥ 1`.
pub fn permute(mut i: u32, l: u32, p: u32) -> u32 {
    // Mask of the smallest power of two ≥ l.
    let mut w = l.wrapping_sub(1);
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    // A bijection on [0, w]; walk its cycle until it returns into [0, l).
    loop {
        i ^= p;
        i = i.wrapping_mul(0xe170_893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929_eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | (p >> 27));
        i = i.wrapping_mul(0x6935_fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dc_b303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e50_1cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860_a3df);
        i &= w;
        i ^= i >> 5;
        if i < l {
            break;
        }
    }
    // Final rotation by the key: Kensler's `(i + p) % l`, written so that `i + p` cannot wrap
    // (wrapping would break the bijection when l is not a power of two).
    let r = div_rem(p, l).1;
    if i >= l - r {
        i - (l - r)
    } else {
        i + r
    }
}

/// Laine–Karras-style hash on *bit-reversed* values with Vegdahl's constants ("Building a Better
/// LK Hash", 2021): output bit `k` is input bit `k` xor a function of bits `< k` and the seed,
/// so in the un-reversed domain it is a base-2 Owen scramble.
/// ```text
/// x ^= x * 0x3d20adea; x += seed; x *= (seed >> 16) | 1; x ^= x * 0x05526c56; x ^= x * 0x53a22864
/// ```
#[inline]
pub fn lk_hash(mut x: u32, seed: u32) -> u32 {
    x ^= x.wrapping_mul(0x3d20_adea);
    x = x.wrapping_add(seed);
    x = x.wrapping_mul((seed >> 16) | 1);
    x ^= x.wrapping_mul(0x0552_6c56);
    x ^= x.wrapping_mul(0x53a2_2864);
    x
}

/// Nested uniform (Owen) scramble of a 32-bit fixed-point value, Burley 2020, "Practical
/// Hash-based Owen Scrambling" (JCGT 9(4)):
/// `owen_scramble(x, seed) = reverse_bits(lk_hash(reverse_bits(x), seed))`.
///
/// Bit `j` of the result is bit `j` of `x` xor a function of the bits above `j`: values that
/// share their top `k` bits still share them afterwards (aligned intervals map onto aligned
/// intervals of the same size).
#[inline]
pub fn owen_scramble(x: u32, seed: u32) -> u32 {
    lk_hash(x.reverse_bits(), seed).reverse_bits()
}

/// High 32 bits of the 64-bit product `a · b`, from 16-bit limbs (WGSL has no `u64`).
#[inline]
pub fn mul_hi(a: u32, b: u32) -> u32 {
    let (a0, a1) = (a & 0xffff, a >> 16);
    let (b0, b1) = (b & 0xffff, b >> 16);
    let p00 = a0 * b0;
    let p01 = a0 * b1;
    let p10 = a1 * b0;
    let p11 = a1 * b1;
    // Carry out of the low word; each term is < 2^16, so the sum cannot overflow.
    let mid = (p00 >> 16) + (p01 & 0xffff) + (p10 & 0xffff);
    p11 + (p01 >> 16) + (p10 >> 16) + (mid >> 16)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shift-and-mask path of `div_rem` gives the division's quotient and remainder.
    #[test]
    fn div_rem_is_division() {
        for d in (1..=64).chain((6..32).map(|j| 1u32 << j)).chain([u32::MAX]) {
            for a in [
                0,
                1,
                2,
                63,
                64,
                65,
                1000,
                0x8000_0000,
                u32::MAX - 1,
                u32::MAX,
            ] {
                assert_eq!(div_rem(a, d), (a / d, a % d), "{a} / {d}");
            }
        }
    }

    #[test]
    fn mul_hi_matches_u64() {
        let mut x = 1u32;
        for _ in 0..10_000 {
            let a = lowbias32(x);
            let b = lowbias32(a ^ 0x5bd1_e995);
            x = x.wrapping_add(1);
            assert_eq!(mul_hi(a, b), ((a as u64 * b as u64) >> 32) as u32);
        }
        assert_eq!(mul_hi(u32::MAX, u32::MAX), u32::MAX - 1);
    }
}
