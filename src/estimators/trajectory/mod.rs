//! One trajectory from exact initial conditions, to certified decimal digits.
//!
//! The start (x, y), the direction (dx, dy), the time T and the scene's parameters are exact
//! rationals. At a working precision P the start is located in its cell ([`Scene::locate`]), the
//! direction is normalised at P (never through `f64`), and the flow runs event by event until
//! the accumulated time would pass T; the last free flight is then advanced by the remaining
//! time. The world position (x, y) and the distance √(x² + y²) at time T follow.
//!
//! Certification (`proofs-notes/trajectory.md`): rounding errors grow like e^{λn} over n
//! collisions, so P starts at ⌈(D + 2)·log₂10 + n·λ/ln 2⌉ + [`TRAJECTORY_GUARD_BITS`] with n = T/⟨ℓ⟩
//! (Santaló) and λ the scene's Lyapunov exponent per collision. The runs at P and 2P must go
//! through the same event sequence and agree in x, y and the distance to the requested digits;
//! otherwise P doubles (up to [`MAX_TRAJECTORY_BITS`]). Digits are counted from the leading digit for
//! |q| ≥ 1 and from the first decimal place for |q| < 1 (absolute near zero); one agreed digit
//! is kept back as a guard, so each printed value (the 2P run, correctly rounded) is within one
//! unit of its last digit of the exact value, unless the two runs' agreement was a coincidence
//! (the caveat of `proofs-notes/trajectory.md`).

use crate::engine::work::{Work, mpfr_seconds_per_collision};
use rug::{Float, Rational};
use serde::Serialize;

use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::kernel::vec2::Vec2;
use crate::kernel::{flight::EventKind, flight::Flight};
use crate::numbers::real::Real;
use crate::scenes::Scene;
use crate::scenes::lattice::{CellIndex, Lattice, LatticeState};
use crate::scenes::motion::MotionInput;
use crate::verification::lyapunov::{self, LyapunovConfig};

mod digits;
mod events;
mod flow;
pub use digits::{decimal, digits_agreed};
pub use events::EventRecord;
use flow::{Flow, electric_of, field_of};

/// Most digits a trajectory may ask for: 10⁴ digits already need ≥ 33 000 bits before any
/// chaos, and more only hides a typo.
pub const MAX_DIGITS: u32 = 10_000;
/// Guard bits added to the starting precision for the prefactor of the error growth.
pub const TRAJECTORY_GUARD_BITS: u32 = 64;
/// Smallest precision tried.
pub const MIN_TRAJECTORY_BITS: u32 = 128;
/// Largest precision P tried (the 2P run then has 2¹⁹ bits): one event then costs about a
/// millisecond, and a time that needs more is not worth running this way.
pub const MAX_TRAJECTORY_BITS: u32 = 1 << 18;
/// Agreed digits kept back from the printed ones, so that rounding the 2P value to the printed
/// digits plus the P/2P deviation stay within one unit of the last printed digit.
pub const GUARD_DIGITS: u32 = 1;
/// Collisions per orbit of the Lyapunov estimate that sets the starting precision (its error,
/// a few per cent, changes P by a few bits; the doubling loop absorbs any shortfall).
pub const PLAN_LAMBDA_COLLISIONS: u64 = 20_000;
/// Orbits of the Lyapunov estimate (at least 2 for its error bar).
pub const PLAN_LAMBDA_ORBITS: u32 = 2;
/// Seed of the Lyapunov estimate: fixed, so the precisions tried depend on the input only.
pub const PLAN_LAMBDA_SEED: u64 = 17;
/// Bound on cell-edge crossings per unit time used for the resource estimate (a unit-speed
/// particle crosses about |vₓ| + |v_y| ≤ √2 unit-square edges per unit time, and fewer trap
/// edges; 3 leaves room for corners).
pub const CROSSINGS_PER_UNIT_TIME: f64 = 3.0;
/// Exponent of the cost of one MPFR multiplication in the number of 64-bit limbs (Karatsuba /
/// Toom range; measured: doubling P multiplies the time per event by about 3).
pub const COST_EXPONENT: f64 = 1.6;
/// Seconds per cost unit (one event at one limb), measured with the release build on the
/// development machine (T = 3000 in the square gas at r = 1/3: 7 s for 1.1·10⁸ units).
pub const SECONDS_PER_COST_UNIT: f64 = 6.4e-8;
/// Longest estimated run accepted (seconds of the first P/2P attempt): five minutes; a longer
/// time is refused before anything is allocated.
pub const MAX_SECONDS: f64 = 300.0;
/// Events a run may take beyond the estimate before it is stopped (the estimate is an average;
/// an orbit may collide more often, but not by this factor).
pub const EVENT_SLACK: f64 = 100.0;

/// The fields a trajectory takes besides 0: cyclotron radii from 10⁻⁶ to 10⁶, where the arc
/// kernel is tested (`proofs-notes/magnetic-arcs.md`).
pub const TRAJECTORY_FIELD_RANGE: (f64, f64) = (1e-6, 1e6);

/// The exact input of one trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryInput {
    /// Start, world x.
    pub x: Rational,
    /// Start, world y.
    pub y: Rational,
    /// Direction, x component (any length but zero; normalised at the working precision).
    pub dx: Rational,
    /// Direction, y component.
    pub dy: Rational,
    /// Total time T > 0 (speed 1, so also the path length).
    pub time: Rational,
    /// Digits requested, 1 to [`MAX_DIGITS`].
    pub digits: u32,
    /// Keep every event of the final run in the report (`--events`).
    pub record_events: bool,
    /// A uniform magnetic field B (exact; `None` or 0: straight flights with their own bits):
    /// flights are arcs of the generic arc kernel at the working precision, turning
    /// counter-clockwise for B > 0 on circles of radius 1/|B|.
    pub field: Option<Rational>,
    /// A Gaussian-thermostatted electric field E (exact), its signed strength and its angle from
    /// the x axis in degrees (`None` or E = 0: straight flights with their own bits): flights of
    /// the thermostat's kernel at the working precision, |E| ≤ 10 and |angle| ≤ 360
    /// ([`crate::estimators::diffusion::check_electric`]).
    pub electric: Option<(Rational, Rational)>,
}

/// The plan made before anything is allocated.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plan {
    /// Lyapunov exponent per collision of the scene (equilibrium estimate).
    pub lambda_per_collision: f64,
    /// Santaló's mean free path ⟨ℓ⟩.
    pub mean_free_path: f64,
    /// Expected collisions T/⟨ℓ⟩.
    pub expected_collisions: f64,
    /// Expected events (collisions and crossings), for the resource check.
    pub expected_events: f64,
    /// Starting precision P.
    pub bits: u32,
    /// Estimated seconds of the first attempt (runs at P and 2P): expected events ×
    /// ((P/64)^1.6 + (2P/64)^1.6) × [`SECONDS_PER_COST_UNIT`].
    pub estimated_seconds: f64,
}

/// Estimated seconds of the runs at `bits` and 2·`bits` over `events` events.
pub fn estimated_seconds(bits: f64, events: f64) -> f64 {
    let limbs = bits / 64.0;
    events * (limbs.powf(COST_EXPONENT) + (2.0 * limbs).powf(COST_EXPONENT)) * SECONDS_PER_COST_UNIT
}

/// A trajectory at time T with certified digits.
#[derive(Debug, Clone, Serialize)]
pub struct TrajectoryReport {
    /// The scene ([`Scene::label`]).
    pub scene: String,
    /// The motion, each parameter as an exact fraction (flattened: the keys `field`, `electric`
    /// and `electric_angle`, absent for straight flights).
    #[serde(flatten)]
    pub motion: MotionInput,
    /// World x at time T, exactly `certified_digits` digits.
    pub x: String,
    /// World y at time T.
    pub y: String,
    /// Distance from the origin √(x² + y²) at time T.
    pub distance: String,
    /// Collisions up to time T.
    pub collisions: u64,
    /// Cell-edge crossings up to time T.
    pub crossings: u64,
    /// Digits printed: the smallest agreement over x, y and the distance, less
    /// [`GUARD_DIGITS`] (at least the digits requested).
    pub certified_digits: u32,
    /// Digits requested.
    pub digits_requested: u32,
    /// Smallest agreement of the P and 2P runs over x, y and the distance, in digits.
    pub digits_agreed: f64,
    /// The precision P (bits) of the certifying pair (the printed values are from the 2P run).
    pub precision_bits: u32,
    /// Precisions P tried, in order.
    pub tried: Vec<u32>,
    /// The plan (Lyapunov exponent, expected collisions, starting precision).
    pub plan: Plan,
    /// Events of the 2P run (filled only when asked for).
    #[serde(skip)]
    pub events: Vec<EventRecord>,
    /// x, y and the distance of the 2P run at its full precision.
    #[serde(skip)]
    pub values: [Float; 3],
    /// Version, precision P, command line.
    pub meta: RunMeta,
}

/// One run at one precision.
#[derive(Debug, Clone)]
struct Run {
    values: [Float; 3],
    collisions: u64,
    crossings: u64,
    sequence: Vec<(EventKind, CellIndex)>,
    events: Vec<EventRecord>,
}

/// Refuses digits outside 1..=[`MAX_DIGITS`], a time ≤ 0, a zero direction, a start or
/// direction too far out, or a field outside [`TRAJECTORY_FIELD_RANGE`].
fn check_input(input: &TrajectoryInput) -> Result<(), Error> {
    if input.digits == 0 || input.digits > MAX_DIGITS {
        return Err(Error::out_of_range(
            "digits",
            input.digits,
            format!("use 1 to {MAX_DIGITS}"),
        ));
    }
    if input.time <= 0 {
        return Err(Error::out_of_range(
            "time",
            crate::numbers::exact::nearest_f64(&input.time),
            "use a time > 0",
        ));
    }
    if input.dx == 0 && input.dy == 0 {
        return Err(Error::parameter(
            "direction",
            "0,0",
            "a zero direction: use a nonzero direction such as 1,0",
        ));
    }
    crate::scenes::check_world_point(&input.x, &input.y)?;
    if let Some(b) = field_of(input) {
        let f = crate::numbers::exact::nearest_f64(b);
        let (lo, hi) = TRAJECTORY_FIELD_RANGE;
        if !(lo..=hi).contains(&f.abs()) {
            return Err(Error::out_of_range(
                "field",
                f,
                format!(
                    "use 0 or {lo:e} <= |field| <= {hi:e} (cyclotron radii the arc kernel is tested at)"
                ),
            ));
        }
    }
    flow::check_electric_input(input)?;
    crate::scenes::check_pair(
        "direction",
        &input.dx,
        &input.dy,
        "components (only the direction matters: scale it down)",
    )?;
    Ok(())
}

/// Checks the input and makes the plan: Lyapunov estimate, expected events, starting precision,
/// and the resource check (bits × events) — before anything large is allocated.
///
/// # Errors
/// Digits outside 1..=[`MAX_DIGITS`], a time ≤ 0, a zero direction, a start too far out, or a
/// time whose precision or estimated run time exceeds [`MAX_TRAJECTORY_BITS`] or [`MAX_SECONDS`].
pub fn plan<S: Scene>(scene: &S, input: &TrajectoryInput) -> Result<Plan, Error> {
    check_input(input)?;
    let mean_free_path = scene.mean_free_path();
    let time = crate::numbers::exact::nearest_f64(&input.time);
    let expected_collisions = time / mean_free_path;
    let expected_events = expected_collisions + CROSSINGS_PER_UNIT_TIME * time;
    let digits_bits = (input.digits + GUARD_DIGITS + 1) as f64 * std::f64::consts::LOG2_10;
    if !expected_events.is_finite()
        || estimated_seconds(MIN_TRAJECTORY_BITS as f64, expected_events) > MAX_SECONDS
    {
        return Err(Error::out_of_range(
            "time",
            format!("{time:e}"),
            format!(
                "it means about {expected_events:.2e} events, more than a certified run can afford in {MAX_SECONDS} s; use a shorter time"
            ),
        ));
    }
    // The plan's exponent walks its cells, as the runs do: priced before either starts.
    let planning = f64::from(PLAN_LAMBDA_ORBITS) * PLAN_LAMBDA_COLLISIONS as f64;
    Work::new("trajectory's plan", &["time", "digits"], planning)
        .walking(scene)
        .check(1)?;
    let lambda = lyapunov::run(
        scene,
        &LyapunovConfig {
            collisions_per_batch: PLAN_LAMBDA_COLLISIONS,
            batches: PLAN_LAMBDA_ORBITS,
            seed: PLAN_LAMBDA_SEED,
            // The plan keeps its bits: the walk, as before long flights.
            flights: crate::engine::long_flight::Flights::Walk,
            motion: Default::default(),
        },
        &RunOptions {
            threads: 1,
            ..RunOptions::default()
        },
    )?
    .per_collision;
    let need = digits_bits + expected_collisions * lambda / std::f64::consts::LN_2;
    let bits = (need.ceil() + TRAJECTORY_GUARD_BITS as f64).max(MIN_TRAJECTORY_BITS as f64);
    let seconds = estimated_seconds(bits, expected_events);
    if bits > MAX_TRAJECTORY_BITS as f64 || seconds > MAX_SECONDS {
        return Err(Error::parameter(
            "time",
            time,
            format!(
                "to {} digits needs about {bits:.0} bits over {expected_events:.0} events \
                 (lambda = {lambda:.3} per collision, {expected_collisions:.0} collisions), about \
                 {seconds:.0} s, beyond the limits of {MAX_TRAJECTORY_BITS} bits and \
                 {MAX_SECONDS} s: use a shorter time or fewer digits",
                input.digits
            ),
        ));
    }
    let per = mpfr_seconds_per_collision(bits as u32)
        + mpfr_seconds_per_collision((2.0 * bits).min(f64::from(u32::MAX)) as u32);
    Work::new("trajectory", &["time", "digits"], expected_events)
        .costing(per)
        .check(1)?;
    Ok(Plan {
        lambda_per_collision: lambda,
        mean_free_path,
        expected_collisions,
        expected_events,
        bits: bits as u32,
        estimated_seconds: seconds,
    })
}

/// Runs the trajectory at precisions P, 2P, 4P, … until two consecutive runs go through the
/// same events and agree to the requested digits; prints the 2P run's values with the certified
/// digits. `input.record_events` keeps the events of the final run; `options.progress` receives collision
/// counts.
///
/// # Errors
/// Everything [`plan`] refuses; a start inside a disk; no agreement within [`MAX_TRAJECTORY_BITS`].
///
/// # Examples
///
/// ```no_run
/// use lorentz_gas::numbers::exact::parse_exact;
/// use lorentz_gas::scenes::square::SquareScene;
/// use lorentz_gas::engine::options::RunOptions;
/// use lorentz_gas::estimators::trajectory::{self, TrajectoryInput};
/// let scene = SquareScene::exact(parse_exact("1/3").unwrap()).unwrap();
/// let input = TrajectoryInput {
///     x: parse_exact("1/2").unwrap(),
///     y: parse_exact("1/10").unwrap(),
///     dx: parse_exact("1").unwrap(),
///     dy: parse_exact("0").unwrap(),
///     time: parse_exact("10").unwrap(),
///     digits: 30,
///     record_events: false,
///     field: None,
///     electric: None,
/// };
/// let r = trajectory::run(&scene, &input, &RunOptions::default()).unwrap();
/// assert!(r.distance.starts_with("0.99526"));
/// ```
pub fn run<S: Scene>(
    scene: &S,
    input: &TrajectoryInput,
    options: &RunOptions,
) -> Result<TrajectoryReport, Error> {
    options.accept("trajectory", &[])?;
    let (record_events, progress) = (input.record_events, options.progress);
    let plan = plan(scene, input)?;
    let max_events = (plan.expected_events * EVENT_SLACK) as u64 + 10_000;
    let mut bits = plan.bits;
    let mut tried = Vec::new();
    let mut lo = run_at(scene, input, bits, record_events, max_events, progress)?;
    loop {
        tried.push(bits);
        let hi = run_at(scene, input, 2 * bits, record_events, max_events, progress)?;
        let same_events = lo.sequence == hi.sequence;
        let agreed = (0..3)
            .map(|k| digits_agreed(&lo.values[k], &hi.values[k], bits))
            .fold(f64::INFINITY, f64::min);
        let certified = (agreed.floor() - GUARD_DIGITS as f64).max(0.0) as u32;
        if same_events && certified >= input.digits {
            let text = |k: usize| decimal(&hi.values[k], certified);
            return Ok(TrajectoryReport {
                scene: scene.label(),
                motion: MotionInput {
                    field: field_of(input).map(|b| b.to_string()),
                    electric: electric_of(input).map(|(e, _)| e.to_string()),
                    electric_angle: electric_of(input).map(|(_, a)| a.to_string()),
                },
                x: text(0),
                y: text(1),
                distance: text(2),
                collisions: hi.collisions,
                crossings: hi.crossings,
                certified_digits: certified,
                digits_requested: input.digits,
                digits_agreed: agreed,
                precision_bits: bits,
                tried,
                plan,
                events: hi.events,
                values: hi.values,
                meta: RunMeta::new(None, None, bits, Some(1)),
            });
        }
        if 2 * bits > MAX_TRAJECTORY_BITS {
            return Err(Error::Failed(format!(
                "could not certify {} digits within {MAX_TRAJECTORY_BITS} bits: the runs at {bits} and {} bits {} (agreement {agreed:.1} digits); use a shorter time or fewer digits",
                input.digits,
                2 * bits,
                if same_events {
                    "go through the same events"
                } else {
                    "go through different events (a grazing collision or a corner)"
                }
            )));
        }
        bits *= 2;
        lo = hi;
    }
}

/// The refusal of a start inside the disk of radius `radius` centred at `centre`.
fn inside_disk(input: &TrajectoryInput, centre: &Vec2<Float>, radius: f64) -> Error {
    let near = crate::numbers::exact::nearest_f64;
    Error::parameter(
        "start",
        format!("{},{}", near(&input.x), near(&input.y)),
        format!(
            "inside the disk at ({}, {}) of radius {radius}: choose a start at distance >= the \
             radius from every disk centre",
            centre.x.to_f64(),
            centre.y.to_f64()
        ),
    )
}

/// The run at `bits` bits.
fn run_at<S: Scene>(
    scene: &S,
    input: &TrajectoryInput,
    bits: u32,
    record_events: bool,
    max_events: u64,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Run, Error> {
    let lat = scene.lattice::<Float>(bits)?;
    let mut s = start_state(scene, &lat, input, bits)?;
    let total = <Float as Real>::from_rational(bits, &input.time);
    let mut elapsed = Float::with_val(bits, 0);
    let (mut collisions, mut crossings) = (0u64, 0u64);
    let mut sequence = Vec::new();
    let mut events = Vec::new();
    let flow = Flow::of(input, bits);
    loop {
        let Some((kind, time)) = flow.next(&lat, &mut s, &elapsed, &total)? else {
            break;
        };
        elapsed = time;
        sequence.push((kind, s.cell));
        let (kind, obstacle) = match kind {
            EventKind::Collision(m) => {
                collisions += 1;
                progress(1);
                ("collision", m)
            }
            EventKind::Crossing(k) => {
                crossings += 1;
                ("crossing", k)
            }
        };
        if record_events {
            events.push(events::record(
                &lat,
                &s,
                flow.field(),
                (kind, obstacle),
                &elapsed,
            ));
        }
        if (sequence.len() as u64) > max_events {
            return Err(Error::Failed(format!(
                "the run passed {max_events} events before time T, far beyond the estimate: use a shorter time"
            )));
        }
    }
    let w = lat.world(&s);
    let distance = (w.x.clone().square() + &w.y.clone().square()).sqrt();
    Ok(Run {
        values: [w.x, w.y, distance],
        collisions,
        crossings,
        sequence,
        events,
    })
}

/// The input's start at `bits` of precision, in its cell's frame: its position, refused inside a
/// disk, and its direction normalised.
fn start_state<S: Scene>(
    scene: &S,
    lat: &Lattice<Float, S::Kernel<Float>>,
    input: &TrajectoryInput,
    bits: u32,
) -> Result<LatticeState<Float>, Error> {
    let (cell, pos) = scene.locate::<Float>(bits, &input.x, &input.y)?;
    for d in &lat.cell().disks {
        let c = &d.centre;
        if (pos.sub(c).norm2() - d.radius2()).lt0() {
            let centre = lat.world(&LatticeState {
                cell,
                flight: Flight::new(c.clone(), c.clone()),
            });
            return Err(inside_disk(input, &centre, d.radius().to_f64()));
        }
    }
    let (dx, dy) = (
        <Float as Real>::from_rational(bits, &input.dx),
        <Float as Real>::from_rational(bits, &input.dy),
    );
    let norm = (dx.clone().square() + &dy.clone().square()).sqrt();
    let mut vel = Vec2::new(dx / &norm, dy / &norm);
    if cell.down {
        // A point-reflected cell (s = −1) sees the world velocity reversed: world = L − p.
        vel = -vel;
    }
    Ok(LatticeState {
        cell,
        flight: Flight::new(pos, vel),
    })
}
