//! `section(params, progress)`: a Poincaré section in Birkhoff coordinates
//! (`estimators::section`), the command line's `lorentz section` with its bits.

use pyo3::prelude::*;

use lorentz_gas::estimators::section::{self, SectionConfig};
use lorentz_gas::scenes::spec::{Motion, Table};

use crate::analyses::options;
use crate::params::{Params, Work, work};
use crate::scenes::Where;
use crate::watch::{compute, json};

/// `section(params, progress)`: the table (`scene`, `table`, `w`, `radius`) in the `field`,
/// `orbits`, `collisions`, `classify_collisions`, `seed` and `threads`.
pub fn section(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let place = Where::read(p)?;
    let field = p.opt_text("field")?;
    let trajectories = p.count_u32("trajectories")?;
    let collisions = p.count_u64("collisions")?;
    let classify_collisions = p.count_u64("classify_collisions")?;
    let seed = p.count_u64("seed")?;
    let threads = p.threads()?;
    Ok(work(move |py, progress| {
        let cfg = SectionConfig {
            table: Table {
                scene: place.spec()?,
                motion: Motion::in_field(field.as_deref().unwrap_or("0")),
            },
            trajectories,
            collisions,
            classify_collisions,
            seed,
        };
        cfg.validate().map_err(crate::py_err)?;
        section::work(&cfg)
            .and_then(|w| w.check(threads))
            .map_err(crate::py_err)?;
        let r = compute(py, progress, |ctl| {
            section::run(
                &cfg,
                &options(ctl, threads, lorentz_gas::engine::Engine::Auto),
            )
        })?;
        json(&r)
    }))
}
