//! What a study measures: every configuration's kernel warmed up off the clock, then each
//! configuration × seed rendered level by level (1, 2, 4, … spp), timed, and its error measured
//! against the reference.

use super::reference::Reference;
use super::report::{self, Row};
use crate::progress::Meter;
use indicatif::{ProgressBar, ProgressStyle};
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};
use stratapt_film::Render;
use stratapt_scene::{FlatScene, RenderSettings, SamplerKind, Strategy};

/// What a study renders: each configuration at each level, `seeds` times.
pub struct Plan {
    /// Every chosen sampler × strategy.
    pub configs: Vec<(SamplerKind, Strategy)>,
    /// 1, 2, 4, … spp up to the largest.
    pub levels: Vec<u32>,
    pub seeds: u32,
    /// No level is started that would end past it.
    pub budget: Option<Duration>,
}

impl Plan {
    /// Every sampler × strategy named (all where none is) at 1, 2, 4, … up to `max_spp`.
    pub fn new(
        samplers: &[SamplerKind],
        strategies: &[Strategy],
        max_spp: u32,
        seeds: u32,
        budget: Option<Duration>,
    ) -> Self {
        let samplers = if samplers.is_empty() {
            SamplerKind::ALL.to_vec()
        } else {
            samplers.to_vec()
        };
        let strategies = if strategies.is_empty() {
            Strategy::ALL.to_vec()
        } else {
            strategies.to_vec()
        };
        let configs = samplers
            .iter()
            .flat_map(|&s| strategies.iter().map(move |&t| (s, t)))
            .collect();
        let levels =
            std::iter::successors(Some(1u32), |&s| (s < max_spp).then(|| (s * 2).min(max_spp)))
                .collect();
        Self {
            configs,
            levels,
            seeds,
            budget,
        }
    }

    /// The progress over every sample the study takes on a film of `pixels`: a bar on a
    /// terminal, plain lines on a log.
    pub fn progress_bar(&self, pixels: usize) -> Meter {
        let samples_per_level =
            |spp: u32| self.configs.len() as u64 * self.seeds as u64 * pixels as u64 * spp as u64;
        let total = self.levels.iter().map(|&s| samples_per_level(s)).sum();
        let bar = ProgressBar::new(total);
        bar.set_style(
            ProgressStyle::with_template(
                "{bar:40.cyan/blue} {percent:>3}% study: {msg} {elapsed} (eta {eta})",
            )
            .expect("valid progress template"),
        );
        Meter::new(bar)
    }
}

/// Compile each configuration's kernel (and lavapipe's JIT) off the clock, in 8×8 renders.
pub fn warm_up(
    renderer: &dyn Render,
    scene: &mut FlatScene,
    configs: &[(SamplerKind, Strategy)],
    cancel: &AtomicBool,
) -> anyhow::Result<()> {
    let size = (scene.camera.width, scene.camera.height);
    (scene.camera.width, scene.camera.height) = (8, 8);
    for &(sampler, strategy) in configs {
        let settings = RenderSettings {
            pattern_spp: 1,
            sampler,
            strategy,
            ..scene.settings
        };
        renderer
            .render(scene, &settings, &|_| {}, Some(cancel))
            .map_err(|e| anyhow::anyhow!("{}: {e}", renderer.describe()))?;
    }
    (scene.camera.width, scene.camera.height) = size;
    Ok(())
}

/// What was measured, and why measuring stopped early if it did.
pub struct Measured {
    pub rows: Vec<Row>,
    pub stopped: Option<String>,
    /// `GPU timestamps` once a render was timed by them, else `wall`.
    pub time_source: &'static str,
    /// When the first timed level started.
    pub start: Instant,
}

/// What every timed render shares.
pub struct Timed<'a> {
    pub renderer: &'a dyn Render,
    pub scene: &'a FlatScene,
    pub reference: &'a Reference,
    pub cancel: &'a AtomicBool,
    pub bar: &'a Meter,
}

impl Timed<'_> {
    /// Render level by level, so a budget or Ctrl-C leaves every configuration comparable.
    pub fn measure(&self, plan: &Plan) -> anyhow::Result<Measured> {
        let mut measured = Measured {
            rows: Vec::new(),
            stopped: None,
            time_source: "wall",
            start: Instant::now(),
        };
        let mut last_level_seconds = 0.0;
        for &spp in &plan.levels {
            if let Some(why) = past_budget(plan.budget, &measured, last_level_seconds, spp) {
                measured.stopped = Some(why);
                break;
            }
            let level_start = Instant::now();
            if !self.level(plan, spp, &mut measured)? {
                measured.stopped = Some("interrupted by Ctrl-C".to_string());
                break;
            }
            last_level_seconds = level_start.elapsed().as_secs_f64();
            self.bar.line(&format!(
                "measured: {spp} spp, {} renders in {last_level_seconds:.2} s",
                plan.configs.len() as u64 * plan.seeds as u64
            ));
        }
        self.bar.bar().finish_and_clear();
        Ok(measured)
    }

    /// Render every configuration × seed at `spp` into the rows; false once Ctrl-C stops one.
    fn level(&self, plan: &Plan, spp: u32, measured: &mut Measured) -> anyhow::Result<bool> {
        for &config in &plan.configs {
            for seed in 0..plan.seeds {
                let Some(row) = self.render(config, spp, seed)? else {
                    return Ok(false);
                };
                if row.time_source == "gpu-timestamps" {
                    measured.time_source = "GPU timestamps";
                }
                measured.rows.push(row);
            }
        }
        Ok(true)
    }

    /// Render one configuration and seed at `spp`, time it (the kernel's compile and first
    /// dispatch left out) and measure its error; `None` when Ctrl-C stopped it.
    fn render(
        &self,
        (sampler, strategy): (SamplerKind, Strategy),
        spp: u32,
        seed: u32,
    ) -> anyhow::Result<Option<Row>> {
        self.bar
            .bar()
            .set_message(format!("{sampler} / {strategy}, {spp} spp, seed {seed}"));
        let settings = RenderSettings {
            pattern_spp: spp,
            sampler,
            strategy,
            seed,
            ..self.scene.settings
        };
        let t = Instant::now();
        let (film, stats) = self
            .renderer
            .render(
                self.scene,
                &settings,
                &|n| self.bar.inc(n),
                Some(self.cancel),
            )
            .map_err(|e| anyhow::anyhow!("{}: {e}", self.renderer.describe()))?;
        let wall = t.elapsed().as_secs_f64() - stats.compile_seconds - stats.first_dispatch_seconds;
        if stats.cancelled {
            return Ok(None);
        }
        Ok(Some(Row {
            sampler,
            strategy,
            spp,
            seed,
            seconds: stats.gpu_seconds.unwrap_or(wall),
            time_source: if stats.gpu_seconds.is_some() {
                "gpu-timestamps"
            } else {
                "wall"
            },
            errors: report::measure(&film, self.reference),
        }))
    }
}

/// Why the level at `spp` is not started: it would end past the budget (never before the first
/// row is measured).
fn past_budget(
    budget: Option<Duration>,
    measured: &Measured,
    last_level_seconds: f64,
    spp: u32,
) -> Option<String> {
    let budget = budget?;
    // Each level takes about twice the one before.
    let expect = measured.start.elapsed().as_secs_f64() + 2.0 * last_level_seconds;
    (expect > budget.as_secs_f64() && !measured.rows.is_empty()).then(|| {
        format!(
            "the next level ({spp} spp) would end past the {}-s budget",
            budget.as_secs()
        )
    })
}
