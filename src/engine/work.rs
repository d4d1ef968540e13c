//! Work bounded before it starts. Every analysis estimates from its inputs the collisions it
//! will compute, the cell edges its flights will cross on the way, the precision it computes at
//! and the set-up it does first (a trajectory's plan, a field's classification of orbits), and
//! refuses a run that could not finish within [`MAX_SECONDS`] on its threads even at the floor
//! costs below. So an input such as `w = 1e300` (flights that cross 10³⁰⁰ cells), a gap of
//! 10⁻¹² (10¹² collisions per hop out of a trap), 2⁶⁴ − 1 particles or 10¹² collisions at 2²⁰
//! bits is refused at once, naming the estimate and the parameters to lower, instead of running
//! for weeks or years.
//!
//! The limit is a week of every thread: the longest wall time clusters commonly grant one job,
//! beyond which work is split into a campaign's parts anyway.
//!
//! # The cost model
//!
//! A run's floor is, on one thread,
//!
//! ```text
//! seconds = collisions · (c(engine, precision) + crossings · x(engine)) + set-up
//! ```
//!
//! divided by its threads (the set-up on one thread where it is serial), with
//!
//! * c, a collision: [`SIMD_SECONDS_PER_COLLISION`], [`SCALAR_SECONDS_PER_COLLISION`] in `f64`;
//!   at p bits of MPFR `a + b·(p/1024)^α` ([`mpfr_seconds_per_collision`]: [`MPFR_SECONDS`],
//!   [`MPFR_SECONDS_AT_1024_BITS`], [`MPFR_EXPONENT`]); on arcs in a field
//!   [`ARC_SIMD_SECONDS_PER_COLLISION`], [`ARC_SCALAR_SECONDS_PER_COLLISION`];
//! * x, a cell edge crossed between collisions by the walk (a straight flight walked cell by
//!   cell: [`SECONDS_PER_CROSSING`]; an arc: [`ARC_SECONDS_PER_CROSSING`]);
//! * the set-up: a field's classification of orbits ([`SECONDS_PER_CLASSIFICATION`] each) on
//!   the run's threads, and its exact pinned share on one, a quadrature whose cost grows as a
//!   power 3 of the lattice rows within ρ + r, ρ = 1/|B| ([`quadrature_seconds`]).
//!
//! Each constant is a floor, about half of what `lorentz bench --costs` measures or less (its
//! report prints each measured value beside the floor here), so that a faster machine is not
//! refused what it could finish: the check stops only what is out of reach. Measured on an AMD
//! EPYC (Zen 4; 2 cores shared with other jobs, so the spread between two calls is up to 3×),
//! `lorentz bench --costs --repetitions 3`, medians, one thread (two calls):
//!
//! | cost | measured | floor |
//! |---|---|---|
//! | collision, SIMD engine, `f64` (w = 0.1) | 9.7 to 23 ns | 5 ns |
//! | collision, scalar engine, `f64` | 50 to 66 ns | 15 ns |
//! | collision, MPFR 64 bits | 2.1 to 2.6 µs | 0.81 µs |
//! | collision, MPFR 1024 bits | 9.0 to 9.5 µs | 4.7 µs |
//! | collision, MPFR 16 384 bits | 453 to 472 µs | 148 µs |
//! | collision, MPFR 262 144 bits | 27 to 80 ms | 5.4 ms |
//! | collision, MPFR 2²⁰ bits (`bench --precision`) | 115 ms | 33 ms |
//! | collision on arcs, SIMD arc engine (B = 1) | 44 to 200 ns | 20 ns |
//! | collision on arcs, scalar (B = 1) | 188 to 774 ns | 80 ns |
//! | cell edge, square walk (r = 10⁻⁴) | 54 to 166 ns | 25 ns |
//! | cell edge, triangular walk (w = 1000) | 23 to 72 ns | 12 ns |
//! | cell edge, arcs (square, r = 10⁻³, B = 0.1) | see `bench --costs` | 10 ns |
//! | classification of an orbit in a field | 48 ns | 20 ns |
//! | the pinned share's quadrature, per rows³ (r = 1/50 to 10⁻⁴) | 4.2 to 29 µs | 4 µs |
//!
//! The MPFR fit of the measurements at 1024 bits and above is 2.0–2.5 µs + 7.3–9.1 µs ·
//! (p/1024)^1.45–1.64; the floor's exponent is lower, 1.3, because MPFR's FFT multiplication
//! makes the cost near-linear beyond 2¹⁶ bits (115 ms at 2²⁰ bits, not the 200 ms the power
//! 1.45 gives), and a floor must stay below every measurement.

use crate::Error;
use crate::numbers::precision::Precision;
use crate::scenes::{Scene, Walk};

/// The most work a run accepts: a week of every thread it is given.
pub const MAX_SECONDS: f64 = 7.0 * 86_400.0;

/// A floor on the cost of one collision of the SIMD engine.
pub const SIMD_SECONDS_PER_COLLISION: f64 = 5e-9;

/// A floor on the cost of one collision of the scalar engine in `f64`.
pub const SCALAR_SECONDS_PER_COLLISION: f64 = 15e-9;

/// The constant term a of the floor on an MPFR collision, a + b·(p/1024)^α.
pub const MPFR_SECONDS: f64 = 0.7e-6;

/// The term b of the floor on an MPFR collision at 1024 bits, a + b·(p/1024)^α.
pub const MPFR_SECONDS_AT_1024_BITS: f64 = 4.0e-6;

/// The exponent α of the floor on an MPFR collision, a + b·(p/1024)^α: below the 1.45 of
/// schoolbook multiplication up to 2¹⁶ bits, since MPFR's FFT multiplication is near-linear
/// beyond (the fit over 2¹⁰ to 2²⁰ bits).
pub const MPFR_EXPONENT: f64 = 1.3;

/// A floor on the cost of one collision on arcs in a field, on the SIMD arc engine.
pub const ARC_SIMD_SECONDS_PER_COLLISION: f64 = 20e-9;

/// A floor on the cost of one collision on arcs in a field, on the scalar arc kernel.
pub const ARC_SCALAR_SECONDS_PER_COLLISION: f64 = 80e-9;

/// The floor on the cost of a collision under the thermostatted electric field (measured: about
/// 1.8 µs per collision and thread, `lorentz bench --electric 0.3`).
pub const THERMOSTAT_SECONDS_PER_COLLISION: f64 = 0.5e-6;

/// A floor on the cost of one crossing of a cell edge by a straight flight walked cell by cell
/// between collisions, on the generic convex-cell walk (the square lattice, tables as data).
pub const SECONDS_PER_CROSSING: f64 = 25e-9;

/// A floor on the cost of one crossing of a cell edge by a straight flight walked cell by cell
/// between collisions, on the triangular lattice's walk.
pub const TRIANGULAR_SECONDS_PER_CROSSING: f64 = 12e-9;

/// The floor on one crossing of a cell edge by `scene`'s walk.
pub fn seconds_per_crossing<S: Scene>(scene: &S) -> f64 {
    match scene.walk() {
        Walk::Triangular => TRIANGULAR_SECONDS_PER_CROSSING,
        Walk::Cell => SECONDS_PER_CROSSING,
    }
}

/// A floor on the cost of one crossing of a cell edge by an arc between collisions.
pub const ARC_SECONDS_PER_CROSSING: f64 = 10e-9;

/// A floor on the cost of the classification of one orbit in a field (pinned, skipping or
/// diffusing, `theory::magnetic::FieldGeometry::classify`): a diffusing orbit's circle is found
/// meeting a disk in the first rows scanned, a pinned one scans every row within ρ + r.
pub const SECONDS_PER_CLASSIFICATION: f64 = 20e-9;

/// A floor on the exact pinned share's quadrature in a field, per power
/// [`QUADRATURE_EXPONENT`] of the lattice rows within ρ + r of a height (the kinks of the free
/// length times the rows each evaluation scans), where the annuli about the lattice points leave
/// lines free; 0 elsewhere, where a line's free length is found covered at once.
pub const QUADRATURE_SECONDS_PER_ROW_POWER: f64 = 4e-6;

/// The growth of the exact pinned share's quadrature with the rows (pieces cut at every kink of
/// the free length, `theory::magnetic::shares`: the circle pairs grow as rows², each crossing is
/// tested against the rows, and each evaluation scans the rows): `pinned_fraction()` measured
/// 5.6 ms and 27 ms at 11 and 21 rows (square lattice, r = 1/50, B = 1/5 and 1/10), 0.15 s and
/// 0.50 s at 21 and 41 rows (r = 1/200), and whole runs at r = 10⁻⁴ (thin annuli, most
/// crossings on the boundary) 1.8 s, 15.6 s and 104 s at 41, 81 and 161 rows (B = 1/20, 1/40,
/// 1/80: local slopes 3.1 and 2.7, 2.5·10⁻⁵ to 2.9·10⁻⁵ per rows³). The floor is the least of
/// these per rows³, the r = 1/50 case's 4.2·10⁻⁶; thin annuli cost up to seven times it. Before
/// the cuts (kinks found by bisection) the first three took 3.5 s, 18 to 26 s and over 100 s.
pub const QUADRATURE_EXPONENT: f64 = 3.0;

/// The floor on the classification of `samples` orbits in a field, on one thread.
pub fn classification_seconds(samples: f64) -> f64 {
    samples * SECONDS_PER_CLASSIFICATION
}

/// The floor on the exact pinned share's quadrature over `rows` rows (0 where every line is
/// covered by the annuli: see `theory::magnetic::FieldGeometry::quadrature_rows`), serial.
pub fn quadrature_seconds(rows: f64) -> f64 {
    QUADRATURE_SECONDS_PER_ROW_POWER * rows.powf(QUADRATURE_EXPONENT)
}

/// The cell edges an arc of cyclotron radius `rho` crosses per collision on `scene`, a floor:
/// half of ⟨ℓ⟩/τ ([`crossings_per_collision`]; the localized orbits set aside shorten the
/// diffusing ones' mean free time, Kac's), at most the edges of one turn, 2πρ/τ (an orbit whose
/// circle meets a disk meets it within a turn).
pub fn arc_crossings_per_collision<S: Scene>(scene: &S, rho: f64) -> f64 {
    match scene.crossing_time() {
        Some(tau) => {
            let c = 0.5 * scene.mean_free_path().min(2.0 * std::f64::consts::PI * rho) / tau;
            if c.is_nan() { f64::INFINITY } else { c }
        }
        None => 0.0,
    }
}

/// A floor on the MPFR collisions at `bits` bits that shadowing one collision of a segment
/// costs (the true orbit's Newton iterations and their linear solves): 64 · (bits/1024)^¼, the
/// share of the linear algebra growing with the precision. Measured with
/// `time lorentz shadow --w 0.1 --segments 1 --collisions-per-segment 100 --reference-bits B`
/// (whole process, AMD EPYC, unloaded): 0.07 s at 1024 bits and 1.51 s at 8192, that is 149 and
/// 250 collisions at [`mpfr_seconds_per_collision`], against the floor's 64 and 108.
pub fn shadow_collisions_per_collision(bits: u32) -> f64 {
    64.0 * (f64::from(bits) / 1024.0).max(1.0).powf(0.25)
}

/// The floor on one collision at `bits` bits of MPFR, a + b·(p/1024)^α.
///
/// # Examples
///
/// ```
/// use lorentz_gas::engine::work::mpfr_seconds_per_collision;
/// assert!(mpfr_seconds_per_collision(1 << 20) > 1e-2);
/// assert!(mpfr_seconds_per_collision(64) < 1e-5);
/// ```
pub fn mpfr_seconds_per_collision(bits: u32) -> f64 {
    MPFR_SECONDS + MPFR_SECONDS_AT_1024_BITS * (f64::from(bits) / 1024.0).powf(MPFR_EXPONENT)
}

/// The floor on one collision of the scalar engine at `precision`.
pub fn seconds_per_collision(precision: Precision) -> f64 {
    match precision {
        Precision::F64 => SCALAR_SECONDS_PER_COLLISION,
        Precision::Bits(bits) => mpfr_seconds_per_collision(bits),
    }
}

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
    /// The floor on the cost of a cell edge crossed, in seconds.
    pub per_crossing: f64,
    /// Seconds of set-up on the run's threads before the collisions (a field's classification
    /// of orbits), at the floor costs.
    pub setup: f64,
    /// Seconds of set-up on one thread (a field's exact pinned share), at the floor costs.
    pub serial: f64,
}

impl<'a> Work<'a> {
    /// `collisions` collisions on the scalar engine in `f64`, with no crossings to speak of (the
    /// triangular scene below w∞).
    pub fn new(analysis: &'a str, lower: &'static [&'static str], collisions: f64) -> Self {
        Work {
            analysis,
            lower,
            raise: None,
            collisions,
            crossings: 0.0,
            per_collision: SCALAR_SECONDS_PER_COLLISION,
            per_crossing: SECONDS_PER_CROSSING,
            setup: 0.0,
            serial: 0.0,
        }
    }

    /// The same work, refused with `raise` as the parameter to raise instead.
    pub fn or_raise(self, raise: &'static str) -> Self {
        Work {
            raise: Some(raise),
            ..self
        }
    }

    /// The same work walking `scene`'s cells, ⟨ℓ⟩/τ a collision ([`crossings_per_collision`]),
    /// each at the floor of its walk ([`seconds_per_crossing`]).
    pub fn walking<S: Scene>(self, scene: &S) -> Self {
        Work {
            crossings: crossings_per_collision(scene),
            per_crossing: seconds_per_crossing(scene),
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

    /// The same work at `precision`: MPFR's floor at its bits ([`mpfr_seconds_per_collision`]),
    /// unchanged in `f64`.
    pub fn at(self, precision: Precision) -> Self {
        match precision {
            Precision::F64 => self,
            Precision::Bits(bits) => self.costing(mpfr_seconds_per_collision(bits)),
        }
    }

    /// The same work at the higher of its floor per collision and `seconds` (a collision that
    /// also replays itself, or that is replayed at a reference precision).
    pub fn costing(self, seconds: f64) -> Self {
        Work {
            per_collision: self.per_collision.max(seconds),
            ..self
        }
    }

    /// The same work with a `rate` of its collisions replayed at `bits` bits of MPFR (a
    /// per-event audit).
    pub fn replaying(self, rate: f64, bits: u32) -> Self {
        Work {
            per_collision: self.per_collision + rate.max(0.0) * mpfr_seconds_per_collision(bits),
            ..self
        }
    }

    /// The same work with the audit `audit` of a diffusion run, if any ([`Work::replaying`]).
    pub fn audited(self, audit: Option<crate::engine::options::AuditSpec>) -> Self {
        match audit {
            Some(a) => self.replaying(a.rate, a.bits),
            None => self,
        }
    }

    /// The same work with `seconds` more per collision (a long flight replayed whole).
    pub fn costing_more(self, seconds: f64) -> Self {
        Work {
            per_collision: self.per_collision + seconds.max(0.0),
            ..self
        }
    }

    /// The same work on arcs in a field, on the SIMD arc engine if `simd` (else the scalar arc
    /// kernel), each arc crossing cell edges at [`ARC_SECONDS_PER_CROSSING`].
    pub fn arcs(self, simd: bool) -> Self {
        Work {
            per_collision: if simd {
                ARC_SIMD_SECONDS_PER_COLLISION
            } else {
                ARC_SCALAR_SECONDS_PER_COLLISION
            },
            per_crossing: ARC_SECONDS_PER_CROSSING,
            ..self
        }
    }

    /// The same work on arcs of cyclotron radius `rho` on `scene` ([`Work::arcs`],
    /// [`arc_crossings_per_collision`]) after `(parallel, serial)` seconds of set-up
    /// ([`classification_seconds`], [`quadrature_seconds`]).
    pub fn in_field<S: Scene>(
        self,
        scene: &S,
        rho: f64,
        simd: bool,
        (parallel, serial): (f64, f64),
    ) -> Self {
        let w = self
            .arcs(simd)
            .crossing(arc_crossings_per_collision(scene, rho))
            .after(parallel);
        Work {
            serial: w.serial + serial.max(0.0),
            ..w
        }
    }

    /// The same work after `seconds` of set-up on the run's threads.
    pub fn after(self, seconds: f64) -> Self {
        Work {
            setup: self.setup + seconds.max(0.0),
            ..self
        }
    }

    /// The floor on the cost of one collision, its crossings included, in seconds.
    pub fn seconds_per_collision(&self) -> f64 {
        let crossings = self.crossings.max(0.0);
        let walk = if crossings == 0.0 {
            0.0
        } else {
            crossings * self.per_crossing
        };
        self.per_collision + walk
    }

    /// The floor on the whole run on one thread, in seconds.
    pub fn seconds(&self) -> f64 {
        self.collisions * self.seconds_per_collision() + self.setup + self.serial
    }

    /// The works of `parts` (a sweep's points) as one, for one check before any part starts.
    pub fn sum(
        analysis: &'a str,
        lower: &'static [&'static str],
        parts: impl IntoIterator<Item = Work<'a>>,
    ) -> Self {
        let (mut collisions, mut seconds, mut setup, mut serial) = (0.0, 0.0, 0.0, 0.0);
        for p in parts {
            collisions += p.collisions;
            seconds += p.collisions * p.seconds_per_collision();
            setup += p.setup;
            serial += p.serial;
        }
        Work {
            per_collision: if collisions > 0.0 {
                seconds / collisions
            } else {
                0.0
            },
            setup,
            serial,
            ..Work::new(analysis, lower, collisions)
        }
    }

    /// Refuses the work when even the floor costs make it longer than [`MAX_SECONDS`] on
    /// `threads` threads.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::engine::work::Work;
    /// use lorentz_gas::numbers::precision::Precision;
    /// assert!(Work::new("diffusion", &["collisions"], 1e12).simd().check(2).is_ok());
    /// let e = Work::new("lyapunov", &["collisions_per_batch", "batches"], 3.7e19).check(2).unwrap_err();
    /// assert!(e.to_string().contains("a week"), "{e}");
    /// assert!(e.to_string().ends_with("; lower collisions_per_batch or batches"), "{e}");
    /// let flag = |p: &str| format!("--{}", p.replace('_', "-"));
    /// assert!(e.presented(&flag).ends_with("; lower --collisions-per-batch or --batches"), "{e}");
    /// assert!(Work::new("audit", &["collisions"], 1e6).crossing(f64::INFINITY).check(2).is_err());
    /// let mpfr = Work::new("diffusion", &["collisions", "precision"], 1e12);
    /// assert!(mpfr.at(Precision::Bits(1 << 20)).check(2).is_err());
    /// ```
    ///
    /// # Errors
    /// [`Error::TooMuchWork`] naming the estimate, the floor, the limit and the parameters to
    /// lower.
    pub fn check(&self, threads: usize) -> Result<(), Error> {
        let per = self.seconds_per_collision();
        let parallel = self.collisions * per + self.setup;
        let seconds = parallel / threads.max(1) as f64 + self.serial;
        if seconds <= MAX_SECONDS && !seconds.is_nan() {
            return Ok(());
        }
        let (analysis, collisions, crossings) = (self.analysis, self.collisions, self.crossings);
        let flights = if crossings.is_infinite() {
            ", each flight crossing more cells between collisions than a double can count"
                .to_string()
        } else if crossings > 1e3 {
            format!(", each flight crossing about {crossings:.1e} cells between collisions")
        } else {
            String::new()
        };
        let setup = if self.setup + self.serial >= 1.0 {
            format!(" after {} of set-up", duration(self.setup + self.serial))
        } else {
            String::new()
        };
        Err(Error::TooMuchWork {
            estimate: format!(
                "{analysis} would compute about {collisions:.1e} collisions{flights}{setup}: {} \
                 on {threads} thread{} at {} per collision or more, beyond the limit of a week of \
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
    } else if days < 1.0 {
        format!("{seconds:.0} s")
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
