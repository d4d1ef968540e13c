//! How an analysis runs, as opposed to what it computes: one [`RunOptions`] for every
//! `run(&config, &options)` of the crate.
//!
//! The options never change a result's bits: the engine, the thread count and progress
//! reporting are invisible in the numbers; `resume` only skips work already finished (of the
//! same configuration) and `audit` adds a summary beside the numbers.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use super::Engine;
use crate::Error;

/// Fewest reference bits of a shadow audit: 128 bits resolve the f64 one-step errors (~10⁻¹⁶)
/// by more than twenty orders of magnitude, so the reference's own rounding never enters a
/// verdict.
pub const MIN_AUDIT_BITS: u32 = 128;

/// Most reference bits of a shadow audit: beyond 2¹⁶ bits one replayed event costs milliseconds
/// and the verdicts cannot change (the reference error is already below 10⁻¹⁹⁰⁰⁰).
pub const MAX_AUDIT_BITS: u32 = 1 << 16;

/// Sampling rate and reference precision of a production run's self-audit (a fraction of the
/// events replayed in MPFR as the run goes; `f64` runs only).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AuditSpec {
    /// Fraction of events replayed, in (0, 1].
    pub rate: f64,
    /// Reference precision, [`MIN_AUDIT_BITS`] to [`MAX_AUDIT_BITS`] bits.
    pub bits: u32,
}

impl AuditSpec {
    /// A checked audit specification; the error names the valid ranges.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::engine::options::AuditSpec;
    /// assert!(AuditSpec::new(1e-3, 256).is_ok());
    /// assert!(AuditSpec::new(0.0, 256).is_err());
    /// assert!(AuditSpec::new(1e-3, 64).is_err());
    /// ```
    pub fn new(rate: f64, bits: u32) -> Result<Self, Error> {
        let s = AuditSpec { rate, bits };
        s.validate()?;
        Ok(s)
    }

    /// Checks the rate and the bits (a struct built by hand is checked again before a run).
    pub fn validate(&self) -> Result<(), Error> {
        let (rate, bits) = (self.rate, self.bits);
        if !(rate > 0.0 && rate <= 1.0) {
            return Err(Error::out_of_range(
                "audit",
                rate,
                "use a sample rate in (0, 1]",
            ));
        }
        Error::unless_in(
            "reference_bits",
            bits,
            MIN_AUDIT_BITS..=MAX_AUDIT_BITS,
            " bits for the audit's replay",
        )?;
        Ok(())
    }
}

/// A request to stop a run before it finishes, shared between whoever asks (a Python binding
/// that saw Ctrl-C, a signal handler) and the run's workers, which look at it between segments
/// of their trajectories (about 0.1 s of work each) and then end the run with
/// [`Error::Interrupted`]. Clones share one flag.
///
/// # Examples
///
/// ```
/// use lorentz_gas::engine::options::StopFlag;
/// let stop = StopFlag::default();
/// let seen_by_a_worker = stop.clone();
/// assert!(seen_by_a_worker.check().is_ok());
/// stop.request();
/// assert!(seen_by_a_worker.check().is_err());
/// ```
#[derive(Debug, Clone, Default)]
pub struct StopFlag(Arc<AtomicBool>);

impl StopFlag {
    /// Asks every run watching this flag to stop.
    pub fn request(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// The flag itself, for a signal handler to raise (an atomic store is async-signal-safe).
    pub fn shared(&self) -> Arc<AtomicBool> {
        self.0.clone()
    }

    /// Whether a stop was requested.
    pub fn requested(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// [`Error::Interrupted`] if a stop was requested.
    pub fn check(&self) -> Result<(), Error> {
        if self.requested() {
            Err(Error::Interrupted)
        } else {
            Ok(())
        }
    }
}

fn no_progress(_: u64) {}

/// How a computation runs: engine, worker threads, progress, where to resume from, and the
/// optional shadow audit.
///
/// # Examples
///
/// ```
/// use lorentz_gas::engine::{options::RunOptions, Engine};
/// let opts = RunOptions { engine: Engine::Scalar, threads: 1, ..RunOptions::default() };
/// assert_eq!(opts.threads, 1);
/// assert!(opts.resume.is_none());
/// ```
#[derive(Clone)]
pub struct RunOptions<'a> {
    /// The engine ([`Engine::Auto`]: SIMD for `f64` where the CPU has it); the bits are the same
    /// on every engine.
    pub engine: Engine,
    /// Worker threads (≥ 1; default: the cores available); the bits are the same at every count.
    pub threads: usize,
    /// Receives units of work as they are done (collisions, visits or particles, as the
    /// analysis documents), from any worker thread.
    pub progress: &'a (dyn Fn(u64) + Sync),
    /// Where finished work is kept, so that an interrupted run continues where it stopped (a
    /// file or a directory, as the analysis documents); `None`: nothing is kept.
    pub resume: Option<PathBuf>,
    /// Replay a fraction of the events in MPFR as the run goes (analyses that offer it).
    pub audit: Option<AuditSpec>,
    /// With `resume`: how often the trajectories in flight are saved whole (positions,
    /// velocities, cells, observer accumulators), so that an interruption loses at most about
    /// this much work (analyses that offer it; default [`DEFAULT_CHECKPOINT_EVERY`]).
    pub checkpoint_every: Duration,
    /// A flag whose request stops the run early with [`Error::Interrupted`] (analyses that
    /// offer it: diffusion, its packed runs and sweeps, superdiffusion and hops between segments
    /// of about 0.1 s; backscatter and escape between particles; Lyapunov exponents and the
    /// shadow audit between batches; a field run's classification every few milliseconds;
    /// `None`: the run cannot be stopped).
    /// Never changes the bits of a run that finishes.
    pub stop: Option<StopFlag>,
}

/// Default interval between saves of the trajectories in flight: a minute of work at risk, and
/// a checkpoint write (tens of kilobytes) per thread per minute.
pub const DEFAULT_CHECKPOINT_EVERY: Duration = Duration::from_secs(60);

/// Longest interval between saves: a day.
pub const MAX_CHECKPOINT_EVERY: Duration = Duration::from_secs(86_400);

impl Default for RunOptions<'_> {
    fn default() -> Self {
        RunOptions {
            engine: Engine::Auto,
            threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
            progress: &no_progress,
            resume: None,
            audit: None,
            checkpoint_every: DEFAULT_CHECKPOINT_EVERY,
            stop: None,
        }
    }
}

impl std::fmt::Debug for RunOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RunOptions")
            .field("engine", &self.engine)
            .field("threads", &self.threads)
            .field("resume", &self.resume)
            .field("audit", &self.audit)
            .field("checkpoint_every", &self.checkpoint_every)
            .field("stop", &self.stop)
            .finish_non_exhaustive()
    }
}

/// An option of [`RunOptions`] that an analysis may not use. `threads`, `progress` and `stop`
/// are taken by every analysis (a stop request is honoured at the analysis's next boundary of
/// work); these four are not, and an analysis refuses each it does not use
/// ([`RunOptions::refuse_unused`]) rather than ignore it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunOption {
    /// [`RunOptions::engine`] other than [`Engine::Auto`].
    Engine,
    /// [`RunOptions::resume`] given.
    Resume,
    /// [`RunOptions::audit`] given.
    Audit,
    /// [`RunOptions::checkpoint_every`] other than [`DEFAULT_CHECKPOINT_EVERY`].
    CheckpointEvery,
}

impl RunOption {
    /// Every option that can be refused.
    pub const ALL: [RunOption; 4] = [
        RunOption::Engine,
        RunOption::Resume,
        RunOption::Audit,
        RunOption::CheckpointEvery,
    ];

    /// The field of [`RunOptions`] it is.
    pub fn field(self) -> &'static str {
        match self {
            RunOption::Engine => "engine",
            RunOption::Resume => "resume",
            RunOption::Audit => "audit",
            RunOption::CheckpointEvery => "checkpoint_every",
        }
    }
}

impl std::fmt::Display for RunOption {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.field())
    }
}

impl RunOptions<'_> {
    /// Whether `option` is set away from its default.
    pub fn is_set(&self, option: RunOption) -> bool {
        match option {
            RunOption::Engine => self.engine != Engine::Auto,
            RunOption::Resume => self.resume.is_some(),
            RunOption::Audit => self.audit.is_some(),
            RunOption::CheckpointEvery => self.checkpoint_every != DEFAULT_CHECKPOINT_EVERY,
        }
    }

    /// The options checked ([`Self::validate`]) and those `analysis` does not use (`uses`)
    /// refused ([`Self::refuse_unused`]): what every analysis asks of its options first.
    ///
    /// # Errors
    /// As those two.
    pub fn accept(&self, analysis: &'static str, uses: &[RunOption]) -> Result<(), Error> {
        self.validate()?;
        self.refuse_unused(analysis, uses)
    }

    /// Refuses, with [`Error::UnusedOption`], the first option set away from its default that
    /// `analysis` does not use (`uses`): an option that would be ignored is an error, never a
    /// silent no-op.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::engine::options::{RunOption, RunOptions};
    /// let opts = RunOptions { resume: Some("run.ckpt".into()), ..RunOptions::default() };
    /// assert!(opts.refuse_unused("diffusion", &[RunOption::Resume]).is_ok());
    /// let e = opts.refuse_unused("lyapunov", &[]).unwrap_err();
    /// assert_eq!(e.to_string(), "lyapunov does not take `resume`: leave it out");
    /// ```
    pub fn refuse_unused(&self, analysis: &'static str, uses: &[RunOption]) -> Result<(), Error> {
        match RunOption::ALL
            .into_iter()
            .find(|o| self.is_set(*o) && !uses.contains(o))
        {
            Some(option) => Err(Error::UnusedOption { analysis, option }),
            None => Ok(()),
        }
    }

    /// Checks the thread count and the audit before any work.
    pub fn validate(&self) -> Result<(), Error> {
        if let Some(path) = self
            .resume
            .as_ref()
            .filter(|_| cfg!(not(feature = "checkpoints")))
        {
            return Err(Error::parameter(
                "resume",
                path.display(),
                super::resume::NO_CHECKPOINTS,
            ));
        }
        if self.threads == 0 {
            return Err(Error::Zero { what: "threads" });
        }
        if let Some(a) = &self.audit {
            a.validate()?;
        }
        if self.checkpoint_every > MAX_CHECKPOINT_EVERY {
            return Err(Error::out_of_range(
                "checkpoint_every",
                self.checkpoint_every.as_secs_f64(),
                format!("use 0 to {} seconds", MAX_CHECKPOINT_EVERY.as_secs()),
            ));
        }
        Ok(())
    }
}
