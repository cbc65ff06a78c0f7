//! `strata render --part K/N | --samples A..B | --part-from-env`: which sample indices of the
//! render this process takes, for job arrays on a batch engine (Slurm, Kubernetes Indexed Jobs)
//! whose parts `strata merge` sums into the whole.

use anyhow::{bail, Context};
use clap::Args;
use std::ops::Range;
use std::path::{Path, PathBuf};

#[derive(Args, Clone, Debug, Default)]
pub struct PartArgs {
    /// Render part K of N (K = 0 … N−1): the K-th of N disjoint, contiguous ranges of sample
    /// indices of every pixel, written as a part EXR for `strata merge`.
    #[arg(long, value_parser = parse_part, value_name = "K/N",
          conflicts_with_all = ["samples", "part_from_env"])]
    part: Option<(u32, u32)>,
    /// Render the sample indices A..B (A included, B not) of every pixel, a range of the
    /// render's `--spp` samples, written as a part EXR for `strata merge`.
    #[arg(long, value_parser = parse_samples, value_name = "A..B",
          conflicts_with = "part_from_env")]
    samples: Option<Range<u32>>,
    /// Take K and N from a job array's environment: Slurm's SLURM_ARRAY_TASK_ID
    /// (minus SLURM_ARRAY_TASK_MIN) and SLURM_ARRAY_TASK_COUNT, or Kubernetes'
    /// JOB_COMPLETION_INDEX with N from --parts.
    #[arg(long)]
    part_from_env: bool,
    /// With --part-from-env: the number of parts N (needed under Kubernetes, whose Indexed
    /// Jobs give only the index; overrides SLURM_ARRAY_TASK_COUNT).
    #[arg(long, value_name = "N", requires = "part_from_env",
          value_parser = clap::value_parser!(u32).range(1..))]
    parts: Option<u32>,
}

/// The part this process renders.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Part {
    /// Sample indices of every pixel.
    pub samples: Range<u32>,
    /// `part-K-of-N` or `samples-A-B`: the default output's suffix.
    pub label: String,
}

impl PartArgs {
    /// The part of a render of `total` samples per pixel (`None` for the whole render), with
    /// the environment read through `env`.
    pub fn resolve(
        &self,
        total: u32,
        env: impl Fn(&str) -> Option<String>,
    ) -> anyhow::Result<Option<Part>> {
        if let Some(r) = &self.samples {
            if r.end > total {
                bail!(
                    "--samples {}..{}: the render has {total} samples per pixel (indices \
                     0..{total}); pass --spp for a larger render",
                    r.start,
                    r.end
                );
            }
            return Ok(Some(Part {
                samples: r.clone(),
                label: format!("samples-{}-{}", r.start, r.end),
            }));
        }
        let (k, n) = match (self.part, self.part_from_env) {
            (Some(kn), _) => kn,
            (None, true) => from_env(self.parts, env)?,
            (None, false) => return Ok(None),
        };
        if n > total {
            bail!(
                "part {k}/{n}: {n} parts of a render of {total} samples per pixel would leave \
                 some empty; use at most {total} parts or raise --spp"
            );
        }
        Ok(Some(Part {
            samples: split(total, k, n),
            label: format!("part-{k}-of-{n}"),
        }))
    }
}

/// The K-th of N contiguous ranges that split `0..total` as evenly as can be.
pub fn split(total: u32, k: u32, n: u32) -> Range<u32> {
    let at = |i: u32| (i as u64 * total as u64 / n as u64) as u32;
    at(k)..at(k + 1)
}

/// K and N from a job array's environment variables.
fn from_env(
    parts: Option<u32>,
    env: impl Fn(&str) -> Option<String>,
) -> anyhow::Result<(u32, u32)> {
    let number = |name: &str| -> anyhow::Result<Option<u32>> {
        env(name)
            .map(|v| {
                v.trim()
                    .parse::<u32>()
                    .with_context(|| format!("{name}={v}: not a whole number"))
            })
            .transpose()
    };
    let (k, n) = if let Some(id) = number("SLURM_ARRAY_TASK_ID")? {
        let min = number("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
        let Some(k) = id.checked_sub(min) else {
            bail!("SLURM_ARRAY_TASK_ID={id} is below SLURM_ARRAY_TASK_MIN={min}");
        };
        let n = match (parts, number("SLURM_ARRAY_TASK_COUNT")?) {
            (Some(n), _) | (None, Some(n)) => n,
            (None, None) => bail!(
                "--part-from-env: SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is \
                 not; pass --parts N"
            ),
        };
        (k, n)
    } else if let Some(k) = number("JOB_COMPLETION_INDEX")? {
        let Some(n) = parts else {
            bail!(
                "--part-from-env: JOB_COMPLETION_INDEX={k} (a Kubernetes Indexed Job) gives the \
                 index only; pass --parts N with the Job's completions"
            );
        };
        (k, n)
    } else {
        bail!(
            "--part-from-env: neither SLURM_ARRAY_TASK_ID (a Slurm job array) nor \
             JOB_COMPLETION_INDEX (a Kubernetes Indexed Job) is set"
        );
    };
    check_part(k, n).map_err(|e| anyhow::anyhow!("--part-from-env: {e}"))?;
    Ok((k, n))
}

fn check_part(k: u32, n: u32) -> Result<(), String> {
    if n == 0 {
        return Err("the number of parts must be at least 1".into());
    }
    if k >= n {
        return Err(format!(
            "part {k} of {n}: parts are numbered 0 to {}",
            n - 1
        ));
    }
    Ok(())
}

fn parse_part(s: &str) -> Result<(u32, u32), String> {
    let bad = || "expected K/N, e.g. 0/4 (parts are numbered 0 to N−1)".to_string();
    let (k, n) = s.split_once('/').ok_or_else(bad)?;
    let (k, n) = (
        k.trim().parse::<u32>().map_err(|_| bad())?,
        n.trim().parse::<u32>().map_err(|_| bad())?,
    );
    check_part(k, n)?;
    Ok((k, n))
}

fn parse_samples(s: &str) -> Result<Range<u32>, String> {
    let bad = || "expected A..B with A < B, e.g. 0..16 (A included, B not)".to_string();
    let (a, b) = s.split_once("..").ok_or_else(bad)?;
    let (a, b) = (
        a.trim().parse::<u32>().map_err(|_| bad())?,
        b.trim().parse::<u32>().map_err(|_| bad())?,
    );
    if a >= b {
        return Err(bad());
    }
    Ok(a..b)
}

/// A part's output: the paths given (each must be an EXR: only it keeps the sums), or
/// `SCENE-NAME.LABEL.exr` in the current folder.
pub fn outputs(given: &[PathBuf], scene: &Path, part: &Part) -> anyhow::Result<Vec<PathBuf>> {
    if given.is_empty() {
        let stem = scene
            .file_stem()
            .unwrap_or(scene.as_os_str())
            .to_string_lossy();
        return Ok(vec![PathBuf::from(format!("{stem}.{}.exr", part.label))]);
    }
    for path in given {
        if !is_exr(path) {
            bail!(
                "{}: a part is written as EXR (it keeps the sums `strata merge` adds); merge \
                 the parts to get a PNG",
                path.display()
            );
        }
    }
    Ok(given.to_vec())
}

/// Whether `path` names an EXR (a part, which keeps the sums), not a PNG.
pub fn is_exr(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_split_the_samples_without_gap_or_overlap() {
        for total in [1, 7, 64, 1000] {
            for n in 1..=total.min(9) {
                let ranges: Vec<_> = (0..n).map(|k| split(total, k, n)).collect();
                assert_eq!(ranges[0].start, 0);
                assert_eq!(ranges[n as usize - 1].end, total);
                assert!(ranges.windows(2).all(|w| w[0].end == w[1].start));
                assert!(ranges.iter().all(|r| r.end > r.start));
            }
        }
    }

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |name| {
            vars.iter()
                .find(|(k, _)| *k == name)
                .map(|(_, v)| v.to_string())
        }
    }

    #[test]
    fn the_index_comes_from_slurm_or_kubernetes() {
        let args = PartArgs {
            part_from_env: true,
            ..Default::default()
        };
        let slurm = [
            ("SLURM_ARRAY_TASK_ID", "5"),
            ("SLURM_ARRAY_TASK_MIN", "4"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ];
        let part = args.resolve(64, env(&slurm)).unwrap().unwrap();
        assert_eq!((part.samples, part.label.as_str()), (16..32, "part-1-of-4"));
        let k8s = [("JOB_COMPLETION_INDEX", "3")];
        let e = args.resolve(64, env(&k8s)).unwrap_err().to_string();
        assert!(e.contains("--parts N"), "{e}");
        let with_n = PartArgs {
            parts: Some(4),
            ..args.clone()
        };
        assert_eq!(
            with_n.resolve(64, env(&k8s)).unwrap().unwrap().samples,
            48..64
        );
        let e = args.resolve(64, env(&[])).unwrap_err().to_string();
        assert!(e.contains("neither"), "{e}");
        let out_of_range = [
            ("SLURM_ARRAY_TASK_ID", "4"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ];
        let e = args
            .resolve(64, env(&out_of_range))
            .unwrap_err()
            .to_string();
        assert!(e.contains("numbered 0 to 3"), "{e}");
    }

    #[test]
    fn bad_parts_and_ranges_are_refused() {
        assert!(parse_part("4/4").unwrap_err().contains("numbered 0 to 3"));
        assert!(parse_part("1/0").is_err() && parse_part("x").is_err());
        assert!(parse_samples("8..8").is_err() && parse_samples("9..3").is_err());
        assert_eq!(parse_samples("0..16"), Ok(0..16));
        let args = PartArgs {
            samples: Some(0..65),
            ..Default::default()
        };
        assert!(args
            .resolve(64, env(&[]))
            .unwrap_err()
            .to_string()
            .contains("64 samples"));
        let args = PartArgs {
            part: Some((0, 65)),
            ..Default::default()
        };
        assert!(args
            .resolve(64, env(&[]))
            .unwrap_err()
            .to_string()
            .contains("at most 64"));
    }
}
