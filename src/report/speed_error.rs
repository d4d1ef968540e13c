//! Speed against error: what each precision costs and what it buys (`lorentz bench --report`).
//!
//! For f64 and MPFR at 53 … 1024 bits, measured side by side in one run at one gap:
//! ns per collision (median of repetitions, one thread) and its ratio to f64; the median and worst
//! one-step error (flight time of the next event from the same exact pre-event state, against a
//! 2048-bit reference); the divergence horizon (collisions until an orbit leaves a 4096-bit
//! reference by 10⁻³); and the CPU time a D with 0.1 % relative error would take, from a measured
//! f64 calibration run (statistics do not depend on precision: `tests/numerics/verification.rs`).

use std::path::{Path, PathBuf};

use rug::Float;
use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::estimators::diffusion::{self, DiffusionConfig};
use crate::estimators::throughput::{self, Observe, ThroughputConfig};
use crate::kernel::{flight::Flight, trap::Trap};
use crate::numbers::exact::param_at;
use crate::numbers::precision::Precision;
use crate::numbers::real::Real;
use crate::report::figures::{PlotSpec, Series, plot};
use crate::scenes::lattice::TriangularLattice;
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::scenes::spec::{SceneChoice, Table};
use crate::scenes::triangular::TriangularScene;
use crate::scenes::triangular::equilibrium_state;
use crate::verification::divergence::{
    self, DIVERGENCE_COLLISIONS, DIVERGENCE_REFERENCE_BITS, Divergence, DivergenceConfig,
};

/// One row of the report.
#[derive(Debug, Clone, Serialize)]
pub struct ReportRow {
    /// "f64" or bits.
    pub precision: String,
    /// Significand bits.
    pub bits: u32,
    /// Median ns per collision (one thread).
    pub ns_per_collision: f64,
    /// Cost relative to f64.
    pub ratio_to_f64: f64,
    /// Median one-step flight-time error against 2048 bits.
    pub one_step_median: f64,
    /// Worst one-step error.
    pub one_step_worst: f64,
    /// Divergence horizon in collisions (mean over initial conditions).
    pub horizon: f64,
    /// CPU seconds (one core) for D with 0.1 % relative error at this cost per collision.
    pub cpu_seconds_d_0_1_percent: f64,
}

/// The whole report.
#[derive(Debug, Clone, Serialize)]
pub struct SpeedReport {
    /// Gap.
    pub w: f64,
    /// Rows, f64 first.
    pub rows: Vec<ReportRow>,
    /// Collisions needed for 0.1 % relative error on D (from the calibration run).
    pub collisions_for_0_1_percent: f64,
    /// The calibration run's relative error on D (D_err/D).
    pub calibration_relative_err: f64,
    /// The calibration run's collisions.
    pub calibration_collisions: u64,
    /// Version, seed, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// Collisions of the f64 calibration run whose relative error on D is scaled (as N^(−1/2)) to the
/// collisions a 0.1 % error needs: 10⁸ gives that error to ~15 %.
pub const CALIBRATION_COLLISIONS: u64 = 100_000_000;
/// Events of the f64 orbit whose every tenth pre-event state is replayed for the one-step errors.
pub const ONE_STEP_EVENTS: usize = 20_000;
/// Reference precision of the one-step errors: twice the largest precision measured.
pub const ONE_STEP_REFERENCE_BITS: u32 = 2048;
/// MPFR precisions measured.
pub const REPORT_BITS: [u32; 6] = [53, 64, 128, 256, 512, 1024];
/// Repetitions of each timing (the median is reported).
pub const REPORT_REPETITIONS: usize = 7;
/// Collisions per f64 timing repetition.
pub const F64_TIMING_COLLISIONS: u64 = 20_000_000;
/// Collisions per MPFR timing repetition (10⁵ at 1024 bits and above, where one costs ~10 µs).
pub const MPFR_TIMING_COLLISIONS: u64 = 200_000;
/// Initial conditions of the divergence horizons.
pub const HORIZON_STARTS: u32 = 8;

/// Steps of the report, for a progress bar: calibration, divergence, and one timing per precision.
pub const REPORT_STEPS: u64 = 2 + 1 + REPORT_BITS.len() as u64;

/// The pre-event state of every tenth of the first [`ONE_STEP_EVENTS`] events (an observer).
struct EveryTenth {
    states: Vec<Flight<f64>>,
    events: usize,
}

impl crate::engine::observe::Observer<1> for EveryTenth {
    fn observe<V: crate::numbers::lanes::Lanes>(
        &mut self,
        steps: &[crate::engine::observe::EventLanes<1>],
    ) {
        for e in steps {
            if self.events < ONE_STEP_EVENTS && self.events.is_multiple_of(10) {
                self.states.push(e.state(0).flight);
            }
            self.events += 1;
        }
    }
}

fn one_step<T: Real>(trap: &Trap<T>, tref: &Trap<Float>, states: &[Flight<f64>]) -> (f64, f64) {
    let ctx = trap.a.ctx();
    let mut errs: Vec<f64> = states
        .iter()
        .filter_map(|s| {
            let e = trap.next_event(&Flight::<T>::convert_from_f64(ctx, s))?;
            let r = tref.next_event(&Flight::<Float>::convert_from_f64(tref.a.prec(), s))?;
            if e.kind != r.kind {
                return Some(f64::INFINITY);
            }
            Some(
                (e.time.to_mpfr(ONE_STEP_REFERENCE_BITS) - &r.time)
                    .abs()
                    .to_f64(),
            )
        })
        .collect();
    errs.sort_by(|a, b| a.total_cmp(b));
    (errs[errs.len() / 2], *errs.last().unwrap_or(&f64::NAN))
}

/// What the speed-against-error report measures, and where it is written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedErrorConfig {
    /// The triangular gas at a gap 0 < w < w∞, without a field: the `f64` rows run at the double
    /// nearest the gap, the MPFR rows and the references at the gap as typed rounded once to
    /// their precision (in JSON `w` and `w_exact`).
    #[serde(flatten)]
    pub table: Table,
    /// Everything random comes from it (the calibration run's batches, the orbit of the one-step
    /// errors, the divergence starts).
    pub seed: u64,
    /// Folder of `speed-vs-error.{md,json,png,svg}` (created).
    pub out: PathBuf,
}

/// Measures the report and writes `speed-vs-error.{md,json,png,svg}` into `cfg.out`; returns
/// the report and its Markdown. `options.threads` runs the calibration; every timing runs on one
/// thread. `options.progress` receives finished steps (of [`REPORT_STEPS`]).
///
/// # Errors
/// A gap outside (0, w∞), invalid options, or an I/O error.
pub fn run(cfg: &SpeedErrorConfig, options: &RunOptions) -> Result<(SpeedReport, String), Error> {
    options.accept("speed against error", &[])?;
    let table = &cfg.table;
    table.motion_taken_by("speed against error")?;
    let w = crate::estimators::diffusive_gap(table, "speed against error")?;
    let exact = table.gap_text();
    let (dir, seed) = (cfg.out.as_path(), cfg.seed);
    let (threads, progress) = (options.threads, options.progress);
    let (cfg, rel) = calibrate(w, dir, seed, threads)?;
    progress(2);
    let n_needed = cfg.collisions as f64 * (rel / 1e-3).powi(2);
    let states = one_step_states(w, seed)?;
    let tref = Trap::new(param_at::<Float>(ONE_STEP_REFERENCE_BITS, w, exact)?)?;
    let div = divergence::run(
        &exact_scene(table)?,
        &DivergenceConfig {
            bits: REPORT_BITS.to_vec(),
            reference_bits: DIVERGENCE_REFERENCE_BITS,
            collisions: DIVERGENCE_COLLISIONS,
            starts: HORIZON_STARTS,
            seed,
        },
        &RunOptions {
            threads: 1,
            ..RunOptions::default()
        },
    )?;
    progress(1);
    let bench = Bench {
        table,
        w,
        seed,
        n_needed,
        states: &states,
        tref: &tref,
        div: &div,
        progress,
    };
    let report = SpeedReport {
        w,
        rows: bench.rows()?,
        collisions_for_0_1_percent: n_needed,
        calibration_relative_err: rel,
        calibration_collisions: cfg.collisions,
        meta: RunMeta::new(
            Some(seed),
            Some(cfg.batches as u64),
            "f64 and MPFR",
            Some(threads),
        ),
    };
    let md = speed_markdown(&report, states.len());
    crate::files::write(dir.join("speed-vs-error.md"), &md)?;
    crate::files::write(
        dir.join("speed-vs-error.json"),
        serde_json::to_string_pretty(&report).map_err(Error::encode)?,
    )?;
    speed_plot(&report, dir)?;
    Ok((report, md))
}

/// The triangular scene at the gap as typed (the divergence horizons' orbits at every precision
/// start from it).
fn exact_scene(table: &Table) -> Result<TriangularScene, Error> {
    match table.scene.resolve()? {
        SceneChoice::Triangular(scene) => Ok(*scene),
        _ => Err(table.lacks(crate::Capability::TrapSymbols, "speed against error")),
    }
}

/// The files the speed-against-error document writes into its directory.
const FILES: [&str; 4] = [
    "speed-vs-error.md",
    "speed-vs-error.json",
    "speed-vs-error.png",
    "speed-vs-error.svg",
];

/// Calibration: the relative error of D from [`CALIBRATION_COLLISIONS`] f64 collisions (error ∝
/// N^(−1/2)), with the run's configuration; creates `dir` once the configuration is valid.
fn calibrate(
    w: f64,
    dir: &Path,
    seed: u64,
    threads: usize,
) -> Result<(DiffusionConfig, f64), Error> {
    let mut cfg = DiffusionConfig::new(w);
    cfg.collisions = CALIBRATION_COLLISIONS;
    cfg.seed = seed;
    cfg.validate()?;
    let mut outputs = vec![crate::files::Output::Dir(dir.to_path_buf())];
    outputs.extend(crate::files::Output::files_in(dir, &FILES));
    crate::files::check_outputs(&[], &outputs)?;
    crate::files::create_dir_all(dir)?;
    let cal = diffusion::run(
        &cfg,
        &RunOptions {
            threads,
            ..RunOptions::default()
        },
    )?;
    Ok((cfg, cal.D_err / cal.D))
}

/// Pre-event states from an f64 orbit: every tenth of the first [`ONE_STEP_EVENTS`] events.
fn one_step_states(w: f64, seed: u64) -> Result<Vec<Flight<f64>>, Error> {
    let lat = TriangularLattice::new(w)?;
    let mut s = equilibrium_state(
        lat.trap(),
        &mut StreamKey::new(seed, Purpose::Verification, 0).rng(),
    );
    let mut every_tenth = EveryTenth {
        states: Vec::new(),
        events: 0,
    };
    // ONE_STEP_EVENTS collisions make more than ONE_STEP_EVENTS events.
    crate::engine::drive(
        &lat,
        &mut s,
        ONE_STEP_EVENTS as u64,
        &mut every_tenth,
        &|_| {},
    )?;
    Ok(every_tenth.states)
}

/// What the rows are measured with: the gap and seed, the collisions a 0.1 % D needs, the
/// one-step states and their reference trap, the divergence horizons, and the progress callback.
struct Bench<'a> {
    table: &'a Table,
    w: f64,
    seed: u64,
    n_needed: f64,
    states: &'a [Flight<f64>],
    tref: &'a Trap<Float>,
    div: &'a [Divergence],
    progress: &'a (dyn Fn(u64) + Sync),
}

impl Bench<'_> {
    /// Median ns per collision at precision `p` over `n` collisions (one thread), one step done.
    fn time(&self, p: Precision, n: u64) -> Result<f64, Error> {
        // What production runs on: the SIMD engine for f64, the scalar engine for MPFR.
        let cfg = ThroughputConfig {
            table: self.table.clone(),
            precision: p,
            observe: Observe::None,
            collisions_per_thread: n,
            repetitions: REPORT_REPETITIONS,
            seed: self.seed,
            field: None,
            straight_beside: false,
            oracle_floor: false,
            table_beside: None,
            diffusion_beside: false,
        };
        let one = RunOptions {
            threads: 1,
            ..RunOptions::default()
        };
        let t = throughput::run(&cfg, &one)?;
        (self.progress)(1);
        Ok(t.ns_per_collision)
    }

    /// The rows: f64 first, then each of [`REPORT_BITS`].
    fn rows(&self) -> Result<Vec<ReportRow>, Error> {
        let w = self.w;
        let mut rows = Vec::new();
        let f64_ns = self.time(Precision::F64, F64_TIMING_COLLISIONS)?;
        let cpu = |ns: f64| self.n_needed * ns * 1e-9;
        let (m, x) = one_step(&Trap::new(w)?, self.tref, self.states);
        rows.push(ReportRow {
            precision: "f64".into(),
            bits: 53,
            ns_per_collision: f64_ns,
            ratio_to_f64: 1.0,
            one_step_median: m,
            one_step_worst: x,
            horizon: self.div[0].horizon,
            cpu_seconds_d_0_1_percent: cpu(f64_ns),
        });
        for (i, &b) in REPORT_BITS.iter().enumerate() {
            let n = if b >= 1024 {
                MPFR_TIMING_COLLISIONS / 2
            } else {
                MPFR_TIMING_COLLISIONS
            };
            let ns = self.time(Precision::Bits(b), n)?;
            let trap = Trap::new(param_at::<Float>(b, w, self.table.gap_text())?)?;
            let (m, x) = one_step(&trap, self.tref, self.states);
            rows.push(ReportRow {
                precision: b.to_string(),
                bits: b,
                ns_per_collision: ns,
                ratio_to_f64: ns / f64_ns,
                one_step_median: m,
                one_step_worst: x,
                horizon: self.div[i + 1].horizon,
                cpu_seconds_d_0_1_percent: cpu(ns),
            });
        }
        Ok(rows)
    }
}

/// The report as a Markdown paragraph and table (`states` one-step states were replayed).
fn speed_markdown(report: &SpeedReport, states: usize) -> String {
    let (w, n_needed, rel, calibration) = (
        report.w,
        report.collisions_for_0_1_percent,
        report.calibration_relative_err,
        report.calibration_collisions,
    );
    let mut md = format!(
        "Speed against error at w = {w} (one thread per measurement; medians of {REPORT_REPETITIONS} repetitions; one-step error = |flight time − {ONE_STEP_REFERENCE_BITS}-bit value| from the same exact pre-event state over {} events; horizon = collisions until 10⁻³ from a {DIVERGENCE_REFERENCE_BITS}-bit orbit, mean of {HORIZON_STARTS} starts; CPU time for D at 0.1 %: {:.2e} collisions, calibrated by an f64 run of {:.0e} collisions with relative error {:.3} %)\n\n",
        states,
        n_needed,
        calibration as f64,
        100.0 * rel
    );
    md.push_str("| precision | ns / collision | × f64 | one-step error (median) | one-step error (worst) | divergence horizon (collisions) | CPU time for D ± 0.1 % |\n|---|---|---|---|---|---|---|\n");
    for r in &report.rows {
        let name = if r.precision == "f64" {
            "f64".to_string()
        } else {
            format!("MPFR {} bits", r.bits)
        };
        md.push_str(&format!(
            "| {} | {:.1} | {:.0} | {:.1e} | {:.1e} | {:.0} | {} |\n",
            name,
            r.ns_per_collision,
            r.ratio_to_f64,
            r.one_step_median,
            r.one_step_worst,
            r.horizon,
            human_time(r.cpu_seconds_d_0_1_percent)
        ));
    }
    md
}

/// The figure `speed-vs-error.{png,svg}`: ns per collision against correct digits per event.
fn speed_plot(report: &SpeedReport, dir: &Path) -> Result<(), Error> {
    let w = report.w;
    let pts: Vec<(f64, f64, f64)> = report
        .rows
        .iter()
        .map(|r| {
            (
                -r.one_step_median.max(1e-320).log10(),
                r.ns_per_collision,
                0.0,
            )
        })
        .collect();
    let notes = report
        .rows
        .iter()
        .map(|r| {
            if r.precision == "f64" {
                "  f64".to_string()
            } else {
                format!("  {} bits", r.bits)
            }
        })
        .collect();
    plot(
        &dir.join("speed-vs-error"),
        &PlotSpec {
            log_y: true,
            ..PlotSpec::new(
                &format!("Speed against error, w = {w}"),
                "correct digits per event (-log10 of the median one-step error)",
                "ns per collision (one core)",
            )
        },
        &[Series {
            label: "kernel (f64 and MPFR)".into(),
            points: pts,
            notes,
            line: true,
        }],
    )
}

fn human_time(s: f64) -> String {
    if s < 120.0 {
        format!("{s:.0} s")
    } else if s < 7200.0 {
        format!("{:.0} min", s / 60.0)
    } else if s < 172_800.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{:.1} days", s / 86400.0)
    }
}
