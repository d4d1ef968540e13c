//! The diffusion tensor over a grid of gaps and fields: a sweep over B at a fixed gap, over w at a
//! fixed field, or both. Every point is one transport run in a field ([`super::run`]) on its own
//! streams (point i is run i of the seed), so points are independent and each error bar is its
//! own batches'. Where the grid holds B and −B at the same gap, Onsager–Casimir is checked:
//! D_xx(B) − D_xx(−B) and D_xy(B) + D_xy(−B) against 0 with the Welch error of two independent
//! estimates, at the crate's agreement level corrected for the number of comparisons (Bonferroni,
//! [`largest_of_bound`]).
//!
//! Resumption: with `options.resume` (a directory) each finished point is sealed into
//! `DIR/field-points/point-NNNN.json` as it finishes and reused (its configuration and digest
//! checked) when the sweep runs again, so an interrupted sweep loses at most the point in
//! progress.

use std::path::{Path, PathBuf};

use rug::{Integer, Rational};
use serde::{Deserialize, Serialize};

use super::{FieldConfig, FieldReport};
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::resume::{difference, seal, unseal};
use crate::numbers::exact::parse_exact;
use crate::scenes::spec::SceneSpec;
use crate::statistics::comparison::{self, Comparison, largest_of_bound};
use crate::statistics::welch_dof;

/// Most points of a field sweep (each is a transport run of its own).
pub const MAX_FIELD_SWEEP_POINTS: usize = 1_000;

/// What defines a sweep of the diffusion tensor over gaps and fields.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FieldSweepConfig {
    /// The gaps, each an exact decimal or fraction as given (one gap: a sweep over B).
    pub gaps: Vec<String>,
    /// The fields, each an exact decimal or fraction as given, nonzero, 10⁻³ ≤ |B| ≤ 10³ (one
    /// field: a sweep over w).
    pub fields: Vec<String>,
    /// Collisions of each point (one run), over its batches (serialized as
    /// `collisions_per_run`, the command line's name).
    #[serde(rename = "collisions_per_run")]
    pub collisions: u64,
    /// Independent batches of each point (≥ 2): a point's error is the standard error over them
    /// (serialized as `batches_per_run`).
    #[serde(rename = "batches_per_run")]
    pub batches: u32,
    /// Seed: point i uses the streams of run i of this seed.
    pub seed: u64,
    /// Phase points classified per point for the sampled localized share.
    pub localization_samples: u64,
}

/// The grid of a field sweep as the command line and Python give it: one gap `w` (a sweep over
/// the field) or the exact grid `w_from` … `w_to` in `steps` points (a sweep over w); one `field`
/// or a list `fields`. Returns (gaps, fields) as exact texts.
///
/// # Errors
/// Neither or both of `w` and the range, neither or both of `field` and `fields`, or an end of
/// the range that is not exact.
pub fn grid_of(
    w: Option<&str>,
    range: (Option<&str>, Option<&str>, u32),
    field: Option<&str>,
    fields: &[String],
) -> Result<(Vec<String>, Vec<String>), Error> {
    let gaps = match (w, range) {
        (Some(w), (None, None, _)) => vec![w.trim().to_string()],
        (None, (Some(from), Some(to), steps)) => exact_grid(from, to, steps)?,
        _ => {
            return Err(Error::Invalid(
                "a sweep in a field needs either w (a sweep over the field) or w_from and w_to \
                 (a sweep over w), not both"
                    .into(),
            ));
        }
    };
    let fields = match (field, fields.is_empty()) {
        (Some(b), true) => vec![b.trim().to_string()],
        (None, false) => fields.iter().map(|b| b.trim().to_string()).collect(),
        _ => {
            return Err(Error::Invalid(
                "give either field (a sweep over w) or fields (a sweep over the field), not both"
                    .into(),
            ));
        }
    };
    Ok((gaps, fields))
}

impl FieldSweepConfig {
    /// The points in order, gap-major: point i = (gap i / F, field i mod F) for F fields.
    pub fn grid(&self) -> Vec<(&str, &str)> {
        self.gaps
            .iter()
            .flat_map(|g| self.fields.iter().map(move |f| (g.as_str(), f.as_str())))
            .collect()
    }

    /// The transport run of point `i` at gap `gap` and field `field`.
    ///
    /// # Errors
    /// A gap that is not an exact decimal or fraction.
    pub fn point_config(&self, i: usize, gap: &str, field: &str) -> Result<FieldConfig, Error> {
        let scene = SceneSpec::parse("triangular", Some(gap), None)?;
        let mut cfg = FieldConfig {
            run: i as u64,
            localization_samples: self.localization_samples,
            ..FieldConfig::new(scene, field)
        };
        let s = &mut cfg.statistics;
        (s.collisions, s.batches, s.seed) = (self.collisions, self.batches, self.seed);
        Ok(cfg)
    }

    /// Checks every parameter (every point's run) before anything runs or is written.
    ///
    /// # Errors
    /// An empty or oversized grid, a point repeated, or a point's invalid run (naming the range).
    pub fn validate(&self) -> Result<(), Error> {
        if self.gaps.is_empty() || self.fields.is_empty() {
            return Err(Error::Invalid(
                "a field sweep needs at least one gap and one field".into(),
            ));
        }
        let n = self.gaps.len() * self.fields.len();
        if n > MAX_FIELD_SWEEP_POINTS {
            return Err(Error::out_of_range(
                "points",
                n,
                format!("use 1 to {MAX_FIELD_SWEEP_POINTS} (gaps x fields)"),
            ));
        }
        let mut seen = Vec::with_capacity(n);
        for (i, (g, f)) in self.grid().into_iter().enumerate() {
            let c = self.point_config(i, g, f)?;
            c.validate()?;
            let w = c.scene_parameters()?.0.unwrap_or(f64::NAN);
            let key = (w.to_bits(), c.field_value()?.to_bits());
            if seen.contains(&key) {
                return Err(Error::Invalid(format!(
                    "w = {g}, B = {f} appears twice in the grid: give each gap and field once"
                )));
            }
            seen.push(key);
        }
        Ok(())
    }
}

/// One point of the sweep.
#[allow(non_snake_case)]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FieldSweepRow {
    /// Gap.
    pub w: f64,
    /// Field B.
    pub field: f64,
    /// Cyclotron radius 1/|B|.
    pub cyclotron_radius: f64,
    /// D_xx over the whole phase space.
    pub D_xx: f64,
    /// Its standard error over the point's batches.
    pub D_xx_err: f64,
    /// The Hall part D_xy over the whole phase space.
    pub D_xy: f64,
    /// Its standard error.
    pub D_xy_err: f64,
    /// Exact share of phase space in pinned orbits.
    pub pinned_fraction_exact: f64,
    /// Exact share in skipping orbits.
    pub skipping_fraction_exact: f64,
    /// Exact localized share.
    pub localized_fraction_exact: f64,
    /// Sampled localized share.
    pub localized_fraction: f64,
    /// Its binomial standard error.
    pub localized_fraction_err: f64,
    /// Every orbit is localized: D = 0 exactly.
    pub all_localized: bool,
    /// Mean free time of the diffusing part, measured.
    pub mean_free_time: f64,
    /// Its standard error.
    pub mean_free_time_err: f64,
    /// Kac's closed form for it.
    pub mean_free_time_exact: f64,
}

/// Onsager–Casimir at one gap and one |B|.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OnsagerCheck {
    /// Gap.
    pub w: f64,
    /// |B|.
    pub field: f64,
    /// D_xx(B) − D_xx(−B), expected 0.
    pub d_xx_even: Comparison,
    /// D_xy(B) + D_xy(−B), expected 0.
    pub d_xy_odd: Comparison,
}

/// The finished sweep.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FieldSweepReport {
    /// One row per point, in grid order.
    pub rows: Vec<FieldSweepRow>,
    /// Onsager–Casimir wherever the grid holds ±B at a gap; each bound is the Bonferroni bound
    /// over all of them.
    pub onsager: Vec<OnsagerCheck>,
    /// Every Onsager–Casimir comparison within its bound (true when there is none).
    pub onsager_agrees: bool,
    /// Points reused from an earlier run of the same sweep.
    pub resumed_points: u32,
    /// The configuration.
    pub config: FieldSweepConfig,
    /// Provenance.
    pub meta: RunMeta,
}

/// One finished point on disk (the unit of resumption).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FieldSweepPoint {
    /// The sweep it belongs to.
    pub config: FieldSweepConfig,
    /// Its index in the grid.
    pub index: u32,
    /// Its row.
    pub row: FieldSweepRow,
}

/// Runs the sweep (see the module documentation).
///
/// # Errors
/// An invalid configuration or options (before any work or file), a directory holding another
/// sweep's points or an edited one, an I/O error, or an interruption.
pub fn run(cfg: &FieldSweepConfig, opts: &RunOptions) -> Result<FieldSweepReport, Error> {
    cfg.validate()?;
    opts.validate()?;
    let dir = opts.resume.as_deref();
    // The points' runs take no checkpoint of their own: the point is the unit of resumption.
    let point_opts = RunOptions {
        resume: None,
        ..opts.clone()
    };
    point_opts.refuse_unused("a field sweep", &[])?;
    if let Some(d) = dir {
        crate::files::create_dir_all(d)?;
        crate::files::create_subdir(d.join("field-points"))?;
    }
    let grid = cfg.grid();
    // Every point already on disk is checked before any work.
    let mut found = Vec::with_capacity(grid.len());
    for i in 0..grid.len() {
        found.push(match dir {
            Some(d) => reuse(cfg, &point_path(d, i), i)?,
            None => None,
        });
    }
    let mut rows = Vec::with_capacity(grid.len());
    let mut resumed = 0;
    for (i, ((g, f), old)) in grid.into_iter().zip(found).enumerate() {
        let row = match old {
            Some(row) => {
                (opts.progress)(cfg.collisions);
                resumed += 1;
                row
            }
            None => {
                let row = row_of(&super::run(&cfg.point_config(i, g, f)?, &point_opts)?);
                if let Some(d) = dir {
                    let p = FieldSweepPoint {
                        config: cfg.clone(),
                        index: i as u32,
                        row: row.clone(),
                    };
                    crate::files::write(point_path(d, i), seal(&p)?.as_bytes())?;
                }
                row
            }
        };
        rows.push(row);
    }
    let onsager = onsager(&rows, cfg.batches);
    Ok(FieldSweepReport {
        onsager_agrees: onsager
            .iter()
            .all(|c| c.d_xx_even.agrees() && c.d_xy_odd.agrees()),
        onsager,
        rows,
        resumed_points: resumed,
        config: cfg.clone(),
        meta: RunMeta::new(
            Some(cfg.seed),
            Some(cfg.batches as u64),
            crate::numbers::precision::Precision::F64,
            Some(opts.threads),
        ),
    })
}

/// The row of a point's report.
fn row_of(r: &FieldReport) -> FieldSweepRow {
    FieldSweepRow {
        w: r.w.unwrap_or(f64::NAN),
        field: r.field,
        cyclotron_radius: r.cyclotron_radius,
        D_xx: r.D_xx,
        D_xx_err: r.D_xx_err,
        D_xy: r.D_xy,
        D_xy_err: r.D_xy_err,
        pinned_fraction_exact: r.pinned_fraction_exact,
        skipping_fraction_exact: r.skipping_fraction_exact,
        localized_fraction_exact: r.localized_fraction_exact,
        localized_fraction: r.localized_fraction,
        localized_fraction_err: r.localized_fraction_err,
        all_localized: r.all_localized,
        mean_free_time: r.mean_free_time,
        mean_free_time_err: r.mean_free_time_err,
        mean_free_time_exact: r.mean_free_time_exact,
    }
}

/// Onsager–Casimir for every gap and |B| with both signs in the grid. Points are independent, so
/// a sum or difference has the quadrature error with Welch's degrees of freedom; every bound is
/// the Bonferroni bound over the 2m comparisons. Where every orbit is localized both are 0 exactly.
pub fn onsager(rows: &[FieldSweepRow], batches: u32) -> Vec<OnsagerCheck> {
    let pairs: Vec<(&FieldSweepRow, &FieldSweepRow)> = rows
        .iter()
        .filter(|p| p.field > 0.0)
        .filter_map(|p| {
            rows.iter()
                .find(|m| m.w == p.w && m.field == -p.field)
                .map(|m| (p, m))
        })
        .collect();
    let m = 2 * pairs.len();
    let n = batches as f64;
    let compare = |x: f64, ea: f64, eb: f64| {
        let err = ea.hypot(eb);
        if err == 0.0 {
            // Both exactly 0 (every orbit localized): no statistics, the difference itself.
            return comparison::of(x, 0.0, f64::INFINITY);
        }
        let dof = welch_dof(ea, n, eb, n);
        Comparison {
            bound: largest_of_bound(dof, m),
            ..comparison::of(x, err, dof)
        }
    };
    pairs
        .into_iter()
        .map(|(p, q)| OnsagerCheck {
            w: p.w,
            field: p.field,
            d_xx_even: compare(p.D_xx - q.D_xx, p.D_xx_err, q.D_xx_err),
            d_xy_odd: compare(p.D_xy + q.D_xy, p.D_xy_err, q.D_xy_err),
        })
        .collect()
}

/// The file of point `i` in the sweep directory `dir`.
pub fn point_path(dir: &Path, i: usize) -> PathBuf {
    dir.join("field-points").join(format!("point-{i:04}.json"))
}

/// Most bytes a point file may have (a configuration and one row).
const MAX_POINT_BYTES: u64 = 1 << 20;

/// The finished row of point `i` at `path`, if there is one of this sweep; a file of another
/// sweep, an edited, renamed or oversized one is an error naming the path.
fn reuse(cfg: &FieldSweepConfig, path: &Path, i: usize) -> Result<Option<FieldSweepRow>, Error> {
    if !path.exists() {
        return Ok(None);
    }
    let text = crate::files::read_to_string_limited(path, MAX_POINT_BYTES)?;
    let p: FieldSweepPoint = unseal(path, &text, "field sweep point")?;
    if p.config != *cfg {
        return Err(Error::Invalid(format!(
            "{} belongs to another sweep ({}): use another directory",
            path.display(),
            difference(&p.config, cfg).unwrap_or_else(|| "another configuration".into())
        )));
    }
    if p.index as usize != i {
        return Err(Error::Invalid(format!(
            "{} holds point {}: a renamed or copied point file (point i lives in point-iiii.json)",
            path.display(),
            p.index
        )));
    }
    Ok(Some(p.row))
}

/// The exact points `from + (to − from)·k/(steps − 1)`, k = 0 … steps − 1, as exact texts: a
/// terminating decimal where there is one, else a fraction `p/q` (both parse back to the same
/// rational).
///
/// # Examples
///
/// ```
/// use lorentz_gas::estimators::field::sweep::exact_grid;
/// assert_eq!(exact_grid("0.1", "0.2", 3).unwrap(), ["0.1", "0.15", "0.2"]);
/// assert_eq!(exact_grid("0", "1", 4).unwrap(), ["0", "1/3", "2/3", "1"]);
/// ```
///
/// # Errors
/// Fewer than 2 steps, or an end that is not an exact decimal or fraction.
pub fn exact_grid(from: &str, to: &str, steps: u32) -> Result<Vec<String>, Error> {
    if steps < 2 {
        return Err(Error::out_of_range("steps", steps, "use at least 2 points"));
    }
    let (a, b) = (parse_exact(from)?, parse_exact(to)?);
    let span = Rational::from(&b - &a);
    Ok((0..steps)
        .map(|k| exact_text(&(a.clone() + span.clone() * Rational::from((k, steps - 1)))))
        .collect())
}

/// A rational as a terminating decimal if it is one (denominator 2ᵃ5ᵇ), else as `p/q`.
fn exact_text(x: &Rational) -> String {
    let mut den = x.denom().clone();
    let (mut twos, mut fives) = (0u32, 0u32);
    while den.is_divisible_u(2) {
        den /= 2;
        twos += 1;
    }
    while den.is_divisible_u(5) {
        den /= 5;
        fives += 1;
    }
    if den != 1 {
        return x.to_string();
    }
    let places = twos.max(fives);
    let scaled = (x.numer() * Integer::from(Integer::u_pow_u(10, places))) / x.denom().clone();
    let digits = scaled.clone().abs().to_string();
    let sign = if scaled < 0 { "-" } else { "" };
    if places == 0 {
        return format!("{sign}{digits}");
    }
    let p = places as usize;
    let padded = format!("{digits:0>width$}", width = p + 1);
    let (int, frac) = padded.split_at(padded.len() - p);
    format!("{sign}{int}.{frac}")
}

/// Writes `field-sweep.csv` (one line per point; its columns are the keys of the JSON rows) and
/// `field-sweep.json` (the whole report) into `dir`.
///
/// # Errors
/// An I/O error naming the path.
pub fn write_tables(r: &FieldSweepReport, dir: &Path) -> Result<(), Error> {
    let mut csv = String::from(
        "w,field,cyclotron_radius,D_xx,D_xx_err,D_xy,D_xy_err,pinned_fraction_exact,\
         skipping_fraction_exact,localized_fraction_exact,localized_fraction,\
         localized_fraction_err,all_localized,mean_free_time,mean_free_time_err,\
         mean_free_time_exact\n",
    );
    for x in &r.rows {
        csv.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            x.w,
            x.field,
            x.cyclotron_radius,
            x.D_xx,
            x.D_xx_err,
            x.D_xy,
            x.D_xy_err,
            x.pinned_fraction_exact,
            x.skipping_fraction_exact,
            x.localized_fraction_exact,
            x.localized_fraction,
            x.localized_fraction_err,
            x.all_localized,
            x.mean_free_time,
            x.mean_free_time_err,
            x.mean_free_time_exact
        ));
    }
    crate::files::write(dir.join("field-sweep.csv"), csv)?;
    crate::files::write(
        dir.join("field-sweep.json"),
        serde_json::to_string_pretty(r).map_err(Error::encode)?,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(w: f64, field: f64, d_xx: f64, d_xy: f64, err: f64) -> FieldSweepRow {
        FieldSweepRow {
            w,
            field,
            cyclotron_radius: 1.0 / field.abs(),
            D_xx: d_xx,
            D_xx_err: err,
            D_xy: d_xy,
            D_xy_err: err,
            pinned_fraction_exact: 0.0,
            skipping_fraction_exact: 0.0,
            localized_fraction_exact: 0.0,
            localized_fraction: 0.0,
            localized_fraction_err: 0.0,
            all_localized: false,
            mean_free_time: 1.0,
            mean_free_time_err: 0.0,
            mean_free_time_exact: 1.0,
        }
    }

    #[test]
    fn onsager_pairs_b_with_minus_b_at_the_same_gap_and_catches_a_violation() {
        let rows = [
            row(0.1, 1.0, 0.10, 0.05, 0.001),
            row(0.1, -1.0, 0.1005, -0.0495, 0.001),
            row(0.2, -1.0, 0.3, 0.0, 0.001),
            row(0.1, 2.0, 0.07, 0.08, 0.001),
        ];
        let c = onsager(&rows, 16);
        assert_eq!(c.len(), 1);
        assert_eq!((c[0].w, c[0].field), (0.1, 1.0));
        assert!((c[0].d_xx_even.difference + 0.0005).abs() < 1e-15);
        assert!((c[0].d_xy_odd.difference - 0.0005).abs() < 1e-15);
        assert!((c[0].d_xx_even.err - 0.001 * 2f64.sqrt()).abs() < 1e-15);
        assert!(c[0].d_xx_even.agrees() && c[0].d_xy_odd.agrees());
        // A Hall part even in B (the same sign at ±B) is 70 errors from 0.
        let even = [
            row(0.1, 1.0, 0.10, 0.05, 0.001),
            row(0.1, -1.0, 0.10, 0.05, 0.001),
        ];
        let c = onsager(&even, 16);
        assert!(c[0].d_xx_even.agrees() && !c[0].d_xy_odd.agrees(), "{c:?}");
    }

    #[test]
    fn exact_grid_texts_parse_back_to_the_grid() {
        let g = exact_grid("-0.25", "1/3", 5).unwrap();
        assert_eq!(g, ["-0.25", "-5/48", "1/24", "0.1875", "1/3"]);
        let f = exact_grid("0.1", "0.3", 21).unwrap();
        assert_eq!(f[1], "0.11");
        assert_eq!(exact_grid("0.001", "0.002", 2).unwrap(), ["0.001", "0.002"]);
        assert!(exact_grid("0.1", "0.2", 1).is_err());
    }
}
