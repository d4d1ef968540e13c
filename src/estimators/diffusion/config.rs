//! What defines a diffusion run: the fit windows and [`DiffusionConfig`], validated.

use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::execution::Job;
use crate::Error;
use crate::numbers::precision::Precision;
use crate::numbers::real::Real;
use crate::scenes::triangular::geometry::{Geometry, check_diffusive_gap_exact};

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

/// The lags at which the MSD is kept: those of the fit windows only (what D is fitted from), or
/// those and a logarithmic grid from inside the first free flight on, with the velocity
/// autocorrelation and its running Green–Kubo integral ([`crate::observers::msd_curve`]). D has
/// the same bits on either grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MsdGrid {
    /// The lags of the fit windows only.
    #[default]
    Fit,
    /// The fit windows' lags and the logarithmic grid of the MSD curve.
    Log,
}

impl MsdGrid {
    /// True for the default, the fit grid (which a configuration's JSON leaves out).
    pub fn is_fit(&self) -> bool {
        *self == MsdGrid::Fit
    }
}

impl FromStr for MsdGrid {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s {
            "fit" => Ok(MsdGrid::Fit),
            "log" => Ok(MsdGrid::Log),
            _ => Err(Error::parameter(
                "msd_grid",
                format!("{s:?}"),
                "must be fit (the fit windows' lags) or log (also a logarithmic grid from inside \
                 the first flight, with the velocity autocorrelation and its Green-Kubo \
                 integral)",
            )),
        }
    }
}

impl std::fmt::Display for MsdGrid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            MsdGrid::Fit => "fit",
            MsdGrid::Log => "log",
        })
    }
}

/// A batch must cover the end of the later fit window this many times (so that the MSD at the
/// longest lag averages over many independent time origins).
pub const MIN_HOPS_PER_LAG: usize = 20;

/// Everything that defines a diffusion run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DiffusionConfig {
    /// Gap w: the double that `f64` runs use.
    pub w: f64,
    /// The gap exactly as the user gave it (a decimal or a fraction such as `"1/10"`), whose
    /// nearest double is `w`: runs at an MPFR precision start from it, rounded once, so they
    /// never see the double's representation error. `None`: the double `w` is the gap.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub w_exact: Option<String>,
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
    /// pilot recorded), in the same batches. `None`: a plain run of `collisions`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rel_err: Option<f64>,
    /// Where the MSD is kept: the fit windows' lags, or also the logarithmic grid of the MSD
    /// curve ([`MsdGrid`]).
    #[serde(default, skip_serializing_if = "MsdGrid::is_fit")]
    pub msd_grid: MsdGrid,
}

impl DiffusionConfig {
    /// The default run at `w`: 2·10⁹ collisions in 32 batches, windows [10τ, 40τ] and [20τ, 80τ].
    pub fn new(w: f64) -> Self {
        DiffusionConfig {
            w,
            w_exact: None,
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

    /// Checks every parameter; errors name the valid range.
    pub fn validate(&self) -> Result<(), Error> {
        check_diffusive_gap_exact(self.w, self.w_exact.as_deref())?;
        if let Some(r) = self.rel_err {
            super::plan::check_rel_err(r)?;
        }
        check_run(
            self.collisions,
            self.batches,
            self.precision,
            &self.window,
            &self.check_window,
        )?;
        // Each batch must be long enough to reach the far end of the check window many times.
        let g = Geometry::new(self.w)?;
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
                    format!("{:?}", self.w),
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

/// The checks every diffusion run shares, whatever its table: at least one collision and two
/// batches (within the thread pool's and a trajectory's limits), a usable precision, and a check
/// window that is not the fit window.
pub(super) fn check_run(
    collisions: u64,
    batches: u32,
    precision: Precision,
    window: &Window,
    check_window: &Window,
) -> Result<(), Error> {
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
