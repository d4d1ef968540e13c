//! `cycles`: the three-disk repeller by certified periodic orbits, the command line's
//! `lorentz cycles` with its bits.

use pyo3::prelude::*;

use lorentz_gas::engine::Engine;
use lorentz_gas::verification::cycles::repeller::{self, RepellerConfig};

use crate::analyses::options;
use crate::params::{Params, Work, work};
use crate::watch::{compute, json};

/// `cycles(params, progress)`: every fundamental-domain prime cycle up to `max_length`,
/// certified, and the convergence tables of the cycle expansions.
pub fn cycles(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let (side, radius) = (p.text("side")?, p.text("radius")?);
    let cfg = RepellerConfig {
        max_length: p.count_usize("max_length")?,
        bits: p.count_u32("bits")?,
        ..RepellerConfig::new(&side, &radius)
    };
    let threads = p.threads()?;
    Ok(work(move |py, progress| {
        cfg.validate().map_err(crate::py_err)?;
        json(&compute(py, progress, |ctl| {
            repeller::run(&cfg, &options(ctl, threads, Engine::Auto))
        })?)
    }))
}
