//! The arc kernel's throughput (`lorentz bench --field B`): the generic cell kernel on arcs, one
//! trajectory per thread, events only.

use rayon::prelude::*;

use crate::Error;
use crate::engine::Engine;
use crate::engine::Resolved;
use crate::kernel::flight::EventKind;
use crate::kernel::trap::Trap;
use crate::numbers::precision::Precision;
use crate::numbers::real::Real;
use crate::scenes::lattice::{Lattice, LatticeState, TriangularLattice};
use crate::scenes::magnetic::DiskLattice;
use crate::scenes::sampling::stream;
use crate::scenes::triangular::equilibrium_state;
use crate::theory::magnetic::{FieldGeometry, Orbit};

use super::Observe;

/// Refuses what an arc benchmark cannot do yet: MPFR, observers, the SIMD engine. The engine
/// that runs: the scalar one.
pub(super) fn check(
    b: f64,
    precision: Precision,
    observe: Observe,
    engine: Engine,
) -> Result<Resolved, Error> {
    if !b.is_finite() {
        return Err(Error::NotFinite { what: "field" });
    }
    if precision != Precision::F64 {
        return Err(Error::Invalid(
            "bench with --field times the f64 arc kernel: leave out --precision".into(),
        ));
    }
    if observe != Observe::None {
        return Err(Error::Invalid(
            "bench with --field times the bare arc kernel: leave out --observe".into(),
        ));
    }
    if engine == Engine::Simd {
        return Err(Error::Invalid(
            "the SIMD engine has no arcs yet: use --engine scalar (or auto) with --field".into(),
        ));
    }
    Ok(Resolved::Scalar)
}

/// One start per thread from equilibrium (thread k: the seed's stream k), drawn again from the
/// same stream while it is on a pinned orbit (which never collides).
pub(super) fn starts<T: Real>(
    ctx: T::Ctx,
    trap64: &Trap<f64>,
    seed: u64,
    threads: usize,
    b: f64,
) -> Result<Vec<Vec<LatticeState<T>>>, Error> {
    let a = trap64.a;
    let lattice = DiskLattice {
        a,
        beta: 0.5,
        h: trap64.h,
        radius: 1.0,
    };
    let geometry = FieldGeometry::new(lattice, b)?;
    let lat64 = Lattice::from_kernel(trap64.clone());
    (0..threads)
        .map(|k| {
            let mut rng = stream(seed, k as u64);
            for _ in 0..1_000_000 {
                let s64 = equilibrium_state(trap64, &mut rng);
                let p = lat64.world(&s64);
                let sg = s64.cell.sign();
                let (vx, vy) = (sg * s64.flight.vel.x, sg * s64.flight.vel.y);
                if geometry.classify(p.x, p.y, vx, vy) != Orbit::Pinned {
                    let mut s = LatticeState::convert_from_f64(ctx, &s64);
                    s.flight.normalise_speed();
                    return Ok(vec![s]);
                }
            }
            Err(Error::Failed(
                "no start off a pinned orbit in 10^6 draws: almost every orbit is pinned at this field"
                    .into(),
            ))
        })
        .collect()
}

/// Every thread's trajectory continued by `n` collisions on arcs in the field `b`; returns the
/// crossings made.
pub(super) fn advance<T: Real>(
    pool: &rayon::ThreadPool,
    lat: &TriangularLattice<T>,
    states: &mut [Vec<LatticeState<T>>],
    n: u64,
    b: &T,
) -> Result<u64, Error> {
    pool.install(|| {
        states
            .par_iter_mut()
            .map(|block| {
                let mut crossings = 0;
                for s in block.iter_mut() {
                    let mut done = 0;
                    while done < n {
                        let ev = lat.next_event_in_field(s, b).ok_or_else(|| {
                            Error::Failed("a benchmark orbit has no next event".into())
                        })?;
                        lat.apply_in_field(s, &ev);
                        match ev.kind {
                            EventKind::Collision(_) => done += 1,
                            EventKind::Crossing(_) => crossings += 1,
                        }
                    }
                }
                Ok(crossings)
            })
            .collect::<Result<Vec<u64>, Error>>()
            .map(|v| v.iter().sum())
    })
}
