//! One diffusion analysis, whichever the table and motion: [`run`] takes a
//! [`DiffusionConfig`] and runs the estimator its table asks for.
//!
//! * the triangular gas without a field: the trap estimator ([`diffusion::run`], planned for a
//!   relative error with `rel_err`), D with the paper's hierarchy beside it;
//! * any other table without a field: the Einstein estimator on a scene
//!   ([`diffusion::scene::run_on`]), D with the table's exact identities measured;
//! * any table in a field: the tensor D_xx, D_xy with the localized orbits counted exactly
//!   ([`field::run`]);
//! * any table under the thermostatted electric field: the current J(E), its mobility and the
//!   diffusion tensor about the drift ([`current::run`]).
//!
//! Each result is written in the form its kind has always had, so that `report`, `merge` and
//! resume read the files of every version.

use serde::Serialize;

use super::current::{self, CurrentReport};
use super::diffusion::scene::SceneDiffusionReport;
use super::diffusion::{self, DiffusionConfig, DiffusionReport};
use super::field::{self, FieldReport};
use crate::Error;
use crate::engine::options::RunOptions;
use crate::scenes::spec::{Motion, SceneChoice};

/// The result of [`run`]: the one its table and motion give.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum Transport {
    /// The triangular gas without a field.
    Trap(Box<DiffusionReport>),
    /// Another table without a field.
    Table(Box<SceneDiffusionReport>),
    /// Any table in a field.
    Field(Box<FieldReport>),
    /// Any table under the thermostatted electric field: the current.
    Current(Box<CurrentReport>),
}

/// Runs `cfg` (validated first) with `options`, on the estimator its table asks for.
///
/// # Errors
/// An invalid configuration (an infinite horizon without a field names its corridor), options
/// the estimator does not use, an I/O error or an interruption.
pub fn run(cfg: &DiffusionConfig, options: &RunOptions) -> Result<Transport, Error> {
    cfg.validate()?;
    if let Motion::Thermostat { .. } = cfg.table.motion {
        return Ok(Transport::Current(Box::new(current::run(cfg, options)?)));
    }
    if cfg.table.field().is_some() {
        return Ok(Transport::Field(Box::new(field::run(cfg, options)?)));
    }
    let scene = cfg.table.scene.resolve()?;
    if let SceneChoice::Triangular(_) = scene {
        return Ok(Transport::Trap(Box::new(diffusion::run(cfg, options)?)));
    }
    let sampling = cfg.sampling();
    let r = crate::with_scene!(&scene, |s| diffusion::scene::run_on(s, &sampling, options))?;
    Ok(Transport::Table(Box::new(r)))
}
