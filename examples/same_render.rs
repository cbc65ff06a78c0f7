//! Whether two strata part EXRs (from `strata render --part`/`--samples` or `strata merge`)
//! hold the same render: the same samples of the same scene and settings, with sums equal to
//! f64 rounding (a merge adds the parts' sums in another grouping than one render does).
//!
//! ```text
//! cargo run --release --example same_render -- A.exr B.exr [TOLERANCE]
//! ```
//!
//! Prints the largest relative difference of the pixel sums and exits 0 when it is within
//! TOLERANCE (default 1e-12, for CPU renders; GPU renders fold f32 batch sums, use 1e-6), 1
//! when not, 2 when a file cannot be read. `scripts/slurm-demo.sh` uses it to check a merged
//! job array against a single render.

use std::path::PathBuf;
use std::process::ExitCode;
use stratapt::film::part;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 2 {
        eprintln!("usage: same_render A.exr B.exr [TOLERANCE]");
        return ExitCode::from(2);
    }
    let tolerance: f64 = args.get(2).and_then(|t| t.parse().ok()).unwrap_or(1e-12);
    let read = |p: &String| part::read(&PathBuf::from(p));
    let ((a, ia), (b, ib)) = match (read(&args[0]), read(&args[1])) {
        (Ok(a), Ok(b)) => (a, b),
        (Err(e), _) | (_, Err(e)) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    if (ia.samples.clone(), ia.settings, ia.scene_hash)
        != (ib.samples.clone(), ib.settings, ib.scene_hash)
        || a.count != b.count
    {
        println!(
            "different renders: samples {} vs {}, settings or scene differ",
            part::format_ranges(&ia.samples),
            part::format_ranges(&ib.samples)
        );
        return ExitCode::from(1);
    }
    let worst = a
        .sum
        .iter()
        .zip(&b.sum)
        .chain(a.sum_sq.iter().zip(&b.sum_sq))
        .flat_map(|(x, y)| (0..3).map(move |c| (x[c], y[c])))
        .map(|(x, y)| (x - y).abs() / x.abs().max(y.abs()).max(1e-30))
        .fold(0.0, f64::max);
    let same = worst <= tolerance;
    println!(
        "samples {} of {}: largest relative difference of the sums {worst:.2e} ({} {tolerance:e})",
        part::format_ranges(&ia.samples),
        ia.settings.pattern_spp,
        if same { "within" } else { "beyond" }
    );
    if same {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
