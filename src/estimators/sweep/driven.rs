//! The driven gas over a grid of gaps and fields E: the current, the mobility J/E, the Lyapunov
//! pair and the rest of the steady state ([`crate::estimators::current`]) at every point, each a
//! run of its own on its own streams (point i is run i of the seed), so that points are
//! independent and each error bar is its own batches'.
//!
//! Per gap, the analysis asks what Bonetto, Daems & Lebowitz asked of J(E)/E: is it smooth? The
//! χ² of weighted polynomials in |E| of degree 1 … 7 through the mobilities says whether a
//! low-degree polynomial absorbs them within their errors (structure that none absorbs is not
//! curvature). The Einstein relation's limit J/E → D as E → 0 is extrapolated two ways, as
//! D + a|E| and as D + cE² (`proofs-notes/thermostat-current.md`: the derivation promises only
//! J = DE + o(E)). Where the grid holds E and −E at a gap, J(−E) = −J(E) is checked: the
//! mobilities, each along its own field, must agree (Welch, Bonferroni over the comparisons).
//!
//! Resumption: the points are sealed into `DIR/driven-points/` as they finish
//! ([`super::point_grid`]).

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::point_grid::{self, GridPoint, PointGrid};
use super::{Grid, PolynomialChi2, SweepConfig, analysis::polynomial_chi2};
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::work::Work;
use crate::estimators::current::{self, Steady};
use crate::estimators::diffusion::DiffusionConfig;
use crate::numbers::exact::{nearest_f64, parse_exact};
use crate::scenes::spec::{Motion, SceneSpec, Table};
use crate::statistics::comparison::Comparison;
use crate::statistics::fits::{LineFit, weighted_line_fit};

/// Most points of a driven sweep (each is a run of its own).
pub const MAX_DRIVEN_SWEEP_POINTS: usize = 1_000;

/// The grid of a sweep of the driven gas: the triangular gas at each gap × the fields, all along
/// one direction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DrivenGrid {
    /// The gaps, each an exact decimal or fraction as given.
    pub gaps: Vec<String>,
    /// The fields' signed strengths E, each an exact decimal or fraction as given, 0 < |E| ≤ 10
    /// (−E is the field turned by 180°).
    pub electric: Vec<String>,
    /// The fields' angle from the x axis in degrees, as given.
    pub electric_angle: String,
}

/// One point of a driven sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct DrivenSweepRow {
    /// The gap.
    pub w: f64,
    /// The field's signed strength E as given (nearest double): the row's `mobility` is
    /// J_parallel/|E|, along the field's own direction.
    pub electric: f64,
    /// The field's angle from the x axis in degrees (nearest double).
    pub electric_angle: f64,
    /// The steady state (flattened: J_x … mean_free_time).
    #[serde(flatten)]
    pub steady: Steady,
    /// Per-batch J_parallel (so that the point can be re-checked).
    pub batch_J_parallel: Vec<f64>,
}

/// The mobility's analysis at one gap.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MobilityAnalysis {
    /// The gap.
    pub w: f64,
    /// Points at this gap.
    pub points: usize,
    /// χ² of weighted polynomials of J/E in |E| of degree 1 … 7 (as far as the points allow).
    pub polynomial_chi2: Vec<PolynomialChi2>,
    /// J/E = D + a|E| weighted (the intercept is the Einstein relation's D), with 3 points or more.
    pub einstein_linear: Option<LineFit>,
    /// J/E = D + cE² weighted, with 3 points or more.
    pub einstein_quadratic: Option<LineFit>,
}

/// J(−E) = −J(E) at one gap and one |E|: the mobilities along ±E, each along its own field.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OddCheck {
    /// The gap.
    pub w: f64,
    /// |E|.
    pub electric: f64,
    /// mobility(E) − mobility(−E), expected 0.
    pub mobility_even: Comparison,
}

/// The finished driven sweep.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct DrivenSweepReport {
    /// One row per point, in grid order (gap-major).
    pub rows: Vec<DrivenSweepRow>,
    /// The mobility's analysis per gap.
    pub mobility: Vec<MobilityAnalysis>,
    /// J(−E) = −J(E) wherever the grid holds ±E at a gap.
    pub odd: Vec<OddCheck>,
    /// Every such comparison within its bound (true when there is none).
    pub odd_agrees: bool,
    /// Points reused from an earlier run of the same sweep.
    pub resumed_points: u32,
    /// The configuration.
    pub config: SweepConfig,
    /// Provenance.
    pub meta: RunMeta,
}

/// One finished point on disk.
pub type DrivenSweepPoint = GridPoint<DrivenSweepRow>;

impl DrivenGrid {
    /// The number of points: gaps × fields.
    pub fn points(&self) -> usize {
        self.gaps.len() * self.electric.len()
    }

    /// Point `i`'s gap and field, as given (gap-major).
    fn at(&self, i: usize) -> (&str, &str) {
        let f = self.electric.len().max(1);
        (&self.gaps[i / f], &self.electric[i % f])
    }

    /// Checks every parameter of `sweep`, whose grid this is (every point's run), before
    /// anything runs or is written.
    ///
    /// # Errors
    /// An empty or oversized grid, a point repeated, or a point's invalid run (naming the range).
    pub fn validate(&self, sweep: &SweepConfig) -> Result<(), Error> {
        if self.gaps.is_empty() {
            return Err(Error::missing("gaps", "a driven sweep needs a gap w"));
        }
        if self.electric.is_empty() {
            return Err(Error::missing(
                "electric",
                "a driven sweep needs at least one field E",
            ));
        }
        let n = self.points();
        if n > MAX_DRIVEN_SWEEP_POINTS {
            return Err(Error::out_of_range(
                "points",
                n,
                format!("use 1 to {MAX_DRIVEN_SWEEP_POINTS} (gaps x fields)"),
            ));
        }
        let mut seen = Vec::with_capacity(n);
        for i in 0..n {
            self.point(sweep, i)?.validate()?;
            let (w, e) = self.at(i);
            let key = (parse_exact(w)?, parse_exact(e)?);
            if seen.contains(&key) {
                return Err(Error::parameter(
                    "electric",
                    self.electric.join(","),
                    format!(
                        "w = {w}, E = {e} appears twice in the grid: give each gap and field once"
                    ),
                ));
            }
            seen.push(key);
        }
        Ok(())
    }
}

impl PointGrid for DrivenGrid {
    type Row = DrivenSweepRow;
    const FOLDER: &'static str = "driven-points";
    const WHAT: &'static str = "driven sweep point";
    const SWEEP: &'static str = "a driven sweep";
    const LOWER: &'static [&'static str] = &["collisions_per_run", "electric"];

    fn of(cfg: &SweepConfig) -> Result<&Self, Error> {
        match &cfg.grid {
            Grid::Driven(g) => Ok(g),
            _ => Err(Error::missing(
                "electric",
                "a driven sweep needs its fields E",
            )),
        }
    }

    fn points(&self) -> usize {
        Self::points(self)
    }

    fn point(&self, sweep: &SweepConfig, i: usize) -> Result<DiffusionConfig, Error> {
        let (w, e) = self.at(i);
        // A field of 0 stays the thermostat here, for validation to refuse.
        let table = Table {
            scene: SceneSpec::parse("triangular", Some(w), None)?,
            motion: Motion::Thermostat {
                field: e.trim().to_string(),
                angle: self.electric_angle.trim().to_string(),
            },
        };
        Ok(DiffusionConfig {
            run: i as u64,
            collisions: sweep.collisions,
            batches: sweep.batches,
            seed: sweep.seed,
            ..DiffusionConfig::on(table)
        })
    }

    fn label(&self, i: usize) -> String {
        let (w, e) = self.at(i);
        format!("w = {w}, E = {e}")
    }

    fn row(point: &DiffusionConfig, opts: &RunOptions) -> Result<DrivenSweepRow, Error> {
        let r = current::run(point, opts)?;
        let Motion::Thermostat { field, angle } = &point.table.motion else {
            return Err(Error::missing(
                "electric",
                "a driven sweep's point has a field",
            ));
        };
        Ok(DrivenSweepRow {
            w: point.table.gap_for("a driven sweep")?,
            electric: nearest_f64(&parse_exact(field)?),
            electric_angle: nearest_f64(&parse_exact(angle)?),
            steady: r.steady,
            batch_J_parallel: r.batch_J_parallel,
        })
    }

    fn work(point: &DiffusionConfig, _simd: bool) -> Result<Work<'static>, Error> {
        Ok(current::work(point))
    }
}

/// Runs the sweep (see the module documentation).
///
/// # Errors
/// An invalid configuration or options (before any work or file), a directory holding another
/// sweep's points or an edited one, an I/O error, or an interruption.
pub fn run(cfg: &SweepConfig, opts: &RunOptions) -> Result<DrivenSweepReport, Error> {
    let (rows, resumed) = point_grid::run_points::<DrivenGrid>(cfg, opts, &|_| true)?;
    report(cfg, rows.into_iter().flatten().collect(), resumed, opts)
}

/// The report of the sweep `cfg` from every point's row (in grid order), `resumed` of them
/// reused.
///
/// # Errors
/// A fit that cannot be made (errors that are not positive).
pub(crate) fn report(
    cfg: &SweepConfig,
    rows: Vec<DrivenSweepRow>,
    resumed: u32,
    opts: &RunOptions,
) -> Result<DrivenSweepReport, Error> {
    let mut gaps: Vec<f64> = rows.iter().map(|r| r.w).collect();
    gaps.dedup();
    let mobility = (gaps.iter())
        .map(|&w| analyse_gap(w, &rows))
        .collect::<Result<Vec<_>, Error>>()?;
    let odd = odd(&rows, cfg.batches);
    Ok(DrivenSweepReport {
        odd_agrees: odd.iter().all(|c| c.mobility_even.agrees()),
        odd,
        mobility,
        rows,
        resumed_points: resumed,
        config: cfg.clone(),
        meta: RunMeta::new(
            Some(cfg.seed),
            Some(u64::from(cfg.batches)),
            crate::numbers::precision::Precision::F64,
            Some(opts.threads),
        )
        .with_engine(crate::engine::Resolved::Scalar),
    })
}

/// The mobility's polynomial χ² and Einstein extrapolations at the gap `w`.
fn analyse_gap(w: f64, rows: &[DrivenSweepRow]) -> Result<MobilityAnalysis, Error> {
    let at: Vec<&DrivenSweepRow> = rows.iter().filter(|r| r.w == w).collect();
    let col = |f: &dyn Fn(&DrivenSweepRow) -> f64| at.iter().map(|r| f(r)).collect::<Vec<f64>>();
    let (e, mu, err) = (
        col(&|r| r.electric.abs()),
        col(&|r| r.steady.mobility),
        col(&|r| r.steady.mobility_err),
    );
    let line = |x: &[f64]| -> Result<Option<LineFit>, Error> {
        if x.len() < 3 {
            return Ok(None);
        }
        weighted_line_fit(x, &mu, &err).map(Some)
    };
    Ok(MobilityAnalysis {
        w,
        points: at.len(),
        polynomial_chi2: polynomial_chi2(&e, &mu, &err)?,
        einstein_linear: line(&e)?,
        einstein_quadratic: line(&e.iter().map(|x| x * x).collect::<Vec<_>>())?,
    })
}

/// J(−E) = −J(E) for every gap and |E| with both signs in the grid ([`Comparison::welch`]).
fn odd(rows: &[DrivenSweepRow], batches: u32) -> Vec<OddCheck> {
    let pairs: Vec<(&DrivenSweepRow, &DrivenSweepRow)> = (rows.iter())
        .filter(|p| p.electric > 0.0)
        .filter_map(|p| {
            let m = rows
                .iter()
                .find(|m| m.w == p.w && m.electric == -p.electric)?;
            Some((p, m))
        })
        .collect();
    let m = pairs.len();
    (pairs.into_iter())
        .map(|(p, q)| OddCheck {
            w: p.w,
            electric: p.electric,
            mobility_even: Comparison::welch(
                p.steady.mobility - q.steady.mobility,
                (p.steady.mobility_err, q.steady.mobility_err),
                batches,
                m,
            ),
        })
        .collect()
}

/// The files [`write_tables`] writes.
pub const TABLE_FILES: [&str; 2] = ["driven-sweep.csv", "driven-sweep.json"];

/// Writes `driven-sweep.csv` (one line per point) and `driven-sweep.json` (the whole report)
/// into `dir`.
///
/// # Errors
/// An I/O error naming the path.
pub fn write_tables(r: &DrivenSweepReport, dir: &Path) -> Result<(), Error> {
    let mut csv = String::from(
        "w,electric,electric_angle,J_parallel,J_parallel_err,J_perp,J_perp_err,mobility,\
         mobility_err,lambda_plus,lambda_plus_err,lambda_minus,lambda_minus_err,sum_rule,\
         sum_rule_err,kaplan_yorke,kaplan_yorke_err,mean_free_time,mean_free_time_err\n",
    );
    for x in &r.rows {
        let s = &x.steady;
        let cols = [
            x.w,
            x.electric,
            x.electric_angle,
            s.J_parallel,
            s.J_parallel_err,
            s.J_perp,
            s.J_perp_err,
            s.mobility,
            s.mobility_err,
            s.lambda_plus,
            s.lambda_plus_err,
            s.lambda_minus,
            s.lambda_minus_err,
            s.sum_rule,
            s.sum_rule_err,
            s.kaplan_yorke,
            s.kaplan_yorke_err,
            s.mean_free_time,
            s.mean_free_time_err,
        ];
        let line: Vec<String> = cols.iter().map(|c| c.to_string()).collect();
        csv.push_str(&line.join(","));
        csv.push('\n');
    }
    crate::files::write(dir.join("driven-sweep.csv"), csv)?;
    crate::files::write(
        dir.join("driven-sweep.json"),
        serde_json::to_string_pretty(r).map_err(Error::encode)?,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(e: f64, mobility: f64) -> DrivenSweepRow {
        row_err(e, mobility, 1e-3)
    }

    fn row_err(e: f64, mobility: f64, err: f64) -> DrivenSweepRow {
        DrivenSweepRow {
            w: 0.2,
            electric: e,
            electric_angle: 0.0,
            steady: Steady {
                mobility,
                mobility_err: err,
                ..Steady::default()
            },
            batch_J_parallel: Vec::new(),
        }
    }

    #[test]
    fn the_einstein_fits_recover_the_intercept_of_their_own_form() {
        let es = [0.05, 0.1, 0.2, -0.2, 0.3];
        let linear: Vec<_> = (es.iter())
            .map(|&e| row_err(e, 0.17 - 0.05 * e.abs(), 1e-4))
            .collect();
        let m = analyse_gap(0.2, &linear).unwrap();
        let fit = m.einstein_linear.unwrap();
        assert!(
            (fit.intercept - 0.17).abs() < 1e-12 && fit.chi2 < 1e-18,
            "{fit:?}"
        );
        // The E² form does not absorb a |E| term: its χ² (3 dof) is beyond χ²₃'s 0.999 quantile.
        assert!(m.einstein_quadratic.unwrap().chi2 > 16.27, "{m:?}");
        // Four distinct |E|: polynomials of degree 1 and 2 only.
        assert_eq!(m.polynomial_chi2.len(), 2);
        let quadratic: Vec<_> = es.iter().map(|&e| row(e, 0.17 - 0.1 * e * e)).collect();
        let fit = analyse_gap(0.2, &quadratic)
            .unwrap()
            .einstein_quadratic
            .unwrap();
        assert!((fit.intercept - 0.17).abs() < 1e-12, "{fit:?}");
    }

    #[test]
    fn plus_and_minus_e_are_compared_once_and_a_difference_of_ten_sigma_fails() {
        let rows = [row(0.3, 0.158), row(-0.3, 0.158), row(0.1, 0.16)];
        let same = odd(&rows, 16);
        assert_eq!(same.len(), 1);
        assert!(same[0].mobility_even.agrees());
        let apart = odd(&[row(0.3, 0.158), row(-0.3, 0.158 + 0.0141)], 16);
        assert!(!apart[0].mobility_even.agrees(), "{apart:?}");
    }
}
