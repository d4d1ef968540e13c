//! The walk both curved oracles take ([`super::arcs`], [`super::thermostat`]): a decoded start
//! flown in `f64` and in MPFR at 53 bits side by side on one [`Curved`] motion, every event the
//! same in both to the bit and judged by the motion's own checks, the state kept in the domain
//! where the two agree bit for bit.

use super::arcs::{in_domain, into_domain};
use super::*;
use crate::scenes::lattice::Lattice;
use crate::verification::curved::{Curved, CurvedEvent};

/// What judges one event: the state before it, the event, the state after it, the report.
pub(super) type Judge<'j> = dyn FnMut(
        &LatticeState<f64>,
        &CurvedEvent<f64>,
        &LatticeState<f64>,
        &mut OracleReport,
    ) -> Result<(), String>
    + 'j;

/// Flies `start` of `scene` (brought into the domain), whose `f64` lattice is `lat`, on the
/// motion `m64` and its MPFR-53 twin `m53` for up to `steps` events; a flight without a next event in both ends the input.
///
/// # Errors
/// The first violation, with the state before the failing event: different events or states in
/// the two, `judge`'s verdict, or a state that left the domain.
pub(super) fn walk<S: Scene>(
    scene: &S,
    lat: &Lattice<f64, S::Kernel<f64>>,
    (case, label, steps): (Option<PrimitiveCase>, &str, u32),
    start: &LatticeState<f64>,
    (m64, m53): (&Curved<f64>, &Curved<Float>),
    judge: &mut Judge<'_>,
) -> Result<OracleReport, OracleFailure> {
    let fail_at = |event: Option<u64>, reason: String, state: String| {
        OracleFailure::new(case, label, event, reason, state)
    };
    let l53 = scene
        .lattice::<Float>(53)
        .map_err(|e| fail_at(None, e.to_string(), String::new()))?;
    let mut s = into_domain(lat.cell(), start.clone());
    let mut m = LatticeState::<Float>::convert_from_f64(53, &s);
    let mut rep = OracleReport::new(case, label.to_string());
    for n in 0..u64::from(steps) {
        let before = s.clone();
        let fail = |reason: String| fail_at(Some(n), reason, format!("{before:?}"));
        let (ev, ev53) = (m64.next(lat, &s), m53.next(&l53, &m));
        let Some((ev, ev53)) = super::both(ev, ev53).map_err(fail)? else {
            break;
        };
        m64.apply(lat, &mut s, &ev);
        m53.apply(&l53, &mut m, &ev53);
        if ev.kind() != ev53.kind() || m.to_f64() != s {
            return Err(fail(format!(
                "MPFR-53 {:?} to {:?}, f64 {:?} to {s:?}",
                ev53.kind(),
                m.to_f64(),
                ev.kind()
            )));
        }
        judge(&before, &ev, &s, &mut rep).map_err(fail)?;
        if !in_domain(&s) {
            return Err(fail(format!("left the kernel's domain: {s:?}")));
        }
        rep.events += 1;
    }
    Ok(rep)
}

/// The state after the event `kind` is finite and of unit speed within `band` units of
/// rounding (the worst kept in `rep`).
pub(super) fn unit_speed_after(
    fl: &Flight<f64>,
    kind: EventKind,
    band: f64,
    rep: &mut OracleReport,
) -> Result<(), String> {
    super::finite_after(fl, kind)?;
    let dev = (fl.vel.norm2() - 1.0).abs() / U;
    rep.worst_energy_u = rep.worst_energy_u.max(dev);
    if dev.is_nan() || dev > band {
        return Err(format!(
            "|v|^2 - 1 = {dev} u after {kind:?} (band {band} u)"
        ));
    }
    Ok(())
}

/// After the event `kind` the particle is in the cell the event leaves it in, and excludes the
/// obstacle it met and nothing else: the disk after a collision, the edge entered after a
/// crossing (counted in `rep`).
pub(super) fn cell_and_exclusions_after(
    cell: &ConvexCell<f64>,
    before: &LatticeState<f64>,
    kind: EventKind,
    after: &LatticeState<f64>,
    rep: &mut OracleReport,
) -> Result<(), String> {
    let fl = &after.flight;
    match kind {
        EventKind::Collision(m) => {
            rep.collisions += 1;
            if after.cell != before.cell
                || fl.excluded_disk != Some(m)
                || fl.excluded_edge.is_some()
            {
                return Err(format!("cell or exclusions after collision {m}: {after:?}"));
            }
        }
        EventKind::Crossing(k) => {
            rep.crossings += 1;
            let edge = &cell.edges[k as usize];
            if after.cell != before.cell.across(edge) || fl.excluded_edge != Some(edge.entered) {
                return Err(format!("cell or exclusions after crossing {k}: {after:?}"));
            }
        }
    }
    Ok(())
}
