//! The lattice stepper: a decoded lattice state stepped in f64 with the invariants checked after every event.

use super::*;

/// Steps the lattice state `start` of `scene` up to `steps` events in `f64` and checks after
/// every event (bounds of `tests/numerics/kernel_properties.rs`, `tests/numerics/square.rs`,
/// `proofs-notes/energy.md`, `tests/numerics/physics.rs`), for any cell:
///
/// * event time finite, ≥ 0 and ≤ 2·diameter of the cell polygon; state finite;
/// * after a collision ||v|² − 1| ≤ [`energy_band`]·u; after a crossing |v|² unchanged bit for
///   bit (translations and point reflections are exact);
/// * |x − c|² ≥ r² − 256u for every disk, σₖ(x) ≥ −256u·extent for every edge;
/// * unwrapped world displacement = t·(s·v) within 64ε(diameter + t);
/// * the cell index moves by [`CellIndex::across`] exactly on a crossing and not at all on a
///   collision; the disk hit (`Some(m)`) / edge entered (`Some(edge.entered)`) is the one
///   excluded.
///
/// # Errors
/// The first violation, with the state before the failing event.
pub fn step_lattice<S: Scene>(
    scene: &S,
    case: Option<PrimitiveCase>,
    start: &LatticeState<f64>,
    steps: u32,
) -> Result<OracleReport, OracleFailure> {
    let label = scene.label();
    let lat = scene
        .lattice::<f64>(())
        .map_err(|e| OracleFailure::new(case, &label, None, e.to_string(), format!("{start:?}")))?;
    let basis = lat.basis_f64();
    let bounds = EventBounds::new(lat.cell().clone());
    let diam = bounds.diam;
    let mut s = start.clone();
    let mut rep = OracleReport::new(case, label.clone());
    for n in 0..steps as u64 {
        let before = s.clone();
        let fail = |reason: String| {
            OracleFailure::new(case, &label, Some(n), reason, format!("{before:?}"))
        };
        let u_before = lat.unwrapped(&s, 0.0);
        let sg = s.cell.sign();
        let (vx, vy) = (sg * s.flight.vel.x, sg * s.flight.vel.y);
        let ev = lat
            .step(&mut s)
            .map_err(|e| fail(format!("step failed: {e}")))?;
        bounds
            .check_after(&before, &ev, &s, &mut rep)
            .map_err(fail)?;
        let d = lat.unwrapped(&s, 0.0).displacement_from(&u_before, &basis);
        let err = ((d[0] - ev.time * vx).powi(2) + (d[1] - ev.time * vy).powi(2)).sqrt();
        if err.is_nan() || err > UNWRAP_EPS * f64::EPSILON * (diam + ev.time) {
            return Err(fail(format!("unwrapped jump {err:e} over {:?}", ev.kind)));
        }
        rep.events += 1;
    }
    Ok(rep)
}

/// The cell of [`step_lattice`] with the bounds its per-event checks use: extent, diameter and
/// energy band.
pub(super) struct EventBounds {
    pub(super) cell: ConvexCell<f64>,
    pub(super) extent: f64,
    pub(super) diam: f64,
    pub(super) band: f64,
}

impl EventBounds {
    /// The bounds of `cell`.
    pub(super) fn new(cell: ConvexCell<f64>) -> Self {
        EventBounds {
            extent: cell.extent(),
            diam: diameter(&cell),
            band: energy_band(&cell),
            cell,
        }
    }

    /// The checks of one event `ev` from `before` to `after` but the unwrapped displacement,
    /// counting it in `rep`; the reason of the first violation.
    pub(super) fn check_after(
        &self,
        before: &LatticeState<f64>,
        ev: &Event<f64>,
        after: &LatticeState<f64>,
        rep: &mut OracleReport,
    ) -> Result<(), String> {
        let fl = &after.flight;
        if !(ev.time.is_finite() && ev.time >= 0.0 && ev.time <= 2.0 * self.diam) {
            return Err(format!("bad event time {:e} ({:?})", ev.time, ev.kind));
        }
        if ![fl.pos.x, fl.pos.y, fl.vel.x, fl.vel.y]
            .iter()
            .all(|x| x.is_finite())
        {
            return Err(format!("non-finite state after {:?}: {fl:?}", ev.kind));
        }
        match ev.kind {
            EventKind::Collision(m) => self.check_collision(m, before, after, rep)?,
            EventKind::Crossing(k) => self.check_crossing(k, before, after, rep)?,
        }
        self.check_position(fl, ev.kind)
    }

    /// After collision `m`: |v|² within the energy band, the same cell, disk `m` excluded.
    pub(super) fn check_collision(
        &self,
        m: u8,
        before: &LatticeState<f64>,
        after: &LatticeState<f64>,
        rep: &mut OracleReport,
    ) -> Result<(), String> {
        let (fl, band) = (&after.flight, self.band);
        let e2 = fl.vel.norm2();
        rep.collisions += 1;
        let dev = (e2 - 1.0).abs() / U;
        rep.worst_energy_u = rep.worst_energy_u.max(dev);
        if dev.is_nan() || dev > band {
            return Err(format!(
                "|v|^2 - 1 = {:e} = {dev} u after a collision (band {band} u)",
                e2 - 1.0
            ));
        }
        if after.cell != before.cell {
            return Err(format!("cell changed on a collision: {:?}", after.cell));
        }
        if fl.excluded_disk != Some(m) || fl.excluded_edge.is_some() {
            return Err(format!("exclusions after collision {m}: {fl:?}"));
        }
        Ok(())
    }

    /// After crossing edge `k`: |v|² unchanged bit for bit, the cell moved across the edge, the
    /// edge entered excluded.
    pub(super) fn check_crossing(
        &self,
        k: u8,
        before: &LatticeState<f64>,
        after: &LatticeState<f64>,
        rep: &mut OracleReport,
    ) -> Result<(), String> {
        let fl = &after.flight;
        let (e2_before, e2) = (before.flight.vel.norm2(), fl.vel.norm2());
        rep.crossings += 1;
        if e2.to_bits() != e2_before.to_bits() {
            return Err(format!(
                "|v|^2 changed on a crossing: {e2_before:e} -> {e2:e}"
            ));
        }
        let edge = &self.cell.edges[k as usize];
        let expected = before.cell.across(edge);
        if after.cell != expected {
            return Err(format!(
                "cell {:?} after crossing {k}, expected {expected:?}",
                after.cell
            ));
        }
        if fl.excluded_edge != Some(edge.entered) {
            return Err(format!("exclusions after crossing {k}: {fl:?}"));
        }
        Ok(())
    }

    /// After event `kind`: outside every disk and inside every edge, up to rounding.
    pub(super) fn check_position(&self, fl: &Flight<f64>, kind: EventKind) -> Result<(), String> {
        self.check_position_within(fl, kind, 1.0)
    }

    /// [`Self::check_position`] with the disk bound times `kappa` (an arc's conditioning).
    pub(super) fn check_position_within(
        &self,
        fl: &Flight<f64>,
        kind: EventKind,
        kappa: f64,
    ) -> Result<(), String> {
        let cell = &self.cell;
        for (m, disk) in cell.disks.iter().enumerate() {
            let d = fl.pos.sub(&disk.centre).norm2() - disk.radius2();
            if d.is_nan() || d < -POST_EVENT_U * U * kappa {
                return Err(format!(
                    "inside disk {m} after {kind:?}: |x-c|^2 - r^2 = {d:e}"
                ));
            }
        }
        for k in 0..cell.edges.len() {
            let sig = cell.edge_distance(k, &fl.pos);
            if sig.is_nan() || sig < -POST_EVENT_U * U * self.extent {
                return Err(format!("outside edge {k} after {kind:?}: sigma = {sig:e}"));
            }
        }
        Ok(())
    }
}
