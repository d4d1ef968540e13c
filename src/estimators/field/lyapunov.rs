//! The largest Lyapunov exponent in a magnetic field (`lorentz lyapunov --field B`): tangent
//! vectors carried through the arc kernel's events by the magnetic tangent map
//! ([`crate::verification::arc_tangent`], `proofs-notes/tangent-map.md`) along orbits started in
//! the diffusing part of phase space (orbit b starts where batch b of the transport run in the
//! same field starts: the invariant measure with the pinned and skipping orbits set aside, on
//! which the exponent is 0), renormalised at every collision. λ per collision and per unit time,
//! with standard errors over orbits. Compare Datseris, Hupe & Fleischmann, Chaos 29, 093115 (2019).

use nalgebra::Vector4;
use serde::{Deserialize, Serialize};

use super::FieldWalk;
use super::lanes::RING;
use crate::Error;
use crate::engine::arcs::{ArcBlock, ArcRecord};
use crate::engine::metadata::RunMeta;
use crate::engine::options::{RunOption, RunOptions};
use crate::engine::parallel::{par_batches_watched, par_lane_blocks};
use crate::engine::{Resolved, SimdPath};
use crate::kernel::arc::arc_time;
use crate::kernel::cell::ConvexCell;
use crate::kernel::field::ArcEvent;
use crate::kernel::flight::{EventKind, Flight};
use crate::scenes::Scene;
use crate::scenes::magnetic::no_next_event;
use crate::statistics::mean_se;
use crate::theory::magnetic::FieldGeometry;
use crate::verification::arc_tangent::arc_tangent_step;
use crate::verification::lyapunov::{LyapunovConfig, LyapunovReport, TANGENT_TRANSIENT};

/// What a Lyapunov measurement in a field runs: the orbits of [`LyapunovConfig`] in the field B.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FieldLyapunovConfig {
    /// Collisions of each batch (one orbit), after a transient of [`TANGENT_TRANSIENT`].
    pub collisions_per_batch: u64,
    /// Independent batches (orbits), at least 2; the error is over them.
    pub batches: u32,
    /// Seed: orbit b starts where batch b of the transport run with this seed starts.
    pub seed: u64,
    /// The field B, an exact decimal or fraction, 10⁻³ ≤ |B| ≤ 10³.
    pub field: String,
}

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
    pub config: FieldLyapunovConfig,
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
    cfg: &FieldLyapunovConfig,
    opts: &RunOptions,
) -> Result<FieldLyapunovReport, Error> {
    opts.validate()?;
    opts.refuse_unused("lyapunov in a field", &[RunOption::Engine])?;
    let b = super::field_value(&cfg.field)?;
    if cfg.collisions_per_batch == 0 || cfg.batches < 2 {
        return Err(Error::TooFew {
            what: "collisions_per_batch, batches (>= 2)",
            min: 2,
            got: cfg.batches as u64,
        });
    }
    crate::engine::check_trajectory_length(cfg.collisions_per_batch)?;
    let geometry = FieldGeometry::new(
        crate::scenes::require_disk_lattice(scene, "Lyapunov in a field")?,
        b,
    )?;
    let engine = opts.engine.resolve(true)?;
    let start = |i: u32| FieldWalk::start(scene, &cfg.field, cfg.seed, i as u64);
    let target = cfg.collisions_per_batch + TANGENT_TRANSIENT;
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

/// The report of the finished `orbits`.
fn report<S: Scene>(
    scene: &S,
    cfg: &FieldLyapunovConfig,
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
            scene: format!("{} B={}", scene.label(), cfg.field),
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

/// Collisions between two reports of progress (and looks at the stop flag) by one orbit.
const REPORT_EVERY: u64 = 1 << 16;

/// The tangent vector (δq, δv) of one orbit, in its state's cell frame, and its sums: every
/// event carries it on ([`arc_tangent_step`]), every collision renormalises it, and after
/// [`TANGENT_TRANSIENT`] collisions the logarithms of its growth and the flight time add up.
/// The scalar and the lane drivers feed it the same events, so they give the same bits.
struct Tangent {
    vector: Vector4<f64>,
    collisions: u64,
    target: u64,
    logsum: f64,
    time: f64,
    rejected: u64,
}

impl Tangent {
    /// The orbit of `walk`, its tangent vector (Jv, 0.3·Jv) (transverse to the flow and on the
    /// energy shell), to run to `target` collisions.
    fn new(walk: &FieldWalk<impl Scene>, target: u64) -> Self {
        let v = &walk.state().flight.vel;
        Tangent {
            vector: Vector4::new(-v.y, v.x, -0.3 * v.y, 0.3 * v.x),
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

    /// The event `ev` of the flight `f` (cell `cell`, field `w`); `true` for a collision.
    fn event(
        &mut self,
        f: &Flight<f64>,
        ev: &ArcEvent<f64>,
        cell: &ConvexCell<f64>,
        w: f64,
    ) -> bool {
        let time = arc_time(&f.vel, &ev.chord, &w);
        arc_tangent_step(&mut self.vector, f, ev, time, cell, w);
        if self.collisions >= TANGENT_TRANSIENT {
            self.time += time;
        }
        let EventKind::Collision(_) = ev.kind else {
            return false;
        };
        self.collisions += 1;
        let g = self.vector.norm();
        self.vector /= g;
        if self.collisions > TANGENT_TRANSIENT {
            self.logsum += g.ln();
        }
        true
    }
}

/// One orbit on the scalar arc kernel.
fn scalar<S: Scene>(walk: &FieldWalk<S>, target: u64, opts: &RunOptions) -> Result<Tangent, Error> {
    let (lattice, w) = (walk.lattice(), walk.field());
    let mut state = walk.state().clone();
    let mut t = Tangent::new(walk, target);
    while t.running() {
        let ev = lattice
            .next_event_in_field(&state, &w)
            .ok_or_else(|| no_next_event(state.flight.vel.to_f64()))?;
        if t.event(&state.flight, &ev, lattice.cell(), w) && t.collisions % REPORT_EVERY == 0 {
            (opts.progress)(REPORT_EVERY);
            if let Some(stop) = &opts.stop {
                stop.check()?;
            }
        }
        lattice.apply_in_field(&mut state, &ev);
    }
    (opts.progress)(t.collisions % REPORT_EVERY);
    Ok(t)
}

/// The orbits of `walks` (at most [`crate::engine::simd::BLOCK`]) in the lanes of one block of
/// the SIMD arc engine, each lane the scalar kernel bit for bit and each recorded event fed to
/// its orbit's [`Tangent`] as [`scalar`] feeds it.
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
    let mut ring = vec![ArcRecord::default(); RING];
    let mut unreported = 0;
    while orbits.iter().any(Tangent::running) {
        let lost = block.advance(&mut ring);
        for rec in &ring {
            for (l, t) in orbits.iter_mut().enumerate() {
                let Some((before, ev)) = rec.event(l).filter(|_| t.running()) else {
                    continue;
                };
                unreported += u64::from(t.event(&before.flight, &ev, cell, w));
                if !t.running() {
                    block.retire(l);
                }
            }
        }
        if let Some(l) = lost.filter(|&l| orbits[l].running()) {
            return Err(no_next_event(block.state(l).flight.vel.to_f64()));
        }
        if unreported >= REPORT_EVERY {
            (opts.progress)(unreported);
            unreported = 0;
            if let Some(stop) = &opts.stop {
                stop.check()?;
            }
        }
    }
    (opts.progress)(unreported);
    Ok(orbits)
}

/// The defaults of [`LyapunovConfig`] in the field `field`.
impl FieldLyapunovConfig {
    /// 2·10⁶ collisions in each of 16 batches, seed 1, as without a field.
    pub fn new(field: &str) -> Self {
        let l = LyapunovConfig::new();
        FieldLyapunovConfig {
            collisions_per_batch: l.collisions_per_batch,
            batches: l.batches,
            seed: l.seed,
            field: field.trim().to_string(),
        }
    }
}
