//! The diffusion tensor over a grid of gaps and fields: a sweep over B at a fixed gap, over w at a
//! fixed field, or both. Every point is one transport run in a field ([`crate::estimators::field::run`]) on its own
//! streams (point i is run i of the seed), so points are independent and each error bar is its
//! own batches'. Where the grid holds B and −B at the same gap, Onsager–Casimir is checked:
//! D_xx(B) − D_xx(−B) and D_xy(B) + D_xy(−B) against 0 with the Welch error of two independent
//! estimates, at the crate's agreement level corrected for the number of comparisons (Bonferroni,
//! [`largest_of_bound`](crate::statistics::comparison::largest_of_bound)).
//!
//! Resumption: the points are sealed into `DIR/field-points/` as they finish
//! ([`super::point_grid`], the mechanism of every sweep of transport runs).

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::point_grid::{self, GridPoint, PointGrid};
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::work::Work;
use crate::estimators::diffusion::DiffusionConfig;
use crate::estimators::sweep::SweepConfig;
use crate::scenes::spec::SceneSpec;
use crate::scenes::spec::{Motion, Table};
use crate::statistics::comparison::Comparison;

/// Most points of a field sweep (each is a transport run of its own).
pub const MAX_FIELD_SWEEP_POINTS: usize = 1_000;

/// The grid of a sweep in a field: the tables (the triangular gas at each gap, the square one at
/// a radius, or a table given as data) × the fields.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FieldGrid {
    /// The gaps of the triangular scene, each an exact decimal or fraction as given (one gap: a
    /// sweep over B); empty with `radius` or `table`.
    pub gaps: Vec<String>,
    /// The square lattice at this radius (exact, as given) instead of the triangular one: a
    /// sweep over B on it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<String>,
    /// The fields, each an exact decimal or fraction as given, nonzero, 10⁻³ ≤ |B| ≤ 10³ (one
    /// field: a sweep over w).
    pub fields: Vec<String>,
    /// Phase points classified per point for the sampled localized share.
    pub localization_samples: u64,
    /// A table given as data instead of the triangular or square scene: a sweep over B on it
    /// (`gaps` empty, no `radius`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub table: Option<crate::scenes::table::spec::TableSpec>,
}

impl FieldGrid {
    /// Where it runs, in words.
    pub fn place(&self) -> String {
        match (&self.table, &self.radius) {
            (Some(t), _) => format!("the table {}", t.title()),
            (None, Some(r)) => format!("the square lattice at radius {r}"),
            (None, None) => format!("the triangular lattice at w = {}", self.gaps.join(", ")),
        }
    }

    /// The scenes of the grid: the triangular one at each gap, the square one at `radius`, or the
    /// table.
    pub fn scenes(&self) -> Vec<SceneSpec> {
        match (&self.table, &self.radius) {
            (Some(t), _) => vec![SceneSpec::Table(t.clone())],
            (None, Some(r)) => vec![SceneSpec::Square { radius: r.clone() }],
            (None, None) => (self.gaps.iter())
                .map(|g| SceneSpec::Triangular { w: g.clone() })
                .collect(),
        }
    }

    /// The number of points: tables × fields.
    pub fn points(&self) -> usize {
        let tables = match (&self.table, &self.radius) {
            (None, None) => self.gaps.len(),
            _ => 1,
        };
        tables * self.fields.len()
    }

    /// The points in order, scene-major: point i = (scene i / F, field i mod F) for F fields.
    pub fn grid(&self) -> Vec<(SceneSpec, &str)> {
        self.scenes()
            .into_iter()
            .flat_map(|s| self.fields.iter().map(move |f| (s.clone(), f.as_str())))
            .collect()
    }

    /// The transport run of point `i` of `sweep` on `scene` in the field `field`.
    ///
    /// # Errors
    /// A scene parameter that is not an exact decimal or fraction.
    pub fn point_config(
        &self,
        sweep: &SweepConfig,
        i: usize,
        (scene, field): (SceneSpec, &str),
    ) -> Result<DiffusionConfig, Error> {
        let scene = match scene {
            SceneSpec::Triangular { w } => SceneSpec::parse("triangular", Some(&w), None)?,
            SceneSpec::Square { radius } => SceneSpec::parse("square", None, Some(&radius))?,
            table @ (SceneSpec::Table(_) | SceneSpec::Open(_)) => table,
        };
        // A field of 0 stays a field here, for validation to refuse: a sweep in a field has none.
        let table = Table {
            scene,
            motion: Motion::Field(field.trim().to_string()),
        };
        Ok(DiffusionConfig {
            run: i as u64,
            collisions: sweep.collisions,
            batches: sweep.batches,
            seed: sweep.seed,
            localization_samples: Some(self.localization_samples),
            ..DiffusionConfig::on(table)
        })
    }

    /// Checks every parameter of `sweep`, whose grid this is (every point's run), before
    /// anything runs or is written.
    ///
    /// # Errors
    /// An empty or oversized grid, a point repeated, or a point's invalid run (naming the range).
    pub fn validate(&self, sweep: &SweepConfig) -> Result<(), Error> {
        self.check_places()?;
        let n = self.points();
        if n > MAX_FIELD_SWEEP_POINTS {
            return Err(Error::out_of_range(
                "points",
                n,
                format!("use 1 to {MAX_FIELD_SWEEP_POINTS} (gaps x fields)"),
            ));
        }
        let mut seen: Vec<(_, usize)> = Vec::with_capacity(n);
        for (i, (g, f)) in self.grid().into_iter().enumerate() {
            let c = self.point_config(sweep, i, (g.clone(), f))?;
            c.validate()?;
            let (w, r) = crate::estimators::field::scene_parameters(&c.table)?;
            let key = (
                w.map(f64::to_bits),
                r.map(f64::to_bits),
                crate::estimators::field::field_of(&c)?.to_bits(),
            );
            let scene = i / self.fields.len();
            if let Some(&(_, s)) = seen.iter().find(|(k, _)| *k == key) {
                let why = format!(
                    "{g:?}, B = {f} appears twice in the grid: give each gap and field once"
                );
                return Err(if s == scene {
                    Error::parameter("fields", self.fields.join(","), why)
                } else {
                    Error::parameter("gaps", self.gaps.join(","), why)
                });
            }
            seen.push((key, scene));
        }
        Ok(())
    }

    /// Refuses a sweep without a field, or without exactly one of gaps, a radius and a table.
    fn check_places(&self) -> Result<(), Error> {
        const PLACES: &str = "a field sweep needs one of: gaps (the triangular scene), a radius (the square one), a table";
        if self.fields.is_empty() {
            return Err(Error::missing(
                "fields",
                "a field sweep needs at least one field",
            ));
        }
        let given: Vec<(&'static str, String)> = [
            ("gaps", (!self.gaps.is_empty()).then(|| self.gaps.join(","))),
            ("radius", self.radius.clone()),
            ("table", self.table.as_ref().map(|t| t.title().to_string())),
        ]
        .into_iter()
        .filter_map(|(p, v)| Some((p, v?)))
        .collect();
        match given.as_slice() {
            [_] => Ok(()),
            [] => Err(Error::missing("gaps", PLACES)),
            [_, (p, v), ..] => Err(Error::parameter(p, v, format!("{PLACES}, not several"))),
        }
    }
}

/// One point of the sweep: what its transport run measured.
pub type FieldSweepRow = crate::estimators::field::FieldPoint;

/// Onsager–Casimir at one gap (or radius) and one |B|.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OnsagerCheck {
    /// Gap of the triangular scene.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub w: Option<f64>,
    /// Disk radius of the square scene.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
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
    pub config: SweepConfig,
    /// Provenance.
    pub meta: RunMeta,
}

/// One finished point on disk (the unit of resumption).
pub type FieldSweepPoint = GridPoint<FieldSweepRow>;

/// Runs the sweep (see the module documentation).
///
/// # Errors
/// An invalid configuration or options (before any work or file), a directory holding another
/// sweep's points or an edited one, an I/O error, or an interruption.
pub fn run(cfg: &SweepConfig, opts: &RunOptions) -> Result<FieldSweepReport, Error> {
    let (rows, resumed) = point_grid::run_points::<FieldGrid>(cfg, opts, &|_| true)?;
    report(cfg, rows.into_iter().flatten().collect(), resumed, opts)
}

/// The report of the sweep `cfg` from every point's row (in grid order), `resumed` of them
/// reused: the rows and Onsager–Casimir wherever the grid holds ±B (an error: an engine that
/// cannot run here).
pub(crate) fn report(
    cfg: &SweepConfig,
    rows: Vec<FieldSweepRow>,
    resumed: u32,
    opts: &RunOptions,
) -> Result<FieldSweepReport, Error> {
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
        )
        .with_engine(opts.engine.resolve(true)?),
    })
}

impl PointGrid for FieldGrid {
    type Row = FieldSweepRow;
    const FOLDER: &'static str = "field-points";
    const WHAT: &'static str = "field sweep point";
    const SWEEP: &'static str = "a field sweep";
    const LOWER: &'static [&'static str] =
        &["collisions_per_run", "fields", "localization_samples"];

    fn of(cfg: &SweepConfig) -> Result<&Self, Error> {
        cfg.field_grid()
    }

    fn points(&self) -> usize {
        Self::points(self)
    }

    fn point(&self, sweep: &SweepConfig, i: usize) -> Result<DiffusionConfig, Error> {
        let place = self.grid().swap_remove(i);
        self.point_config(sweep, i, place)
    }

    fn label(&self, i: usize) -> String {
        let (scene, field) = self.grid().swap_remove(i);
        let at = match &scene {
            SceneSpec::Triangular { w } => format!("w = {w}"),
            SceneSpec::Square { radius } => format!("radius {radius}"),
            SceneSpec::Table(t) => t.title().to_string(),
            SceneSpec::Open(t) => t.title(),
        };
        format!("{at}, B = {field}")
    }

    fn row(point: &DiffusionConfig, opts: &RunOptions) -> Result<FieldSweepRow, Error> {
        Ok(crate::estimators::field::run(point, opts)?.point)
    }

    fn work(point: &DiffusionConfig, simd: bool) -> Result<Work<'static>, Error> {
        crate::estimators::field::work(point, simd)
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
                .find(|m| (m.w, m.radius) == (p.w, p.radius) && m.field == -p.field)
                .map(|m| (p, m))
        })
        .collect();
    let m = 2 * pairs.len();
    // Where every orbit is localized both are 0 exactly: the difference itself.
    let compare = |x: f64, ea: f64, eb: f64| Comparison::welch(x, (ea, eb), batches, m);
    pairs
        .into_iter()
        .map(|(p, q)| OnsagerCheck {
            w: p.w,
            radius: p.radius,
            field: p.field,
            d_xx_even: compare(p.D_xx - q.D_xx, p.D_xx_err, q.D_xx_err),
            d_xy_odd: compare(p.D_xy + q.D_xy, p.D_xy_err, q.D_xy_err),
        })
        .collect()
}

/// The files [`write_tables`] writes.
pub const TABLE_FILES: [&str; 2] = ["field-sweep.csv", "field-sweep.json"];

/// Writes `field-sweep.csv` (one line per point; its columns are the keys of the JSON rows) and
/// `field-sweep.json` (the whole report) into `dir`.
///
/// # Errors
/// An I/O error naming the path.
pub fn write_tables(r: &FieldSweepReport, dir: &Path) -> Result<(), Error> {
    // A table's rows have no scene parameter: no such column.
    let fg = r.config.field_grid()?;
    let place = match (&fg.table, &fg.radius) {
        (Some(_), _) => "",
        (None, Some(_)) => "radius,",
        (None, None) => "w,",
    };
    let mut csv = format!(
        "{place}field,cyclotron_radius,D_xx,D_xx_err,D_xy,D_xy_err,pinned_fraction_exact,\
         skipping_fraction_exact,localized_fraction_exact,localized_fraction,\
         localized_fraction_err,all_localized,mean_free_time,mean_free_time_err,\
         mean_free_time_exact\n"
    );
    for x in &r.rows {
        csv.push_str(&format!(
            "{}{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            if place.is_empty() {
                String::new()
            } else {
                format!("{},", x.place())
            },
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
