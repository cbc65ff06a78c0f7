//! Sampler properties: stratification (one sample per stratum / cell for the stratified
//! sampler, (0,m,2)-nets for Sobol), range, decorrelation across pixels / dimensions / seeds,
//! purity, and the hash building blocks the WGSL mirror copies.

mod common;

use common::{accept, fit, reject, Fit, Plant};

use std::collections::HashSet;

use stratapt_sampling::hash::{
    hash_combine, lk_hash, lowbias32, owen_scramble, pattern_seed, permute, pixel_seed,
};
use stratapt_sampling::sampler::{independent, sobol, stratified, to_unit_float};
use stratapt_sampling::testing::TestRng;
use stratapt_sampling::{Sampler, SamplerKind};

const PIXELS: [[u32; 2]; 4] = [[0, 0], [3, 7], [123, 45], [4095, 2160]];
const DIMS: [u32; 4] = [0, 1, 5, 38];
const SEEDS: [u32; 2] = [0, 0x00c0_ffee];

/// Stratum of `v ∈ [0,1)` among `n` equal strata (exact: `v` is a multiple of 2⁻²⁴).
fn stratum(v: f32, n: u32) -> usize {
    (f64::from(v) * f64::from(n)).floor() as usize
}

/// `Ok` when `cells` holds every value of `0..n` exactly once; else what is wrong.
fn one_each(cells: impl Iterator<Item = usize>, n: usize) -> Result<(), String> {
    let mut seen = vec![0u32; n];
    for c in cells {
        if c >= n {
            return Err(format!("cell {c} out of range {n}"));
        }
        seen[c] += 1;
    }
    if seen.iter().all(|&k| k == 1) {
        Ok(())
    } else {
        Err(format!("occupancy {seen:?}"))
    }
}

/// Assert that `cells` holds every value of `0..n` exactly once.
fn assert_one_each(cells: impl Iterator<Item = usize>, n: usize, what: &str) {
    if let Err(why) = one_each(cells, n) {
        panic!("{what}: {why}");
    }
}

/// `v` moved to the middle of the next of `n` strata (the last to the first): its own stratum
/// left empty, the next holding two.
fn next_stratum(v: f32, n: u32) -> f32 {
    let s = (stratum(v, n) + 1) % n as usize;
    ((s as f64 + 0.5) / f64::from(n)) as f32
}

const STRATIFIED_SIZES: [u32; 6] = [1, 7, 12, 16, 50, 64];

/// Every stratified 1D pattern the tests check, `(description, N, one pass of N values)`: pass 0
/// and the fresh pattern of pass 3 (indices beyond spp).
fn stratified_1d_patterns() -> Vec<(String, u32, Vec<f32>)> {
    let mut patterns = Vec::new();
    for n in STRATIFIED_SIZES {
        for seed in SEEDS {
            let sampler = Sampler::new(SamplerKind::Stratified, n, seed);
            for pixel in PIXELS {
                for dim in DIMS {
                    for pass in [0, 3] {
                        let values = (pass * n..(pass + 1) * n)
                            .map(|i| sampler.sample_1d(pixel, i, dim))
                            .collect();
                        let what =
                            format!("1D N={n} seed={seed} pixel={pixel:?} dim={dim} pass={pass}");
                        patterns.push((what, n, values));
                    }
                }
            }
        }
    }
    patterns
}

/// One value in each of the `n` strata.
fn stratified_1d_check(values: &[f32], n: u32) -> Result<(), String> {
    one_each(values.iter().map(|&v| stratum(v, n)), n as usize)
}

#[test]
fn stratified_1d_has_one_sample_per_stratum() {
    for (what, n, values) in stratified_1d_patterns() {
        if let Err(why) = stratified_1d_check(&values, n) {
            panic!("{what}: {why}");
        }
    }
}

/// Companion: every pattern of N ≥ 2 with its first value moved to the next stratum (a stratum
/// then holds two samples, its own none) is rejected.
#[test]
fn stratified_1d_check_rejects_a_sample_in_the_wrong_stratum() {
    let mut rejected = 0;
    for (what, n, mut values) in stratified_1d_patterns() {
        if n < 2 {
            continue;
        }
        values[0] = next_stratum(values[0], n);
        let why = stratified_1d_check(&values, n).expect_err(&format!(
            "{what}: a sample moved to the next stratum passed"
        ));
        if rejected == 0 {
            eprintln!("{what}, first value moved: rejected, {why}");
        }
        rejected += 1;
    }
    // 5 sizes × 2 seeds × 4 pixels × 4 dims × 2 passes.
    assert_eq!(rejected, 320);
}

/// Every stratified 2D pattern the tests check, `(description, N, one pass of N points)`.
fn stratified_2d_patterns() -> Vec<(String, u32, Vec<glam::Vec2>)> {
    let mut patterns = Vec::new();
    for n in STRATIFIED_SIZES {
        let (m, rows) = stratified::grid(n);
        assert_eq!(m * rows, n);
        for seed in SEEDS {
            let sampler = Sampler::new(SamplerKind::Stratified, n, seed);
            for pixel in PIXELS {
                for dim in DIMS {
                    for pass in [0, 2] {
                        let pts = (pass * n..(pass + 1) * n)
                            .map(|i| sampler.sample_2d(pixel, i, dim))
                            .collect();
                        let what = format!("2D N={n} ({m}×{rows}) seed={seed} pixel={pixel:?} dim={dim} pass={pass}");
                        patterns.push((what, n, pts));
                    }
                }
            }
        }
    }
    patterns
}

/// The cell of `p` on the `m × rows` grid of the stratified pattern of `n` points.
fn grid_cell(p: glam::Vec2, n: u32) -> usize {
    let (m, rows) = stratified::grid(n);
    stratum(p.y, rows) * m as usize + stratum(p.x, m)
}

/// One point in each of the `n` strata of x, of y, and in each cell of the grid; `Err` names
/// every check that failed ("x", "y", "cells").
fn stratified_2d_check(pts: &[glam::Vec2], n: u32) -> Result<(), String> {
    let check =
        |cell: &dyn Fn(glam::Vec2) -> usize| one_each(pts.iter().map(|&p| cell(p)), n as usize);
    let checks = [
        ("x", check(&|p| stratum(p.x, n))),
        ("y", check(&|p| stratum(p.y, n))),
        ("cells", check(&|p| grid_cell(p, n))),
    ];
    let failed: Vec<String> = checks
        .into_iter()
        .filter_map(|(name, r)| r.err().map(|why| format!("{name}: {why}")))
        .collect();
    if failed.is_empty() {
        Ok(())
    } else {
        Err(failed.join("; "))
    }
}

#[test]
fn stratified_2d_has_one_sample_per_stratum_and_cell() {
    for (what, n, pts) in stratified_2d_patterns() {
        if let Err(why) = stratified_2d_check(&pts, n) {
            panic!("{what}: {why}");
        }
    }
}

/// Companion, one plant per check: every pattern of N ≥ 2 with its first point's x moved to the
/// next x stratum is rejected by the x check, likewise y; and every pattern whose grid has two
/// rows and two columns, with the x of two points in different rows and columns swapped (every x
/// and y stratum still holds one point, but a cell now holds two), is rejected by the cell check
/// alone.
#[test]
fn stratified_2d_check_rejects_a_point_in_the_wrong_stratum_or_cell() {
    let (mut moved, mut swapped) = (0, 0);
    for (what, n, pts) in stratified_2d_patterns() {
        if n < 2 {
            continue;
        }
        for (axis, check) in [(0, "x: "), (1, "y: ")] {
            let mut bad = pts.clone();
            bad[0][axis] = next_stratum(bad[0][axis], n);
            let why = stratified_2d_check(&bad, n)
                .expect_err(&format!("{what}: a point moved in {check}passed"));
            assert!(why.contains(check), "{what}: rejected for {why}");
            moved += 1;
        }
        let (m, rows) = stratified::grid(n);
        let col_row = |p: glam::Vec2| (stratum(p.x, m), stratum(p.y, rows));
        let (c0, r0) = col_row(pts[0]);
        if let Some(j) = pts.iter().position(|&p| {
            let (c, r) = col_row(p);
            c != c0 && r != r0
        }) {
            let mut bad = pts.clone();
            (bad[0].x, bad[j].x) = (pts[j].x, pts[0].x);
            let why = stratified_2d_check(&bad, n)
                .expect_err(&format!("{what}: two points swapped across cells passed"));
            assert!(why.starts_with("cells: "), "{what}: rejected for {why}");
            if swapped == 0 {
                eprintln!("{what}, x of points 0 and {j} swapped: rejected, {why}");
            }
            swapped += 1;
        }
    }
    // 5 sizes ≥ 2 (× 2 seeds × 4 pixels × 4 dims × 2 passes) × 2 axes; the swap where the grid
    // has two rows and columns: N = 12 (3×4), 16, 50 (5×10), 64, not 7 (1×7).
    assert_eq!((moved, swapped), (640, 256));
}

/// `Ok` when `pts` (2^m points) is a (0,m,2)-net: one point in every elementary interval
/// `2^-a × 2^-b`, `a + b = m`; else the first shape (smallest `a`) that fails.
fn net(pts: &[[u32; 2]], m: u32) -> Result<(), String> {
    for a in 0..=m {
        let b = m - a;
        // With 32-bit fixed point, the cell index is the top bits.
        let cell = |p: &[u32; 2]| {
            let x = if a == 0 {
                0
            } else {
                (p[0] >> (32 - a)) as usize
            };
            let y = if b == 0 {
                0
            } else {
                (p[1] >> (32 - b)) as usize
            };
            (y << a) | x
        };
        one_each(pts.iter().map(cell), 1 << m).map_err(|why| format!("a={a} b={b}: {why}"))?;
    }
    Ok(())
}

/// One block of Sobol points the net test checks: its description, size `2^m`, first index,
/// the 2D points in fixed point and the 1D values of the same indices.
struct SobolBlock {
    what: String,
    seed: u32,
    pixel: [u32; 2],
    dim: u32,
    m: u32,
    start: u32,
    pts: Vec<[u32; 2]>,
    values: Vec<f32>,
}

/// The prefixes of 2^m points, m ≤ 10, and two later aligned blocks of each size, for every seed,
/// pixel and dimension.
fn sobol_blocks() -> Vec<SobolBlock> {
    let mut blocks = Vec::new();
    for seed in SEEDS {
        let sampler = Sampler::new(SamplerKind::Sobol, 1, seed);
        for pixel in PIXELS {
            for dim in DIMS {
                for m in 0..=10u32 {
                    for block in [0u32, 1, 5] {
                        let start = block << m;
                        let idx = start..start + (1 << m);
                        blocks.push(SobolBlock {
                            what: format!(
                                "sobol 2D seed={seed} pixel={pixel:?} dim={dim} m={m} block={block}"
                            ),
                            seed,
                            pixel,
                            dim,
                            m,
                            start,
                            pts: idx
                                .clone()
                                .map(|i| sobol::bits_2d(pixel_seed(seed, pixel), i, dim))
                                .collect(),
                            values: idx.map(|i| sampler.sample_1d(pixel, i, dim)).collect(),
                        });
                    }
                }
            }
        }
    }
    blocks
}

/// The shift-xor Sobol dimension 1 is the Pascal-matrix product, column by column, on every
/// 16-bit index and a million random 32-bit ones (and the extremes).
#[test]
fn sobol_dim1_equals_its_generator_matrix() {
    let mut rng = TestRng(0x9e37_79b9_7f4a_7c15);
    let random = (0..1_000_000).map(|_| rng.u32());
    for i in (0..=u16::MAX as u32)
        .chain(random)
        .chain([u32::MAX, 1 << 31])
    {
        assert_eq!(
            sobol::sobol_dim1(i),
            sobol::sobol_dim1_columns(i),
            "index {i:#x}"
        );
    }
}

#[test]
fn sobol_prefixes_and_aligned_blocks_are_nets() {
    for b in sobol_blocks() {
        if let Err(why) = net(&b.pts, b.m) {
            panic!("{} {why}", b.what);
        }
        // The floats are the top 24 bits: the same strata.
        let sampler = Sampler::new(SamplerKind::Sobol, 1, b.seed);
        for (i, p) in (b.start..).zip(&b.pts) {
            let v = sampler.sample_2d(b.pixel, i, b.dim);
            assert_eq!((v.x, v.y), (to_unit_float(p[0]), to_unit_float(p[1])));
        }
        let strata = b.values.iter().map(|&v| stratum(v, 1 << b.m));
        assert_one_each(strata, 1 << b.m, &format!("{} 1D", b.what));
    }
}

/// Companion, one plant per interval shape: in every block of 2^m ≥ 2 points, the first point
/// moved by one interval width `2^-a` in x (its top `a` bits' last one flipped, so it joins the
/// neighbouring `2^-a × 2^-(m−a)` interval, which already holds a point) is rejected by the
/// check of that shape, every shape `a = 1..=m`; and its 1D value moved to the next of the 2^m
/// strata is rejected by the 1D check.
#[test]
fn sobol_net_check_rejects_a_point_moved_one_interval() {
    let (mut rejected_2d, mut rejected_1d) = (0, 0);
    for b in sobol_blocks().into_iter().filter(|b| b.m >= 1) {
        for a in 1..=b.m {
            let mut pts = b.pts.clone();
            pts[0][0] ^= 1 << (32 - a);
            let why = net(&pts, b.m)
                .expect_err(&format!("{}: a point moved by 2^-{a} in x passed", b.what));
            assert!(
                why.starts_with(&format!("a={a} b={}:", b.m - a)),
                "{}: moved by 2^-{a}, rejected for {why}",
                b.what
            );
            if rejected_2d == 0 {
                eprintln!("{}, point 0 moved by 2^-{a} in x: rejected, {why}", b.what);
            }
            rejected_2d += 1;
        }
        let mut values = b.values.clone();
        values[0] = next_stratum(values[0], 1 << b.m);
        assert!(
            one_each(values.iter().map(|&v| stratum(v, 1 << b.m)), 1 << b.m).is_err(),
            "{}: a 1D value moved to the next stratum passed",
            b.what
        );
        rejected_1d += 1;
    }
    // 2 seeds × 4 pixels × 4 dims × 3 blocks = 96 per size; Σ m over m = 1..=10 is 55.
    assert_eq!((rejected_2d, rejected_1d), (96 * 55, 96 * 10));
}

/// Sobol dimension 2 is the Joe–Kuo dimension 3 (1-based): direction numbers from the
/// primitive polynomial x² + x + 1 and m = 1, 3 by the general recurrence
/// `m_k = 2a₁m_{k−1} ⊕ 2²m_{k−2} ⊕ m_{k−2}`, each column being the value of one index bit.
#[test]
fn sobol_dim2_equals_joe_kuo_direction_numbers() {
    let mut m = vec![1u64, 3];
    for k in 2..32 {
        m.push((2 * m[k - 1]) ^ (4 * m[k - 2]) ^ m[k - 2]);
    }
    for (j, &mj) in m.iter().enumerate() {
        assert!(mj % 2 == 1 && mj < 1 << (j + 1), "m_{j} = {mj}");
        let column = (mj << (31 - j)) as u32;
        assert_eq!(sobol::SOBOL_DIM2[j], column, "column {j}");
        assert_eq!(sobol::sobol_dim2(1 << j), column, "index bit {j}");
    }
    // Linear over GF(2): the value of an index is the XOR of its bits' columns.
    for i in common::uniforms(2000, 3).map(|u| u.x.to_bits() ^ u.y.to_bits().rotate_left(7)) {
        let xor = (0..32)
            .filter(|j| i >> j & 1 == 1)
            .fold(0, |acc, j| acc ^ sobol::SOBOL_DIM2[j]);
        assert_eq!(sobol::sobol_dim2(i), xor, "index {i:#x}");
    }
}

/// Points `(c, x, y)` in 32-bit fixed point per elementary box `2^-a × 2^-b × 2^-c`,
/// `a + b + c = m − t`: `true` when every box holds exactly `2^t` points (a (t,m,3)-net).
fn is_net_3d(pts: &[[u32; 3]], m: u32, t: u32) -> bool {
    if t > m {
        return true;
    }
    let k = m - t;
    let top = |v: u32, bits: u32| {
        if bits == 0 {
            0
        } else {
            (v >> (32 - bits)) as usize
        }
    };
    for a in 0..=k {
        for b in 0..=k - a {
            let c = k - a - b;
            let mut count = vec![0u32; 1 << k];
            for p in pts {
                count[(top(p[0], a) << (b + c)) | (top(p[1], b) << c) | top(p[2], c)] += 1;
            }
            if count.iter().any(|&n| n != 1 << t) {
                return false;
            }
        }
    }
    true
}

/// `Ok` when the choices (first coordinates) of `joint` (2^m points) hold one in each of the
/// 2^m strata.
fn choice_strata(joint: &[[u32; 3]], m: u32) -> Result<(), String> {
    let top = |p: &[u32; 3]| (p[0] >> (32 - m.max(1))) as usize >> (m == 0) as u32;
    one_each(joint.iter().map(top), 1 << m)
}

/// A 1D domain drawn with a 2D one by the Sobol sampler (the light choice with the point on the
/// light, the shutter instant with the pixel position): the point is exactly the 2D pattern of its
/// dimension; the choice is stratified on its own (one per stratum of every power-of-two prefix and
/// aligned block) and jointly with the point: (choice, point) is a (1,m,3)-net. The choice drawn
/// apart (the 1D pattern of its own dimension, as before) is not: the check rejects it every time
/// from m = 5 on (with 8 or 16 points a random choice can pass).
#[test]
fn sobol_1d_with_2d_is_a_net_of_three_dimensions() {
    let mut apart_rejected = 0;
    for seed in SEEDS {
        for pixel in PIXELS {
            let key = pixel_seed(seed, pixel);
            for dim in DIMS {
                for m in 0..=10u32 {
                    for block in [0u32, 1, 5] {
                        let start = block << m;
                        let what =
                            format!("seed={seed} pixel={pixel:?} dim={dim} m={m} block={block}");
                        let mut joint = Vec::new();
                        let mut apart = Vec::new();
                        for i in start..start + (1 << m) {
                            let (c, [x, y]) = sobol::bits_1d_2d(key, i, dim + 1);
                            assert_eq!([x, y], sobol::bits_2d(key, i, dim + 1), "{what}");
                            joint.push([c, x, y]);
                            apart.push([sobol::bits_1d(key, i, dim), x, y]);
                        }
                        if let Err(why) = choice_strata(&joint, m) {
                            panic!("{what} choice: {why}");
                        }
                        assert!(is_net_3d(&joint, m, 1), "{what}: not a (1,m,3)-net");
                        if m >= 5 && !is_net_3d(&apart, m, 1) {
                            apart_rejected += 1;
                        }
                    }
                }
            }
        }
    }
    // 2 seeds × 4 pixels × 4 dims × 6 sizes (m = 5..=10) × 3 blocks.
    assert_eq!(
        apart_rejected, 576,
        "a choice drawn apart passed as a (1,m,3)-net"
    );
}

/// Companion of the structural checks (the choice drawn apart is the test's own): in every block
/// of 2^m joint points, one point moved by one box width `2^-(m−1)` along any of the three axes
/// (so a `2^-(m−1)` slab along that axis holds three points, its own one) is not a (1,m,3)-net,
/// m ≥ 2 (with two points, one box of the whole cube, nothing can move out); and its choice moved
/// by `2^-m` (to the next stratum) fails the choice's stratification, m ≥ 1.
#[test]
fn sobol_1d_2d_checks_reject_a_point_moved_one_box() {
    let (mut rejected_net, mut rejected_choice) = (0, 0);
    for seed in SEEDS {
        for pixel in PIXELS {
            let key = pixel_seed(seed, pixel);
            for dim in DIMS {
                for m in 1..=10u32 {
                    for block in [0u32, 1, 5] {
                        let start = block << m;
                        let what =
                            format!("seed={seed} pixel={pixel:?} dim={dim} m={m} block={block}");
                        let joint: Vec<[u32; 3]> = (start..start + (1 << m))
                            .map(|i| {
                                let (c, [x, y]) = sobol::bits_1d_2d(key, i, dim + 1);
                                [c, x, y]
                            })
                            .collect();
                        for axis in 0..3 {
                            if m < 2 {
                                break;
                            }
                            let mut moved = joint.clone();
                            moved[0][axis] ^= 1 << (32 - (m - 1));
                            assert!(
                                !is_net_3d(&moved, m, 1),
                                "{what}: a point moved by 2^-{} on axis {axis} passed",
                                m - 1
                            );
                            rejected_net += 1;
                        }
                        let mut moved = joint.clone();
                        moved[0][0] ^= 1 << (32 - m);
                        let why = choice_strata(&moved, m)
                            .expect_err(&format!("{what}: a choice moved by 2^-{m} passed"));
                        if rejected_choice == 0 {
                            eprintln!("{what}, choice 0 moved by 2^-{m}: rejected, {why}");
                        }
                        rejected_choice += 1;
                    }
                }
            }
        }
    }
    // 2 seeds × 4 pixels × 4 dims × 3 blocks = 96 per size: 9 sizes (m = 2..=10) × 3 axes for
    // the net, 10 (m = 1..=10) for the choice.
    assert_eq!((rejected_net, rejected_choice), (96 * 27, 96 * 10));
}

#[test]
fn values_lie_in_unit_interval() {
    let extremes = [0u32, 1, 2, 0x7fff_ffff, 0x8000_0000, u32::MAX - 1, u32::MAX];
    for kind in SamplerKind::ALL {
        for spp in [1u32, 3, 64, 1 << 24, u32::MAX] {
            for seed in [0, 1, u32::MAX] {
                let sampler = Sampler::new(kind, spp, seed);
                let inputs = common::uniforms(3000, seed ^ spp)
                    .map(|u| (u.x.to_bits(), u.y.to_bits()))
                    .chain(extremes.iter().map(|&e| (e, e)));
                for (a, b) in inputs {
                    for (pixel, index, dim) in [([a, b], b, a % 64), ([b, 7], a, b), ([0, 0], a, 0)]
                    {
                        let v = sampler.sample_1d(pixel, index, dim);
                        let p = sampler.sample_2d(pixel, index, dim);
                        for x in [v, p.x, p.y] {
                            assert!((0.0..1.0).contains(&x), "{kind} {x} out of [0,1)");
                        }
                    }
                }
            }
        }
    }
    assert!(to_unit_float(u32::MAX) < 1.0);
    assert_eq!(to_unit_float(0), 0.0);
}

/// The first 16 values (1D and 2D) of one pattern, as bits.
fn sequence(sampler: &Sampler, pixel: [u32; 2], dim: u32) -> Vec<u32> {
    (0..16)
        .flat_map(|i| {
            let p = sampler.sample_2d(pixel, i, dim);
            [
                sampler.sample_1d(pixel, i, dim).to_bits(),
                p.x.to_bits(),
                p.y.to_bits(),
            ]
        })
        .collect()
}

#[test]
fn patterns_differ_across_pixels_dims_and_seeds() {
    for kind in SamplerKind::ALL {
        let mut seen = HashSet::new();
        let mut count = 0;
        for seed in [0, 1, 2, 0xdead_beef] {
            let sampler = Sampler::new(kind, 16, seed);
            for pixel in [[0, 0], [1, 0], [0, 1], [1, 1], [640, 480], [480, 640]] {
                for dim in 0..12 {
                    seen.insert(sequence(&sampler, pixel, dim));
                    count += 1;
                }
            }
        }
        assert_eq!(seen.len(), count, "{kind}: two patterns coincide");
    }
}

/// Pearson correlation of two equally long series.
fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma) * (x - ma)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb) * (y - mb)).sum();
    cov / (va * vb).sqrt()
}

/// Samples per series in the correlation test.
const CORRELATION_N: u32 = 4096;

/// The correlation test's bound: |ρ| < 5/√n, a 5-sigma bound under independence.
fn correlation_bound() -> f64 {
    5.0 / f64::from(CORRELATION_N).sqrt()
}

/// The smallest correlation the bound surely sees: a sample correlation of true value ρ₀ has
/// standard deviation (1 − ρ₀²)/√n ≤ 1/√n, so ρ₀ = 9/√n lies 4 deviations past the bound 5/√n.
fn detectable_correlation() -> f64 {
    (5.0 + 4.0) / f64::from(CORRELATION_N).sqrt()
}

/// One pair of series and its verdict.
struct Correlation {
    what: String,
    rho: f64,
    verdict: Result<(), String>,
}

/// Within one pixel, across the sample index: each pair of dimensions (1D and the axes of 2D
/// domains), and the same dimension in neighbouring pixels, with the correlation `planted` planted
/// (0: none): the second series made `b + c·a`, `c = ρ₀/√(1 − ρ₀²)`, which for two independent
/// series of equal variance has correlation ρ₀.
fn correlations(planted: f64) -> Vec<Correlation> {
    let n = CORRELATION_N;
    let bound = correlation_bound();
    let c = planted / (1.0 - planted * planted).sqrt();
    let mut out = Vec::new();
    for kind in SamplerKind::ALL {
        let sampler = Sampler::new(kind, n, 11);
        let series = |pixel: [u32; 2], dim: u32, axis: u32| -> Vec<f64> {
            (0..n)
                .map(|i| match axis {
                    0 => f64::from(sampler.sample_1d(pixel, i, dim)),
                    1 => f64::from(sampler.sample_2d(pixel, i, dim).x),
                    _ => f64::from(sampler.sample_2d(pixel, i, dim).y),
                })
                .collect()
        };
        let pairs = [
            (([5, 9], 0, 1), ([5, 9], 0, 2)), // x vs y of one 2D domain
            (([5, 9], 0, 1), ([5, 9], 2, 1)), // x of two 2D domains
            (([5, 9], 0, 2), ([5, 9], 2, 2)),
            (([5, 9], 4, 0), ([5, 9], 5, 0)), // two consecutive 1D domains
            (([5, 9], 3, 1), ([6, 9], 3, 1)), // neighbouring pixels
            (([5, 9], 3, 0), ([5, 10], 3, 0)),
        ];
        for ((p1, d1, a1), (p2, d2, a2)) in pairs {
            let a = series(p1, d1, a1);
            let b: Vec<f64> = series(p2, d2, a2)
                .iter()
                .zip(&a)
                .map(|(y, x)| y + c * x)
                .collect();
            let rho = correlation(&a, &b);
            let what = format!("{kind}: {p1:?}/{d1}/{a1} vs {p2:?}/{d2}/{a2}");
            let verdict = if rho.abs() < bound {
                Ok(())
            } else {
                Err(format!("|ρ| = {:.4} ≥ {bound:.4}", rho.abs()))
            };
            out.push(Correlation { what, rho, verdict });
        }
    }
    out
}

#[test]
fn dimensions_and_pixels_are_uncorrelated() {
    for r in correlations(0.0) {
        if let Err(why) = r.verdict {
            panic!("{}: ρ = {} ({why})", r.what, r.rho);
        }
    }
}

/// Companion: every pair, made correlated by the smallest correlation the bound surely sees
/// (ρ₀ = 9/√n = 0.141 at n = 4096), is rejected.
#[test]
fn correlation_check_rejects_correlated_dimensions() {
    let planted = detectable_correlation();
    let fits = correlations(planted);
    assert_eq!(fits.len(), 18);
    for r in fits {
        eprintln!(
            "{}: ρ₀ = {planted:.4} planted, ρ = {:.4}: {:?}",
            r.what, r.rho, r.verdict
        );
        assert!(r.verdict.is_err(), "{}: correlated series accepted", r.what);
    }
}

/// Pooled over pixels each sampler is uniform on [0,1)²: chi-square on a 16×16 grid, with
/// `plant` planted.
fn uniformity(plant: Plant) -> Vec<Fit> {
    let (nx, ny) = (16, 16);
    let probs = vec![1.0 / (nx * ny) as f64; nx * ny];
    let mut fits = Vec::new();
    for kind in SamplerKind::ALL {
        let spp = 32;
        let sampler = Sampler::new(kind, spp, 5);
        let samples = (0..100_000u32).map(|k| {
            let (pixel, i) = ([k / spp % 64, k / spp / 64], k % spp);
            let p = sampler.sample_2d(pixel, i, 3 + (k & 1));
            Some([f64::from(p.x), f64::from(p.y)])
        });
        let name = format!("{kind} sampler 2D uniformity");
        fits.push(fit(&name, samples, &probs, nx, ny, plant));
    }
    fits
}

#[test]
fn samplers_are_uniform_over_many_pixels() {
    accept(uniformity(Plant::None));
}

/// A 1D domain drawn with a 2D one (the light choice and point), pooled over pixels, on [0,1)³:
/// chi-square on 4 × 8 × 8 cells (the choice's quarter and the point's x as one axis), with
/// `plant` planted.
fn joint_uniformity(plant: Plant) -> Vec<Fit> {
    let probs = vec![1.0 / 256.0; 256];
    let mut fits = Vec::new();
    for kind in SamplerKind::ALL {
        let spp = 32;
        let sampler = Sampler::new(kind, spp, 9);
        let samples = (0..100_000u32).map(|k| {
            let (pixel, i) = ([k / spp % 64, k / spp / 64], k % spp);
            let (c, p) = sampler.sample_1d_2d(pixel, i, 7, 8);
            let quarter = (c * 4.0).floor();
            Some([(f64::from(quarter) + f64::from(p.x)) / 4.0, f64::from(p.y)])
        });
        let name = format!("{kind} light domain");
        fits.push(fit(&name, samples, &probs, 32, 8, plant));
    }
    fits
}

/// A 1D domain drawn with a 2D one (the light choice and point), pooled over pixels, is uniform on
/// [0,1)³ for every sampler ([`joint_uniformity`]), and is what the contract says: Sobol's point
/// is its 2D pattern, the other samplers' domains are their 1D and 2D patterns.
#[test]
fn joint_1d_2d_is_uniform_and_as_documented() {
    accept(joint_uniformity(Plant::None));
    for kind in SamplerKind::ALL {
        let sampler = Sampler::new(kind, 32, 9);
        for pixel in PIXELS {
            for i in [0, 5, 31, 32, 1000] {
                let (c, p) = sampler.sample_1d_2d(pixel, i, 7, 8);
                assert_eq!(p, sampler.sample_2d(pixel, i, 8), "{kind}");
                assert_eq!(
                    (c.to_bits(), p),
                    {
                        let (c, p) = sampler.path(pixel, i).sample_1d_2d(7, 8);
                        (c.to_bits(), p)
                    },
                    "{kind}"
                );
                if kind != SamplerKind::Sobol {
                    assert_eq!(
                        c.to_bits(),
                        sampler.sample_1d(pixel, i, 7).to_bits(),
                        "{kind}"
                    );
                }
            }
        }
    }
}

/// Companion of both sampler chi-square tests: every sampler's samples biased toward high y, by
/// the bend `y + δ·y(1 − y)` (a relative density error `δ(1 − 2y)`) with δ the smallest that
/// each fit's own sample count, bins and significance surely resolve
/// ([`common::detectable_bend`]), are rejected by the p-value.
#[test]
fn sampler_chi2_rejects_samples_biased_to_one_side() {
    reject(uniformity(Plant::WarpBend), "p =");
    reject(joint_uniformity(Plant::WarpBend), "p =");
}

#[test]
fn sampler_is_a_pure_function_of_its_inputs() {
    for kind in SamplerKind::ALL {
        let a = Sampler::new(kind, 12, 77);
        let b = Sampler {
            kind,
            spp: 12,
            seed: 77,
        };
        for pixel in PIXELS {
            for i in [0, 5, 11, 12, 1000] {
                for dim in DIMS {
                    assert_eq!(
                        a.sample_1d(pixel, i, dim).to_bits(),
                        b.sample_1d(pixel, i, dim).to_bits()
                    );
                    assert_eq!(a.sample_2d(pixel, i, dim), b.sample_2d(pixel, i, dim));
                    // The dispatch is exactly the per-kind module functions.
                    let key = pixel_seed(77, pixel);
                    let direct = match kind {
                        SamplerKind::Independent => independent::sample_2d(key, i, dim),
                        SamplerKind::Stratified => stratified::sample_2d(key, i, dim, 12),
                        SamplerKind::Sobol => sobol::sample_2d(key, i, dim),
                    };
                    assert_eq!(a.sample_2d(pixel, i, dim), direct);
                    // One path's sampler: the same values, the pixel hashed once.
                    let path = a.path(pixel, i);
                    assert_eq!(path.sample_2d(dim), direct);
                    assert_eq!(
                        path.sample_1d(dim).to_bits(),
                        a.sample_1d(pixel, i, dim).to_bits()
                    );
                }
            }
        }
    }
    // spp = 0 in a literal behaves like 1 (one stratum, every index a fresh pass).
    let zero = Sampler {
        kind: SamplerKind::Stratified,
        spp: 0,
        seed: 3,
    };
    assert_eq!(
        zero.sample_2d([1, 2], 9, 4),
        Sampler::new(SamplerKind::Stratified, 0, 3).sample_2d([1, 2], 9, 4)
    );
    // Independent 2D is two 1D dimensions.
    let ind = Sampler::new(SamplerKind::Independent, 1, 9);
    let p = ind.sample_2d([3, 4], 17, 6);
    assert_eq!(
        (p.x, p.y),
        (ind.sample_1d([3, 4], 17, 6), ind.sample_1d([3, 4], 17, 7))
    );
}

#[test]
fn permute_is_a_permutation_for_every_length() {
    for l in 1..=300u32 {
        for p in [0u32, 1, 0x1234_5678, lowbias32(l), u32::MAX] {
            assert_one_each(
                (0..l).map(|i| permute(i, l, p) as usize),
                l as usize,
                &format!("l={l} p={p}"),
            );
        }
    }
    // Different keys give different permutations.
    let a: Vec<u32> = (0..64).map(|i| permute(i, 64, 1)).collect();
    let b: Vec<u32> = (0..64).map(|i| permute(i, 64, 2)).collect();
    assert_ne!(a, b);
}

#[test]
fn owen_scramble_is_a_nested_bijection() {
    for seed in [0u32, 1, 0x9e37_79b9, u32::MAX] {
        // Top k bits of the output depend only on the top k bits of the input.
        let mut x = 12345u32;
        for _ in 0..2000 {
            x = lowbias32(x);
            let noise = lowbias32(x ^ 0x55);
            for k in [1u32, 4, 9, 16, 24, 31] {
                let low = (1u32 << (32 - k)) - 1;
                let y = (x & !low) | (noise & low);
                assert_eq!(
                    owen_scramble(x, seed) >> (32 - k),
                    owen_scramble(y, seed) >> (32 - k)
                );
            }
            // In the reversed domain, bit k depends only on bits ≤ k.
            assert_eq!(
                lk_hash(x & 0xffff, seed) & 0xffff,
                lk_hash(x, seed) & 0xffff
            );
        }
        // A bijection on the top 16 bits.
        let tops = (0..1u32 << 16).map(|t| (owen_scramble(t << 16, seed) >> 16) as usize);
        assert_one_each(tops, 1 << 16, &format!("owen seed={seed}"));
    }
}

#[test]
fn hashes_are_bijective_in_their_value() {
    for h in [0u32, 1, 0xabcd_ef01, u32::MAX] {
        let images: HashSet<u32> = (0..1u32 << 16).map(|v| hash_combine(h, v)).collect();
        assert_eq!(images.len(), 1 << 16, "hash_combine({h}, ·) collides");
    }
    let images: HashSet<u32> = (0..1u32 << 16).map(|v| lowbias32(v << 16)).collect();
    assert_eq!(images.len(), 1 << 16);
    // pattern_seed is the pixel's seed folded with the dimension.
    assert_eq!(
        pattern_seed(9, [1, 2], 3),
        hash_combine(pixel_seed(9, [1, 2]), 3)
    );
    // pattern_seed separates its arguments (no symmetric collisions).
    assert_ne!(pattern_seed(0, [1, 2], 3), pattern_seed(0, [2, 1], 3));
    assert_ne!(pattern_seed(0, [1, 2], 3), pattern_seed(3, [1, 2], 0));
    assert_ne!(pattern_seed(1, [0, 0], 0), pattern_seed(0, [0, 0], 1));
}
