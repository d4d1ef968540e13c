//! One trajectory in the field, event by event, for a user's own observables (Python
//! `events(field=…)`): the start of a batch of [`super::run`] and the arc kernel's steps.

use super::track;
use crate::Error;
use crate::scenes::Scene;
use crate::scenes::lattice::{Lattice, LatticeState};
use crate::scenes::magnetic::ArcStep;
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::scenes::triangular::TriangularScene;
use crate::theory::magnetic::FieldGeometry;

/// A trajectory of a scene (the triangular lattice unless named) in a field, on the `f64` arc
/// kernel.
#[derive(Debug, Clone)]
pub struct FieldWalk<S: Scene = TriangularScene> {
    lattice: Lattice<f64, S::Kernel<f64>>,
    state: LatticeState<f64>,
    field: f64,
    rejected: u64,
}

impl<S: Scene> FieldWalk<S> {
    /// The trajectory of batch `batch` of `diffusion(w, field=field, seed=seed)` (run 0): the
    /// same diffusing start, drawn from the invariant measure with the localized orbits set
    /// aside (`proofs-notes/magnetic-localized.md`).
    ///
    /// # Errors
    /// A field that is not an exact decimal or fraction, zero or out of range (as for
    /// [`super::field_value`]), a field in which every orbit is localized (nothing
    /// diffuses: the start would never be found), or a bad scene.
    pub fn start(scene: &S, field: &str, seed: u64, batch: u64) -> Result<Self, Error> {
        let b = super::field_value(field)?;
        let disks = crate::scenes::require_disk_lattice(scene, "field")?;
        let geometry = FieldGeometry::new(disks, b)?;
        if geometry.all_localized() {
            return Err(Error::parameter(
                "field",
                field,
                format!(
                    "every orbit is localized on {} (pinned or skipping), so no trajectory \
                     diffuses; use a weaker field",
                    scene.label()
                ),
            ));
        }
        let key = StreamKey::new(seed, Purpose::Trajectory, batch);
        let (mut state, rejected) = track::start(scene, &geometry, key)?;
        state.flight.normalise_speed();
        Ok(FieldWalk {
            lattice: scene.lattice::<f64>(())?,
            state,
            field: b,
            rejected,
        })
    }

    /// The next event: carried out, and described in world coordinates.
    ///
    /// # Errors
    /// An orbit without a next event (not reached from a diffusing start but by a measure-zero
    /// creeping slide).
    pub fn step(&mut self) -> Result<ArcStep, Error> {
        self.lattice.step_in_field(&mut self.state, &self.field)
    }

    /// The state (cell and flight in the cell's frame).
    pub fn state(&self) -> &LatticeState<f64> {
        &self.state
    }

    /// The lattice.
    pub fn lattice(&self) -> &Lattice<f64, S::Kernel<f64>> {
        &self.lattice
    }

    /// The field as a double.
    pub fn field(&self) -> f64 {
        self.field
    }

    /// Localized starts set aside before this one.
    pub fn rejected(&self) -> u64 {
        self.rejected
    }
}
