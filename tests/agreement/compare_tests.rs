//! The comparison of `compare.rs` on synthetic films (only `tests/agreement.rs` includes this
//! file, so the tests run once): it accepts what should agree and rejects a real difference,
//! and the paired comparison rejects small shifts the unpaired one cannot see.

use super::compare::*;
use stratapt::film::Film;
use stratapt::sampling::testing::TestRng;

// ---------------------------------------------------------------------------------------------
// The comparison on synthetic films: it accepts what should agree and rejects a real difference
// ---------------------------------------------------------------------------------------------

/// A 16×16 film of 64 samples per pixel (enough for the normal approximation of the z-test),
/// each `shift(x, y) + spread · u` with u uniform in [0, 1).
fn synthetic(seed: u64, spread: f32, shift: impl Fn(u32, u32) -> f32) -> Film {
    let mut rng = TestRng(seed);
    let mut film = Film::new(16, 16);
    for y in 0..16 {
        for x in 0..16 {
            for _ in 0..64 {
                let value = [(); 3].map(|_| shift(x, y) + spread * rng.f32());
                film.add_sample(x, y, value);
            }
        }
    }
    film
}

#[test]
fn comparison_accepts_films_of_one_distribution() {
    let cmp = compare(
        &synthetic(1, 1.0, |_, _| 0.0),
        &synthetic(2, 1.0, |_, _| 0.0),
    );
    assert!(cmp.problems().is_empty(), "{cmp:?}");
    assert_eq!(cmp.bit_close, 0);
}

#[test]
fn comparison_rejects_a_shifted_image_mean() {
    // A shift of 0.025 is half a combined per-pixel standard deviation (uniform: σ = 0.29, 64
    // spp), which the per-pixel test cannot see, but about 8 of the image mean's (16384 samples).
    let cmp = compare(
        &synthetic(2, 1.0, |_, _| 0.025),
        &synthetic(1, 1.0, |_, _| 0.0),
    );
    assert_eq!(cmp.failing, 0, "{cmp:?}");
    assert_eq!(cmp.image.len(), 3, "{cmp:?}");
    assert!(cmp.image.iter().all(|&(.., z)| z > 6.0), "{cmp:?}");
}

#[test]
fn comparison_finds_one_wrong_pixel() {
    // Pixel (5, 3) off by 0.5: about 10 combined standard deviations.
    let wrong = |x, y| if (x, y) == (5, 3) { 0.5 } else { 0.0 };
    let cmp = compare(&synthetic(1, 1.0, wrong), &synthetic(1, 1.0, |_, _| 0.0));
    assert_eq!(cmp.failing, 1, "{cmp:?}");
    assert_eq!((cmp.worst.x, cmp.worst.y), (5, 3));
    assert_eq!(cmp.bit_close, 255);
}

#[test]
fn deterministic_pixels_agree_up_to_rounding() {
    let exact = synthetic(1, 0.0, |_, _| 0.7);
    let rounded = synthetic(1, 0.0, |_, _| 0.7 * (1.0 + 3e-5));
    assert!(compare(&rounded, &exact).problems().is_empty());
    let near_zero = compare(
        &synthetic(1, 0.0, |_, _| 5e-7),
        &synthetic(1, 0.0, |_, _| 0.0),
    );
    assert!(near_zero.problems().is_empty(), "{near_zero:?}");
    let off = compare(&synthetic(1, 0.0, |_, _| 0.7 * (1.0 + 1e-3)), &exact);
    assert_eq!(off.failing, 256, "{off:?}");
    assert_eq!(off.image.len(), 3, "{off:?}");
}

// ---------------------------------------------------------------------------------------------
// The paired comparison: renders of the same samples
// ---------------------------------------------------------------------------------------------

/// `film` with every sample scaled by `scale` at pixel `at` (all pixels when None).
fn scaled(film: &Film, scale: f64, at: Option<(u32, u32)>) -> Film {
    let mut out = Film::new(film.width, film.height);
    for y in 0..film.height {
        for x in 0..film.width {
            let i = film.index(x, y);
            let s = if at.is_none_or(|p| p == (x, y)) {
                scale
            } else {
                1.0
            };
            out.count[i] = film.count[i];
            out.sum[i] = film.sum[i].map(|v| v * s);
            out.sum_sq[i] = film.sum_sq[i].map(|v| v * s * s);
        }
    }
    out
}

#[test]
fn paired_comparison_accepts_identical_samples() {
    let film = synthetic(1, 1.0, |_, _| 0.5);
    let cmp = compare(&film, &film);
    assert!(
        cmp.problems().is_empty() && cmp.paired_problems().is_empty(),
        "{cmp:?}"
    );
    assert_eq!(cmp.bit_close, 256);
    // f32 rounding of every sample (a relative 1e-7, random sign) passes too.
    let mut rng = TestRng(7);
    let mut rounded = film.clone();
    for s in rounded.sum.iter_mut() {
        *s = s.map(|v| v * (1.0 + 1e-7 * (2.0 * rng.f32() as f64 - 1.0)));
    }
    let cmp = compare(&rounded, &film);
    assert!(cmp.paired_problems().is_empty(), "{cmp:?}");
}

#[test]
fn paired_comparison_rejects_a_small_bias() {
    let film = synthetic(1, 1.0, |_, _| 0.5);
    for shift in [1e-2, 1e-3] {
        let cmp = compare(&scaled(&film, 1.0 + shift, None), &film);
        // 0.1 % is far below the noise: the unpaired tests cannot see it (1 % is 3 standard
        // errors of the image mean, at their edge) ...
        if shift < 1e-2 {
            assert!(cmp.problems().is_empty(), "{shift}: {cmp:?}");
        }
        // ... the paired one sees both.
        let problems = cmp.paired_problems();
        assert!(
            problems
                .iter()
                .filter(|p| p.contains("paired image means"))
                .count()
                == 3,
            "{shift}: {problems:?}"
        );
    }
}

#[test]
fn paired_comparison_rejects_one_pixel_off_by_ten_percent() {
    // A pixel whose own relative error (0.6 %) is far below 10 %: the per-pixel z-test sees it.
    let film = synthetic(1, 0.1, |_, _| 0.5);
    let cmp = compare(&scaled(&film, 1.1, Some((9, 4))), &film);
    assert_eq!(cmp.failing, 1, "{cmp:?}");
    assert_eq!((cmp.worst.x, cmp.worst.y), (9, 4));
    assert_eq!(cmp.bit_close, 255);
}

#[test]
fn paired_comparison_rejects_other_samples() {
    // Two films of one distribution but different samples pass the unpaired tests; as renders
    // of the same samples they fail the bit-close floor.
    let cmp = compare(
        &synthetic(1, 1.0, |_, _| 0.0),
        &synthetic(2, 1.0, |_, _| 0.0),
    );
    assert!(cmp.problems().is_empty(), "{cmp:?}");
    let problems = cmp.paired_problems();
    assert!(
        problems.iter().any(|p| p.contains("bit-close")),
        "{problems:?}"
    );
}

#[test]
fn paired_statistical_test_leaves_out_the_bit_level_parts_only() {
    // What another adapter than lavapipe is held to (`STRATA_TESTS_ADAPTER`): renders of other
    // samples pass, as paths a different rounding sends elsewhere must ...
    let other = compare(
        &synthetic(1, 1.0, |_, _| 0.0),
        &synthetic(2, 1.0, |_, _| 0.0),
    );
    assert!(other.paired_statistical_problems().is_empty(), "{other:?}");
    assert!(!other.paired_problems().is_empty());
    // ... and the same samples biased by 0.1 % still fail: every pixel's difference has the
    // same sign, many standard errors of their mean.
    let film = synthetic(1, 1.0, |_, _| 0.5);
    let biased = compare(&scaled(&film, 1.001, None), &film);
    let problems = biased.paired_statistical_problems();
    assert_eq!(
        problems
            .iter()
            .filter(|p| p.contains("paired image means"))
            .count(),
        3,
        "{problems:?}"
    );
}

#[test]
fn paired_comparison_below_a_lowered_floor_judges_the_means_by_their_spread() {
    // What room-far's paired renders look like (`tests/hard.rs`, floor 5 %): nine pixels in ten
    // a rounding apart (1e-5, beyond bit-close) and one pixel 4 % off, as one of its samples sent
    // elsewhere by that rounding makes. Their means are further apart than f32 rounding's bound
    // but within their own spread: below the tier's floor they pass ...
    let film = synthetic(1, 1.0, |_, _| 0.5);
    let mut rng = TestRng(3);
    let mut diverged = scaled(&film, 1.04, Some((5, 3)));
    for (i, s) in diverged.sum.iter_mut().enumerate() {
        if i % 10 != 0 {
            *s = s.map(|v| v * (1.0 + 1e-5 * (2.0 * rng.f32() as f64 - 1.0)));
        }
    }
    let cmp = compare(&diverged, &film);
    assert!(
        cmp.paired.iter().all(|p| p.relative > PAIRED_RELATIVE),
        "{cmp:?}"
    );
    assert!(cmp.paired_problems_with_floor(0.05).is_empty(), "{cmp:?}");
    assert!(!cmp.paired_problems().is_empty(), "{cmp:?}");
    // ... and the same with a 0.1 % bias fails on its standard errors.
    let biased = compare(&scaled(&diverged, 1.001, None), &film);
    let problems = biased.paired_problems_with_floor(0.05);
    assert_eq!(
        problems
            .iter()
            .filter(|p| p.contains("paired image means"))
            .count(),
        3,
        "{problems:?}"
    );
}
