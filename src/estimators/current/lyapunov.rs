//! The Lyapunov pair of the driven gas (`lorentz lyapunov --electric E`): along each of
//! `batches` trajectories under the Gaussian-thermostatted field, started from the field-free
//! invariant measure (trajectory b from the stream of batch b of the run of the steady state,
//! [`super::run`]) and warmed up towards the steady state, the two tangent vectors of
//! `current::tangent` (`proofs-notes/thermostat-lyapunov.md`) over `collisions_per_batch`
//! collisions: λ₊ and λ₋ (per unit time and per collision) with standard errors over the
//! trajectories, the mean contraction ⟨α⟩ = E·J, the sum rule λ₊ + λ₋ = −⟨α⟩ on average (paired
//! over the trajectories, Student-t, [`comparison::paired`]) and per trajectory (the residual of
//! the logarithmic stretchings against ∫α beside its rounding bound), and the Kaplan–Yorke
//! dimension 2 + λ₊/|λ₋| of the attractor.

use serde::{Deserialize, Serialize};

use super::tangent::{Pair, PairBatch, pair_summary};
use super::track::{LOOK_EVERY, look, start, tangent, world_velocity};
use super::{WARM_UP_SHARE, mean_of};
use crate::Error;
use crate::engine::Resolved;
use crate::engine::long_flight::Flights;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::parallel::par_batches_watched;
use crate::estimators::diffusion::{Estimate, check_electric};
use crate::kernel::flight::EventKind;
use crate::kernel::thermostat::Thermostat;
use crate::scenes::Scene;
use crate::scenes::lattice::Lattice;
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::scenes::thermostat::CellFields;
use crate::statistics::comparison::{self, Comparison};
use crate::verification::lyapunov::{LyapunovConfig, LyapunovReport, TANGENT_TRANSIENT};

/// The Lyapunov pair under the thermostat.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct DrivenLyapunovReport {
    /// λ₊ per collision and per unit time, as without a field (the same record as the
    /// command's `tangent` without a field).
    pub tangent: LyapunovReport,
    /// The field's strength ε = |E| (the double nearest the exact value).
    pub electric: f64,
    /// Its direction ê in the world (x, y).
    pub direction: [f64; 2],
    /// λ₊ per unit time.
    pub lambda_plus: f64,
    /// Its standard error over the trajectories.
    pub lambda_plus_err: f64,
    /// λ₋ per unit time (the third exponent, along the flow, is 0).
    pub lambda_minus: f64,
    /// Its standard error.
    pub lambda_minus_err: f64,
    /// λ₋ per collision.
    pub lambda_minus_per_collision: f64,
    /// Its standard error.
    pub lambda_minus_per_collision_err: f64,
    /// ⟨α⟩ = E·J, the mean phase-space contraction rate (the entropy production).
    pub contraction: f64,
    /// Its standard error.
    pub contraction_err: f64,
    /// The sum rule on average: λ₊ + λ₋ against −⟨α⟩, paired over the trajectories (Student-t
    /// with batches − 1 dof, the crate's 4σ-equivalent bound): `difference` (λ₊ + λ₋ + ⟨α⟩),
    /// `err`, `dof`, `z`, `bound`.
    pub sum_rule: Comparison,
    /// The sum rule per trajectory: the largest |Σ ln stretchings + ∫α dt + ln(|f(T)|/|f(0)|)|
    /// relative to its bound, 0 but for rounding.
    pub sum_rule_residual: f64,
    /// That trajectory's rounding bound (`proofs-notes/thermostat-lyapunov.md`).
    pub sum_rule_residual_bound: f64,
    /// The Kaplan–Yorke dimension of the flow's attractor, 2 + λ₊/|λ₋| (per trajectory).
    pub kaplan_yorke: f64,
    /// Its standard error.
    pub kaplan_yorke_err: f64,
    /// Collisions of each trajectory's warm-up, before the pair is measured.
    pub warm_up_collisions: u64,
    /// The mean time between collisions in the steady state.
    pub mean_free_time: f64,
    /// Per trajectory: λ₊, λ₋ and ⟨α⟩ per unit time.
    pub batch_lambda_plus: Vec<f64>,
    /// Per trajectory λ₋.
    pub batch_lambda_minus: Vec<f64>,
    /// Per trajectory ⟨α⟩.
    pub batch_contraction: Vec<f64>,
    /// The configuration.
    pub config: LyapunovConfig,
}

/// What one trajectory measured: its pair, and the collisions over the pair's stretch.
struct Orbit {
    pair: PairBatch,
    collisions: u64,
}

/// Collisions of the warm-up before a trajectory of `n` collisions: 1/[`WARM_UP_SHARE`] of
/// them, at least [`TANGENT_TRANSIENT`].
pub fn warm_up(n: u64) -> u64 {
    (n / WARM_UP_SHARE as u64).max(TANGENT_TRANSIENT)
}

/// The field of a configuration at double precision, checked as the diffusion run checks it
/// ([`check_electric`]): 0 < |E| ≤ 10, the angle within ±360°.
fn field_of(cfg: &LyapunovConfig) -> Result<Thermostat<f64>, Error> {
    let motion = cfg.motion.resolve()?;
    check_electric(&motion)?;
    motion.thermostat_at::<f64>(())?.ok_or(Error::missing(
        "electric",
        "the driven gas's pair needs a nonzero field E",
    ))
}

/// Runs the measurement (see the module documentation) on the scalar kernel, one trajectory per
/// task (the same bits at any thread count).
///
/// # Errors
/// A configuration without the thermostat or with a field out of range, fewer than 2 batches or
/// no collisions, jumping flights, options the analysis does not use, too much work, or an
/// interruption.
pub fn run<S: Scene>(
    scene: &S,
    cfg: &LyapunovConfig,
    opts: &RunOptions,
) -> Result<DrivenLyapunovReport, Error> {
    opts.accept("lyapunov under the thermostat", &[])?;
    if cfg.flights == Flights::Jump {
        return Err(Error::parameter(
            "flights",
            "jump",
            "thermostatted flights cross the lattice cell by cell; use walk or auto",
        ));
    }
    let world = field_of(cfg)?;
    if cfg.collisions_per_batch == 0 || cfg.batches < 2 {
        return Err(Error::TooFew {
            what: "collisions_per_batch, batches (>= 2)",
            min: 2,
            got: u64::from(cfg.batches),
        });
    }
    let n = cfg.collisions_per_batch;
    crate::engine::check_trajectory_length(n, "collisions_per_batch", n)?;
    let per = n.saturating_add(warm_up(n)) as f64;
    crate::engine::work::Work::new(
        "lyapunov under the thermostat",
        &["collisions_per_batch", "batches"],
        f64::from(cfg.batches) * per,
    )
    .costing(crate::engine::work::THERMOSTAT_SECONDS_PER_COLLISION)
    .check(opts.threads)?;
    let lattice = scene.lattice::<f64>(())?;
    let fields = CellFields::new(world.clone());
    let orbits = par_batches_watched(opts.threads, cfg.batches, opts.stop.as_ref(), |i| {
        let key = StreamKey::new(cfg.seed, Purpose::Trajectory, u64::from(i));
        let on = Flight {
            scene,
            lat: &lattice,
            fields: &fields,
            world: &world,
        };
        orbit(&on, key, n, opts)
    })?;
    Ok(report(scene, cfg, &world, &orbits, opts.threads))
}

/// Where the trajectories fly: the scene, its lattice and the field (in every cell's frame and
/// in the world's).
struct Flight<'a, S: Scene> {
    scene: &'a S,
    lat: &'a Lattice<f64, S::Kernel<f64>>,
    fields: &'a CellFields<f64>,
    world: &'a Thermostat<f64>,
}

/// One trajectory of stream `key`: the warm-up, then `n` collisions measured.
fn orbit<S: Scene>(
    on: &Flight<'_, S>,
    key: StreamKey,
    n: u64,
    opts: &RunOptions,
) -> Result<Orbit, Error> {
    let (lat, fields, world) = (on.lat, on.fields, on.world);
    let mut s = start::<f64, S>(on.scene, (), key);
    let mut pair = Pair::new(world, &world_velocity(&s));
    let watch = (opts.progress, opts.stop.as_ref());
    let mut count = 0;
    let mut fly = |s: &mut _, pair: &mut Pair<'_>, collisions: u64| -> Result<(), Error> {
        let mut done = 0;
        while done < collisions {
            let flight = world.start(&world_velocity(s));
            let step = lat.step_thermostat(s, fields)?;
            tangent(lat, s, pair, (&flight, &step));
            done += u64::from(matches!(step.kind, EventKind::Collision(_)));
            look(watch, &mut count, &step)?;
        }
        Ok(())
    };
    fly(&mut s, &mut pair, warm_up(n))?;
    pair.restart_at(&world_velocity(&s));
    fly(&mut s, &mut pair, n)?;
    (opts.progress)(count % LOOK_EVERY);
    Ok(Orbit {
        pair: pair.finish(),
        collisions: n,
    })
}

/// The report of the trajectories `orbits`.
fn report<S: Scene>(
    scene: &S,
    cfg: &LyapunovConfig,
    world: &Thermostat<f64>,
    orbits: &[Orbit],
    threads: usize,
) -> DrivenLyapunovReport {
    let pairs: Vec<PairBatch> = orbits.iter().map(|o| o.pair).collect();
    let summary = pair_summary(&pairs);
    let column = |f: &dyn Fn(&Orbit) -> f64| orbits.iter().map(f).collect::<Vec<f64>>();
    let per_collision = |k: usize| {
        mean_of(&column(&|o| {
            o.pair.lambda[k] * o.pair.time / o.collisions as f64
        }))
    };
    let (plus_pc, minus_pc): (Estimate, Estimate) = (per_collision(0), per_collision(1));
    let rate = mean_of(&column(&|o| o.collisions as f64 / o.pair.time));
    let sums = column(&|o| o.pair.lambda[0] + o.pair.lambda[1]);
    let minus_alpha = column(&|o| -o.pair.alpha);
    let sum_rule = comparison::paired(&sums, &minus_alpha)
        .expect("at least 2 trajectories, checked before the run");
    let meta = RunMeta::new(
        Some(cfg.seed),
        Some(u64::from(cfg.batches)),
        "f64",
        Some(threads),
    )
    .with_engine(Resolved::Scalar);
    let label = format!("{} under E = {}", scene.label(), world.strength);
    DrivenLyapunovReport {
        tangent: LyapunovReport {
            scene: label,
            per_collision: plus_pc.value,
            per_collision_err: plus_pc.err,
            per_time: summary.plus.value,
            per_time_err: summary.plus.err,
            collisions_per_batch: cfg.collisions_per_batch,
            flights: Flights::Walk,
            batches: cfg.batches,
            meta,
        },
        electric: world.strength,
        direction: [world.dir.x, world.dir.y],
        lambda_plus: summary.plus.value,
        lambda_plus_err: summary.plus.err,
        lambda_minus: summary.minus.value,
        lambda_minus_err: summary.minus.err,
        lambda_minus_per_collision: minus_pc.value,
        lambda_minus_per_collision_err: minus_pc.err,
        contraction: summary.alpha.value,
        contraction_err: summary.alpha.err,
        sum_rule,
        sum_rule_residual: summary.residual.0,
        sum_rule_residual_bound: summary.residual.1,
        kaplan_yorke: summary.kaplan_yorke.value,
        kaplan_yorke_err: summary.kaplan_yorke.err,
        warm_up_collisions: warm_up(cfg.collisions_per_batch),
        mean_free_time: 1.0 / rate.value,
        batch_lambda_plus: column(&|o| o.pair.lambda[0]),
        batch_lambda_minus: column(&|o| o.pair.lambda[1]),
        batch_contraction: minus_alpha.iter().map(|a| -a).collect(),
        config: cfg.clone(),
    }
}
