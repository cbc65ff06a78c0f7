//! The GPU renderer agrees with the CPU reference. Every scene in `scenes/`, rendered small with
//! every sampler × strategy on the software adapter (lavapipe, on purpose), gives a GPU mean
//! image that passes a per-pixel z-test against the CPU's (both variance estimates, Šidák-
//! corrected at family significance 0.01) and an image mean within 3 combined standard errors.
//!
//! Both renderers consume exactly the same samples, so most pixels agree to f32 rounding; the
//! bounds are statistical so that a divergence is judged against the noise it hides in. A failing
//! combination writes GPU, CPU and |difference| EXRs under `target/tmp/agreement-failures/`.
//! A table of bit-close pixels per combination is printed (see it with `--nocapture`).

mod common;

use statrs::distribution::{ContinuousCDF, Normal};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};
use std::time::Instant;
use stratapt::gpu::Renderer;
use stratapt::scene::{load::load, Film, FlatScene, RenderSettings, SamplerKind, Strategy};

/// Film size on the long side; the short side keeps the scene's aspect.
const LONG_SIDE: u32 = 48;
/// Samples per pixel (a power of two and a square: every sampler's natural count).
const SPP: u32 = 16;
/// Cap on the scene's path depth, for speed: only glass (10) and cornell-box (8) are cut short,
/// and depth 6 still exercises Russian roulette (from vertex 3).
const MAX_DEPTH: u32 = 6;
/// Probability that some pixel channel of one agreeing combination fails by chance.
const FAMILY_ALPHA: f64 = 0.01;
/// Combined standard errors the two image means may differ by.
const IMAGE_Z: f64 = 3.0;
/// Relative difference under which two means count as bit-close (reported, not asserted).
const BIT_CLOSE: f64 = 1e-6;

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
// One test per scene
// ---------------------------------------------------------------------------------------------

macro_rules! scenes {
    ($($test:ident => $name:literal,)*) => {
        /// Every scene the agreement tests render (`every_scene_is_tested` keeps it complete).
        const SCENES: &[&str] = &[$($name),*];
        $(
            #[test]
            fn $test() {
                agree($name);
            }
        )*
    };
}

scenes! {
    cornell_box => "cornell-box",
    depth_of_field => "depth-of-field",
    glass => "glass",
    mesh => "mesh",
    motion_blur_camera => "motion-blur-camera",
    motion_blur_object => "motion-blur-object",
    soft_shadow_area => "soft-shadow-area",
    soft_shadow_line => "soft-shadow-line",
    soft_shadow_sun => "soft-shadow-sun",
    veach_mis => "veach-mis",
}

#[test]
fn every_scene_is_tested() {
    let mut found: Vec<String> = std::fs::read_dir(scenes_dir())
        .expect("scenes/ directory")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    found.sort();
    assert_eq!(
        found, SCENES,
        "add the new scene to `scenes!` in tests/agreement.rs"
    );
}

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

/// The renderer on the software device, shared by the tests (it caches compiled kernels).
fn renderer() -> &'static Renderer {
    static RENDERER: OnceLock<Renderer> = OnceLock::new();
    RENDERER.get_or_init(|| {
        let (device, queue) =
            stratapt::gpu::testing::software_device().unwrap_or_else(|e| panic!("{e}"));
        Renderer::new(&device, &queue).unwrap_or_else(|e| panic!("GPU renderer: {e}"))
    })
}

/// Scene `name` at LONG_SIDE pixels on its long side, keeping the aspect (and, as `strata
/// render --size` does, the vertical field of view).
fn small_scene(name: &str) -> FlatScene {
    let mut scene =
        load(&scenes_dir().join(format!("{name}.toml"))).unwrap_or_else(|e| panic!("{e}"));
    let (w, h) = (scene.camera.width, scene.camera.height);
    let side = |s: u32| ((s * LONG_SIDE) as f64 / w.max(h) as f64).round().max(1.0) as u32;
    (scene.camera.width, scene.camera.height) = (side(w), side(h));
    scene
}

/// Render scene `name` with every sampler × strategy on both renderers, print the bit-close
/// table, and panic listing every combination that disagrees.
fn agree(name: &str) {
    // One scene at a time: lavapipe and the CPU renderer each use every core, and side by side
    // they only get in each other's way (all scenes on 2 cores: 16 s in parallel, 13 s in turn).
    static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());
    let _turn = ONE_AT_A_TIME
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    let scene = small_scene(name);
    let renderer = renderer();
    let mut table = Table::new(name, &scene);
    let mut failures = Vec::new();
    for sampler in SamplerKind::ALL {
        for strategy in Strategy::ALL {
            let settings = RenderSettings {
                spp: SPP,
                max_depth: scene.settings.max_depth.min(MAX_DEPTH),
                sampler,
                strategy,
                ..scene.settings
            };
            let label = format!("{name}-{sampler}-{strategy}");
            let (cmp, failure) = check(renderer, &scene, &settings, &label, &mut table.seconds);
            table.add(cmp.as_ref(), failure.is_none());
            failures.extend(failure);
        }
    }
    eprintln!("{table}");
    assert!(
        failures.is_empty(),
        "{} of {} combinations of {name} disagree (GPU vs CPU):\n{}",
        failures.len(),
        table.cells.len(),
        failures.join("\n")
    );
}

/// Render one combination on both renderers and compare them. Returns the comparison (None if
/// the GPU failed) and, on disagreement, what went wrong and where the images were written.
fn check(
    renderer: &Renderer,
    scene: &FlatScene,
    settings: &RenderSettings,
    label: &str,
    seconds: &mut [f64; 2],
) -> (Option<Comparison>, Option<String>) {
    let start = Instant::now();
    let gpu = renderer.render_with_stats(scene, settings, &|_| {}, None);
    seconds[0] += start.elapsed().as_secs_f64();
    let (gpu, gpu_stats) = match gpu {
        Ok(rendered) => rendered,
        Err(e) => return (None, Some(format!("{label}: GPU render failed: {e}"))),
    };
    let start = Instant::now();
    let (cpu, cpu_stats) = stratapt::cpu::render_with_stats(scene, settings, &|_| {}, None);
    seconds[1] += start.elapsed().as_secs_f64();

    let cmp = compare(&gpu, &cpu);
    let mut problems = cmp.problems();
    if gpu_stats.non_finite != cpu_stats.non_finite {
        problems.push(format!(
            "non-finite samples: GPU {}, CPU {}",
            gpu_stats.non_finite, cpu_stats.non_finite
        ));
    }
    let paths = image_paths(label);
    let failure = if problems.is_empty() {
        // An image left by an earlier failure would mislead.
        for path in &paths {
            let _ = std::fs::remove_file(path);
        }
        None
    } else {
        let written = write_images(&paths, &gpu, &cpu);
        Some(format!("{label}: {}\n    {written}", problems.join("; ")))
    };
    (Some(cmp), failure)
}

/// Where combination `label`'s GPU, CPU and |difference| images go when it fails:
/// `target/tmp/agreement-failures/LABEL-{gpu,cpu,diff}.exr`.
fn image_paths(label: &str) -> [PathBuf; 3] {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("agreement-failures");
    ["gpu", "cpu", "diff"].map(|kind| dir.join(format!("{label}-{kind}.exr")))
}

/// Write the GPU, CPU and |difference| images; returns a line naming them (or the error).
fn write_images(paths: &[PathBuf; 3], gpu: &Film, cpu: &Film) -> String {
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

// ---------------------------------------------------------------------------------------------
// The comparison
// ---------------------------------------------------------------------------------------------

/// Two films of one size compared pixel by pixel and as a whole.
#[derive(Debug)]
struct Comparison {
    /// Per-test critical |z|: Šidák over pixels × 3 channels at FAMILY_ALPHA, two-sided.
    z_crit: f64,
    /// Pixels with some channel's |z| above `z_crit`.
    failing: usize,
    pixels: usize,
    /// The pixel channel with the largest z.
    worst: Worst,
    /// Channels whose image means differ by more than IMAGE_Z combined standard errors:
    /// (channel, mean a, mean b, z).
    image: Vec<(usize, f64, f64, f64)>,
    /// Pixels whose three channel means agree within BIT_CLOSE (relative).
    bit_close: usize,
}

#[derive(Debug, Default)]
struct Worst {
    x: u32,
    y: u32,
    channel: usize,
    a: f64,
    b: f64,
    z: f64,
}

impl Comparison {
    /// One line per violated bound, naming `a` "GPU" and `b` "CPU".
    fn problems(&self) -> Vec<String> {
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
}

/// Compare `a` with `b` (same size) by the per-pixel z-test and the image means.
fn compare(a: &Film, b: &Film) -> Comparison {
    assert_eq!(
        (a.width, a.height),
        (b.width, b.height),
        "film sizes differ"
    );
    let pixels = a.sum.len();
    let z_crit = critical_z(pixels * 3);
    let (mut failing, mut bit_close) = (0, 0);
    let mut worst = Worst {
        z: f64::NEG_INFINITY,
        ..Default::default()
    };
    for i in 0..pixels {
        let (ma, mb) = (a.mean(i), b.mean(i));
        let (va, vb) = (a.variance_of_mean(i), b.variance_of_mean(i));
        let mut fails = false;
        for c in 0..3 {
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
    Comparison {
        z_crit,
        failing,
        pixels,
        worst,
        image,
        bit_close,
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
fn critical_z(tests: usize) -> f64 {
    let alpha = -((-FAMILY_ALPHA).ln_1p() / tests as f64).exp_m1();
    Normal::standard().inverse_cdf(1.0 - alpha / 2.0)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= BIT_CLOSE * a.abs().max(b.abs())
}

// ---------------------------------------------------------------------------------------------
// The bit-close table
// ---------------------------------------------------------------------------------------------

/// Bit-close pixel counts of one scene, samplers down, strategies across.
struct Table {
    header: String,
    pixels: usize,
    /// (bit-close pixels, agrees) per combination, sampler-major.
    cells: Vec<(Option<usize>, bool)>,
    /// Largest per-pixel z over the combinations, and the critical z.
    z: Option<(f64, f64)>,
    /// Seconds spent rendering on the GPU and on the CPU.
    seconds: [f64; 2],
}

impl Table {
    fn new(name: &str, scene: &FlatScene) -> Self {
        let (w, h) = (scene.camera.width, scene.camera.height);
        let depth = scene.settings.max_depth.min(MAX_DEPTH);
        Self {
            header: format!("{name} {w}×{h}, {SPP} spp, depth {depth}"),
            pixels: (w * h) as usize,
            cells: Vec::new(),
            z: None,
            seconds: [0.0; 2],
        }
    }

    /// The next combination's cell (sampler-major order).
    fn add(&mut self, cmp: Option<&Comparison>, agrees: bool) {
        self.cells.push((cmp.map(|c| c.bit_close), agrees));
        if let Some(c) = cmp.filter(|c| self.z.is_none_or(|(z, _)| c.worst.z > z)) {
            self.z = Some((c.worst.z, c.z_crit));
        }
    }
}

impl std::fmt::Display for Table {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut counts: Vec<usize> = self.cells.iter().filter_map(|c| c.0).collect();
        counts.sort();
        let (min, median) = (counts.first(), counts.get(counts.len() / 2));
        let show = |v: Option<&usize>| v.map_or("-".into(), |v| v.to_string());
        writeln!(
            f,
            "{}: bit-close pixels of {} (min {}, median {}; * = disagrees)",
            self.header,
            self.pixels,
            show(min),
            show(median),
        )?;
        if let Some((z, z_crit)) = self.z {
            write!(f, "    largest z {z:.2e} (critical {z_crit:.2}),")?;
        }
        writeln!(
            f,
            " rendering took GPU {:.1} s, CPU {:.1} s",
            self.seconds[0], self.seconds[1]
        )?;
        write!(f, "{:>12}", "")?;
        for strategy in Strategy::ALL {
            write!(f, "{:>9}", strategy.name())?;
        }
        for (row, sampler) in SamplerKind::ALL.iter().enumerate() {
            write!(f, "\n{:>12}", sampler.name())?;
            let cells = self.cells.iter().skip(row * Strategy::ALL.len());
            for &(count, agrees) in cells.take(Strategy::ALL.len()) {
                let count = count.map_or("-".into(), |v| v.to_string());
                let mark = if agrees { " " } else { "*" };
                write!(f, "{count:>8}{mark}")?;
            }
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------------------------
// The comparison on synthetic films: it accepts what should agree and rejects a real difference
// ---------------------------------------------------------------------------------------------

/// A 16×16 film of 64 samples per pixel (enough for the normal approximation of the z-test),
/// each `shift(x, y) + spread · u` with u uniform in [0, 1).
fn synthetic(seed: u64, spread: f32, shift: impl Fn(u32, u32) -> f32) -> Film {
    let mut rng = common::Lcg(seed);
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
