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
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::parallel::par_batches_watched;
use crate::kernel::arc::arc_time;
use crate::kernel::cell::CellKernel;
use crate::kernel::flight::EventKind;
use crate::scenes::Scene;
use crate::scenes::lattice::{Lattice, LatticeState};
use crate::statistics::mean_se;
use crate::theory::magnetic::FieldGeometry;
use crate::verification::arc_tangent::{arc_flight, arc_tangent_step};
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

/// Runs the measurement (see the module documentation).
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
    opts.refuse_unused("lyapunov in a field", &[])?;
    let b = super::field_value(&cfg.field)?;
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
    let per = par_batches_watched(opts.threads, cfg.batches, opts.stop.as_ref(), |i| {
        let walk = FieldWalk::start(scene, &cfg.field, cfg.seed, i as u64)?;
        let orbit = Orbit::new(walk.lattice(), walk.state().clone(), b);
        let (logsum, time) = orbit.run(cfg.collisions_per_batch, opts)?;
        Ok((
            logsum / cfg.collisions_per_batch as f64,
            logsum / time,
            walk.rejected(),
        ))
    })?;
    let (pc, pce) = mean_se(&per.iter().map(|p| p.0).collect::<Vec<_>>());
    let (pt, pte) = mean_se(&per.iter().map(|p| p.1).collect::<Vec<_>>());
    Ok(FieldLyapunovReport {
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
            meta: RunMeta::new(
                Some(cfg.seed),
                Some(cfg.batches as u64),
                "f64",
                Some(opts.threads),
            ),
        },
        field: b,
        cyclotron_radius: geometry.cyclotron_radius(),
        localized_fraction_exact: geometry.localized_fraction(),
        rejected_starts: per.iter().map(|p| p.2).sum(),
        config: cfg.clone(),
    })
}

/// One orbit in the field with its tangent vector.
pub struct Orbit<'a, K: CellKernel<f64>> {
    lattice: &'a Lattice<f64, K>,
    /// The state.
    pub state: LatticeState<f64>,
    /// The tangent vector (δq, δv) in the state's cell frame.
    pub tangent: Vector4<f64>,
    field: f64,
}

impl<'a, K: CellKernel<f64>> Orbit<'a, K> {
    /// The orbit from `state` with the tangent vector (Jv, 0.3·Jv): transverse to the flow and on
    /// the energy shell.
    pub fn new(lattice: &'a Lattice<f64, K>, state: LatticeState<f64>, field: f64) -> Self {
        let v = &state.flight.vel;
        let tangent = Vector4::new(-v.y, v.x, -0.3 * v.y, 0.3 * v.x);
        Orbit {
            lattice,
            state,
            tangent,
            field,
        }
    }

    /// The next event of the arc kernel with its flight time, carried out on the state and the
    /// tangent vector.
    ///
    /// # Errors
    /// No next event (a pinned orbit or a creeping slide).
    pub fn step(&mut self) -> Result<(EventKind, f64), Error> {
        let w = self.field;
        let ev = self
            .lattice
            .next_event_in_field(&self.state, &w)
            .ok_or_else(|| Error::Failed("an orbit in the field has no next event".into()))?;
        let time = arc_time(&self.state.flight.vel, &ev.chord, &w);
        let cell = self.lattice.cell();
        arc_tangent_step(&mut self.tangent, &self.state.flight, &ev, time, cell, w);
        self.lattice.apply_in_field(&mut self.state, &ev);
        Ok((ev.kind, time))
    }

    /// Moves the tangent vector on by the free flight `time` (no event on the way).
    pub fn drift(&mut self, time: f64) {
        arc_flight(&mut self.tangent, time, self.field);
    }

    /// Runs `collisions` collisions after [`TANGENT_TRANSIENT`], renormalising at every one:
    /// (Σ ln growth, flight time) over the counted collisions.
    fn run(mut self, collisions: u64, opts: &RunOptions) -> Result<(f64, f64), Error> {
        let (mut n, mut logsum, mut time) = (0u64, 0.0, 0.0);
        while n < collisions + TANGENT_TRANSIENT {
            let (kind, t) = self.step()?;
            if n >= TANGENT_TRANSIENT {
                time += t;
            }
            if let EventKind::Collision(_) = kind {
                n += 1;
                let g = self.tangent.norm();
                self.tangent /= g;
                if n > TANGENT_TRANSIENT {
                    logsum += g.ln();
                }
                if n % (1 << 16) == 0 {
                    (opts.progress)(1 << 16);
                    if let Some(stop) = &opts.stop {
                        stop.check()?;
                    }
                }
            }
        }
        (opts.progress)(n % (1 << 16));
        Ok((logsum, time))
    }
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
