// needs: nothing
// Samplers: the bit-exact WGSL mirror of `crates/sampling/src/hash.rs`, `sampler.rs` and
// `sampler/{independent,stratified,sobol}.rs`. Pure u32 arithmetic (WGSL's wraps like Rust's
// `wrapping_*`), so every value equals the Rust `Sampler`'s bit for bit.
//
// Interface (other modules may call):
//   fn sampler_begin_pixel(pixel: vec2u)                          // once per invocation, after
//                                                                 // sampler_replica is set
//   fn sampler_sample_1d(index: u32, dim: u32) -> f32      // that pixel, params.sampler/spp/seed
//   fn sampler_sample_2d(index: u32, dim: u32) -> vec2f    // dims dim, dim + 1
//   fn sampler_sample_1d_with(kind: u32, spp: u32, seed: u32, pixel: vec2u, index: u32,
//                             dim: u32) -> f32                   // explicit sampler settings
//   fn sampler_sample_2d_with(kind: u32, spp: u32, seed: u32, pixel: vec2u, index: u32,
//                             dim: u32) -> vec2f
//   fn sampler_sample_1d_2d(index: u32, dim_1d: u32, dim_2d: u32) -> vec3f
//                             // a 1D domain drawn with a 2D one: x = the 1D value, yz = the point
//   fn sampler_sample_1d_2d_with(kind: u32, spp: u32, seed: u32, pixel: vec2u, index: u32,
//                             dim_1d: u32, dim_2d: u32) -> vec3f
//   fn sampler_to_unit_float(bits: u32) -> f32
//   Hashes: sampler_lowbias32(x), sampler_hash_combine(h, v), sampler_pixel_seed(seed, pixel),
//   sampler_pattern_seed(seed, pixel, dim), sampler_permute(i, l, p), sampler_lk_hash(x, seed),
//   sampler_owen_scramble(x, seed), sampler_mul_hi(a, b) — all u32.
// Every sampler function takes the pixel's `key` = sampler_pixel_seed(seed, pixel) (hashed once
// per pixel); sampler_hash_combine(key, dim) is a domain's pattern seed.
// Rust tuples become vectors: `grid` returns vec2u(m, n), `bits_2d` returns vec2u(x, y).
// No Option is involved.

// ---- Hashes (hash.rs) ------------------------------------------------------------------------

// Chris Wellons' lowbias32 integer hash (a bijection on u32).
fn sampler_lowbias32(x_in: u32) -> u32 {
    var x = x_in;
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

// Boost's hash_combine, finalized by lowbias32.
fn sampler_hash_combine(h: u32, v: u32) -> u32 {
    let mixed = v + 0x9e3779b9u + (h << 6u) + (h >> 2u);
    return sampler_lowbias32(h ^ mixed);
}

// The pixel's part of every pattern seed: render seed, then the pixel.
fn sampler_pixel_seed(seed: u32, pixel: vec2u) -> u32 {
    return sampler_hash_combine(sampler_hash_combine(sampler_lowbias32(seed), pixel.x), pixel.y);
}

// Seed of one sample pattern: render seed, pixel, then the domain's first dimension.
fn sampler_pattern_seed(seed: u32, pixel: vec2u, dim: u32) -> u32 {
    return sampler_hash_combine(sampler_pixel_seed(seed, pixel), dim);
}

// Whether n >= 1 is a power of two (Rust's `u32::is_power_of_two`).
fn sampler_is_pow2(n: u32) -> bool {
    return (n & (n - 1u)) == 0u;
}

// (a / d, a % d) for d >= 1, by a shift and a mask when d is a power of two (hash.rs `div_rem`):
// the same values, without an integer division, which lavapipe's 8-lane code does lane by lane.
fn sampler_div_rem(a: u32, d: u32) -> vec2u {
    if (sampler_is_pow2(d)) {
        return vec2u(a >> firstTrailingBit(d), a & (d - 1u));
    }
    return vec2u(a / d, a % d);
}

// Kensler 2013, "Correlated Multi-Jittered Sampling", `permute`: element i of a pseudo-random
// permutation of [0, l) keyed by p. Requires i < l, l >= 1.
fn sampler_permute(i_in: u32, l: u32, p: u32) -> u32 {
    var i = i_in;
    // Mask of the smallest power of two >= l.
    var w = l - 1u;
    w |= w >> 1u;
    w |= w >> 2u;
    w |= w >> 4u;
    w |= w >> 8u;
    w |= w >> 16u;
    // A bijection on [0, w]; walk its cycle until it returns into [0, l).
    loop {
        i ^= p;
        i *= 0xe170893du;
        i ^= p >> 16u;
        i ^= (i & w) >> 4u;
        i ^= p >> 8u;
        i *= 0x0929eb3fu;
        i ^= p >> 23u;
        i ^= (i & w) >> 1u;
        i *= 1u | (p >> 27u);
        i *= 0x6935fa69u;
        i ^= (i & w) >> 11u;
        i *= 0x74dcb303u;
        i ^= (i & w) >> 2u;
        i *= 0x9e501cc3u;
        i ^= (i & w) >> 2u;
        i *= 0xc860a3dfu;
        i &= w;
        i ^= i >> 5u;
        if (i < l) {
            break;
        }
    }
    // Final rotation by the key, (i + p) % l without wrapping.
    let r = sampler_div_rem(p, l).y;
    if (i >= l - r) {
        return i - (l - r);
    }
    return i + r;
}

// Laine–Karras-style hash on bit-reversed values, Vegdahl's constants ("Building a Better LK
// Hash", 2021).
fn sampler_lk_hash(x_in: u32, seed: u32) -> u32 {
    var x = x_in;
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16u) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

// Nested uniform (Owen) scramble of 32-bit fixed point: Burley 2020, "Practical Hash-based Owen
// Scrambling" (JCGT 9(4)).
fn sampler_owen_scramble(x: u32, seed: u32) -> u32 {
    return reverseBits(sampler_lk_hash(reverseBits(x), seed));
}

// High 32 bits of the 64-bit product a * b, from 16-bit limbs.
fn sampler_mul_hi(a: u32, b: u32) -> u32 {
    let a0 = a & 0xffffu;
    let a1 = a >> 16u;
    let b0 = b & 0xffffu;
    let b1 = b >> 16u;
    let p00 = a0 * b0;
    let p01 = a0 * b1;
    let p10 = a1 * b0;
    let p11 = a1 * b1;
    // Carry out of the low word (each term < 2^16: no overflow).
    let mid = (p00 >> 16u) + (p01 & 0xffffu) + (p10 & 0xffffu);
    return p11 + (p01 >> 16u) + (p10 >> 16u) + (mid >> 16u);
}

// Top 24 bits times 2^-24: exact in f32.
fn sampler_to_unit_float(bits: u32) -> f32 {
    return f32(bits >> 8u) * (1.0 / 16777216.0);
}

// ---- Independent (sampler/independent.rs) ----------------------------------------------------

// 32 random bits for dimension dim of sample index.
fn sampler_independent_bits(key: u32, index: u32, dim: u32) -> u32 {
    return sampler_hash_combine(sampler_hash_combine(key, dim), index);
}

// ---- Stratified (sampler/stratified.rs; Kensler 2013) ----------------------------------------

// Stratum count for spp samples per pixel: clamp(spp, 1, SAMPLER_MAX_STRATA), generated from
// `stratified::MAX_STRATA` (2^24).
fn sampler_strata(spp: u32) -> u32 {
    return clamp(spp, 1u, SAMPLER_MAX_STRATA);
}

// Grid (m, n), m * n = count, m the largest divisor of count not above sqrt(count).
fn sampler_grid(count_in: u32) -> vec2u {
    let count = max(count_in, 1u);
    if (sampler_is_pow2(count)) {
        // 2^j: the largest power of two not above its root, 2^(j / 2), divides it.
        let half = firstTrailingBit(count) >> 1u;
        return vec2u(1u << half, count >> half);
    }
    // Integer square root: f32 estimate, corrected exactly (so the result is the exact isqrt
    // whatever the estimate's rounding).
    var m = u32(sqrt(f32(count)));
    m = max(m, 1u);
    while (m > count / m) {
        m -= 1u;
    }
    while (m < count / (m + 1u)) {
        m += 1u;
    }
    // Largest divisor not above the root.
    while (count % m != 0u) {
        m -= 1u;
    }
    return vec2u(m, count / m);
}

// ceil(k * 2^24 / n) for k <= n <= 2^24, without an integer division (stratified.rs
// `scaled_ceil`): a shift when n is a power of two; else an f32 estimate of the quotient, a few
// units off at most, corrected to the exact value by its remainder k * 2^24 - q * n, exact in
// wrapping u32 arithmetic while within +-2^31. The estimate's rounding never reaches the result.
fn sampler_scaled_ceil(k: u32, n: u32) -> u32 {
    if (sampler_is_pow2(n)) {
        return k << (24u - firstTrailingBit(n));
    }
    var q = u32(f32(k) * (16777216.0 / f32(n)));
    var r = bitcast<i32>((k << 24u) - q * n);
    let ni = i32(n);
    while (r < 0) {
        q -= 1u;
        r += ni;
    }
    while (r >= ni) {
        q += 1u;
        r -= ni;
    }
    return q + select(0u, 1u, r != 0);
}

// 32-bit fixed-point value jittered inside stratum k of n (24 significant bits, shifted left 8).
fn sampler_stratum_bits(k: u32, jitter: u32, n: u32) -> u32 {
    if (sampler_is_pow2(n)) {
        // n = 2^j: the stratum is 2^(24 - j) values from k * 2^(24 - j), and the jitter's top
        // 24 - j bits pick one (mul_hi by a power of two).
        let j = firstTrailingBit(n);
        return ((k << (24u - j)) + ((jitter >> 8u) >> j)) << 8u;
    }
    let lo = sampler_scaled_ceil(k, n);
    let hi = sampler_scaled_ceil(k + 1u, n);
    return (lo + sampler_mul_hi(jitter, hi - lo)) << 8u;
}

// Pattern seed of this pass, sample position inside the pass, shuffled position: (base, s, t).
fn sampler_stratified_locate(key: u32, index: u32, dim: u32, n: u32) -> vec3u {
    let pass_s = sampler_div_rem(index, n);
    let s = pass_s.y;
    let base = sampler_hash_combine(sampler_hash_combine(key, dim), pass_s.x);
    let t = sampler_permute(s, n, sampler_hash_combine(base, 1u));
    return vec3u(base, s, t);
}

// 32-bit fixed-point value of the 1D domain at dim.
fn sampler_stratified_bits_1d(key: u32, index: u32, dim: u32, spp: u32) -> u32 {
    let n = sampler_strata(spp);
    let loc = sampler_stratified_locate(key, index, dim, n);
    let jitter = sampler_hash_combine(sampler_hash_combine(loc.x, 4u), loc.y);
    return sampler_stratum_bits(loc.z, jitter, n);
}

// 32-bit fixed-point point of the 2D domain at dim, dim + 1 (correlated multi-jitter).
fn sampler_stratified_bits_2d(key: u32, index: u32, dim: u32, spp: u32) -> vec2u {
    let n = sampler_strata(spp);
    let loc = sampler_stratified_locate(key, index, dim, n);
    let base = loc.x;
    let s = loc.y;
    let t = loc.z;
    let g = sampler_grid(n);
    let cols = g.x;
    let rows = g.y;
    let row_col = sampler_div_rem(t, cols);
    let row = row_col.x;
    let col = row_col.y;
    // One permutation per axis shared by the whole pattern.
    let sx = sampler_permute(col, cols, sampler_hash_combine(base, 2u));
    let sy = sampler_permute(row, rows, sampler_hash_combine(base, 3u));
    let jx = sampler_hash_combine(sampler_hash_combine(base, 4u), s);
    let jy = sampler_hash_combine(sampler_hash_combine(base, 5u), s);
    return vec2u(
        sampler_stratum_bits(col * rows + sy, jx, n),
        sampler_stratum_bits(row * cols + sx, jy, n),
    );
}

// ---- Owen-scrambled Sobol (sampler/sobol.rs; Burley 2020) ------------------------------------

// Sobol dimension 0: the van der Corput radical inverse.
fn sampler_sobol_dim0(i: u32) -> u32 {
    return reverseBits(i);
}

// Sobol dimension 1: Pascal's triangle mod 2 as a superset-parity transform of the index bits
// (five shift-xor steps), then a bit reversal (sobol.rs `sobol_dim1`).
fn sampler_sobol_dim1(i: u32) -> u32 {
    var a = i;
    a ^= (a >> 1u) & 0x55555555u;
    a ^= (a >> 2u) & 0x33333333u;
    a ^= (a >> 4u) & 0x0f0f0f0fu;
    a ^= (a >> 8u) & 0x00ff00ffu;
    a ^= (a >> 16u) & 0x0000ffffu;
    return reverseBits(a);
}

// Sobol dimension 2 (sobol.rs `sobol_dim2`): the XOR of the generator columns of the index bits
// set, the columns from the recurrence v_k = v_{k-1} ^ v_{k-2} ^ (v_{k-2} >> 2), v_0 = 2^31,
// v_1 = 3 * 2^30 (the Rust side's table; a test compares every column).
fn sampler_sobol_dim2(i: u32) -> u32 {
    var r = 0u;
    var v = 0x80000000u;
    var next = 0xc0000000u;
    for (var j = 0u; j < 32u; j++) {
        r ^= v & (0u - ((i >> j) & 1u));
        let after = next ^ v ^ (v >> 2u);
        v = next;
        next = after;
    }
    return r;
}

// 32-bit fixed-point value of the 1D domain at dim.
fn sampler_sobol_bits_1d(key: u32, index: u32, dim: u32) -> u32 {
    // Nested uniform shuffle of the index, then scramble the point.
    let base = sampler_hash_combine(key, dim);
    let i = sampler_owen_scramble(index, base);
    return sampler_owen_scramble(sampler_sobol_dim0(i), sampler_hash_combine(base, 1u));
}

// 32-bit fixed-point point of the 2D domain at dim, dim + 1.
fn sampler_sobol_bits_2d(key: u32, index: u32, dim: u32) -> vec2u {
    let base = sampler_hash_combine(key, dim);
    return sampler_sobol_point(sampler_owen_scramble(index, base), base);
}

// The scrambled Sobol (0,2) point of shuffled index i in the pattern with seed base (sobol.rs
// `point`).
fn sampler_sobol_point(i: u32, base: u32) -> vec2u {
    return vec2u(
        sampler_owen_scramble(sampler_sobol_dim0(i), sampler_hash_combine(base, 1u)),
        sampler_owen_scramble(sampler_sobol_dim1(i), sampler_hash_combine(base, 2u)),
    );
}

// A 1D value drawn with a 2D point (sobol.rs `bits_1d_2d`): x = Sobol dimension 2 of the
// point's shuffled index; yz = the point, the 2D pattern at dim_2d.
fn sampler_sobol_bits_1d_2d(key: u32, index: u32, dim_2d: u32) -> vec3u {
    let base = sampler_hash_combine(key, dim_2d);
    let i = sampler_owen_scramble(index, base);
    return vec3u(
        sampler_owen_scramble(sampler_sobol_dim2(i), sampler_hash_combine(base, 3u)),
        sampler_sobol_point(i, base),
    );
}

// ---- Dispatch (sampler.rs `PathSampler::sample_1d / sample_2d / sample_1d_2d`) ---------------

// Value in [0, 1) of the 1D domain at dim, for explicit sampler settings and the pixel's key.
fn sampler_sample_1d_keyed(kind: u32, spp: u32, key: u32, index: u32, dim: u32) -> f32 {
    var bits: u32;
    switch kind {
        case SAMPLER_INDEPENDENT: {
            bits = sampler_independent_bits(key, index, dim);
        }
        case SAMPLER_STRATIFIED: {
            bits = sampler_stratified_bits_1d(key, index, dim, max(spp, 1u));
        }
        default: {
            bits = sampler_sobol_bits_1d(key, index, dim);
        }
    }
    return sampler_to_unit_float(bits);
}

// Point in [0, 1)^2 of the 2D domain at dim, dim + 1, for explicit sampler settings and the
// pixel's key.
fn sampler_sample_2d_keyed(kind: u32, spp: u32, key: u32, index: u32, dim: u32) -> vec2f {
    var bits: vec2u;
    switch kind {
        case SAMPLER_INDEPENDENT: {
            // Two independent draws: dims dim and dim + 1.
            bits = vec2u(
                sampler_independent_bits(key, index, dim),
                sampler_independent_bits(key, index, dim + 1u),
            );
        }
        case SAMPLER_STRATIFIED: {
            bits = sampler_stratified_bits_2d(key, index, dim, max(spp, 1u));
        }
        default: {
            bits = sampler_sobol_bits_2d(key, index, dim);
        }
    }
    return vec2f(sampler_to_unit_float(bits.x), sampler_to_unit_float(bits.y));
}

// The 1D domain at dim_1d (x) drawn with the 2D domain at dim_2d (yz), for explicit sampler
// settings and the pixel's key; Sobol draws them as one pattern.
fn sampler_sample_1d_2d_keyed(kind: u32, spp: u32, key: u32, index: u32, dim_1d: u32, dim_2d: u32) -> vec3f {
    if (kind == SAMPLER_SOBOL) {
        let bits = sampler_sobol_bits_1d_2d(key, index, dim_2d);
        return vec3f(
            sampler_to_unit_float(bits.x),
            sampler_to_unit_float(bits.y),
            sampler_to_unit_float(bits.z),
        );
    }
    return vec3f(
        sampler_sample_1d_keyed(kind, spp, key, index, dim_1d),
        sampler_sample_2d_keyed(kind, spp, key, index, dim_2d),
    );
}

// Value in [0, 1) of the 1D domain at dim, for explicit sampler settings (sampler.rs
// `Sampler::sample_1d`).
fn sampler_sample_1d_with(kind: u32, spp: u32, seed: u32, pixel: vec2u, index: u32, dim: u32) -> f32 {
    return sampler_sample_1d_keyed(kind, spp, sampler_pixel_seed(seed, pixel), index, dim);
}

// Point in [0, 1)^2 of the 2D domain at dim, dim + 1, for explicit sampler settings.
fn sampler_sample_2d_with(kind: u32, spp: u32, seed: u32, pixel: vec2u, index: u32, dim: u32) -> vec2f {
    return sampler_sample_2d_keyed(kind, spp, sampler_pixel_seed(seed, pixel), index, dim);
}

// The 1D domain at dim_1d drawn with the 2D domain at dim_2d, for explicit sampler settings
// (sampler.rs `Sampler::sample_1d_2d`).
fn sampler_sample_1d_2d_with(kind: u32, spp: u32, seed: u32, pixel: vec2u, index: u32, dim_1d: u32, dim_2d: u32) -> vec3f {
    return sampler_sample_1d_2d_keyed(kind, spp, sampler_pixel_seed(seed, pixel), index, dim_1d, dim_2d);
}

// ---- Replicas (replica.rs) -------------------------------------------------------------------

// Sampler seed of replica r of a render with seed `seed`: the seed itself for replica 0, else
// hash_combine(seed, r).
fn sampler_replica_seed(seed: u32, r: u32) -> u32 {
    if (r == 0u) {
        return seed;
    }
    return sampler_hash_combine(seed, r);
}

// The replica this invocation samples: 0 (the render) or 1 (a twin pixel's independent
// randomization), set by the kernel entry point.
var<private> sampler_replica: u32;

// The pixel's key under the render's seed in this invocation's replica (sampler_begin_pixel).
var<private> sampler_key: u32;

// Hash the pixel's part of every pattern seed once: call after sampler_replica is set.
fn sampler_begin_pixel(pixel: vec2u) {
    sampler_key = sampler_pixel_seed(sampler_replica_seed(params.seed, sampler_replica), pixel);
}

// Value in [0, 1) of the 1D domain at dim under the render's sampler (params), for sample
// `index` of the pixel of sampler_begin_pixel.
fn sampler_sample_1d(index: u32, dim: u32) -> f32 {
    return sampler_sample_1d_keyed(params.sampler, params.spp, sampler_key, index, dim);
}

// Point in [0, 1)^2 of the 2D domain at dim, dim + 1 under the render's sampler, for sample
// `index` of the pixel of sampler_begin_pixel.
fn sampler_sample_2d(index: u32, dim: u32) -> vec2f {
    return sampler_sample_2d_keyed(params.sampler, params.spp, sampler_key, index, dim);
}

// The 1D domain at dim_1d (x) drawn with the 2D domain at dim_2d (yz) under the render's
// sampler, for sample `index` of the pixel of sampler_begin_pixel.
fn sampler_sample_1d_2d(index: u32, dim_1d: u32, dim_2d: u32) -> vec3f {
    return sampler_sample_1d_2d_keyed(params.sampler, params.spp, sampler_key, index, dim_1d, dim_2d);
}
