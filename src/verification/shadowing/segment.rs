//! The `f64` segments that are shadowed: collisions of a straight or arc orbit recorded as
//! Birkhoff points at the working precision.

use super::*;

/// Most events run by [`f64_segment`] per collision recorded before it gives up (a finite-horizon
/// table has a collision every few events).
const EVENTS_PER_COLLISION: usize = 1000;

/// The first `n` collisions of the `f64` orbit from `start`, as Birkhoff points at `bits`: the
/// disk's lattice indices from the f64 world centre (rounded to the lattice, checked to 10⁻⁶),
/// s and p from the f64 contact point and velocity lifted exactly and the disk centre at `bits`
/// (so the points are the f64 states projected to the exact table's phase space).
///
/// # Errors
/// If a collision's disk is not a lattice point, or `n` collisions take more than 1000n events.
pub fn f64_segment<S: Scene>(
    scene: &S,
    start: &LatticeState<f64>,
    n: usize,
    bits: u32,
) -> Result<Vec<OrbitPoint>, Error> {
    let lat = scene.lattice::<f64>(())?;
    record_segment(scene, start, n, bits, |st| Ok(lat.step(st)?.kind))
}

/// As [`f64_segment`], on the `f64` arc kernel in the field `field` (the double the field runs
/// use, nonzero).
///
/// # Errors
/// As [`f64_segment`]; an orbit without a next event (pinned, or a creeping slide).
pub fn f64_segment_in_field<S: Scene>(
    scene: &S,
    start: &LatticeState<f64>,
    field: f64,
    n: usize,
    bits: u32,
) -> Result<Vec<OrbitPoint>, Error> {
    let lat = scene.lattice::<f64>(())?;
    record_segment(scene, start, n, bits, |st| {
        let ev = lat.next_event_in_field(st, &field).ok_or_else(|| {
            Error::Failed(format!(
                "the f64 arc in the field {field:e} has no next event"
            ))
        })?;
        lat.apply_in_field(st, &ev);
        Ok(ev.kind)
    })
}

/// As [`f64_segment`], on the `f64` thermostat kernel in the field `fields` (the run's own
/// [`CellFields`](crate::scenes::thermostat::CellFields)).
///
/// # Errors
/// As [`f64_segment`]; a flight without a next event (a creeping slide).
pub fn f64_segment_in_thermostat<S: Scene>(
    scene: &S,
    start: &LatticeState<f64>,
    fields: &crate::scenes::thermostat::CellFields<f64>,
    n: usize,
    bits: u32,
) -> Result<Vec<OrbitPoint>, Error> {
    let lat = scene.lattice::<f64>(())?;
    record_segment(scene, start, n, bits, |st| {
        Ok(lat.step_thermostat(st, fields)?.kind)
    })
}

/// The first `n` collisions of the orbit from `start` advanced event by event by `step`.
fn record_segment<S: Scene>(
    scene: &S,
    start: &LatticeState<f64>,
    n: usize,
    bits: u32,
    mut step: impl FnMut(&mut LatticeState<f64>) -> Result<EventKind, Error>,
) -> Result<Vec<OrbitPoint>, Error> {
    let lat = scene.lattice::<f64>(())?;
    let latp = scene.lattice::<Float>(bits)?;
    let mut st = start.clone();
    let mut out = Vec::with_capacity(n);
    let mut events = 0usize;
    while out.len() < n {
        let kind = step(&mut st)?;
        events += 1;
        if events > EVENTS_PER_COLLISION * (n + 1) {
            return Err(Error::Failed(format!(
                "no collision in {events} events: the table has an open corridor"
            )));
        }
        if let EventKind::Collision(m) = kind {
            out.push(birkhoff_point(&lat, &latp, &st, m, bits)?);
        }
    }
    Ok(out)
}

/// The collision state `st` just after a collision with disk `m` of its cell, as a Birkhoff
/// point at `bits` (see [`f64_segment`]).
fn birkhoff_point<K64, KP>(
    lat: &crate::scenes::lattice::Lattice<f64, K64>,
    latp: &crate::scenes::lattice::Lattice<Float, KP>,
    st: &LatticeState<f64>,
    m: u8,
    bits: u32,
) -> Result<OrbitPoint, Error>
where
    K64: crate::kernel::cell::CellKernel<f64>,
    KP: crate::kernel::cell::CellKernel<Float>,
{
    let basis = &lat.cell().lattice;
    let f = &st.flight;
    let c64 = &lat.cell().disks[m as usize].centre;
    let cw = lat.world(&LatticeState {
        cell: st.cell,
        flight: crate::kernel::flight::Flight::new(c64.clone(), f.vel.clone()),
    });
    let j = (cw.y / basis.h).round();
    let i = (cw.x / basis.a - basis.beta * j).round();
    let (ex, ey) = (basis.a * (i + basis.beta * j) - cw.x, basis.h * j - cw.y);
    if ex.hypot(ey) > 1e-6 * (1.0 + cw.x.abs() + cw.y.abs()) {
        return Err(Error::Failed(format!(
            "disk centre ({}, {}) is not a lattice point",
            cw.x, cw.y
        )));
    }
    let cp = &latp.cell().disks[m as usize].centre;
    let mut nx = Float::with_val(bits, f.pos.x) - &cp.x;
    let mut ny = Float::with_val(bits, f.pos.y) - &cp.y;
    let (vx, vy) = (
        Float::with_val(bits, f.vel.x),
        Float::with_val(bits, f.vel.y),
    );
    let norm = (nx.clone().square() + &ny.clone().square()).sqrt()
        * &(vx.clone().square() + &vy.clone().square()).sqrt();
    // n × v is invariant under the frame's point reflection (both flip); θ is not.
    let p = (nx.clone() * &vy - &(ny.clone() * &vx)) / &norm;
    if st.cell.down {
        nx = -nx;
        ny = -ny;
    }
    let s = Float::with_val(bits, ny.atan2_ref(&nx));
    Ok(OrbitPoint {
        disk: [i as i64, j as i64],
        s,
        p,
    })
}

/// The segment of `config`'s run number `k`: the `f64` orbit from the equilibrium start of
/// batch k (in a field, the diffusing start of batch k of the transport run in that field; under
/// the thermostat, the equilibrium start of batch k flown under it).
pub(super) fn seeded_segment<S: Scene>(
    scene: &S,
    config: &ShadowConfig,
    field: Option<&(rug::Rational, crate::theory::magnetic::FieldGeometry)>,
    motion: Option<&ExactMotion>,
    k: u32,
) -> Result<Vec<OrbitPoint>, Error> {
    let (n, bits, seed) = (
        config.collisions_per_segment,
        config.reference_bits,
        config.seed,
    );
    let Some((_, geometry)) = field else {
        let start = scene.sample(&mut stream(seed, k as u64));
        if let Some(ExactMotion::Thermostat { field, angle }) = motion {
            let th = crate::kernel::thermostat::Thermostat::<f64>::exact(field, angle, ());
            let fields = crate::scenes::thermostat::CellFields::new(th.expect("a nonzero field"));
            return f64_segment_in_thermostat(scene, &start, &fields, n, bits);
        }
        return f64_segment(scene, &start, n, bits);
    };
    let key = crate::scenes::sampling::StreamKey::new(
        seed,
        crate::scenes::sampling::Purpose::Trajectory,
        k as u64,
    );
    let (mut start, _) = geometry.diffusing_start(scene, &mut key.rng())?;
    start.flight.normalise_speed();
    f64_segment_in_field(scene, &start, geometry.field(), n, bits)
}
