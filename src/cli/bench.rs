//! `lorentz bench`: kernel throughput, and with `--report` the speed-against-error table.

use std::path::PathBuf;

use lorentz_gas::Error;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::observer_costs::{self, ObserverCostsConfig};
use lorentz_gas::estimators::throughput::costs::{self, CostsConfig};
use lorentz_gas::estimators::throughput::long_flights::{self, LongFlightBenchConfig};
use lorentz_gas::estimators::throughput::thermostat::{self, ElectricBenchConfig};
use lorentz_gas::estimators::throughput::{self, ThroughputConfig};
use lorentz_gas::numbers::exact::{nearest_f64, parse_exact};
use lorentz_gas::report::text::bench as text;

use lorentz_gas::report::speed_error::{self, REPORT_STEPS, SpeedErrorConfig};
use lorentz_gas::scenes::spec::Table;

use super::args::{
    ElectricArgs, EngineArg, Exact, OutputArgs, PrecisionArg, SceneName, SeedArg, ThreadsArg,
    parse_count, parse_count_usize, parse_diffusive_gap, parse_threads, table_at,
};
use super::output::{emit, to_json};
use super::progress::Progress;

/// What `--electric` times here.
const ELECTRIC_HELP: &str = "A Gaussian-thermostatted electric field E in the plane, its strength an exact decimal or \
    fraction (the double nearest it) at --electric-angle, 0 < |E| <= 10: time the \
    thermostatted walk (the generic cell kernel with certified events, scalar, bare) and \
    straight flights (E = 0) on the engine asked for (--engine scalar: the scalar kernel), in \
    turns, and report both rates and their ratio (median of the paired ratios). Give fewer \
    --collisions-per-thread (2e5).";

#[derive(clap::Args)]
#[command(group(clap::ArgGroup::new("driven").args(["field", "electric"])))]
#[command(mut_arg("electric", |a| a.help(ELECTRIC_HELP).conflicts_with_all(
    ["report", "observer_costs", "field", "observe", "table", "costs"]
)))]
pub struct Args {
    /// Gap w between neighbouring disks (radius 1), a decimal or a fraction such as 1/10:
    /// 0 < w < w_inf = 4/sqrt(3) - 2 = 0.3094... (every bench but --long-flights).
    #[arg(long = "w", value_name = "W", value_parser = parse_diffusive_gap, allow_hyphen_values = true, required_unless_present_any = ["long_flights", "costs"])]
    gap: Option<Exact>,
    /// Time a collision against the length of its flight: the square scene at these radii
    /// (exact, comma-separated, each 2^-32 <= r <= 1/4), or with --scene triangular the
    /// triangular one at these gaps (w_inf < w <= 2^20 - 2), long flights jumped, each in turn on
    /// one thread in one run, with --walk-collisions of the cell walk beside; reports ns per
    /// collision and each over the first (median of the paired ratios).
    #[arg(long, value_name = "RADII", value_delimiter = ',', conflicts_with_all = ["gap", "report", "observer_costs", "field", "observe", "precision", "threads", "collisions_per_thread"])]
    long_flights: Option<Vec<String>>,
    /// With --long-flights: the lattice timed, square (its values radii; the default) or
    /// triangular (its values gaps w).
    #[arg(long, value_enum)]
    scene: Option<SceneName>,
    /// With --long-flights: collisions of each timed run with jumps, per radius (or gap) and
    /// repetition [default: 1e6].
    #[arg(long, value_parser = parse_count, allow_negative_numbers = true)]
    collisions_per_radius: Option<u64>,
    /// With --long-flights: collisions of each timed walk cell by cell (0: not timed)
    /// [default: 1e4].
    #[arg(long, value_parser = parse_count, allow_negative_numbers = true)]
    walk_collisions: Option<u64>,
    /// Collisions of each thread in each repetition (the SIMD engine shares them out over the
    /// thread's 16 trajectories).
    #[arg(long, default_value = "2e7", value_parser = parse_count, allow_negative_numbers = true)]
    collisions_per_thread: u64,
    /// Repetitions (the median is reported), 1 to 1000.
    #[arg(long, default_value = "7", value_parser = parse_count_usize, allow_negative_numbers = true)]
    repetitions: usize,
    #[command(flatten)]
    precision: PrecisionArg,
    #[command(flatten)]
    engine: EngineArg,
    /// Observers to run along (to measure what observation costs): none (the bare engine),
    /// counters, msd, diffusion (counters + MSD, as in `lorentz diffusion`), hops.
    #[arg(long, value_enum, default_value = "none")]
    observe: lorentz_gas::estimators::throughput::Observe,
    #[command(flatten)]
    seed: SeedArg,
    /// Worker threads, 1 to 4 per core: K threads run K trajectories at once, one per thread (default:
    /// 1, the single-core kernel speed; with --report, all cores for the calibration run).
    #[arg(long, value_parser = parse_threads, allow_negative_numbers = true)]
    threads: Option<usize>,
    /// Speed against error for f64 and MPFR 53..1024 bits: Markdown, JSON, PNG and SVG into --out.
    #[arg(long)]
    report: bool,
    /// Time the engine bare and with each set of observers (counters, msd, diffusion, hops) in
    /// turns, --repetitions rounds of f64 runs, and report what each set adds to the bare time
    /// (median of the paired ratios).
    #[arg(long, conflicts_with_all = ["report", "observe", "precision"])]
    observer_costs: bool,
    /// A uniform magnetic field B perpendicular to the plane, an exact decimal or fraction: time
    /// the f64 arc kernel, bare, on the SIMD arc engine (or the scalar kernel with --engine
    /// scalar); 0: straight flights, the default.
    #[arg(long, allow_hyphen_values = true, conflicts_with_all = ["report", "observer_costs"])]
    field: Option<String>,
    #[command(flatten)]
    electric: ElectricArgs,
    /// With --field: time straight flights too, each repetition right after the arcs' on the same
    /// threads and engine, and report the arcs' speed against them (side by side in one run).
    #[arg(long, requires = "field")]
    straight_beside: bool,
    /// With --field: time `lorentz diffusion --field B` end to end too, each repetition right
    /// after the arcs', with as many collisions on the same threads, and report its speed
    /// against the engine's (median of the paired ratios).
    #[arg(long, requires = "field")]
    diffusion_beside: bool,
    /// With --field on the SIMD engine: also time the arc engine fed each event's winner from a
    /// tape of its own run (only that disk and edge computed, the same bits) beside the full
    /// engine on the same tape, one thread: the speed no choice of the next event in advance
    /// can beat with this kernel's arithmetic, on this CPU. With --electric: the same for the
    /// thermostat, each event of a tape of its walk (at most 2e5 collisions) certified given
    /// only the candidate the full search found.
    #[arg(long, requires = "driven")]
    oracle_floor: bool,
    /// Time this table (a TOML file, as `diffusion --table` reads) beside the triangular gas at
    /// --w: each repetition right after the triangular one, on the same threads and engine (its
    /// cell on the SIMD lanes), and report its speed against the triangular gas's
    #[arg(long, value_name = "FILE", conflicts_with_all = ["report", "observer_costs", "field", "observe"])]
    table: Option<PathBuf>,
    /// Measure every constant of the cost model that refuses work beyond a week (collisions in
    /// f64 and MPFR, on arcs, cell edges walked, a field's classification), one thread, each
    /// beside its floor in `engine::work` (about half of it by design).
    #[arg(long, conflicts_with_all = ["gap", "report", "observer_costs", "field", "observe", "precision", "threads", "table", "long_flights"])]
    costs: bool,
    /// Output directory of --report (speed-vs-error.{md,json,png,svg}).
    #[arg(long, default_value = "results")]
    out: PathBuf,
    #[command(flatten)]
    output: OutputArgs,
}

impl Args {
    /// The triangular gas at the gap exactly as typed (present wherever it is used: clap
    /// requires it without --long-flights).
    fn table(&self) -> Result<Table, Error> {
        let w = self.gap.as_ref().ok_or_else(|| {
            Error::parameter("w", "none", "give the gap of the triangular gas timed")
        })?;
        Ok(table_at(w))
    }
}

/// The options that apply with --long-flights only, refused without it (clap's `requires` is
/// not enforced on these, clap-rs/clap#3076).
fn refuse_long_flight_options(a: &Args) -> Result<(), Error> {
    let given = [
        ("scene", a.scene.map(|s| format!("{s:?}").to_lowercase())),
        (
            "collisions_per_radius",
            a.collisions_per_radius.map(|n| n.to_string()),
        ),
        ("walk_collisions", a.walk_collisions.map(|n| n.to_string())),
    ];
    match given.into_iter().find_map(|(name, v)| Some((name, v?))) {
        Some((name, value)) => Err(Error::parameter(
            name,
            value,
            "applies with --long-flights only (bench --w W times the triangular engine)",
        )),
        None => Ok(()),
    }
}

pub fn run(a: Args) -> Result<(), Error> {
    let threads = a.threads.unwrap_or(1);
    if a.long_flights.is_some() {
        return run_long_flights(&a);
    }
    refuse_long_flight_options(&a)?;
    if a.costs {
        let cfg = CostsConfig {
            repetitions: a.repetitions,
            seed: a.seed.seed,
        };
        return timed(&a, 1, "steps", |o| costs::run(&cfg, o), print_costs);
    }
    if a.report {
        let out = a.out.clone();
        let pb = Progress::new(REPORT_STEPS, "steps", a.output.quiet);
        let cfg = SpeedErrorConfig {
            table: a.table()?,
            seed: a.seed.seed,
            out: out.clone(),
        };
        let all = ThreadsArg { threads: a.threads }.threads();
        let opts = pb.options(all);
        let (r, md) = speed_error::run(&cfg, &opts)?;
        drop(opts);
        drop(pb);
        if a.output.json {
            println!("{}", to_json(&r)?);
        } else {
            println!("{md}");
            println!(
                "written: {}/speed-vs-error.{{md,json,png,svg}}",
                out.display()
            );
        }
        return Ok(());
    }
    if a.observer_costs {
        let cfg = ObserverCostsConfig {
            table: a.table()?,
            collisions_per_thread: a.collisions_per_thread,
            repetitions: a.repetitions,
            seed: a.seed.seed,
        };
        return timed(
            &a,
            threads,
            "rounds",
            |o| observer_costs::run(&cfg, o),
            |r| print!("{}", text::observer_costs(r)),
        );
    }
    let cfg = throughput_config(&a)?;
    if let Some((e, angle)) = a.electric.given() {
        let cfg = ElectricBenchConfig {
            straight: cfg,
            electric: nearest_f64(&parse_exact(e).map_err(|e| e.named("electric"))?),
            electric_angle: angle.trim().to_string(),
        };
        return timed(
            &a,
            threads,
            "repetitions",
            |o| thermostat::run(&cfg, o),
            |r| print!("{}", text::electric(r)),
        );
    }
    timed(
        &a,
        threads,
        "repetitions",
        |o| throughput::run(&cfg, o),
        |r| print!("{}", text::throughput(r)),
    )
}

/// `bench --long-flights`: the long-flight engine against the cell walk at each radius (or gap
/// of the triangular scene).
fn run_long_flights(a: &Args) -> Result<(), Error> {
    let values = a.long_flights.clone().unwrap_or_default();
    let triangular = a.scene == Some(SceneName::Triangular);
    let defaults = LongFlightBenchConfig::new();
    let cfg = LongFlightBenchConfig {
        radii: if triangular {
            Vec::new()
        } else {
            values.clone()
        },
        gaps: if triangular {
            values.clone()
        } else {
            Vec::new()
        },
        collisions: a.collisions_per_radius.unwrap_or(defaults.collisions),
        walk_collisions: a.walk_collisions.unwrap_or(defaults.walk_collisions),
        repetitions: a.repetitions,
        seed: a.seed.seed,
    };
    cfg.scenes()?;
    timed(
        a,
        1,
        "repetitions",
        |o| long_flights::run(&cfg, o),
        |r| print!("{}", text::long_flights(r)),
    )
}

/// The throughput measurement these options ask for (the field parsed exactly, the table read).
fn throughput_config(a: &Args) -> Result<ThroughputConfig, Error> {
    Ok(ThroughputConfig {
        table: a.table()?,
        precision: a.precision.precision,
        observe: a.observe,
        collisions_per_thread: a.collisions_per_thread,
        repetitions: a.repetitions,
        seed: a.seed.seed,
        field: a
            .field
            .as_deref()
            .map(|b| {
                Ok::<_, Error>(lorentz_gas::numbers::exact::nearest_f64(
                    &lorentz_gas::numbers::exact::parse_exact(b).map_err(|e| e.named("field"))?,
                ))
            })
            .transpose()?,
        straight_beside: a.straight_beside,
        diffusion_beside: a.diffusion_beside,
        oracle_floor: a.oracle_floor,
        table_beside: a
            .table
            .as_deref()
            .map(lorentz_gas::scenes::table::spec::TableSpec::read)
            .transpose()?,
    })
}

/// The cost model's constants, measured beside their floors.
fn print_costs(r: &costs::Costs) {
    println!(
        "{:<64} {:>12} {:>12} {:>8}",
        "cost", "measured", "floor", "ratio"
    );
    for row in &r.rows {
        let s = |t: f64| format!("{:.3e} s", t);
        let (m, f) = (s(row.measured), s(row.floor));
        println!(
            "{:<64} {m:>12} {f:>12} {:>8.2}",
            row.cost, row.floor_over_measured
        );
    }
    let f = &r.mpfr_fit;
    println!(
        "MPFR fit of the measured collisions: {:.2e} s + {:.2e} s * (p/1024)^{:.2}",
        f.a, f.b, f.alpha
    );
}

/// Runs `measure` with a progress bar of --repetitions `unit` on `threads` threads and the
/// engine asked for, then prints its result (JSON or `text`).
fn timed<R: serde::Serialize>(
    a: &Args,
    threads: usize,
    unit: &'static str,
    measure: impl FnOnce(&RunOptions) -> Result<R, Error>,
    text: fn(&R),
) -> Result<(), Error> {
    let pb = Progress::new(a.repetitions as u64, unit, a.output.quiet);
    let opts = RunOptions {
        engine: a.engine.engine,
        ..pb.options(threads)
    };
    let r = measure(&opts)?;
    drop(opts);
    drop(pb);
    emit(a.output.json, &r, text)
}
