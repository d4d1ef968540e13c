//! What defines a diffusion run: the fit windows and [`DiffusionConfig`], validated.

use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::execution::Job;
use crate::Error;
use crate::numbers::precision::Precision;
use crate::numbers::real::Real;
use crate::scenes::Scene;
use crate::scenes::spec::{Motion, SceneSpec, Table};
use crate::scenes::triangular::geometry::{Geometry, check_diffusive_gap_exact};

mod grid;
pub use grid::{CURVE_WINDOWS, MsdGrid};

/// A fit window in units of the mean hop time τ.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Window {
    /// Start, in units of τ.
    pub lo: usize,
    /// End, in units of τ.
    pub hi: usize,
}

impl Window {
    /// Seven lags evenly spaced over the window (in units of τ).
    pub fn lags(&self) -> Vec<usize> {
        let mut v: Vec<usize> = (0..7)
            .map(|k| self.lo + ((self.hi - self.lo) * k + 3) / 6)
            .collect();
        v.dedup();
        v
    }
}

impl std::fmt::Display for Window {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}", self.lo, self.hi)
    }
}

impl FromStr for Window {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        let bad = || Error::NotANumber {
            text: s.to_string(),
            why: "is not a fit window: use LO:HI in units of tau, 1 <= LO < HI <= 100000",
        };
        let (a, b) = s.split_once(':').ok_or_else(bad)?;
        let lo: usize = a.trim().parse().map_err(|_| bad())?;
        let hi: usize = b.trim().parse().map_err(|_| bad())?;
        if lo < 1 || hi <= lo || hi > 100_000 {
            return Err(bad());
        }
        Ok(Window { lo, hi })
    }
}

/// A batch must cover the end of the later fit window this many times (so that the MSD at the
/// longest lag averages over many independent time origins).
pub const MIN_HOPS_PER_LAG: usize = 20;

/// Default number of phase points classified, in a field, for the sampled localized share.
pub const DEFAULT_LOCALIZATION_SAMPLES: u64 = 1_000_000;

/// Everything that defines a diffusion run, on any table and motion: the triangular gas without a
/// field (the trap estimator of [`super::run`], with the paper's hierarchy beside D), any other
/// table without a field ([`super::scene`]: the Einstein estimator on any finite-horizon table),
/// or any table in a magnetic field ([`crate::estimators::field`]: the tensor D_xx, D_xy with the
/// localized orbits counted exactly). [`crate::estimators::transport::run`] runs whichever the
/// table asks for.
///
/// The fit windows are in units of the table's time unit (the paper's hop time τ on the
/// triangular gas, the crossing time π|Q|/L elsewhere).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DiffusionConfig {
    /// What is simulated: the geometry, its parameters exactly as typed (runs at an MPFR
    /// precision round them once, never through a double), and the motion. In JSON the
    /// triangular gas without a field is `w` and `w_exact`, any other table `scene` (and `field`).
    #[serde(flatten)]
    pub table: Table,
    /// Total number of collisions over all batches.
    pub collisions: u64,
    /// Number of independent batches (trajectories).
    pub batches: u32,
    /// Seed of the random streams.
    pub seed: u64,
    /// Which run of this seed (0 for a single run; run r of sweep point i is i·runs + r): batch b
    /// uses the trajectory stream `(seed, run, b)` ([`crate::scenes::sampling::StreamKey`]).
    #[serde(default)]
    pub run: u64,
    /// Number type.
    pub precision: Precision,
    /// Fit window for D.
    pub window: Window,
    /// Later window, fitted as a check of the linear regime.
    pub check_window: Window,
    /// Plan the run for this relative error D_err/D ([`super::plan`]): `collisions` is then the
    /// size of a pilot run, and the result the plain run of the size the pilot plans (with the
    /// pilot recorded), in the same batches. `None`: a plain run of `collisions`. The triangular
    /// gas without a field only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rel_err: Option<f64>,
    /// Where the MSD is kept: the fit windows' lags, or also the MSD curve on the logarithmic
    /// grid or on the user's times from 0 ([`MsdGrid`]; without a field).
    #[serde(default, skip_serializing_if = "MsdGrid::is_fit")]
    pub msd_grid: MsdGrid,
    /// In a field: phase points drawn from the invariant measure and classified, for the sampled
    /// share of localized orbits (1 to 10⁹). `None` without a field.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub localization_samples: Option<u64>,
}

impl DiffusionConfig {
    /// The default run at the gap that is exactly the double `w` (see [`Self::on`]).
    pub fn new(w: f64) -> Self {
        Self::on(Table::triangular_at(w))
    }

    /// The default run on `table`: 2·10⁹ collisions in 32 batches, seed 1, windows [10τ, 40τ]
    /// and [20τ, 80τ], in a field 10⁶ classified points.
    pub fn on(table: Table) -> Self {
        DiffusionConfig {
            localization_samples: table.field().map(|_| DEFAULT_LOCALIZATION_SAMPLES),
            table,
            collisions: 2_000_000_000,
            batches: 32,
            seed: 1,
            run: 0,
            precision: Precision::F64,
            window: Window { lo: 10, hi: 40 },
            check_window: Window { lo: 20, hi: 80 },
            rel_err: None,
            msd_grid: MsdGrid::Fit,
        }
    }

    /// The run on `table` as a front end asks for it: `collisions`, or when not given the default
    /// of the run (a pilot's with `rel_err`, which only a run without a field is planned by:
    /// [`super::plan::default_collisions`]); `rel_err` as given (validation refuses it in a
    /// field); `localization_samples` kept in a field only. The rest as [`Self::on`].
    pub fn sized(
        table: Table,
        collisions: Option<u64>,
        rel_err: Option<f64>,
        localization_samples: u64,
    ) -> Self {
        let in_field = table.field().is_some();
        let planned = rel_err.filter(|_| !in_field);
        DiffusionConfig {
            collisions: collisions.unwrap_or_else(|| super::plan::default_collisions(planned)),
            rel_err,
            localization_samples: in_field.then_some(localization_samples),
            ..Self::on(table)
        }
    }

    /// The triangular gap as the nearest double, for the trap estimator.
    ///
    /// # Errors
    /// Another table ([`Error::Lacks`] trap symbols) or a gap that is not a number.
    pub fn gap(&self) -> Result<f64, Error> {
        self.table.gap_for("triangular diffusion")
    }

    /// What the run samples, whatever the table: collisions, batches, seed, precision, windows
    /// and MSD grid (the streams of run 0 of the seed).
    pub fn sampling(&self) -> Sampling {
        Sampling {
            collisions: self.collisions,
            batches: self.batches,
            seed: self.seed,
            run: self.run,
            precision: self.precision,
            window: self.window,
            check_window: self.check_window,
            msd_grid: self.msd_grid.clone(),
        }
    }

    /// Checks every parameter against the table and motion; errors name the valid range.
    ///
    /// # Errors
    /// A bad table or field; an infinite horizon without a field (naming the corridor); what only
    /// the triangular gas without a field has (`rel_err`), or only a run without a field (the
    /// logarithmic MSD grid), asked of another; too few batches or collisions for the windows.
    pub fn validate(&self) -> Result<(), Error> {
        if let Motion::Thermostat { .. } = self.table.motion {
            return self.validate_thermostat();
        }
        if let Some(r) = self.rel_err {
            super::plan::check_rel_err(r)?;
        }
        if self.table.field_value()?.is_some() {
            return self.validate_in_field();
        }
        if self.localization_samples.is_some() {
            return Err(Error::parameter(
                "localization_samples",
                format!("{:?}", self.localization_samples),
                "counts the localized orbits of a magnetic field: give a field, or leave it out",
            ));
        }
        if let SceneSpec::Triangular { .. } = self.table.scene {
            return self.validate_triangular();
        }
        refuse_rel_err(self.rel_err)?;
        self.validate_sampling()
    }

    /// The checks of [`Sampling::validate`] on the table's scene (its horizon among them).
    fn validate_sampling(&self) -> Result<(), Error> {
        let scene = self.table.scene.resolve()?;
        crate::with_scene!(&scene, |s| self.sampling().validate(s))
    }

    /// The checks of a run in a field (a finite horizon on every table).
    fn validate_in_field(&self) -> Result<(), Error> {
        refuse_options_of_no_field(self.rel_err, &self.msd_grid, "a magnetic field")?;
        let n = self.localization_samples.unwrap_or(0);
        if !(1..=1_000_000_000).contains(&n) {
            return Err(Error::out_of_range(
                "localization_samples",
                n,
                "use 1 to 1e9",
            ));
        }
        let scene = self.table.scene.resolve()?;
        crate::with_scene!(&scene, |s| self.sampling().check_statistics(s))
    }

    /// The checks of a run under the thermostatted electric field: its strength and angle, a
    /// finite horizon (along a corridor the field would drive a flight forever), the run's
    /// statistics.
    fn validate_thermostat(&self) -> Result<(), Error> {
        refuse_options_of_no_field(self.rel_err, &self.msd_grid, "the thermostatted field")?;
        if self.localization_samples.is_some() {
            return Err(Error::parameter(
                "localization_samples",
                format!("{:?}", self.localization_samples),
                "counts the localized orbits of a magnetic field: leave it out with --electric",
            ));
        }
        check_electric(&self.table.motion)?;
        self.validate_sampling()
    }

    /// The checks of the trap estimator's run on the triangular gas.
    fn validate_triangular(&self) -> Result<(), Error> {
        check_diffusive_gap_exact(self.gap()?, self.table.gap_text())?;
        self.sampling().check_run()?;
        // Each batch must be long enough to reach the far end of the check window many times.
        let w = self.gap()?;
        let g = Geometry::new(w)?;
        self.msd_grid
            .check_reach(g.mean_free_path(), self.collisions, self.batches)?;
        let need_hops = (MIN_HOPS_PER_LAG * self.window.hi.max(self.check_window.hi)) as f64;
        let min = need_hops * g.collisions_per_hop() * self.batches as f64;
        if (self.collisions as f64) < min {
            return Err(if min < u64::MAX as f64 {
                Error::TooFew {
                    what: "collisions (for this w, window and batch count)",
                    min: min.ceil() as u64,
                    got: self.collisions,
                }
            } else {
                Error::parameter(
                    "w",
                    format!("{w:?}"),
                    format!(
                        "needs about {min:.1e} collisions for {} batches to reach the fit window \
                         (pi/(3w) = {:.1e} collisions per hop), more than any run can do (2^64 = \
                         1.8e19): use a larger w",
                        self.batches,
                        g.collisions_per_hop()
                    ),
                )
            });
        }
        Ok(())
    }

    /// The trajectories of this run: batch i follows the stream (seed, run, i) for its share of
    /// the collisions.
    pub(super) fn jobs(&self) -> impl Iterator<Item = Job> + '_ {
        jobs(self.seed, self.run, self.collisions, self.batches)
    }

    /// The lags (in units of τ) the MSD is accumulated at: those of both fit windows.
    pub fn lags(&self) -> Vec<usize> {
        lags(&self.window, &self.check_window)
    }
}

/// What a diffusion run samples, whatever its table: the part of a [`super::DiffusionConfig`]
/// that [`super::scene::run_on`] takes beside a scene (a table of the crate's, or a [`Scene`] written in Rust
/// outside it), and that a table's result records beside its table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sampling {
    /// Total number of collisions over all batches.
    pub collisions: u64,
    /// Number of independent batches (trajectories), at least 2.
    pub batches: u32,
    /// Seed of the random streams: batch b follows the trajectory stream (seed, run, b).
    pub seed: u64,
    /// Which run of this seed (0, left out of the JSON, for a single run).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub run: u64,
    /// Number type.
    pub precision: Precision,
    /// Fit window for D, in units of the scene's time unit ([`time_unit`]).
    pub window: Window,
    /// Later window, fitted as a check of the linear regime.
    pub check_window: Window,
    /// Where the MSD is kept: the fit windows' lags, or also the logarithmic grid of the MSD
    /// curve ([`MsdGrid`]).
    #[serde(default, skip_serializing_if = "MsdGrid::is_fit")]
    pub msd_grid: MsdGrid,
}

impl Default for Sampling {
    /// The defaults of [`super::DiffusionConfig::new`]: 2·10⁹ collisions in 32 batches, seed 1,
    /// `f64`, windows [10, 40] and [20, 80].
    fn default() -> Self {
        let d = super::DiffusionConfig::new(0.1);
        Self {
            collisions: d.collisions,
            batches: d.batches,
            seed: d.seed,
            run: 0,
            precision: d.precision,
            window: d.window,
            check_window: d.check_window,
            msd_grid: d.msd_grid,
        }
    }
}

/// Whether a run index is 0 (a single run, left out of a record).
fn is_zero(run: &u64) -> bool {
    *run == 0
}

/// The time unit of the MSD grid and the fit windows in `scene`: its crossing time τ, or its
/// mean free time ⟨ℓ⟩ (speed 1) if it supplies no τ.
pub fn time_unit<S: Scene>(scene: &S) -> f64 {
    scene
        .crossing_time()
        .unwrap_or_else(|| scene.mean_free_path())
}

/// A relative-error target on a scene the planner does not run on yet (`rel_err` plans the
/// triangular estimator's runs): the one refusal both front ends present in their terms.
pub fn refuse_rel_err(rel_err: Option<f64>) -> Result<(), Error> {
    match rel_err {
        Some(r) => Err(Error::out_of_range(
            "rel_err",
            r,
            "not on a table given as data yet: give the collisions instead",
        )),
        None => Ok(()),
    }
}

impl Sampling {
    /// Checks every parameter against `scene`; errors name the valid range.
    ///
    /// # Errors
    /// An infinite-horizon scene, too few batches or collisions, a precision out of range, or
    /// equal windows.
    pub fn validate<S: Scene>(&self, scene: &S) -> Result<(), Error> {
        require_finite_horizon(scene)?;
        self.check_statistics(scene)
    }

    /// The checks of [`Self::validate`] but the horizon's: batches, collisions (enough for the
    /// windows at the scene's time unit), precision and windows. A run in a magnetic field, whose
    /// horizon is finite on every scene, takes these.
    ///
    /// # Errors
    /// Too few batches or collisions, a precision out of range, or equal windows.
    pub fn check_statistics<S: Scene>(&self, scene: &S) -> Result<(), Error> {
        self.check_run()?;
        let (unit, mfp) = (time_unit(scene), scene.mean_free_path());
        if !(unit > 0.0 && mfp > 0.0 && unit.is_finite() && mfp.is_finite()) {
            return Err(Error::Failed(format!(
                "{}: its mean free path {mfp} and time unit {unit} must be positive and finite",
                scene.label()
            )));
        }
        self.msd_grid
            .check_reach(mfp, self.collisions, self.batches)?;
        let need = (MIN_HOPS_PER_LAG * self.window.hi.max(self.check_window.hi)) as f64;
        let min = need * unit / mfp * self.batches as f64;
        if (self.collisions as f64) < min {
            return Err(Error::TooFew {
                what: "collisions (for this scene, window and batch count)",
                min: min.ceil().min(u64::MAX as f64) as u64,
                got: self.collisions,
            });
        }
        Ok(())
    }
}

/// Refuses a scene in which the diffusion coefficient does not exist: with an infinite horizon
/// (collision-free corridors) free flights have a distribution with ⟨ℓ²⟩ = ∞, the mean squared
/// displacement grows like t ln t and the Einstein limit ⟨Δr²⟩/4t diverges (Bleher 1992).
///
/// # Errors
/// For an infinite-horizon scene, with the reason.
pub fn require_finite_horizon<S: crate::scenes::Scene>(scene: &S) -> Result<(), Error> {
    if scene.finite_horizon() {
        return Ok(());
    }
    if let Some(corridor) = scene.widest_corridor() {
        return Err(Error::OpenCorridor {
            scene: scene.label(),
            corridor: Box::new(corridor),
        });
    }
    Err(Error::Lacks {
        scene: scene.label(),
        capability: crate::error::Capability::FiniteHorizon,
        analysis: "diffusion",
    })
}

/// Refuses what only a run without a field has: a plan for a relative error, the logarithmic
/// MSD grid.
///
/// # Errors
/// Either of them asked for.
pub fn refuse_options_of_no_field(
    rel_err: Option<f64>,
    grid: &MsdGrid,
    field: &str,
) -> Result<(), Error> {
    if let Some(target) = rel_err {
        return Err(Error::parameter(
            "rel_err",
            target,
            format!(
                "a run in {field} is not planned for a relative error (yet): give its \
                 collisions, or plan them with a run without the field"
            ),
        ));
    }
    if !grid.is_fit() {
        return Err(Error::parameter(
            "msd_grid",
            grid,
            format!(
                "a run in {field} keeps its MSD at the fit windows' lags only (the MSD \
                 curve, velocity autocorrelation and Green-Kubo integral are measured without a \
                 field)"
            ),
        ));
    }
    Ok(())
}

/// The largest strength |E| of the thermostatted field a run takes.
pub const MAX_ELECTRIC: f64 = 10.0;

/// Checks the thermostatted field of `motion`: an exact strength 0 < |E| ≤ 10 (`MAX_ELECTRIC`)
/// (zero is the straight table) and an exact angle in degrees, |angle| ≤ 360.
///
/// # Errors
/// A strength or angle that is not an exact decimal or fraction, or out of range.
pub fn check_electric(motion: &Motion) -> Result<(), Error> {
    let Motion::Thermostat { field, angle } = motion else {
        return Ok(());
    };
    let e = crate::numbers::exact::parse_exact(field).map_err(|e| e.named("electric"))?;
    let a = crate::numbers::exact::parse_exact(angle).map_err(|e| e.named("electric_angle"))?;
    let strength = crate::numbers::exact::nearest_f64(&e).abs();
    if !(strength > 0.0 && strength <= MAX_ELECTRIC) {
        return Err(Error::parameter(
            "electric",
            field,
            format!("use 0 < |E| <= {MAX_ELECTRIC} (0 is the table without the field)"),
        ));
    }
    if crate::numbers::exact::nearest_f64(&a).abs() > 360.0 {
        return Err(Error::parameter(
            "electric_angle",
            angle,
            "use an angle in degrees from -360 to 360",
        ));
    }
    Ok(())
}

impl Sampling {
    /// The checks every diffusion run shares, whatever its table: at least one collision and two
    /// batches (within the thread pool's and a trajectory's limits), a usable precision, and a
    /// check window that is not the fit window.
    fn check_run(&self) -> Result<(), Error> {
        let Sampling {
            collisions,
            batches,
            precision,
            ref window,
            ref check_window,
            ..
        } = *self;
        if collisions == 0 {
            return Err(Error::Zero { what: "collisions" });
        }
        if batches == 0 {
            return Err(Error::Zero { what: "batches" });
        }
        if batches < 2 {
            return Err(Error::TooFew {
                what: "batches",
                min: 2,
                got: batches as u64,
            });
        }
        crate::engine::parallel::check_batches("batches", batches)?;
        crate::engine::check_trajectory_length(
            collisions.div_ceil(batches as u64),
            "batches",
            batches,
        )?;
        if let Precision::Bits(b) = precision {
            <rug::Float as Real>::check_ctx(b)?;
        }
        if check_window == window {
            return Err(Error::parameter(
                "check_window",
                window,
                format!(
                    "this is the fit window {}:{}: the check needs another window, such as a later \
                 one ({}:{})",
                    window.lo,
                    window.hi,
                    2 * window.lo,
                    2 * window.hi
                ),
            ));
        }
        Ok(())
    }
}

/// Batch i of a run follows the stream (seed, run, i) for its share of the collisions.
pub(super) fn jobs(
    seed: u64,
    run: u64,
    collisions: u64,
    batches: u32,
) -> impl Iterator<Item = Job> {
    (0..batches).map(move |i| Job {
        seed,
        run,
        index: i,
        collisions: crate::engine::parallel::share(collisions, batches, i),
    })
}

/// The lags (in time units) of both fit windows, sorted, each once.
pub(super) fn lags(window: &Window, check_window: &Window) -> Vec<usize> {
    let mut l = window.lags();
    l.extend(check_window.lags());
    l.sort_unstable();
    l.dedup();
    l
}

/// The time grid that samples the lags `lags` (in units of τ) of a run whose samples are every
/// time origin: spacing g·τ, g the lags' greatest common divisor, and each lag in grid steps.
pub fn lag_grid(tau: f64, lags: &[usize]) -> (f64, Vec<usize>) {
    fn gcd(a: usize, b: usize) -> usize {
        if b == 0 { a } else { gcd(b, a % b) }
    }
    let g = lags.iter().fold(0, |a, &b| gcd(a, b)).max(1);
    (g as f64 * tau, lags.iter().map(|l| l / g).collect())
}
