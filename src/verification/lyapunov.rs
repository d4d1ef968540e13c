//! Chaos, measured two ways.
//!
//! * [`lyapunov`]: the largest Lyapunov exponent from the tangent dynamics
//!   (`proofs-notes/tangent-map.md`) along long f64 orbits — a tangent vector is propagated
//!   event by event and renormalised; λ = Σ ln(growth)/N per collision and Σ ln(growth)/T per
//!   unit time, with the standard error over independent orbits.
//! * [`divergence`]: the same initial condition run at f64 and at 64 … 1024 bits against a 4096-bit
//!   reference; the deviation grows like u_P·e^{λk}, so the number of collisions before it passes
//!   10⁻³ (the divergence horizon) grows linearly in the number of bits, and the fitted growth
//!   rate is the Lyapunov exponent again (`proofs-notes/lyapunov.md`).

use nalgebra::Vector4;

use super::birkhoff::tangent_step;
use rug::Float;
use serde::Serialize;

use crate::engine::drive;
use crate::engine::metadata::RunMeta;
use crate::engine::parallel::par_batches;
use crate::kernel::cell::ConvexCell;
use crate::kernel::{cell::CellKernel, flight::EventKind};
use crate::numbers::lanes::Lanes;
use crate::numbers::real::Real;
use crate::observers::{EventLanes, Observer};
use crate::scenes::lattice::{Lattice, LatticeState};
use crate::scenes::sampling::stream;
use crate::scenes::Scene;
use crate::statistics::{linear_fit, mean_se};
use crate::Error;

/// Collisions discarded at the start of each tangent orbit, so the tangent vector has turned into
/// the unstable direction (it does so within a few collisions at λ ≈ 1 per collision; 1000 is
/// ample and costs 0.05 % of a default orbit).
pub const TANGENT_TRANSIENT: u64 = 1000;

/// Precisions (bits) whose divergence from the reference `lorentz lyapunov` measures, next to f64.
pub const DIVERGENCE_BITS: [u32; 5] = [64, 128, 256, 512, 1024];

/// Reference precision of the divergence measurement: four times the largest precision measured,
/// so the reference's own divergence horizon (~3000 collisions) lies beyond every horizon measured.
pub const DIVERGENCE_REFERENCE_BITS: u32 = 4096;

/// Collisions followed in the divergence measurement: beyond the 1024-bit horizon (~785
/// collisions at w = 0.1) with a margin.
pub const DIVERGENCE_COLLISIONS: usize = 900;

/// Largest Lyapunov exponent with its standard error.
#[derive(Debug, Clone, Serialize)]
pub struct LyapunovReport {
    /// The scene ([`Scene::label`]).
    pub scene: String,
    /// λ per collision.
    pub per_collision: f64,
    /// Its standard error over orbits.
    pub per_collision_err: f64,
    /// λ per unit time.
    pub per_time: f64,
    /// Its standard error.
    pub per_time_err: f64,
    /// Collisions per orbit (after a transient of 1000).
    pub collisions: u64,
    /// Independent orbits.
    pub orbits: u32,
    /// Version, seed, orbits, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// Tangent-space largest Lyapunov exponent from `orbits` independent f64 orbits of `collisions`
/// collisions each.
/// `progress` receives collision counts.
pub fn lyapunov<S: Scene>(
    scene: &S,
    collisions: u64,
    orbits: u32,
    seed: u64,
    threads: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<LyapunovReport, Error> {
    if collisions == 0 || orbits < 2 || threads == 0 {
        return Err(Error::TooFew {
            what: "collisions, orbits (>= 2) or threads",
            min: 2,
            got: orbits as u64,
        });
    }
    let lat = scene.lattice::<f64>(())?;
    let cell = lat.cell().clone();
    let per: Vec<(f64, f64)> = par_batches(threads, orbits, |b| {
        let mut rng = stream(seed, b as u64);
        let mut s = scene.sample(&mut rng);
        let d = crate::scenes::sampling::direction(&mut rng);
        let mut tangent = Tangent {
            t: Vector4::new(d.x, d.y, 0.3 * d.y, -0.3 * d.x),
            cell: &cell,
            collisions: 0,
            transient: TANGENT_TRANSIENT,
            logsum: 0.0,
            time: 0.0,
        };
        drive(
            &lat,
            &mut s,
            collisions + TANGENT_TRANSIENT,
            &mut tangent,
            progress,
        )?;
        let (logsum, time) = (tangent.logsum, tangent.time);
        Ok((logsum / collisions as f64, logsum / time))
    })?;
    let (pc, pce) = mean_se(&per.iter().map(|p| p.0).collect::<Vec<_>>());
    let (pt, pte) = mean_se(&per.iter().map(|p| p.1).collect::<Vec<_>>());
    Ok(LyapunovReport {
        scene: scene.label(),
        per_collision: pc,
        per_collision_err: pce,
        per_time: pt,
        per_time_err: pte,
        collisions,
        orbits,
        meta: RunMeta::new(Some(seed), Some(orbits as u64), "f64", Some(threads)),
    })
}

/// The tangent dynamics along one orbit (an observer of the scalar engine): the tangent vector
/// is carried through every event by the linearised map and renormalised at every collision;
/// after `transient` collisions, the logarithms of the growth factors and the flight times are
/// summed.
struct Tangent<'a> {
    t: Vector4<f64>,
    cell: &'a ConvexCell<f64>,
    collisions: u64,
    transient: u64,
    logsum: f64,
    time: f64,
}

impl Observer<1> for Tangent<'_> {
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<1>]) {
        for e in steps {
            let (s, ev) = (e.state(0), e.event(0));
            tangent_step(&mut self.t, &s.flight, &ev, self.cell);
            if self.collisions >= self.transient {
                self.time += ev.time;
            }
            if let EventKind::Collision(_) = ev.kind {
                self.collisions += 1;
                let n = self.t.norm();
                self.t /= n;
                if self.collisions > self.transient {
                    self.logsum += n.ln();
                }
            }
        }
    }
}

/// World contact points and velocities at the first `n` collisions of an orbit, as 4096-bit
/// (or lower) numbers converted to `Float` at `out_bits`.
pub(crate) fn collision_track<T: Real, K: CellKernel<T>>(
    lat: &Lattice<T, K>,
    start: &LatticeState<T>,
    n: usize,
    out_bits: u32,
) -> Result<Vec<([Float; 4], f64)>, Error> {
    let mut s = start.clone();
    let mut out = Vec::with_capacity(n);
    let mut time = 0.0;
    while out.len() < n {
        let ev = lat.step(&mut s)?;
        time += ev.time.to_f64();
        if let EventKind::Collision(_) = ev.kind {
            let x = lat.world(&s);
            let (vx, vy) = if s.cell.down {
                (-s.flight.vel.x.clone(), -s.flight.vel.y.clone())
            } else {
                (s.flight.vel.x.clone(), s.flight.vel.y.clone())
            };
            // Exact: every T value is a binary float of ≤ out_bits bits.
            let conv = |v: &T| -> Float { v.to_mpfr(out_bits) };
            out.push(([conv(&x.x), conv(&x.y), conv(&vx), conv(&vy)], time));
        }
    }
    Ok(out)
}

/// The divergence of one precision from the reference.
#[derive(Debug, Clone, Serialize)]
pub struct Divergence {
    /// "f64" or bits.
    pub precision: String,
    /// Collisions until the deviation first exceeds 10⁻³ (mean over initial conditions).
    pub horizon: f64,
    /// Its standard error.
    pub horizon_err: f64,
    /// Fitted growth rate of ln(deviation) per collision (mean ± SE over initial conditions).
    pub rate_per_collision: f64,
    /// Its standard error.
    pub rate_per_collision_err: f64,
    /// Fitted growth rate per unit time.
    pub rate_per_time: f64,
    /// Its standard error.
    pub rate_per_time_err: f64,
}

/// Runs `starts` equilibrium initial conditions at f64 and at each of `bits`, against a reference
/// at `ref_bits`, for `n` collisions; fits ln(deviation) against collision number (and time) where
/// 10⁴·u_P < deviation < 10⁻³.
pub fn divergence<S: Scene>(
    scene: &S,
    bits: &[u32],
    ref_bits: u32,
    n: usize,
    starts: u32,
    seed: u64,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<Divergence>, Error> {
    if let Some(&b) = bits.iter().find(|&&b| b >= ref_bits) {
        return Err(Error::Invalid(format!(
            "divergence: precision {b} bits must be below the reference's {ref_bits} bits"
        )));
    }
    let l64 = scene.lattice::<f64>(())?;
    let lref = scene.lattice::<Float>(ref_bits)?;
    let mut precs: Vec<Option<u32>> = vec![None];
    precs.extend(bits.iter().map(|&b| Some(b)));
    let mut per: Vec<Vec<(f64, f64, f64)>> = vec![Vec::new(); precs.len()];
    for k in 0..starts {
        progress(1);
        let s64 = scene.sample(&mut stream(seed, k as u64));
        let r = collision_track(
            &lref,
            &LatticeState::<Float>::convert_from_f64(ref_bits, &s64),
            n,
            ref_bits,
        )?;
        for (pi, p) in precs.iter().enumerate() {
            let track = match p {
                None => collision_track(&l64, &s64, n, ref_bits)?,
                Some(b) => {
                    let lat = scene.lattice::<Float>(*b)?;
                    collision_track(
                        &lat,
                        &LatticeState::<Float>::convert_from_f64(*b, &s64),
                        n,
                        ref_bits,
                    )?
                }
            };
            let u = (-(p.unwrap_or(53) as f64)).exp2();
            let mut dev = Vec::with_capacity(n);
            for (a, b) in track.iter().zip(&r) {
                let mut d = Float::with_val(ref_bits, 0);
                for i in 0..4 {
                    d += (a.0[i].clone() - &b.0[i]).abs();
                }
                dev.push((d.to_f64(), b.1));
            }
            let horizon = dev.iter().position(|d| d.0 > 1e-3).unwrap_or(n) as f64;
            let (mut xs, mut ts, mut ys) = (Vec::new(), Vec::new(), Vec::new());
            for (i, d) in dev.iter().enumerate() {
                if d.0 > 1e4 * u && d.0 < 1e-3 && (i as f64) < horizon {
                    xs.push(i as f64);
                    ts.push(d.1);
                    ys.push(d.0.ln());
                }
            }
            if xs.len() >= 5 {
                per[pi].push((horizon, linear_fit(&xs, &ys).1, linear_fit(&ts, &ys).1));
            } else {
                per[pi].push((horizon, f64::NAN, f64::NAN));
            }
        }
    }
    Ok(precs
        .iter()
        .zip(per)
        .map(|(p, v)| {
            let h: Vec<f64> = v.iter().map(|x| x.0).collect();
            let rc: Vec<f64> = v.iter().map(|x| x.1).filter(|x| x.is_finite()).collect();
            let rt: Vec<f64> = v.iter().map(|x| x.2).filter(|x| x.is_finite()).collect();
            let (hm, he) = mean_se(&h);
            let (cm, ce) = mean_se(&rc);
            let (tm, te) = mean_se(&rt);
            Divergence {
                precision: p.map(|b| b.to_string()).unwrap_or_else(|| "f64".into()),
                horizon: hm,
                horizon_err: he,
                rate_per_collision: cm,
                rate_per_collision_err: ce,
                rate_per_time: tm,
                rate_per_time_err: te,
            }
        })
        .collect())
}
