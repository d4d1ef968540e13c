//! The text `lorentz bench` prints (throughput, observer costs, long flights): the command line
//! writes it to stdout, and Python's `str()` of a bench result is the same text.

use super::line;
use crate::engine::metadata::RunMeta;
use crate::estimators::observer_costs::ObserverCosts;
use crate::estimators::throughput::Throughput;
use crate::estimators::throughput::long_flights::LongFlightBench;
use crate::estimators::throughput::thermostat::ElectricBench;

/// The engine that ran, with its SIMD path if any.
fn engine(m: &RunMeta) -> String {
    match &m.simd {
        Some(p) => format!("{} ({p})", m.engine),
        None => m.engine.clone(),
    }
}

/// Repetition rates, as the text shows them.
fn runs(samples: &[f64]) -> String {
    let shown: Vec<String> = samples.iter().map(|s| format!("{s:.3e}")).collect();
    shown.join(" ")
}

/// `bench --electric`: the thermostatted walk beside straight flights.
pub fn electric(r: &ElectricBench) -> String {
    let mut out = String::new();
    line!(
        out,
        "w = {}  E = {} at {}° from x  precision {}  straight engine {}  {} collisions per thread x {} repetitions on {} thread(s)",
        r.w,
        r.electric,
        r.electric_angle,
        r.meta.precision,
        engine(&r.meta),
        r.collisions_per_thread,
        r.repetitions,
        r.threads
    );
    line!(
        out,
        "thermostat (scalar, certified events): median {:.3e} collisions/s per thread = {:.1} ns/collision  (runs: {})",
        r.collisions_per_second_per_thread,
        r.ns_per_collision,
        runs(&r.samples)
    );
    line!(
        out,
        "straight flights (same run, alternating): median {:.3e} collisions/s per thread  (runs: {})",
        r.straight_collisions_per_second_per_thread,
        runs(&r.straight_samples)
    );
    line!(
        out,
        "thermostat / straight = {:.4} (median of the paired ratios {:.4}; 1/{:.0})",
        r.thermostat_over_straight,
        r.paired_ratio,
        1.0 / r.paired_ratio
    );
    if let Some(f) = &r.oracle {
        line!(
            out,
            "winner-only floor (one thread, a tape of {} events, {} collisions; {} found as the full search finds them): {:.1} ns/collision against {:.1} for the full search on the tape (median paired ratio {:.3})",
            f.events,
            f.collisions,
            f.identical,
            f.times.floor_ns_per_collision,
            f.times.full_ns_per_collision,
            f.times.paired_ratio
        );
        line!(
            out,
            "floor / straight = {:.4} (1/{:.1}): the best ratio this kernel's certificates allow on this CPU",
            f.floor_over_straight,
            1.0 / f.floor_over_straight
        );
    }
    out
}

/// The text of a throughput result (`lorentz bench`).
pub fn throughput(r: &Throughput) -> String {
    let mut out = String::new();
    line!(
        out,
        "w = {}  precision {}  engine {}  {} collisions per thread x {} repetitions on {} thread(s)\nmedian {:.3e} collisions/s ({:.3e} per thread) = {:.2} ns/collision per thread  (runs: {})",
        r.w,
        r.meta.precision,
        engine(&r.meta),
        r.collisions_per_thread,
        r.repetitions,
        r.threads,
        r.collisions_per_second,
        r.collisions_per_second_per_thread,
        r.ns_per_collision,
        runs(&r.samples)
    );
    if let Some(b) = &r.divider_bound {
        line!(
            out,
            "divider bound: {:.2} ns per division and {:.2} ns per square root of {} lanes; {} root(s) + {} divisions per event = {:.2} ns/collision, {:.0} % of the engine's time",
            b.unit.div_ns,
            b.unit.sqrt_ns,
            b.unit.lanes,
            b.unit.roots,
            b.unit.divisions,
            b.ns_per_collision,
            100.0 * b.fraction
        );
    }
    if let Some(s) = &r.straight {
        line!(
            out,
            "straight flights beside (same run, alternating): median {:.3e} collisions/s per thread (runs: {}); arcs / straight = {:.3} (median of the paired ratios {:.3})",
            s.collisions_per_second_per_thread,
            runs(&s.samples),
            s.arcs_over_straight,
            s.paired_ratio
        );
    }
    if let Some(d) = &r.diffusion {
        line!(
            out,
            "diffusion in the field end to end beside (same run, alternating; {:.3e} collisions, {} batches): median {:.3e} collisions/s per thread (runs: {}); diffusion / engine = {:.3} (median of the paired ratios {:.3})",
            d.collisions as f64,
            d.batches,
            d.collisions_per_second_per_thread,
            runs(&d.samples),
            d.over_engine,
            d.paired_ratio
        );
    }
    if let Some(t) = &r.table {
        line!(
            out,
            "table beside (same run, alternating): {}: median {:.3e} collisions/s per thread (runs: {}; {:.3} crossings per collision); table / triangular = {:.3} (median of the paired ratios {:.3})",
            t.table,
            t.collisions_per_second_per_thread,
            runs(&t.samples),
            t.crossings_per_collision,
            t.over_triangular,
            t.paired_ratio
        );
    }
    if let Some(o) = &r.oracle {
        line!(
            out,
            "winner-only floor (one thread; each event's winner read from a tape of {} steps of this engine's own run, only that disk and edge computed, the same bits): {:.3e} collisions/s = {:.2} ns/collision against the full engine's {:.2} on the same tape; floor / full = {:.3} (median of the paired ratios)",
            o.steps,
            o.times.floor_collisions_per_second,
            o.times.floor_ns_per_collision,
            o.times.full_ns_per_collision,
            o.times.paired_ratio
        );
    }
    out
}

/// The text of an observer-cost result (`lorentz bench --observer-costs`).
pub fn observer_costs(r: &ObserverCosts) -> String {
    let mut out = String::new();
    line!(
        out,
        "w = {}  engine {}  {} collisions per thread x {} rounds on {} thread(s), sets in turns",
        r.w,
        engine(&r.meta),
        r.collisions_per_thread,
        r.rounds,
        r.threads,
    );
    line!(
        out,
        "observe     ns/collision  over bare (median of paired ratios)"
    );
    for c in &r.costs {
        line!(
            out,
            "{:<10}  {:>12.2}  {:>+8.1} %",
            format!("{:?}", c.observe).to_lowercase(),
            c.ns_per_collision,
            100.0 * c.over_bare
        );
    }
    out
}

/// The text of a long-flight result (`lorentz bench --long-flights`).
pub fn long_flights(r: &LongFlightBench) -> String {
    let mut out = String::new();
    let c = &r.config;
    let (lattice, per, plural, column) = if c.gaps.is_empty() {
        ("square", "radius", "radii", "radius")
    } else {
        ("triangular", "gap", "gaps", "w")
    };
    line!(
        out,
        "long flights, {lattice} lattice, 1 thread: {} collisions jumping and {} walking per {per} x {} repetitions ({plural} in turns), seed {}",
        c.collisions,
        c.walk_collisions,
        c.repetitions,
        c.seed
    );
    line!(
        out,
        "{column:<12}  mean free path  ns/collision  over the first  walking ns/collision  walk/jump"
    );
    for row in &r.rows {
        let (walk, ratio) = match (row.walk_ns_per_collision, row.walk_over_jump) {
            (Some(w), Some(q)) => (format!("{w:.1}"), format!("{q:.2}")),
            _ => ("-".into(), "-".into()),
        };
        let value = row.radius.as_deref().or(row.w.as_deref()).unwrap_or("-");
        line!(
            out,
            "{:<12}  {:>14.2}  {:>12.1}  {:>14.3}  {:>20}  {:>9}",
            value,
            row.mean_free_path,
            row.ns_per_collision,
            row.over_first,
            walk,
            ratio
        );
    }
    out
}
