//! A scene under the Gaussian-thermostatted electric field: the lattice walked along the
//! thermostat's flights ([`crate::kernel::thermostat`]).
//!
//! The field E is the same vector in the world in every cell, but a cell's frame is the world's
//! or its point reflection (the triangular lattice's down traps): there the field is −E. Both are
//! kept ([`CellFields`]) and the cell's orientation picks one; a translation (the square
//! lattice) keeps the field. A step is described for observers in world coordinates, in `f64`,
//! from the flight's own closed form: the same description whichever precision found it.

use super::lattice::{CellIndex, Lattice, LatticeState};
use crate::Error;
use crate::kernel::cell::CellKernel;
use crate::kernel::flight::EventKind;
use crate::kernel::thermostat::Thermostat;
use crate::kernel::thermostat::cell::ThermoEvent;
use crate::kernel::vec2::Vec2;
use crate::numbers::real::Real;

/// The field in the frames of a lattice's cells: E in a cell of the world's orientation, −E in a
/// point-reflected one (negation is exact, so both are the one field at every precision).
#[derive(Debug, Clone, PartialEq)]
pub struct CellFields<T> {
    up: Thermostat<T>,
    down: Thermostat<T>,
}

impl<T: Real> CellFields<T> {
    /// The field `th` (world frame) in every cell.
    pub fn new(th: Thermostat<T>) -> Self {
        let down = Thermostat {
            strength: th.strength.clone(),
            dir: Vec2::new(-th.dir.x.clone(), -th.dir.y.clone()),
        };
        CellFields { up: th, down }
    }

    /// The field in the frame of `cell`.
    #[inline]
    pub fn in_cell(&self, cell: &CellIndex) -> &Thermostat<T> {
        if cell.down { &self.down } else { &self.up }
    }

    /// The field in the world's frame.
    pub fn world(&self) -> &Thermostat<T> {
        &self.up
    }
}

/// One event of a thermostatted flight, described in world coordinates (`f64`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThermoStep {
    /// Collision or crossing.
    pub kind: EventKind,
    /// Flight time to the event.
    pub time: f64,
    /// The flight's displacement in world coordinates.
    pub disp: [f64; 2],
    /// ξ, the displacement along the field: ε·ξ is the flight's integrated phase-space
    /// contraction ∫α dt (the field's work).
    pub along: f64,
}

impl ThermoStep {
    /// The event `ev` of a flight in a cell of orientation `sign`.
    pub fn new<T: Real>(ev: &ThermoEvent<T>, sign: f64) -> Self {
        ThermoStep {
            kind: ev.kind,
            time: ev.time.to_f64(),
            disp: [sign * ev.at.disp.x.to_f64(), sign * ev.at.disp.y.to_f64()],
            along: ev.at.along.to_f64(),
        }
    }
}

impl<T: Real, K: CellKernel<T>> Lattice<T, K> {
    /// The next event of the state's flight under the field `fields`, or `None` (a particle
    /// creeping along a disk, or a non-finite state).
    #[inline]
    pub fn next_event_thermostat(
        &self,
        s: &LatticeState<T>,
        fields: &CellFields<T>,
    ) -> Option<ThermoEvent<T>> {
        self.cell()
            .next_event_thermostat(&s.flight, fields.in_cell(&s.cell))
    }

    /// Carries out `ev`, moving to the neighbouring cell on a crossing (whose orientation then
    /// picks the field: the point reflection the kernel reports is the cell index's flip).
    #[inline]
    pub fn apply_thermostat(&self, s: &mut LatticeState<T>, ev: &ThermoEvent<T>) {
        self.cell().apply_thermostat(&mut s.flight, ev);
        if let EventKind::Crossing(k) = ev.kind {
            s.cell = s.cell.across(&self.cell().edges[k as usize]);
        }
    }

    /// One event under the field: found, carried out, and described in world coordinates.
    ///
    /// # Errors
    /// [`Error::Failed`] if the flight has no next event (a creeping slide along a disk, of
    /// measure zero, or a non-finite state).
    pub fn step_thermostat(
        &self,
        s: &mut LatticeState<T>,
        fields: &CellFields<T>,
    ) -> Result<ThermoStep, Error> {
        let ev = self.next_event_thermostat(s, fields).ok_or_else(|| {
            Error::Failed(format!(
                "a thermostatted flight has no next event (velocity {:?})",
                s.flight.vel.to_f64()
            ))
        })?;
        let step = ThermoStep::new(&ev, s.cell.sign());
        self.apply_thermostat(s, &ev);
        Ok(step)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::Scene;
    use crate::scenes::triangular::TriangularScene;
    use rand::SeedableRng;
    use rug::Rational;

    /// The world displacement of a walk, the sum of its steps' displacements, equals the
    /// difference of its world positions (each cell's field in its own frame is the one world
    /// field), and ∫α = E·ΔX: the contraction is the field's work.
    #[test]
    fn steps_add_up_to_the_world_displacement_and_the_work() {
        let scene = TriangularScene::exact(Rational::from((1, 10))).unwrap();
        let lat = scene.lattice::<f64>(()).unwrap();
        let th = Thermostat::<f64>::exact(&Rational::from((3, 10)), &Rational::from(30), ());
        let fields = CellFields::new(th.unwrap());
        let mut rng = rand::rngs::StdRng::seed_from_u64(60);
        let mut s = scene.sample(&mut rng);
        let start = lat.world(&s);
        let (mut sum, mut along, mut crossings) = ([0.0f64; 2], 0.0, 0);
        for _ in 0..20_000 {
            let st = lat.step_thermostat(&mut s, &fields).unwrap();
            sum = [sum[0] + st.disp[0], sum[1] + st.disp[1]];
            along += st.along;
            crossings += u32::from(matches!(st.kind, EventKind::Crossing(_)));
        }
        let end = lat.world(&s);
        let d = [end.x - start.x, end.y - start.y];
        let e = &fields.world().dir;
        // 20000 flights, each displacement within ~1e-14 of the cell positions' difference.
        let tol = 1e-9 * (1.0 + d[0].abs() + d[1].abs());
        assert!(
            (sum[0] - d[0]).abs() < tol && (sum[1] - d[1]).abs() < tol,
            "{sum:?} {d:?}"
        );
        assert!((along - (e.x * d[0] + e.y * d[1])).abs() < tol, "{along}");
        // The walk changes frames many times (a hop every ~10 collisions at w = 0.1).
        assert!(crossings > 1000, "{crossings}");
        // The field drives the particle along E: far along it after 20000 events.
        assert!(along > 100.0, "{along}");
    }
}
