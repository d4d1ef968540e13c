//! Speed against error: what each precision costs and what it buys (`lorentz bench --report`).
//!
//! For f64 and MPFR at 53 … 1024 bits, measured side by side in one run at one gap:
//! ns per collision (median of repetitions, one thread) and its ratio to f64; the median and worst
//! one-step error (flight time of the next event from the same exact pre-event state, against a
//! 2048-bit reference); the divergence horizon (collisions until an orbit leaves a 4096-bit
//! reference by 10⁻³); and the CPU time a D with 0.1 % relative error would take, from a measured
//! f64 calibration run (statistics do not depend on precision: `tests/verification.rs`).

use std::path::Path;

use rug::Float;
use serde::Serialize;

use crate::bench::throughput;
use crate::diffusion::{run, DiffusionConfig, Precision};
use crate::error::Error;
use crate::figures::{plot, PlotSpec, Series};
use crate::kernel::trap::{Flight, Trap};
use crate::real::Real;
use crate::sampling::{equilibrium_state, stream};
use crate::scenes::lattice::PeriodicLattice;
use crate::verification::lyapunov::divergence;

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
    /// The calibration run's relative error and collisions.
    pub calibration: (f64, u64),
    /// Crate version.
    pub version: String,
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
            Some((e.time.to_mpfr(2048) - &r.time).abs().to_f64())
        })
        .collect();
    errs.sort_by(|a, b| a.total_cmp(b));
    (errs[errs.len() / 2], *errs.last().unwrap_or(&f64::NAN))
}

/// Measures the report at gap `w` and writes `speed-vs-error.{md,json,png,svg}` into `dir`.
pub fn speed_against_error(
    w: f64,
    dir: &Path,
    threads: usize,
) -> Result<(SpeedReport, String), Error> {
    crate::geometry::check_diffusive_gap(w)?;
    std::fs::create_dir_all(dir)?;
    // Calibration: relative error of D from 10⁸ f64 collisions; error ∝ N^(−1/2).
    let mut cfg = DiffusionConfig::new(w);
    cfg.collisions = 100_000_000;
    let cal = run(&cfg, threads, None, &|_| {})?;
    let rel = cal.D_err / cal.D;
    let n_needed = cfg.collisions as f64 * (rel / 1e-3).powi(2);

    // Pre-event states from an f64 orbit.
    let lat = PeriodicLattice::new(w)?;
    let mut s = equilibrium_state(&lat.trap, &mut stream(77, 0));
    let mut states = Vec::new();
    for k in 0..20_000 {
        if k % 10 == 0 {
            states.push(s.flight.clone());
        }
        lat.step(&mut s)?;
    }
    let tref = Trap::new(Float::with_val(2048, w))?;
    let bits_list = [53u32, 64, 128, 256, 512, 1024];
    let div = divergence(w, &bits_list, 4096, 900, 8, 5)?;
    let mut rows = Vec::new();
    let f64_ns = throughput(w, Precision::F64, 20_000_000, 7, 1)?.ns_per_collision;
    let cpu = |ns: f64| n_needed * ns * 1e-9;
    let (m, x) = one_step(&Trap::new(w)?, &tref, &states);
    rows.push(ReportRow {
        precision: "f64".into(),
        bits: 53,
        ns_per_collision: f64_ns,
        ratio_to_f64: 1.0,
        one_step_median: m,
        one_step_worst: x,
        horizon: div[0].horizon,
        cpu_seconds_d_0_1_percent: cpu(f64_ns),
    });
    for (i, &b) in bits_list.iter().enumerate() {
        let n = if b >= 1024 { 100_000 } else { 200_000 };
        let ns = throughput(w, Precision::Bits(b), n, 7, 1)?.ns_per_collision;
        let (m, x) = one_step(&Trap::new(Float::with_val(b, w))?, &tref, &states);
        rows.push(ReportRow {
            precision: b.to_string(),
            bits: b,
            ns_per_collision: ns,
            ratio_to_f64: ns / f64_ns,
            one_step_median: m,
            one_step_worst: x,
            horizon: div[i + 1].horizon,
            cpu_seconds_d_0_1_percent: cpu(ns),
        });
    }
    let report = SpeedReport {
        w,
        rows,
        collisions_for_0_1_percent: n_needed,
        calibration: (rel, cfg.collisions),
        version: env!("CARGO_PKG_VERSION").into(),
    };
    let mut md = format!(
        "Speed against error at w = {w} (one thread per measurement; medians of 7 repetitions; one-step error = |flight time − 2048-bit value| from the same exact pre-event state over {} events; horizon = collisions until 10⁻³ from a 4096-bit orbit, mean of 8 starts; CPU time for D at 0.1 %: {:.2e} collisions, calibrated by an f64 run of {:.0e} collisions with relative error {:.3} %)\n\n",
        states.len(),
        n_needed,
        cfg.collisions as f64,
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
    std::fs::write(dir.join("speed-vs-error.md"), &md)?;
    std::fs::write(
        dir.join("speed-vs-error.json"),
        serde_json::to_string_pretty(&report).map_err(|e| Error::Io(e.to_string()))?,
    )?;
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
            title: &format!("Speed against error, w = {w}"),
            x_label: "correct digits per event (-log10 of the median one-step error)",
            y_label: "ns per collision (one core)",
            log_x: false,
            log_y: true,
        },
        &[Series {
            label: "kernel (f64 and MPFR)".into(),
            points: pts,
            notes,
            line: true,
        }],
    )?;
    Ok((report, md))
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
