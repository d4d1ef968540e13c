//! The progress bar every long command shows on stderr: hidden with `--quiet` or when stderr is
//! not a terminal, so pipes and CI logs stay clean.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressState, ProgressStyle};
use lorentz_gas::engine::options::RunOptions;

/// A progress bar over a known amount of work (collisions, injections, points, repetitions).
pub struct Progress {
    bar: ProgressBar,
    /// Advances `bar` (a clone of it: the bar is shared), for [`RunOptions::progress`].
    inc: Box<dyn Fn(u64) + Sync + Send>,
}

impl Progress {
    /// A bar for `total` units of `unit` (shown in the bar's message).
    pub fn new(total: u64, unit: &str, quiet: bool) -> Self {
        if quiet || !std::io::stderr().is_terminal() {
            return Self::of(ProgressBar::with_draw_target(
                Some(total),
                ProgressDrawTarget::hidden(),
            ));
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
        Self::of(bar)
    }

    fn of(bar: ProgressBar) -> Self {
        let shared = bar.clone();
        Progress {
            bar,
            inc: Box::new(move |n| shared.inc(n)),
        }
    }

    /// A callback for the library's `progress: &(dyn Fn(u64) + Sync)` parameters.
    pub fn callback(&self) -> impl Fn(u64) + Sync + '_ {
        move |n| self.bar.inc(n)
    }

    /// Run options on `threads` threads that advance this bar (engine auto, nothing resumed).
    pub fn options(&self, threads: usize) -> RunOptions<'_> {
        RunOptions {
            threads,
            progress: &*self.inc,
            ..super::signals::options()
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}
