//! The comparison behind the agreement tests: a per-pixel z-test (Šidák-corrected) and an
//! image-mean test of a GPU film against a CPU film, the count of bit-close pixels, the images
//! written when they disagree, and the comparison's own tests on synthetic films.

use statrs::distribution::{ContinuousCDF, Normal};
use std::path::{Path, PathBuf};
use stratapt::film::Film;

/// Probability that some pixel channel of one agreeing combination fails by chance.
const FAMILY_ALPHA: f64 = 0.01;
/// Combined standard errors the two image means may differ by.
const IMAGE_Z: f64 = 3.0;
/// Relative difference under which two means count as bit-close.
const BIT_CLOSE: f64 = 1e-6;
/// Fewest bit-close pixels a paired render may have. Measured on the agreement renders (every
/// scene × sampler × strategy, 48 px, 16 spp, Mesa 25.0.7 lavapipe): 94.0–100 %, the lowest on
/// veach-mis with light sampling, where 6 % of the pixels have some path whose rounding took
/// another branch. 90 % leaves room for other drivers' rounding; an error in the estimator
/// changes most pixels.
pub const BIT_CLOSE_FLOOR: f64 = 0.90;
/// Largest relative difference of the paired image means of bit-level renders (at least
/// [`BIT_CLOSE_FLOOR`] of the pixels bit-close). f32 rounding bounds it: the GPU sums
/// at most 256 samples per pixel and batch in f32 (relative error ≤ 255 · 2⁻²⁴ ≈ 1.5e-5) and
/// evaluates each sample with FMA contraction and its own transcendentals; measured at most
/// 4.4e-6 (veach-mis, independent, light). A 0.1 % bias is 10× over it.
pub const PAIRED_RELATIVE: f64 = 1e-4;
/// Standard errors the mean paired difference may be off by, when it is also beyond f32
/// rounding (ROUNDING_REL): images whose pixels are all bit-close differ by a systematic
/// rounding of ~3e-8 that is 13 standard errors of their tiny spread, so z alone is no test.
pub const PAIRED_Z: f64 = 5.0;

// The two renderers evaluate each sample with the same f32 operations, but not bit for bit: WGSL
// may contract a·b + c into an FMA and its transcendentals may be a few ULP from libm's, and the
// GPU sums each batch of up to 256 samples in f32 before folding it into the f64 film (relative
// error ≤ 255 · 2⁻²⁴ ≈ 1.5e-5). That discrepancy is modelled as one more independent term of the
// difference's standard deviation, ε = ROUNDING_REL · |mean| + ROUNDING_ABS (the absolute part
// for means near zero), added in quadrature to the two variances of the mean. Where both variances
// are 0 (a sky pixel, a deterministic ray) the means must then agree within z_crit · ε, about
// 1e-4 · |mean| + 1e-6 for z_crit ≈ 4.8 (this test's images).
const ROUNDING_REL: f64 = 2e-5;
const ROUNDING_ABS: f64 = 2e-7;

// ---------------------------------------------------------------------------------------------
// The comparison
// ---------------------------------------------------------------------------------------------

/// Two films of one size compared pixel by pixel and as a whole.
#[derive(Debug)]
pub struct Comparison {
    /// Per-test critical |z|: Šidák over pixels × 3 channels at FAMILY_ALPHA, two-sided.
    pub z_crit: f64,
    /// Pixels with some channel's |z| above `z_crit`.
    pub failing: usize,
    pub pixels: usize,
    /// The pixel channel with the largest z.
    pub worst: Worst,
    /// Channels whose image means differ by more than IMAGE_Z combined standard errors:
    /// (channel, mean a, mean b, z).
    pub image: Vec<(usize, f64, f64, f64)>,
    /// Pixels whose three channel means agree within BIT_CLOSE (relative).
    pub bit_close: usize,
    /// The paired differences d = a − b of the pixel means, per channel.
    pub paired: [Paired; 3],
}

/// Both renderers consume the same samples, so their difference has almost no variance: the
/// mean of the per-pixel differences is tested against their own spread, and their sum against
/// the image's.
#[derive(Debug, Default, Clone, Copy)]
pub struct Paired {
    /// Mean of d over the pixels.
    pub mean: f64,
    /// sd(d) / √pixels.
    pub stderr: f64,
    /// |Σ d| / Σ |b|: the relative difference of the image means.
    pub relative: f64,
}

impl Paired {
    /// |mean| in standard errors (0 for identical images, ∞ for a shift with no spread).
    pub fn z(&self) -> f64 {
        if self.mean == 0.0 {
            0.0
        } else {
            self.mean.abs() / self.stderr
        }
    }
}

#[derive(Debug, Default)]
pub struct Worst {
    pub x: u32,
    pub y: u32,
    pub channel: usize,
    pub a: f64,
    pub b: f64,
    pub z: f64,
}

impl Comparison {
    /// One line per violated bound, naming `a` "GPU" and `b` "CPU".
    pub fn problems(&self) -> Vec<String> {
        let mut problems = Vec::new();
        if self.failing > 0 {
            let w = &self.worst;
            problems.push(format!(
                "{} of {} pixels fail the z-test (|z| > {:.2}); worst ({}, {}) channel {}: \
                 GPU {:.6e}, CPU {:.6e}, z = {:.1}",
                self.failing, self.pixels, self.z_crit, w.x, w.y, w.channel, w.a, w.b, w.z
            ));
        }
        for &(c, a, b, z) in &self.image {
            problems.push(format!(
                "image mean channel {c}: GPU {a:.6e}, CPU {b:.6e}, {z:.1} combined std errors"
            ));
        }
        problems
    }

    /// What the comparison of two renders of the same samples must also pass: most pixels
    /// bit-close, and paired differences whose mean is within f32 rounding.
    pub fn paired_problems(&self) -> Vec<String> {
        self.paired_problems_with_floor(BIT_CLOSE_FLOOR)
    }

    /// [`Comparison::paired_problems`] with another floor on the bit-close fraction.
    pub fn paired_problems_with_floor(&self, floor: f64) -> Vec<String> {
        self.paired_problems_of(Some(floor))
    }

    /// The paired test without its bit-level parts (the bit-close floor and the paired means'
    /// [`PAIRED_RELATIVE`]): the mean paired difference must not be [`PAIRED_Z`] standard
    /// errors off once beyond f32 rounding. For a GPU whose arithmetic rounds otherwise than
    /// lavapipe's, where the bit-level parts do not hold.
    pub fn paired_statistical_problems(&self) -> Vec<String> {
        self.paired_problems_of(None)
    }

    /// The paired test as this run's adapter is held to it: all of it on a software adapter
    /// (lavapipe, whose arithmetic the bit-level parts were set on); on a hardware GPU
    /// (`STRATA_TESTS_ADAPTER`) the statistical part, with the bit-level findings printed under
    /// `label` but not enforced.
    pub fn paired_problems_on_this_adapter(&self, floor: f64, label: &str) -> Vec<String> {
        let all = self.paired_problems_with_floor(floor);
        if stratapt::gpu::testing::tests_on_software() {
            return all;
        }
        let enforced = self.paired_statistical_problems();
        for problem in all.iter().filter(|p| !enforced.contains(p)) {
            eprintln!("{label}: not enforced on this adapter: {problem}");
        }
        enforced
    }

    /// The paired test, with the bit-level parts (at bit-close `floor`) when there is a floor.
    fn paired_problems_of(&self, floor: Option<f64>) -> Vec<String> {
        let mut problems = Vec::new();
        let fraction = self.bit_close as f64 / self.pixels as f64;
        if let Some(floor) = floor.filter(|floor| fraction < *floor) {
            problems.push(format!(
                "{:.1} % of pixels bit-close, fewer than {:.0} %",
                100.0 * fraction,
                100.0 * floor
            ));
        }
        // The relative bound is f32 rounding's: it holds for renders that are bit-level (the
        // agreement tier's floor of bit-close pixels). A scene granted a lower floor, whose
        // samples rounding sends elsewhere in most pixels (room-far, 10⁵ from the origin), has a
        // paired difference with a spread of its own, judged by its standard errors alone.
        let bit_level = floor.is_some() && fraction >= BIT_CLOSE_FLOOR;
        for (c, p) in self.paired.iter().enumerate() {
            if (bit_level && p.relative > PAIRED_RELATIVE)
                || (p.z() > PAIRED_Z && p.relative > ROUNDING_REL)
            {
                problems.push(format!(
                    "channel {c}: paired image means {:.2e} apart (relative), mean difference \
                     {:.1} standard errors",
                    p.relative,
                    p.z()
                ));
            }
        }
        problems
    }
}

/// Compare `a` with `b` (same size) by the per-pixel z-test and the image means.
pub fn compare(a: &Film, b: &Film) -> Comparison {
    assert_eq!(
        (a.width, a.height),
        (b.width, b.height),
        "film sizes differ"
    );
    let pixels = a.sum.len();
    let z_crit = critical_z(pixels * 3);
    let (mut failing, mut bit_close) = (0, 0);
    let (mut d_sum, mut d_sq, mut b_abs) = ([0.0f64; 3], [0.0f64; 3], [0.0f64; 3]);
    let mut worst = Worst {
        z: f64::NEG_INFINITY,
        ..Default::default()
    };
    for i in 0..pixels {
        let (ma, mb) = (a.mean(i), b.mean(i));
        let (va, vb) = (a.sample_variance_of_mean(i), b.sample_variance_of_mean(i));
        let mut fails = false;
        for c in 0..3 {
            let d = ma[c] - mb[c];
            d_sum[c] += d;
            d_sq[c] += d * d;
            b_abs[c] += mb[c].abs();
            let z = z_score(ma[c], mb[c], va[c] + vb[c]);
            fails |= z > z_crit;
            if z > worst.z {
                let (x, y) = (i as u32 % a.width, i as u32 / a.width);
                let (a, b) = (ma[c], mb[c]);
                worst = Worst {
                    x,
                    y,
                    channel: c,
                    a,
                    b,
                    z,
                };
            }
        }
        failing += fails as usize;
        bit_close += (0..3).all(|c| close(ma[c], mb[c])) as usize;
    }
    let ((mean_a, se_a), (mean_b, se_b)) = (a.image_mean(), b.image_mean());
    let image = (0..3)
        .map(|c| {
            let z = z_score(mean_a[c], mean_b[c], se_a[c].powi(2) + se_b[c].powi(2));
            (c, mean_a[c], mean_b[c], z)
        })
        .filter(|&(.., z)| z > IMAGE_Z)
        .collect();
    let n = pixels as f64;
    let paired = std::array::from_fn(|c| {
        let mean = d_sum[c] / n;
        let variance = (d_sq[c] / n - mean * mean).max(0.0) * n / (n - 1.0).max(1.0);
        Paired {
            mean,
            stderr: (variance / n).sqrt(),
            relative: d_sum[c].abs() / b_abs[c].max(f64::MIN_POSITIVE),
        }
    });
    Comparison {
        z_crit,
        failing,
        pixels,
        worst,
        image,
        bit_close,
        paired,
    }
}

/// |a − b| over the standard deviation of the difference: the estimates' `variance` plus the
/// f32 rounding term ε (see ROUNDING_REL). NaN counts as infinitely far.
fn z_score(a: f64, b: f64, variance: f64) -> f64 {
    let eps = ROUNDING_REL * a.abs().max(b.abs()) + ROUNDING_ABS;
    let z = (a - b).abs() / (variance + eps * eps).sqrt();
    if z.is_nan() {
        f64::INFINITY
    } else {
        z
    }
}

/// The two-sided critical |z| of each of `tests` tests so that all pass together with
/// probability 1 − FAMILY_ALPHA (Šidák: α = 1 − (1 − α_family)^(1/tests)).
pub fn critical_z(tests: usize) -> f64 {
    let alpha = -((-FAMILY_ALPHA).ln_1p() / tests as f64).exp_m1();
    Normal::standard().inverse_cdf(1.0 - alpha / 2.0)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= BIT_CLOSE * a.abs().max(b.abs())
}

// ---------------------------------------------------------------------------------------------
// Failure images
// ---------------------------------------------------------------------------------------------

/// Where combination `label`'s GPU, CPU and |difference| images go when it fails:
/// `target/tmp/agreement-failures/LABEL-{gpu,cpu,diff}.exr`.
pub fn image_paths(label: &str) -> [PathBuf; 3] {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("agreement-failures");
    ["gpu", "cpu", "diff"].map(|kind| dir.join(format!("{label}-{kind}.exr")))
}

/// Write the GPU, CPU and |difference| images; returns a line naming them (or the error).
pub fn write_images(paths: &[PathBuf; 3], gpu: &Film, cpu: &Film) -> String {
    let dir = paths[0].parent().expect("a folder");
    if let Err(e) = std::fs::create_dir_all(dir) {
        return format!("cannot create {}: {e}", dir.display());
    }
    let mut names = Vec::new();
    for (path, film) in paths.iter().zip([gpu, cpu, &difference(gpu, cpu)]) {
        match film.write_exr(path) {
            Ok(()) => names.push(path.display().to_string()),
            Err(e) => names.push(format!("(not written: {e})")),
        }
    }
    format!(
        "actual {}, expected {}, |difference| {}",
        names[0], names[1], names[2]
    )
}

/// A film whose mean is |mean(a) − mean(b)| per pixel and channel (one sample: no variance).
fn difference(a: &Film, b: &Film) -> Film {
    let mut film = Film::new(a.width, a.height);
    for y in 0..a.height {
        for x in 0..a.width {
            let i = a.index(x, y);
            let (ma, mb) = (a.mean(i), b.mean(i));
            film.add_sample(x, y, std::array::from_fn(|c| (ma[c] - mb[c]).abs() as f32));
        }
    }
    film
}
