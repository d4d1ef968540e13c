//! Plain-text progress lines for runs whose progress no terminal shows (nohup, Slurm, CI): the
//! fraction done, the rate and the time left, the first line after [`FIRST_LINE`], then every
//! [`EVERY`], and one when the work is done if any was printed. Rates and times left are
//! measured from the first unit of work, not from the start, so set-up does not count as work.

use std::io::Write;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

/// The first plain-text line comes after this long; a run that finishes sooner prints nothing.
pub const FIRST_LINE: Duration = Duration::from_secs(10);
/// Later lines come this far apart.
pub const EVERY: Duration = Duration::from_secs(30);

/// Plain-text progress lines: one after [`FIRST_LINE`], then every [`EVERY`], and a last one
/// when the work ends if any was printed.
pub struct Lines {
    total: u64,
    unit: String,
    created: Instant,
    done: AtomicU64,
    /// When and at what count the first unit of work was reported.
    first: OnceLock<(Instant, u64)>,
    /// Milliseconds after `created` at which the next line is due.
    due_ms: AtomicU64,
    printed: AtomicBool,
    out: Mutex<Box<dyn Write + Send>>,
}

impl Lines {
    /// Lines on stderr for `total` units of `unit`, timed from `now`.
    pub fn new(total: u64, unit: &str, now: Instant) -> Self {
        Self::to(Box::new(std::io::stderr()), total, unit, now)
    }

    /// Lines written to `out` (write errors, a closed pipe included, are ignored).
    pub fn to(out: Box<dyn Write + Send>, total: u64, unit: &str, now: Instant) -> Self {
        Lines {
            total,
            unit: unit.to_string(),
            created: now,
            done: AtomicU64::new(0),
            first: OnceLock::new(),
            due_ms: AtomicU64::new(FIRST_LINE.as_millis() as u64),
            printed: AtomicBool::new(false),
            out: Mutex::new(out),
        }
    }

    /// `n` more units done at `now`; prints a line if one is due.
    pub fn add(&self, n: u64, now: Instant) {
        let before = self.done.fetch_add(n, Ordering::Relaxed);
        self.first.get_or_init(|| (now, before));
        let ms = now.saturating_duration_since(self.created).as_millis() as u64;
        let due = self.due_ms.load(Ordering::Relaxed);
        if ms < due {
            return;
        }
        let next = ms + EVERY.as_millis() as u64;
        // One thread prints each line; the others see the new due time.
        if self
            .due_ms
            .compare_exchange(due, next, Ordering::Relaxed, Ordering::Relaxed)
            .is_ok()
        {
            self.print(now, false);
        }
    }

    /// The last line, if any line was printed before.
    pub fn finish(&self, now: Instant) {
        if self.printed.load(Ordering::Relaxed) {
            self.print(now, true);
        }
    }

    fn print(&self, now: Instant, last: bool) {
        let line = self.line(now, last);
        self.printed.store(true, Ordering::Relaxed);
        if let Ok(mut out) = self.out.lock() {
            let _ = writeln!(out, "{line}");
            let _ = out.flush();
        }
    }

    /// The text of a line at `now`.
    pub fn line(&self, now: Instant, last: bool) -> String {
        let done = self.done.load(Ordering::Relaxed);
        let elapsed = now.saturating_duration_since(self.created);
        let rate = self.first.get().and_then(|&(t0, n0)| {
            let dt = now.saturating_duration_since(t0).as_secs_f64();
            (dt > 0.0 && done > n0).then(|| (done - n0) as f64 / dt)
        });
        let rate_text = rate.map_or_else(String::new, |r| format!(", {r:.3e}/s"));
        if last {
            return format!(
                "progress: done, {} {} in {}{rate_text}",
                count(done),
                self.unit,
                clock(elapsed.as_secs_f64())
            );
        }
        let left = match (rate, self.total) {
            (Some(r), t) if t > done => format!(", about {} left", clock((t - done) as f64 / r)),
            _ => String::new(),
        };
        let share = if self.total > 0 {
            format!(
                "{:.1}% of {}",
                100.0 * done as f64 / self.total as f64,
                count(self.total)
            )
        } else {
            count(done)
        };
        format!(
            "progress: {share} {}{rate_text}{left} (elapsed {})",
            self.unit,
            clock(elapsed.as_secs_f64())
        )
    }
}

/// A count as people read it: exact below a million, else in scientific notation.
fn count(n: u64) -> String {
    if n < 1_000_000 {
        n.to_string()
    } else {
        format!("{:.3e}", n as f64)
    }
}

/// A duration for people: "42 s", "3 min 05 s", "2 h 07 min".
pub fn clock(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    match s {
        0..60 => format!("{s} s"),
        60..3600 => format!("{} min {:02} s", s / 60, s % 60),
        _ => format!("{} h {:02} min", s / 3600, (s % 3600) / 60),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A writer whose text the test can read.
    #[derive(Clone, Default)]
    struct Sink(std::sync::Arc<Mutex<Vec<u8>>>);

    impl Write for Sink {
        fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
            self.0.lock().unwrap().extend_from_slice(b);
            Ok(b.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn lines_come_after_ten_seconds_then_every_thirty_with_the_rate_of_the_work_alone() {
        let t0 = Instant::now();
        let sink = Sink::default();
        let l = Lines::to(Box::new(sink.clone()), 1000, "collisions", t0);
        let at = |s: u64| t0 + Duration::from_secs(s);
        // Set-up takes 20 s; then 10 collisions a second.
        l.add(0, at(20));
        for s in 21..=80 {
            l.add(10, at(s));
        }
        l.finish(at(80));
        let text = String::from_utf8(sink.0.lock().unwrap().clone()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        // Due at 10 s (first work at 20 s: printed then), 50 s, 80 s; and the last line.
        assert_eq!(lines.len(), 4, "{text}");
        assert_eq!(
            lines[1],
            "progress: 30.0% of 1000 collisions, 1.000e1/s, about 1 min 10 s left (elapsed 50 s)"
        );
        assert!(
            lines[3].starts_with("progress: done, 600 collisions in 1 min 20 s"),
            "{text}"
        );
    }

    #[test]
    fn a_short_run_prints_nothing() {
        let t0 = Instant::now();
        let sink = Sink::default();
        let l = Lines::to(Box::new(sink.clone()), 100, "collisions", t0);
        l.add(100, t0 + Duration::from_secs(9));
        l.finish(t0 + Duration::from_secs(9));
        assert!(sink.0.lock().unwrap().is_empty());
    }

    #[test]
    fn durations_read_as_people_write_them() {
        assert_eq!(clock(42.4), "42 s");
        assert_eq!(clock(185.0), "3 min 05 s");
        assert_eq!(clock(7620.0), "2 h 07 min");
    }
}
