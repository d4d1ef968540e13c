//! `cycles`: the three-disk repeller by certified periodic orbits, the command line's
//! `lorentz cycles` with its bits; `survival`: an open table's escape by survival, the command
//! line's `lorentz escape --repeller` with its bits.

use pyo3::prelude::*;

use lorentz_gas::engine::Engine;
use lorentz_gas::estimators::escape::survival::{self, SurvivalConfig};
use lorentz_gas::scenes::open::OpenSpec;
use lorentz_gas::verification::cycles::lattice::run::{self as lattice, LatticeConfig};
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

/// `lattice_cycles(params, progress)`: the triangular Lorentz gas at gap `w` by certified
/// cycles (the command line's `lorentz cycles --w`): every C6v class of prime cycles up to
/// `max_length`, certified, and D by cycle averaging against N beside the MSD's.
pub fn lattice_cycles(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let w = p.text("w")?;
    let cfg = LatticeConfig {
        max_length: p.count_usize("max_length")?,
        bits: p.count_u32("bits")?,
        msd_collisions: p.count_u64("msd_collisions")?,
        ..LatticeConfig::new(&w)
    };
    let threads = p.threads()?;
    Ok(work(move |py, progress| {
        cfg.validate().map_err(crate::py_err)?;
        json(&compute(py, progress, |ctl| {
            lattice::run(&cfg, &options(ctl, threads, Engine::Auto))
        })?)
    }))
}

/// `survival(params, progress)`: an open table's escape rate, Lyapunov exponent and KS entropy
/// by survival (the command line's `lorentz escape --repeller` / `--open FILE`): the
/// three-disk repeller of `side` and `radius`, or the disks of `open_table` (its JSON).
pub fn survival(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let (side, radius) = (p.text("side")?, p.text("radius")?);
    let open_table = p.opt_text("open_table")?;
    let (particles, window) = (p.count_u64("particles")?, p.count_u32("window")?);
    let (seed, threads) = (p.count_u64("seed")?, p.threads()?);
    Ok(work(move |py, progress| {
        let open = match &open_table {
            Some(json) => OpenSpec::from_json(json),
            None => OpenSpec::repeller(&side, &radius),
        }
        .map_err(crate::py_err)?;
        let cfg = SurvivalConfig {
            particles,
            window,
            seed,
            ..SurvivalConfig::new(open)
        };
        cfg.validate().map_err(crate::py_err)?;
        json(&compute(py, progress, |ctl| {
            survival::run(&cfg, &options(ctl, threads, Engine::Auto))
        })?)
    }))
}
