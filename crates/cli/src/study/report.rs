//! A study's measurements: the errors of one render against the reference, the CSV of every
//! render, and the per-configuration summary (convergence slope, time to a threshold,
//! efficiency, calibration of the predicted error) ranked in `report.md`.

use super::reference::Reference;
use std::fmt::Write as _;
use std::path::Path;
use stratapt_film::Film;
use stratapt_scene::{SamplerKind, Strategy};

/// The constant in relMSE's denominator, `(x − ref)² / (ref² + 0.01)`: keeps dark pixels from
/// dominating (the usual rendering definition).
pub const REL_EPSILON: f64 = 0.01;

/// One render of a study.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub sampler: SamplerKind,
    pub strategy: Strategy,
    pub spp: u32,
    pub seed: u32,
    /// Render time, and how it was measured (`gpu-timestamps` or `wall`).
    pub seconds: f64,
    pub time_source: &'static str,
    pub errors: Errors,
}

/// Errors of one film against the reference, the reference's own variance subtracted; and the
/// film's own prediction of them (its calibrated variance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Errors {
    /// Mean over pixels and channels of (x − ref)².
    pub mse: f64,
    /// Mean over pixels and channels of (x − ref)² / (ref² + 0.01).
    pub relmse: f64,
    /// The same two, predicted from the film's variance channel.
    pub predicted_mse: f64,
    pub predicted_relmse: f64,
}

/// Measure `film` against `reference`.
pub fn measure(film: &Film, reference: &Reference) -> Errors {
    let variances = film.variances();
    let n = 3.0 * film.sum.len().max(1) as f64;
    let mut e = Errors {
        mse: 0.0,
        relmse: 0.0,
        predicted_mse: 0.0,
        predicted_relmse: 0.0,
    };
    for (i, variance) in variances.iter().enumerate() {
        let m = film.mean(i);
        for c in 0..3 {
            let r = reference.mean[i][c];
            let weight = 1.0 / (r * r + REL_EPSILON);
            // E[(x − ref)²] = MSE(x) + Var(ref): subtract the reference's own noise.
            let sq = (m[c] - r).powi(2) - reference.variance[i][c];
            e.mse += sq / n;
            e.relmse += sq * weight / n;
            e.predicted_mse += variance[c] / n;
            e.predicted_relmse += variance[c] * weight / n;
        }
    }
    e
}

/// `study.csv`: one row per render.
pub fn csv(rows: &[Row]) -> String {
    let mut out = String::from(
        "sampler,strategy,spp,seed,seconds,time_source,mse,rmse,relmse,rel_rmse,predicted_mse,predicted_relmse\n",
    );
    for r in rows {
        let e = &r.errors;
        let _ = writeln!(
            out,
            "{},{},{},{},{:.6},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e}",
            r.sampler,
            r.strategy,
            r.spp,
            r.seed,
            r.seconds,
            r.time_source,
            e.mse,
            e.mse.max(0.0).sqrt(),
            e.relmse,
            e.relmse.max(0.0).sqrt(),
            e.predicted_mse,
            e.predicted_relmse
        );
    }
    out
}

/// One spp level of one configuration, averaged over its seeds.
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    pub spp: u32,
    pub seconds: f64,
    pub mse: f64,
    pub relmse: f64,
    pub predicted_mse: f64,
    /// Smallest and largest relative RMSE over the seeds (the band in the plots).
    pub rel_rmse_range: (f64, f64),
    pub seeds: usize,
}

/// What the report says of one configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    pub sampler: SamplerKind,
    pub strategy: Strategy,
    pub levels: Vec<Level>,
    /// Least-squares slope of log relative RMSE against log seconds over every render, and its
    /// standard error (None with fewer than 3 usable renders).
    pub slope: Option<(f64, f64)>,
    /// Seconds to reach the relMSE threshold (log-log interpolation between levels), if reached.
    pub time_to_threshold: Option<f64>,
    /// 1 / (MSE · seconds) at the comparison level (the largest spp every configuration has).
    pub efficiency: f64,
    /// Predicted MSE over measured MSE at the comparison level.
    pub predicted_ratio: f64,
}

/// Average each configuration's rows per spp level, fit, and rank by efficiency (best first).
pub fn summarize(rows: &[Row], threshold: f64) -> (Vec<Summary>, Option<u32>) {
    let mut configs: Vec<(SamplerKind, Strategy)> = Vec::new();
    for r in rows {
        if !configs.contains(&(r.sampler, r.strategy)) {
            configs.push((r.sampler, r.strategy));
        }
    }
    let levels: Vec<Vec<Level>> = configs.iter().map(|&c| levels_of(rows, c)).collect();
    // The comparison level: the largest spp that every configuration reached.
    let common = levels
        .iter()
        .map(|l| l.last().map_or(0, |l| l.spp))
        .min()
        .filter(|&spp| spp > 0);
    let mut out: Vec<Summary> = configs
        .iter()
        .zip(levels)
        .map(|(&(sampler, strategy), levels)| {
            let at = common.and_then(|spp| levels.iter().find(|l| l.spp == spp));
            let (efficiency, predicted_ratio) = at.map_or((0.0, f64::NAN), |l| {
                (
                    1.0 / (l.mse.max(1e-300) * l.seconds.max(1e-9)),
                    l.predicted_mse / l.mse,
                )
            });
            let points: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| (r.sampler, r.strategy) == (sampler, strategy))
                .filter(|r| r.errors.relmse > 0.0 && r.seconds > 0.0)
                .map(|r| (r.seconds.ln(), 0.5 * r.errors.relmse.ln()))
                .collect();
            Summary {
                sampler,
                strategy,
                slope: fit(&points),
                time_to_threshold: time_to(&levels, threshold),
                levels,
                efficiency,
                predicted_ratio,
            }
        })
        .collect();
    out.sort_by(|a, b| b.efficiency.total_cmp(&a.efficiency));
    (out, common)
}

fn levels_of(rows: &[Row], config: (SamplerKind, Strategy)) -> Vec<Level> {
    let mine: Vec<&Row> = rows
        .iter()
        .filter(|r| (r.sampler, r.strategy) == config)
        .collect();
    let mut spps: Vec<u32> = mine.iter().map(|r| r.spp).collect();
    spps.sort_unstable();
    spps.dedup();
    spps.into_iter()
        .map(|spp| {
            let at: Vec<&&Row> = mine.iter().filter(|r| r.spp == spp).collect();
            let n = at.len() as f64;
            let avg = |f: &dyn Fn(&Row) -> f64| at.iter().map(|r| f(r)).sum::<f64>() / n;
            let rel: Vec<f64> = at.iter().map(|r| r.errors.relmse.max(0.0).sqrt()).collect();
            Level {
                spp,
                seconds: avg(&|r| r.seconds),
                mse: avg(&|r| r.errors.mse),
                relmse: avg(&|r| r.errors.relmse),
                predicted_mse: avg(&|r| r.errors.predicted_mse),
                rel_rmse_range: (
                    rel.iter().copied().fold(f64::INFINITY, f64::min),
                    rel.iter().copied().fold(0.0, f64::max),
                ),
                seeds: at.len(),
            }
        })
        .collect()
}

/// Least-squares slope of `y` on `x` and its standard error.
pub fn fit(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = points.len() as f64;
    if points.len() < 3 {
        return None;
    }
    let (mx, my) = (
        points.iter().map(|p| p.0).sum::<f64>() / n,
        points.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let slope = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>() / sxx;
    let ssr: f64 = points
        .iter()
        .map(|p| (p.1 - my - slope * (p.0 - mx)).powi(2))
        .sum();
    Some((slope, (ssr / (n - 2.0) / sxx).sqrt()))
}

/// Seconds at which the mean relMSE first reaches `threshold`, interpolated log-log between
/// the levels around the crossing (the first level's time if it is already below).
pub fn time_to(levels: &[Level], threshold: f64) -> Option<f64> {
    let k = levels.iter().position(|l| l.relmse <= threshold)?;
    if k == 0 {
        return Some(levels[0].seconds);
    }
    let (a, b) = (&levels[k - 1], &levels[k]);
    if b.relmse <= 0.0 || a.relmse <= 0.0 || a.seconds <= 0.0 || b.seconds <= 0.0 {
        return Some(b.seconds);
    }
    let t = (threshold.ln() - a.relmse.ln()) / (b.relmse.ln() - a.relmse.ln());
    Some((a.seconds.ln() + t * (b.seconds.ln() - a.seconds.ln())).exp())
}

/// What the report says about the study as a whole.
pub struct Meta<'a> {
    pub scene: &'a Path,
    pub size: (u32, u32),
    pub max_depth: u32,
    pub device: &'a str,
    pub time_source: &'a str,
    pub reference: &'a str,
    pub threshold: f64,
    pub seeds: u32,
    pub command: &'a str,
    /// Why the study stopped early, if it did.
    pub stopped: Option<&'a str>,
}

/// `report.md`.
pub fn markdown(meta: &Meta, summaries: &[Summary], common: Option<u32>) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# strata study: {}\n", meta.scene.display());
    let _ = writeln!(
        s,
        "{}×{}, depth {}, on {}; times: {}; {} seeds per point; reference: {}.\n",
        meta.size.0,
        meta.size.1,
        meta.max_depth,
        meta.device,
        meta.time_source,
        meta.seeds,
        meta.reference
    );
    let _ = writeln!(s, "Regenerate: `{}`\n", meta.command);
    if let Some(why) = meta.stopped {
        let _ = writeln!(s, "**Stopped early: {why}.**\n");
    }
    let _ = writeln!(
        s,
        "relMSE = mean over pixels and channels of (x − ref)² / (ref² + {REL_EPSILON}); \
         efficiency = 1 / (MSE · seconds) at {}; slope = d log(relative RMSE) / d log(seconds) \
         (plain Monte Carlo: −0.5); predicted / measured = mean of the film's calibrated \
         variance over its measured MSE.\n",
        common.map_or("no common spp".to_string(), |spp| format!(
            "{spp} spp (the largest every configuration reached)"
        ))
    );
    let _ = writeln!(
        s,
        "| rank | sampler | strategy | efficiency | relative to best | slope ± SE | time to relMSE {:.0e} | predicted / measured |",
        meta.threshold
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    let best = summaries.first().map_or(1.0, |b| b.efficiency);
    for (rank, m) in summaries.iter().enumerate() {
        let slope = m
            .slope
            .map_or("n/a".to_string(), |(k, se)| format!("{k:.3} ± {se:.3}"));
        let reach = m
            .time_to_threshold
            .map_or("not reached".to_string(), |t| format!("{t:.3} s"));
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.4e} | {:.3} | {} | {} | {:.2} |",
            rank + 1,
            m.sampler,
            m.strategy,
            m.efficiency,
            m.efficiency / best,
            slope,
            reach,
            m.predicted_ratio
        );
    }
    let _ = writeln!(s, "\n## Per spp (means over seeds)\n");
    let _ = writeln!(
        s,
        "| sampler | strategy | spp | seconds | MSE | relMSE | predicted MSE |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for m in summaries {
        for l in &m.levels {
            // One sample per pixel gives no variance estimate (the film's `var.*` is 0).
            let predicted = match l.spp {
                0 | 1 => "not estimated".to_string(),
                _ => format!("{:.3e}", l.predicted_mse),
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.4} | {:.3e} | {:.3e} | {predicted} |",
                m.sampler, m.strategy, l.spp, l.seconds, l.mse, l.relmse
            );
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_recovers_a_known_slope() {
        let points: Vec<(f64, f64)> = (0..10).map(|i| (i as f64, 3.0 - 0.5 * i as f64)).collect();
        let (k, se) = fit(&points).unwrap();
        assert!((k + 0.5).abs() < 1e-12 && se < 1e-9);
        assert!(fit(&points[..2]).is_none());
    }

    #[test]
    fn threshold_time_is_interpolated_log_log() {
        let level = |spp, seconds, relmse| Level {
            spp,
            seconds,
            mse: relmse,
            relmse,
            predicted_mse: relmse,
            rel_rmse_range: (0.0, 0.0),
            seeds: 1,
        };
        let levels = [
            level(1, 1.0, 1e-2),
            level(2, 2.0, 1e-3),
            level(4, 4.0, 1e-4),
        ];
        // 10^-2.5 lies halfway (in logs) between the first two levels: √2 seconds.
        let t = time_to(&levels, 10f64.powf(-2.5)).unwrap();
        assert!((t - 2f64.sqrt()).abs() < 1e-9, "{t}");
        assert_eq!(time_to(&levels, 1e-1), Some(1.0));
        assert_eq!(time_to(&levels, 1e-6), None);
    }
}
