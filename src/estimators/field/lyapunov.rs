//! The largest Lyapunov exponent in a magnetic field (`lorentz lyapunov --field B`): tangent
//! vectors carried through the arc kernel's events by the magnetic tangent map
//! ([`crate::verification::arc_tangent`], `proofs-notes/tangent-map.md`) along orbits started in
//! the diffusing part of phase space (orbit b starts where batch b of the transport run in the
//! same field starts: the invariant measure with the pinned and skipping orbits set aside, on
//! which the exponent is 0), renormalised at every collision. λ per collision and per unit time,
//! with standard errors over orbits. Compare Datseris, Hupe & Fleischmann, Chaos 29, 093115 (2019).

use nalgebra::Vector4;
use serde::Serialize;

use super::FieldWalk;
use super::lanes::{Looked, RING, fly};
use crate::Error;
use crate::engine::arcs::{ArcBlock, ArcRecord};
use crate::engine::metadata::RunMeta;
use crate::engine::options::{RunOption, RunOptions};
use crate::engine::parallel::{par_batches_watched, par_lane_blocks};
use crate::engine::simd::BLOCK;
use crate::engine::{LaneWork, Resolved, SimdPath, on_path};
use crate::kernel::cell::ConvexCell;
use crate::numbers::lanes::Lanes;
use crate::scenes::Scene;
use crate::scenes::magnetic::no_next_event;
use crate::scenes::spec::field_value;
use crate::statistics::mean_se;
use crate::theory::magnetic::FieldGeometry;
use crate::verification::arc_tangent::{
    CollisionTangent, LaneEvent, TangentBlock, TangentCell, TangentLane, half_angle_time,
};
use crate::verification::lyapunov::{LyapunovConfig, LyapunovReport, TANGENT_TRANSIENT};

/// The exponent in a field.
#[derive(Debug, Clone, Serialize)]
pub struct FieldLyapunovReport {
    /// λ per collision and per unit time, as without a field (the same record as the command's
    /// `tangent` without a field).
    pub tangent: LyapunovReport,
    /// The field B.
    pub field: f64,
    /// Cyclotron radius 1/|B|.
    pub cyclotron_radius: f64,
    /// Exact share of phase space in pinned or skipping orbits (λ = 0 there; not sampled).
    pub localized_fraction_exact: f64,
    /// Localized starts set aside before the orbits' diffusing starts.
    pub rejected_starts: u64,
    /// The configuration.
    pub config: LyapunovConfig,
}

/// Runs the measurement (see the module documentation) on the engine `opts` names: the SIMD
/// arc engine's lanes (`auto` on a CPU with AVX2 or AVX-512) or the scalar arc kernel, with the
/// same bits.
///
/// # Errors
/// An invalid field, fewer than 2 batches or no collisions, a field in which every orbit is
/// localized, options the analysis does not use, or an interruption.
pub fn run<S: Scene>(
    scene: &S,
    cfg: &LyapunovConfig,
    opts: &RunOptions,
) -> Result<FieldLyapunovReport, Error> {
    opts.accept("lyapunov in a field", &[RunOption::Engine])?;
    cfg.flights.in_field()?;
    // An electric field beside the magnetic one is refused.
    cfg.motion.resolve()?;
    let field = cfg.motion.field.as_deref().ok_or(Error::missing(
        "field",
        "the exponent in a field needs the field B",
    ))?;
    let b = field_value(field)?;
    if cfg.collisions_per_batch == 0 || cfg.batches < 2 {
        return Err(Error::TooFew {
            what: "collisions_per_batch, batches (>= 2)",
            min: 2,
            got: cfg.batches as u64,
        });
    }
    crate::engine::check_trajectory_length(
        cfg.collisions_per_batch,
        "collisions_per_batch",
        cfg.collisions_per_batch,
    )?;
    let geometry = FieldGeometry::new(
        crate::scenes::require_disk_lattice(scene, "Lyapunov in a field")?,
        b,
    )?;
    let engine = opts.engine.resolve(true)?;
    let collisions = f64::from(cfg.batches) * target_of(cfg) as f64;
    crate::engine::work::Work::new(
        "lyapunov in a field",
        &["collisions_per_batch", "batches"],
        collisions,
    )
    .in_field(
        scene,
        geometry.cyclotron_radius(),
        matches!(engine, Resolved::Simd(_)),
        geometry.setup_seconds(0.0),
    )
    .check(opts.threads)?;
    let start = |i: u32| FieldWalk::start(scene, field, cfg.seed, i as u64);
    let target = target_of(cfg);
    let orbits = match engine {
        Resolved::Simd(path) => {
            let batches: Vec<u32> = (0..cfg.batches).collect();
            par_lane_blocks(opts.threads, &batches, opts.stop.as_ref(), |block| {
                let walks = block
                    .iter()
                    .map(|&i| start(i))
                    .collect::<Result<Vec<_>, _>>()?;
                lanes(path, &walks, target, opts)
            })?
        }
        Resolved::Scalar => {
            par_batches_watched(opts.threads, cfg.batches, opts.stop.as_ref(), |i| {
                scalar(&start(i)?, target, opts)
            })?
        }
    };
    Ok(report(scene, cfg, &geometry, engine, &orbits, opts))
}

/// The collisions of one orbit: its batch and the tangent's transient.
fn target_of(cfg: &LyapunovConfig) -> u64 {
    cfg.collisions_per_batch.saturating_add(TANGENT_TRANSIENT)
}

/// The report of the finished `orbits`.
fn report<S: Scene>(
    scene: &S,
    cfg: &LyapunovConfig,
    geometry: &FieldGeometry,
    engine: Resolved,
    orbits: &[Tangent],
    opts: &RunOptions,
) -> FieldLyapunovReport {
    let n = cfg.collisions_per_batch as f64;
    let (pc, pce) = mean_se(&orbits.iter().map(|o| o.logsum / n).collect::<Vec<_>>());
    let (pt, pte) = mean_se(&orbits.iter().map(|o| o.logsum / o.time).collect::<Vec<_>>());
    let meta = RunMeta::new(
        Some(cfg.seed),
        Some(cfg.batches as u64),
        "f64",
        Some(opts.threads),
    );
    FieldLyapunovReport {
        tangent: LyapunovReport {
            scene: format!(
                "{} B={}",
                scene.label(),
                cfg.motion.field.as_deref().unwrap_or("0")
            ),
            per_collision: pc,
            per_collision_err: pce,
            per_time: pt,
            per_time_err: pte,
            collisions_per_batch: cfg.collisions_per_batch,
            // Arcs cross the lattice cell by cell.
            flights: crate::engine::long_flight::Flights::Walk,
            batches: cfg.batches,
            meta: meta.with_engine(engine),
        },
        field: geometry.field(),
        cyclotron_radius: geometry.cyclotron_radius(),
        localized_fraction_exact: geometry.localized_fraction(),
        rejected_starts: orbits.iter().map(|o| o.rejected).sum(),
        config: cfg.clone(),
    }
}

/// One orbit's sums: after [`TANGENT_TRANSIENT`] collisions, the logarithms of its tangent
/// vector's growth and the arcs' flight times. The scalar and the lane drivers carry the vector
/// with the same operations ([`TangentLane`]) and give each collision's growth and time here in
/// the same order, so they give the same bits.
#[derive(Debug, Clone, Copy)]
struct Tangent {
    collisions: u64,
    target: u64,
    logsum: f64,
    time: f64,
    rejected: u64,
}

impl Tangent {
    /// The orbit of `walk`, to run to `target` collisions.
    fn new(walk: &FieldWalk<impl Scene>, target: u64) -> Self {
        Tangent {
            collisions: 0,
            target,
            logsum: 0.0,
            time: 0.0,
            rejected: walk.rejected(),
        }
    }

    /// `true` while the orbit has collisions to make.
    fn running(&self) -> bool {
        self.collisions < self.target
    }

    /// A collision: the vector grew by `growth` over the arc of duration `time` that ended there.
    fn collision(&mut self, growth: f64, time: f64) {
        if self.collisions >= TANGENT_TRANSIENT {
            self.time += time;
        }
        self.collisions += 1;
        if self.collisions > TANGENT_TRANSIENT {
            self.logsum += growth.ln();
        }
    }
}

/// The tangent vector an orbit starts with: (Jv, 0.3·Jv), transverse to the flow and on the
/// energy shell.
fn first_vector(walk: &FieldWalk<impl Scene>) -> Vector4<f64> {
    let v = &walk.state().flight.vel;
    Vector4::new(-v.y, v.x, -0.3 * v.y, 0.3 * v.x)
}

/// Collisions between two reports of progress (and looks at the stop flag).
const REPORT_EVERY: u64 = 1 << 16;

/// One orbit on the scalar arc kernel.
fn scalar<S: Scene>(walk: &FieldWalk<S>, target: u64, opts: &RunOptions) -> Result<Tangent, Error> {
    let (lattice, w) = (walk.lattice(), walk.field());
    let cell = TangentCell::new(lattice.cell(), w);
    let mut state = walk.state().clone();
    let mut carried = CollisionTangent::new(first_vector(walk));
    let mut t = Tangent::new(walk, target);
    while t.running() {
        let ev = lattice
            .next_event_in_field(&state, &w)
            .ok_or_else(|| no_next_event(state.flight.vel.to_f64()))?;
        if let Some((growth, time)) = carried.event(&state.flight, &ev, &cell, w) {
            t.collision(growth, time);
            if t.collisions.is_multiple_of(REPORT_EVERY) {
                (opts.progress)(REPORT_EVERY);
                if let Some(stop) = &opts.stop {
                    stop.check()?;
                }
            }
        }
        lattice.apply_in_field(&mut state, &ev);
    }
    (opts.progress)(t.collisions % REPORT_EVERY);
    Ok(t)
}

/// The orbits of `walks` (at most [`BLOCK`]) in the lanes of one block of the SIMD arc engine,
/// each lane the scalar kernel bit for bit, their tangent vectors carried in vector lanes too
/// ([`RingTangents`]).
fn lanes<S: Scene>(
    path: SimdPath,
    walks: &[FieldWalk<S>],
    target: u64,
    opts: &RunOptions,
) -> Result<Vec<Tangent>, Error> {
    let Some(first) = walks.first() else {
        return Ok(Vec::new());
    };
    let (cell, w) = (first.lattice().cell(), first.field());
    let states: Vec<_> = walks.iter().map(|o| o.state().clone()).collect();
    let mut block = ArcBlock::new(path, cell, w, &states)?;
    let mut orbits: Vec<Tangent> = walks.iter().map(|o| Tangent::new(o, target)).collect();
    let vectors: Vec<_> = walks.iter().map(first_vector).collect();
    let mut state = TangentState {
        tangents: TangentBlock::new(&vectors),
        left: std::array::from_fn(|l| if l < walks.len() { target as f64 } else { 0.0 }),
        hits: vec![Hits::default(); RING],
    };
    let running = |orbits: &[Tangent]| {
        (orbits.iter().enumerate()).fold(0, |b, (l, t)| b | u64::from(t.running()) << l)
    };
    let first = running(&orbits);
    fly(
        &mut block,
        (opts.progress, opts.stop.as_ref()),
        first,
        |ring, block| {
            let mut work = RingTangents {
                cell,
                w,
                ring,
                state: &mut state,
            };
            on_path(path, &mut work)?;
            let counted = state.count(&mut orbits, w);
            for (l, t) in orbits.iter().enumerate().filter(|(_, t)| !t.running()) {
                block.retire(l);
                debug_assert_eq!(t.collisions, target);
            }
            Ok(Looked {
                counted,
                running: running(&orbits),
            })
        },
    )?;
    Ok(orbits)
}

/// The collisions of one ring entry: the lanes that collided, their vectors' growths and their
/// arcs' half-angle arguments ([`half_angle_time`]).
#[derive(Debug, Clone, Default)]
struct Hits {
    lanes: u64,
    growth: [f64; BLOCK],
    y: [f64; BLOCK],
    x: [f64; BLOCK],
}

/// The tangent vectors of a block's orbits (each carried until it has made its collisions:
/// `left`) and the collisions of the last ring.
struct TangentState {
    tangents: TangentBlock,
    left: [f64; BLOCK],
    hits: Vec<Hits>,
}

/// The tangent vectors carried through the events of one ring in vector lanes.
struct RingTangents<'a> {
    cell: &'a ConvexCell<f64>,
    w: f64,
    ring: &'a [ArcRecord],
    state: &'a mut TangentState,
}

impl TangentState {
    /// Gives every collision of the ring, in order, to its orbit; returns how many there were.
    fn count(&self, orbits: &mut [Tangent], w: f64) -> u64 {
        let mut n = 0;
        for h in &self.hits {
            for (l, t) in orbits.iter_mut().enumerate() {
                if h.lanes >> l & 1 == 1 {
                    t.collision(h.growth[l], half_angle_time(h.y[l], h.x[l], w));
                    n += 1;
                }
            }
        }
        n
    }
}

impl LaneWork for RingTangents<'_> {
    #[inline(always)]
    fn run<V: Lanes>(&mut self) {
        let cell = TangentCell::<V>::new(self.cell, self.w);
        let st = &mut *self.state;
        for h in &mut st.hits {
            h.lanes = 0;
        }
        for o in (0..BLOCK).step_by(V::WIDTH) {
            let mut t = TangentLane::<V>::load(&st.tangents, o);
            let mut left = V::load(&st.left[o..]);
            for (rec, h) in self.ring.iter().zip(&mut st.hits) {
                let b = &rec.before;
                let live = V::and(V::from_bits(b.live_bits >> o), left.gt(V::splat(0.0)));
                let at = |a: &[f64; BLOCK]| V::load(&a[o..]);
                let e = LaneEvent {
                    code: at(&b.code),
                    pos: [at(&b.pos[0]), at(&b.pos[1])],
                    vel: [at(&b.vel[0]), at(&b.vel[1])],
                    chord: [at(&rec.chord[0]), at(&rec.chord[1])],
                    arrival: [at(&rec.arrival[0]), at(&rec.arrival[1])],
                };
                let c = t.event(&cell, live, &e);
                left = V::select(c.lanes, left.sub(V::splat(1.0)), left);
                c.growth.store(&mut h.growth[o..]);
                c.y.store(&mut h.y[o..]);
                c.x.store(&mut h.x[o..]);
                h.lanes |= V::bits(c.lanes) << o;
            }
            t.store(&mut st.tangents, o);
            left.store(&mut st.left[o..]);
        }
    }
}
