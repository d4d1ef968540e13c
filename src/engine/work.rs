//! Work bounded before it starts. Every analysis estimates from its inputs the collisions it
//! will compute, and the cell edges its flights will cross on the way, and refuses a run that
//! could not finish within [`MAX_SECONDS`] on its threads even at the floor costs below. So an
//! input such as `w = 1e300` (flights that cross 10³⁰⁰ cells), a gap of 10⁻¹² (10¹² collisions
//! per hop out of a trap) or 2⁶⁴ − 1 particles is refused at once, naming the limit, instead of
//! running for weeks or years.
//!
//! The limit is a week of every thread: the longest wall time clusters commonly grant one job,
//! beyond which work is split into a campaign's parts anyway. The costs are floors, about half
//! of what `lorentz bench` measures on Zen 4 (9.5 ns per collision on the SIMD engine, 38.8 ns
//! on the scalar one), so that a faster machine is not refused what it could finish: the check
//! stops only what is out of reach.

use crate::Error;
use crate::scenes::Scene;

/// The most work a run accepts: a week of every thread it is given.
pub const MAX_SECONDS: f64 = 7.0 * 86_400.0;

/// A floor on the cost of one collision of the SIMD engine.
pub const SIMD_SECONDS_PER_COLLISION: f64 = 5e-9;

/// A floor on the cost of one collision of the scalar engine in `f64`.
pub const SCALAR_SECONDS_PER_COLLISION: f64 = 15e-9;

/// A floor on the cost of one crossing of a cell edge between collisions.
pub const SECONDS_PER_CROSSING: f64 = 1e-9;

/// The cell edges a flight crosses per collision on `scene`, ⟨ℓ⟩/τ (Santaló's mean free path
/// over the mean time between edge crossings); 0 for a scene that does not supply τ. Infinite
/// where the geometry overflows a double (a gap of 10³⁰⁰).
pub fn crossings_per_collision<S: Scene>(scene: &S) -> f64 {
    match scene.crossing_time() {
        Some(tau) => {
            let c = scene.mean_free_path() / tau;
            if c.is_nan() { f64::INFINITY } else { c }
        }
        None => 0.0,
    }
}

/// The work of a run, estimated from its inputs before it starts.
#[derive(Debug, Clone, Copy)]
pub struct Work<'a> {
    /// The analysis, for the refusal.
    pub analysis: &'a str,
    /// The parameters to lower, in the library's terms (their configuration's fields).
    pub lower: &'static [&'static str],
    /// A parameter to raise instead, if any (a gap: fewer collisions per hop).
    pub raise: Option<&'static str>,
    /// Collisions the run computes (as a double: the product of counts can overflow `u64`).
    pub collisions: f64,
    /// Cell edges crossed per collision ([`crossings_per_collision`]).
    pub crossings: f64,
    /// The floor on the cost of a collision, in seconds.
    pub per_collision: f64,
}

impl<'a> Work<'a> {
    /// `collisions` collisions on the scalar engine, with no crossings to speak of (the
    /// triangular scene below w∞).
    pub fn new(analysis: &'a str, lower: &'static [&'static str], collisions: f64) -> Self {
        Work {
            analysis,
            lower,
            raise: None,
            collisions,
            crossings: 0.0,
            per_collision: SCALAR_SECONDS_PER_COLLISION,
        }
    }

    /// The same work, refused with `raise` as the parameter to raise instead.
    pub fn or_raise(self, raise: &'static str) -> Self {
        Work {
            raise: Some(raise),
            ..self
        }
    }

    /// The same work with `crossings` cell edges crossed per collision.
    pub fn crossing(self, crossings: f64) -> Self {
        Work { crossings, ..self }
    }

    /// The same work on an engine that may be the SIMD one.
    pub fn simd(self) -> Self {
        Work {
            per_collision: SIMD_SECONDS_PER_COLLISION,
            ..self
        }
    }

    /// Refuses the work when even the floor costs make it longer than [`MAX_SECONDS`] on
    /// `threads` threads.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::engine::work::Work;
    /// assert!(Work::new("diffusion", &["collisions"], 1e12).simd().check(2).is_ok());
    /// let e = Work::new("lyapunov", &["collisions_per_batch", "batches"], 3.7e19).check(2).unwrap_err();
    /// assert!(e.to_string().contains("a week"), "{e}");
    /// assert!(e.to_string().ends_with("; lower collisions_per_batch or batches"), "{e}");
    /// let flag = |p: &str| format!("--{}", p.replace('_', "-"));
    /// assert!(e.presented(&flag).ends_with("; lower --collisions-per-batch or --batches"), "{e}");
    /// assert!(Work::new("audit", &["collisions"], 1e6).crossing(f64::INFINITY).check(2).is_err());
    /// ```
    ///
    /// # Errors
    /// [`Error::TooMuchWork`] naming the estimate, the floor, the limit and the parameters to
    /// lower.
    pub fn check(&self, threads: usize) -> Result<(), Error> {
        let crossings = self.crossings.max(0.0);
        let per = self.per_collision + crossings * SECONDS_PER_CROSSING;
        let seconds = self.collisions * per / threads.max(1) as f64;
        if seconds <= MAX_SECONDS {
            return Ok(());
        }
        let (analysis, collisions) = (self.analysis, self.collisions);
        let flights = if crossings.is_infinite() {
            ", each flight crossing more cells between collisions than a double can count"
                .to_string()
        } else if crossings > 1e3 {
            format!(", each flight crossing about {crossings:.1e} cells between collisions")
        } else {
            String::new()
        };
        Err(Error::TooMuchWork {
            estimate: format!(
                "{analysis} would compute about {collisions:.1e} collisions{flights}: {} on \
                 {threads} thread{} at {} per collision or more, beyond the limit of a week of \
                 the run's threads",
                duration(seconds),
                if threads == 1 { "" } else { "s" },
                nanoseconds(per),
            ),
            lower: self.lower,
            raise: self.raise,
        })
    }
}

/// `seconds` as days or years.
fn duration(seconds: f64) -> String {
    let days = seconds / 86_400.0;
    if !days.is_finite() {
        "forever".into()
    } else if days < 365.25 {
        format!("{days:.0} days")
    } else {
        format!("{:.1e} years", days / 365.25)
    }
}

/// `seconds` in nanoseconds, readable at any size.
fn nanoseconds(seconds: f64) -> String {
    let ns = seconds * 1e9;
    if !ns.is_finite() {
        "unbounded time".into()
    } else if ns < 1e4 {
        format!("{ns:.0} ns")
    } else {
        format!("{ns:.1e} ns")
    }
}
