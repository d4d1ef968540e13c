//! The progress every long command reports on stderr: a bar on a terminal; plain-text lines
//! (fraction, rate, time left) when stderr is a file or a pipe — under nohup, Slurm or CI — so a
//! long run is never silent; nothing with `--quiet`.
//!
//! Rates and times left are measured from the first unit of work done, not from the start of
//! the command: set-up (parsing, sampling the localized share, spawning threads) would otherwise
//! be counted as if it were work and make the first estimates of the time left too long.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressState, ProgressStyle};
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::engine::progress_lines::Lines;

/// A progress report over a known amount of work (collisions, injections, points, repetitions).
pub struct Progress {
    bar: ProgressBar,
    lines: Option<std::sync::Arc<Lines>>,
    /// Advances the report (shared with the bar or the lines), for [`RunOptions::progress`].
    inc: Box<dyn Fn(u64) + Sync + Send>,
}

impl Progress {
    /// A report for `total` units of `unit`: a bar on a terminal, lines otherwise, nothing when
    /// `quiet`.
    pub fn new(total: u64, unit: &str, quiet: bool) -> Self {
        if quiet {
            return Self::of(hidden(total), None);
        }
        if !std::io::stderr().is_terminal() {
            return Self::of(hidden(total), Some(Lines::new(total, unit, Instant::now())));
        }
        let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {percent}% {msg} ({rate}, eta {eta})",
            )
            .map(|s| {
                s.with_key("rate", |st: &ProgressState, w: &mut dyn std::fmt::Write| {
                    let _ = write!(w, "{:.3e}/s", st.per_sec());
                })
            })
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar.set_message(unit.to_string());
        Self::of(bar, None)
    }

    fn of(bar: ProgressBar, lines: Option<Lines>) -> Self {
        let shared = bar.clone();
        let lines = lines.map(std::sync::Arc::new);
        let feed = lines.clone();
        let started = AtomicBool::new(false);
        Progress {
            bar,
            lines,
            inc: Box::new(move |n| {
                // The estimate of the time left starts with the first unit of work.
                if !started.swap(true, Ordering::Relaxed) {
                    shared.reset_eta();
                }
                shared.inc(n);
                if let Some(l) = &feed {
                    l.add(n, Instant::now());
                }
            }),
        }
    }

    /// A callback for the library's `progress: &(dyn Fn(u64) + Sync)` parameters.
    pub fn callback(&self) -> impl Fn(u64) + Sync + '_ {
        move |n| (self.inc)(n)
    }

    /// Run options on `threads` threads that advance this report (engine auto, nothing resumed).
    pub fn options(&self, threads: usize) -> RunOptions<'_> {
        RunOptions {
            threads,
            progress: &*self.inc,
            ..super::signals::options()
        }
    }
}

fn hidden(total: u64) -> ProgressBar {
    ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::hidden())
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
        if let Some(l) = &self.lines {
            l.finish(Instant::now());
        }
    }
}
