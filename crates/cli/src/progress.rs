//! Progress as a person sees it: indicatif's bar on a terminal; on a log (stderr a pipe or a
//! batch job's file, where the bar draws nothing) a plain `progress:` line when the first samples
//! land and then at most every [`LOG_EVERY`], so that a job's log shows the render is working and
//! a script (or a test) can wait for work to begin instead of guessing how long it takes.

use indicatif::{HumanCount, ProgressBar};
use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Least time between two `progress:` lines on a log.
pub const LOG_EVERY: Duration = Duration::from_secs(10);

/// A progress bar and, when stderr is no terminal, its plain lines.
pub struct Meter {
    bar: ProgressBar,
    /// Samples in all, when known.
    total: Option<u64>,
    log: Option<Mutex<Log>>,
}

/// What the plain lines have said so far.
struct Log {
    started: Instant,
    done: u64,
    /// When the last line was written (none yet: the next samples write one).
    last: Option<Instant>,
}

impl Meter {
    /// `bar` (styled by the caller): over its length in samples, or open-ended without one.
    pub fn new(bar: ProgressBar) -> Self {
        let total = bar.length();
        let log = (!std::io::stderr().is_terminal()).then(|| {
            Mutex::new(Log {
                started: Instant::now(),
                done: 0,
                last: None,
            })
        });
        Self { bar, total, log }
    }

    /// `n` more samples done.
    pub fn inc(&self, n: u64) {
        self.bar.inc(n);
        let Some(log) = &self.log else { return };
        let mut log = log.lock().unwrap_or_else(|e| e.into_inner());
        log.done += n;
        if log.last.is_some_and(|t| t.elapsed() < LOG_EVERY) {
            return;
        }
        log.last = Some(Instant::now());
        let seconds = log.started.elapsed().as_secs_f64();
        let done = HumanCount(log.done);
        // The bar draws nothing here, so the line needs no room made for it.
        match self.total {
            Some(total) if total > 0 => eprintln!(
                "progress: {:.0} % ({done} of {} samples) after {seconds:.1} s",
                100.0 * log.done as f64 / total as f64,
                HumanCount(total)
            ),
            _ => eprintln!("progress: {done} samples after {seconds:.1} s"),
        }
    }

    /// Write `line` to stderr: above the bar on a terminal, as it is on a log.
    pub fn line(&self, line: &str) {
        match self.log {
            Some(_) => eprintln!("{line}"),
            None => self.bar.println(line),
        }
    }

    /// The bar itself (to reset or clear it).
    pub fn bar(&self) -> &ProgressBar {
        &self.bar
    }

    /// Start counting again (a render redone on another device).
    pub fn reset(&self) {
        self.bar.reset();
        if let Some(log) = &self.log {
            let mut log = log.lock().unwrap_or_else(|e| e.into_inner());
            log.done = 0;
        }
    }
}
