//! `strata merge`: sum render parts (`strata render --part` …) into the whole render, exactly.

use crate::render::{check_outputs, error_line, joined, mean_line};
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;
use stratapt_film::part::{self, format_ranges};

#[derive(Args)]
pub struct MergeArgs {
    /// Part EXRs written by `strata render --part K/N`, `--samples A..B` or
    /// `--part-from-env` (or by an earlier merge), in any order.
    #[arg(required = true)]
    parts: Vec<PathBuf>,
    /// Output image(s): .exr (the merged part: image, variance and exact sums, mergeable
    /// again) or .png (sRGB); repeatable.
    #[arg(short, long = "output", required = true)]
    output: Vec<PathBuf>,
    /// Merge the parts that are here even if some samples are in none of them (a job array
    /// still running); says which are missing. Without it, missing samples are an error.
    #[arg(long)]
    allow_partial: bool,
}

pub fn run(args: MergeArgs) -> anyhow::Result<ExitCode> {
    let start = Instant::now();
    check_outputs(&args.output)?;
    let parts = args
        .parts
        .iter()
        .map(|path| part::read(path).map(|(film, info)| (path.clone(), film, info)))
        .collect::<Result<Vec<_>, _>>()?;
    let count = parts.len();
    let merged = part::merge(parts, args.allow_partial)?;
    for path in &args.output {
        if crate::part::is_exr(path) {
            part::write(&merged.film, &merged.info, path)?;
        } else {
            merged.film.write(path)?;
        }
    }
    let info = &merged.info;
    let missing = info.missing();
    let complete = if missing.is_empty() {
        "complete".to_string()
    } else {
        format!("missing {}", format_ranges(&missing))
    };
    let s = &info.settings;
    eprintln!(
        "merged {count} parts of {} in {:.2} s: samples {} of {} ({complete}), {} / {}, \
         depth {}; wrote {}",
        info.scene,
        start.elapsed().as_secs_f64(),
        format_ranges(&info.samples),
        s.pattern_spp,
        s.sampler,
        s.strategy,
        s.max_depth,
        joined(&args.output)
    );
    eprintln!(
        "{}",
        error_line(&merged.film, &merged.film.relative_error())
    );
    eprintln!("{}", mean_line(&merged.film));
    Ok(ExitCode::SUCCESS)
}
