//! The thermostat's throughput (`lorentz bench --electric E`): the lattice walk under the
//! Gaussian-thermostatted field ([`crate::scenes::thermostat`], the generic cell kernel with
//! certified events, scalar) timed in alternation with straight flights (E = 0) on the engine
//! the options resolve, in one run: both rates and the median of the paired ratios.

use std::time::Instant;

use rug::Rational;
use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::Resolved;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::parallel::thread_pool;
use crate::kernel::flight::EventKind;
use crate::kernel::thermostat::Thermostat;
use crate::kernel::trap::Trap;
use crate::numbers::precision::AtPrecision;
use crate::numbers::real::Real;
use crate::scenes::lattice::{LatticeState, TriangularLattice};
use crate::scenes::spec::Motion;
use crate::scenes::thermostat::CellFields;

use super::check::{Checked, check};
use super::{Observe, ThroughputConfig, advance, lanes, median, par_blocks, starts};

mod floor;
use floor::Tape;
pub use floor::{MAX_TAPE_COLLISIONS, ThermostatFloor};

/// The strongest field timed (the analyses' range).
pub const MAX_ELECTRIC: f64 = 10.0;

/// What `bench --electric` times: the straight bench's configuration (gap, precision,
/// collisions per thread, repetitions, seed; no observers, no magnetic field) and the field.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElectricBenchConfig {
    /// The straight flights' configuration, timed beside.
    #[serde(flatten)]
    pub straight: ThroughputConfig,
    /// The field's strength E (the double nearest the value typed), 0 < |E| ≤ 10.
    pub electric: f64,
    /// The field's angle from the x axis in degrees, exactly as typed (a decimal or a fraction;
    /// rounded once at the working precision, as the diffusion run takes it).
    #[serde(default = "along_x")]
    pub electric_angle: String,
}

/// The angle of a field along the x axis, what a configuration without one means.
fn along_x() -> String {
    "0".into()
}

/// The thermostatted walk against straight flights, timed in alternation in one run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ElectricBench {
    /// Gap w.
    pub w: f64,
    /// Field strength E.
    pub electric: f64,
    /// Its angle from the x axis in degrees, as typed.
    #[serde(default = "along_x")]
    pub electric_angle: String,
    /// Its direction ê in the world (x, y), at double precision.
    #[serde(default)]
    pub direction: [f64; 2],
    /// Collisions of each thread in each repetition (shared out over its trajectories).
    pub collisions_per_thread: u64,
    /// Repetitions.
    pub repetitions: usize,
    /// Threads.
    pub threads: usize,
    /// Trajectories per thread (both walks: 1 on the scalar engine, a SIMD block otherwise).
    pub trajectories_per_thread: usize,
    /// The thermostat's median collisions per second per thread.
    pub collisions_per_second_per_thread: f64,
    /// Its median nanoseconds per collision on one thread.
    pub ns_per_collision: f64,
    /// Every thermostat repetition's collisions per second (all threads), in order.
    pub samples: Vec<f64>,
    /// Crossings per collision of the thermostatted walk.
    pub crossings_per_collision: f64,
    /// The straight flights' median collisions per second per thread (the engine in `meta`).
    pub straight_collisions_per_second_per_thread: f64,
    /// Every straight repetition's collisions per second (all threads), in order.
    pub straight_samples: Vec<f64>,
    /// The thermostat's median over the straight flights' (per thread).
    pub thermostat_over_straight: f64,
    /// The median over repetitions of each pair's ratio (thermostat over straight).
    pub paired_ratio: f64,
    /// With `oracle_floor`: the thermostat's winner-only floor (absent otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub oracle: Option<ThermostatFloor>,
    /// Version, seed, precision, the straight flights' engine, threads, command line.
    pub meta: RunMeta,
}

/// Times `cfg.straight.repetitions` pairs: the thermostatted walk, then straight flights on the
/// same threads, each `cfg.straight.collisions_per_thread` collisions per thread.
///
/// # Errors
/// What [`super::run`] refuses, observers, a magnetic field or a table beside, a field E that
/// is zero, not finite or beyond [`MAX_ELECTRIC`], or invalid options.
pub fn run(cfg: &ElectricBenchConfig, options: &RunOptions) -> Result<ElectricBench, Error> {
    let s = &cfg.straight;
    // `oracle_floor` is the thermostat's own floor here ([`ThermostatFloor`]), not the arc
    // engine's that `check` validates.
    let straight = ThroughputConfig {
        oracle_floor: false,
        ..s.clone()
    };
    let Checked { w, resolved, .. } = check(&straight, options)?;
    let lone = s.field.is_none()
        && s.observe == Observe::None
        && s.table_beside.is_none()
        && !(s.straight_beside || s.diffusion_beside);
    if !lone {
        return Err(Error::Invalid(
            "the thermostat is timed bare beside straight flights: leave out observers, a \
             magnetic field, a table and the other benches"
                .into(),
        ));
    }
    let e = cfg.electric;
    if !(e.is_finite() && e != 0.0 && e.abs() <= MAX_ELECTRIC) {
        return Err(Error::out_of_range(
            "electric",
            e,
            format!("use 0 < |E| <= {MAX_ELECTRIC}"),
        ));
    }
    let typed = crate::numbers::exact::exact_text_of(e).unwrap_or_else(|| format!("{e:?}"));
    crate::estimators::diffusion::check_electric(&Motion::thermostat(&typed, &cfg.electric_angle))?;
    let world = field::<f64>(cfg, ())?;
    let Timed {
        samples,
        crossings_per_collision: cpc,
        straight,
        oracle,
    } = s.precision.dispatch(Pairs {
        cfg,
        w,
        engine: resolved,
        threads: options.threads,
        progress: options.progress,
    })?;
    let (m, ms) = (median(&samples), median(&straight));
    let threads = options.threads;
    let ratios: Vec<f64> = samples.iter().zip(&straight).map(|(a, b)| a / b).collect();
    Ok(ElectricBench {
        w,
        electric: e,
        electric_angle: cfg.electric_angle.clone(),
        direction: [world.dir.x, world.dir.y],
        collisions_per_thread: s.collisions_per_thread,
        repetitions: s.repetitions,
        threads,
        trajectories_per_thread: lanes(resolved),
        collisions_per_second_per_thread: m / threads as f64,
        ns_per_collision: 1e9 * threads as f64 / m,
        samples,
        crossings_per_collision: cpc,
        straight_collisions_per_second_per_thread: ms / threads as f64,
        straight_samples: straight,
        thermostat_over_straight: m / ms,
        paired_ratio: median(&ratios),
        oracle,
        meta: RunMeta::new(Some(s.seed), None, s.precision, Some(threads)).with_engine(resolved),
    })
}

/// The paired repetitions at one precision.
struct Pairs<'a> {
    cfg: &'a ElectricBenchConfig,
    w: f64,
    engine: Resolved,
    threads: usize,
    progress: &'a (dyn Fn(u64) + Sync),
}

/// What the paired repetitions measured.
struct Timed {
    /// The thermostat's rates (all threads), one a repetition.
    samples: Vec<f64>,
    crossings_per_collision: f64,
    /// The straight flights' rates (all threads).
    straight: Vec<f64>,
    /// With `oracle_floor`: the winner-only floor, timed in the same repetitions.
    oracle: Option<ThermostatFloor>,
}

impl AtPrecision for Pairs<'_> {
    type Output = Result<Timed, Error>;
    fn at<T: Real>(self, ctx: T::Ctx) -> Self::Output {
        let s = &self.cfg.straight;
        let (trap64, lat, fields) = scene::<T>(self.cfg, self.w, ctx)?;
        let lanes = lanes(self.engine);
        let mut field_states = starts::<T>(ctx, &trap64, s.seed, self.threads, lanes);
        let mut straight_states = field_states.clone();
        // The floor's tape: the walk of the first thread's first start.
        let mut tape = match s.oracle_floor {
            true => Some(Tape::record(
                &lat,
                &fields,
                field_states[0][0].clone(),
                s.collisions_per_thread,
            )?),
            false => None,
        };
        let pool = thread_pool(self.threads)?;
        let n = s.collisions_per_thread;
        let per_rep = (n / lanes as u64 * (lanes * self.threads) as u64) as f64;
        let field =
            |st: &mut Vec<Vec<LatticeState<T>>>, n: u64| walk(&pool, (&lat, &fields), st, n);
        let plain = |st: &mut Vec<Vec<LatticeState<T>>>, n: u64| {
            advance(&pool, self.engine, Observe::None, &lat, &trap64, st, n)
        };
        // One untimed warm-up of a tenth of the length each.
        field(&mut field_states, (n / 10).max(1))?;
        plain(&mut straight_states, (n / 10).max(1))?;
        let (mut rates, mut straight, mut crossings) = (Vec::new(), Vec::new(), 0);
        for _ in 0..s.repetitions {
            let t0 = Instant::now();
            crossings = field(&mut field_states, n)?;
            rates.push(per_rep / t0.elapsed().as_secs_f64());
            let t0 = Instant::now();
            plain(&mut straight_states, n)?;
            straight.push(per_rep / t0.elapsed().as_secs_f64());
            if let Some(tape) = &mut tape {
                tape.time(&lat, &fields)?;
            }
            (self.progress)(1);
        }
        let per_thread: Vec<f64> = straight.iter().map(|r| r / self.threads as f64).collect();
        Ok(Timed {
            crossings_per_collision: crossings as f64 / per_rep,
            oracle: tape.map(|t| t.result(&per_thread)),
            samples: rates,
            straight,
        })
    }
}

/// The trap in `f64` (where the starts are drawn), the lattice and the field in its cells.
type Scene<T> = (Trap<f64>, TriangularLattice<T>, CellFields<T>);

/// The [`Scene`] at the gap `w` as typed, at the working precision `ctx`.
fn scene<T: Real>(cfg: &ElectricBenchConfig, w: f64, ctx: T::Ctx) -> Result<Scene<T>, Error> {
    let gap = crate::numbers::exact::param_at::<T>(ctx, w, cfg.straight.table.gap_text())?;
    let fields = CellFields::new(field::<T>(cfg, ctx)?);
    Ok((Trap::new(w)?, TriangularLattice::new(gap)?, fields))
}

/// The field of `cfg` at the working precision `ctx`: E the double typed, its angle exact.
///
/// # Errors
/// A strength that is not finite or zero, an angle that is not an exact decimal or fraction.
fn field<T: Real>(cfg: &ElectricBenchConfig, ctx: T::Ctx) -> Result<Thermostat<T>, Error> {
    let e = Rational::from_f64(cfg.electric)
        .ok_or_else(|| Error::out_of_range("electric", cfg.electric, "a finite E"))?;
    let angle = crate::numbers::exact::parse_exact(&cfg.electric_angle)
        .map_err(|e| e.named("electric_angle"))?;
    Thermostat::<T>::exact(&e, &angle, ctx)
        .ok_or_else(|| Error::out_of_range("electric", 0.0, "use 0 < |E|"))
}

/// Every thread's trajectories continued under the field by `n` collisions (shared out over
/// them); returns the crossings made.
fn walk<T: Real>(
    pool: &rayon::ThreadPool,
    (lat, fields): (&TriangularLattice<T>, &CellFields<T>),
    states: &mut [Vec<LatticeState<T>>],
    n: u64,
) -> Result<u64, Error> {
    par_blocks(pool, states, |block| {
        let each = n / block.len() as u64;
        let mut crossings = 0;
        for s in block.iter_mut() {
            let mut collisions = 0;
            while collisions < each {
                match lat.step_thermostat(s, fields)?.kind {
                    EventKind::Collision(_) => collisions += 1,
                    EventKind::Crossing(_) => crossings += 1,
                }
            }
        }
        Ok(crossings)
    })
}
