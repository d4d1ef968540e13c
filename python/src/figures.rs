//! The paper's figures (`lorentz figure`) and the whole reproduction (`lorentz reproduce`) for
//! Python, stopped by Ctrl-C like every other analysis.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use lorentz_gas::engine::options::{RunOptions, StopFlag};
use lorentz_gas::report::figures::paper;
use lorentz_gas::report::reproduce::{self, Budget, Reporter};
use lorentz_gas::report::text;

use crate::inputs::{self, count_u64};
use crate::params::{Params, Work, work};
use crate::watch::{Ctl, compute, json};

/// The figure kinds, as `lorentz figure <KIND>` names them, and the one count each takes.
const KINDS: [(&str, &str); 3] = [
    ("backscatter-map", "particles"),
    ("backscatter", "particles_per_gap"),
    ("hierarchy", "collisions_per_gap"),
];

/// `count` of `kind`, refusing the counts of the other kinds (an option a figure does not use is
/// refused, not ignored) and `w` for all but the map.
fn the_count(
    kind: &str,
    w: Option<&str>,
    counts: [(&str, Option<&str>); 3],
) -> PyResult<Option<u64>> {
    let Some(&(_, own)) = KINDS.iter().find(|(k, _)| *k == kind) else {
        let names: Vec<&str> = KINDS.iter().map(|(k, _)| *k).collect();
        return Err(PyValueError::new_err(format!(
            "kind = {kind:?}: the figures are {} (Figs. 2, 7, 8: sweep)",
            names.join(", ")
        )));
    };
    if w.is_some() && kind != "backscatter-map" {
        return Err(PyValueError::new_err(format!(
            "w: the {kind} figure runs on the paper's own grid of gaps; only backscatter-map takes w"
        )));
    }
    let mut out = None;
    for (name, v) in counts {
        match (name == own, v) {
            (true, Some(v)) => out = Some(count_u64(name, v)?),
            (false, Some(_)) => {
                return Err(PyValueError::new_err(format!(
                    "{name}: the {kind} figure does not take it (it takes {own})"
                )));
            }
            _ => {}
        }
    }
    Ok(out)
}

fn options<'a>(ctl: &'a Ctl<'a>, threads: usize) -> RunOptions<'a> {
    crate::analyses::options(ctl, threads, lorentz_gas::engine::Engine::Auto)
}

/// `figure(params, progress)`: one of the paper's figures into `out`.
pub fn figure(p: &Params<'_, '_>) -> PyResult<Work<(String, String)>> {
    let kind = p.text("kind")?;
    let w = p.opt_text("w")?;
    let counts = [
        ("particles", p.opt_text("particles")?),
        ("particles_per_gap", p.opt_text("particles_per_gap")?),
        ("collisions_per_gap", p.opt_text("collisions_per_gap")?),
    ];
    let seed = p.count_u64("seed")?;
    let threads = p.threads()?;
    let out = p.path("out")?;
    Ok(work(move |py, progress| {
        let counts = counts.each_ref().map(|(name, v)| (*name, v.as_deref()));
        let n = the_count(&kind, w.as_deref(), counts)?;
        let w = inputs::diffusive_gap(w.as_deref().unwrap_or("0.1"))?.value;
        let r = compute(py, progress, |ctl| {
            let opts = options(ctl, threads);
            match kind.as_str() {
                "backscatter-map" => {
                    let n = n.unwrap_or(paper::MAP_SAMPLES);
                    paper::backscatter_map(w, n, seed, &out, &opts)
                }
                "backscatter" => {
                    paper::backscatter_curve(n.unwrap_or(paper::CURVE_SAMPLES), seed, &out, &opts)
                }
                _ => paper::hierarchy(n.unwrap_or(paper::HIERARCHY_COLLISIONS), seed, &out, &opts),
            }
        })?;
        Ok((json(&r)?, text::figure::figure(&r, &out)))
    }))
}

/// A reproduction's reporter for Python: units to the progress sink, Ctrl-C as its stop flag.
struct Watched<'a> {
    progress: &'a (dyn Fn(u64) + Sync),
    stop: StopFlag,
}

impl Reporter for Watched<'_> {
    fn stage(&self, _index: usize, _count: usize, _name: &str, _total: u64, _unit: &str) {}
    fn advance(&self, n: u64) {
        (self.progress)(n)
    }
    fn stop(&self) -> Option<StopFlag> {
        Some(self.stop.clone())
    }
}

/// `reproduce(params, progress)`: every figure and table of the user guide into `out`.
pub fn reproduce(p: &Params<'_, '_>) -> PyResult<Work<(String, String)>> {
    let budget: Budget = p.parsed("budget", Budget::Quick, |t| {
        t.parse().map_err(crate::py_err)
    })?;
    let seed = p.count_u64("seed")?;
    let threads = p.threads()?;
    let out = p.path("out")?;
    Ok(work(move |py, progress| {
        let r = compute(py, progress, |ctl| {
            let watched = Watched {
                progress: ctl.progress,
                stop: ctl.stop.clone(),
            };
            reproduce::reproduce(budget, &out, seed, threads, &watched)
        })?;
        Ok((json(&r)?, text::reproduce::reproduce(&r, &out)))
    }))
}
