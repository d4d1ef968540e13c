//! Sweeps in parts for Python: `sweep(shard="I/N")` (one part, into `out` or carried in memory
//! for a process pool), `merge(shards)` (directories of parts) and `_native.merge_parts` (the
//! parts a pool computed, in memory) — the command line's `--shard` and `lorentz merge`, through
//! the library's one mechanism (`campaigns::shard`, `campaigns::merge`).

use std::path::PathBuf;
use std::time::Duration;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use lorentz_gas::campaigns::merge::{self, PartData};
use lorentz_gas::campaigns::shard::{self, Shard, ShardConfig, SweepPart};
use lorentz_gas::engine::Engine;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::sweep::stored::Finished;
use lorentz_gas::estimators::sweep::{self, SweepConfig, driven, field};

use crate::params::{Params, Progress, Work, work};
use crate::watch::{compute, json};

/// How a sweep runs for Python: its part (`shard`, if one), threads, engine, directory and
/// checkpoint interval (a sweep over w's).
pub struct SweepRun {
    pub shard: Option<Shard>,
    pub threads: usize,
    pub engine: Engine,
    pub out: Option<PathBuf>,
    pub every: Option<Duration>,
}

impl SweepRun {
    /// Reads `shard`, `threads`, `engine` and `out` (the checkpoint interval is the caller's).
    pub fn read(p: &Params<'_, '_>) -> PyResult<SweepRun> {
        let shard = p.opt_text("shard")?;
        let shard = shard.as_deref().map(Shard::parse).transpose();
        Ok(SweepRun {
            shard: shard.map_err(crate::py_err)?,
            threads: p.threads()?,
            engine: p.engine()?,
            out: p.opt_path("out")?,
            every: None,
        })
    }
}

/// The run sizes every sweep takes: collisions and batches per run, and the seed.
pub fn sizes(p: &Params<'_, '_>) -> PyResult<(u64, u32, u64)> {
    Ok((
        p.count_u64("collisions_per_run")?,
        p.count_u32("batches_per_run")?,
        p.count_u64("seed")?,
    ))
}

/// The sweep over `grid` at `sizes` ([`sizes`]), validated, run as `how` says ([`run_sweep`]).
pub fn run_grid(
    py: Python<'_>,
    progress: Progress<'_>,
    grid: sweep::Grid,
    (collisions, batches, seed): (u64, u32, u64),
    how: SweepRun,
) -> PyResult<String> {
    let cfg = SweepConfig {
        grid,
        collisions,
        batches,
        seed,
    };
    cfg.validate().map_err(crate::py_err)?;
    run_sweep(py, progress, cfg, how)
}

/// Runs the sweep `cfg` (any kind) as `how` says: the whole sweep (its tables written into
/// `out`, if given), or one part of it (its points into `out`, or carried in the result).
pub fn run_sweep(
    py: Python<'_>,
    progress: Progress<'_>,
    cfg: SweepConfig,
    how: SweepRun,
) -> PyResult<String> {
    if let Some(s) = how.shard {
        s.validate(&cfg).map_err(crate::py_err)?;
    }
    let r = compute(py, progress, |ctl| {
        let mut opts = RunOptions {
            resume: how.out.clone(),
            ..crate::analyses::options(ctl, how.threads, how.engine)
        };
        if let Some(every) = how.every {
            opts.checkpoint_every = every;
        }
        if let Some(s) = how.shard {
            let part = shard::run(
                &ShardConfig {
                    sweep: cfg,
                    shard: s,
                },
                &opts,
            )?;
            return Ok(Ran::Part(Box::new(part)));
        }
        let whole = match cfg.grid {
            sweep::Grid::Gaps(_) => Finished::OverW(Box::new(sweep::run(&cfg, &opts)?)),
            sweep::Grid::InField(_) => Finished::InField(Box::new(field::run(&cfg, &opts)?)),
            sweep::Grid::Driven(_) => Finished::Driven(Box::new(driven::run(&cfg, &opts)?)),
        };
        if let Some(dir) = &how.out {
            write_tables(&whole, dir)?;
        }
        Ok(Ran::Whole(whole))
    })?;
    match r {
        Ran::Part(p) => json(&*p),
        Ran::Whole(w) => finished_json(&w),
    }
}

/// What [`run_sweep`] ran.
enum Ran {
    Part(Box<SweepPart>),
    Whole(Finished),
}

fn write_tables(r: &Finished, dir: &std::path::Path) -> Result<(), lorentz_gas::Error> {
    match r {
        Finished::OverW(r) => sweep::write_tables(r, dir),
        Finished::InField(r) => field::write_tables(r, dir),
        Finished::Driven(r) => driven::write_tables(r, dir),
    }
}

fn finished_json(r: &Finished) -> PyResult<String> {
    match r {
        Finished::OverW(r) => json(&**r),
        Finished::InField(r) => json(&**r),
        Finished::Driven(r) => json(&**r),
    }
}

/// Merges `parts` into `out` (if given: the points and tables), with `threads`.
fn merged(
    py: Python<'_>,
    parts: impl FnOnce() -> Result<Vec<PartData>, lorentz_gas::Error> + Send,
    out: Option<PathBuf>,
    threads: usize,
) -> PyResult<String> {
    let r = compute(py, None, |ctl| {
        let opts = crate::analyses::options(ctl, threads, Engine::Auto);
        let r = merge::merge(parts()?, out.as_deref(), &opts)?;
        if let Some(dir) = &out {
            write_tables(&r, dir)?;
        }
        Ok(r)
    })?;
    finished_json(&r)
}

/// `merge(params, progress)`: the parts in the directories `shards` merged (into `out`).
pub fn merge(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let parts: Vec<PathBuf> = p.texts("shards")?.into_iter().map(PathBuf::from).collect();
    let out = p.opt_path("out")?;
    let threads = p.threads()?;
    Ok(work(move |py, _progress| {
        if parts.is_empty() {
            return Err(PyValueError::new_err(
                "shards: give the directories of every part of one sweep",
            ));
        }
        if let Some(o) = &out {
            merge::refuse_input_as_output(&parts, o).map_err(crate::py_err)?;
        }
        let read = move || parts.iter().map(|d| merge::read_part(d)).collect();
        merged(py, read, out, threads)
    }))
}

/// `merge_parts(parts, out, threads)`: the parts a process pool computed (each the JSON of a
/// `sweep(shard=...)` without `out`, its points carried), merged in this process (into `out`),
/// with the points already finished in `out` reused (`campaigns::merge::reused_in`: a point of
/// the parts that is also there must be its file's text to the bit).
#[pyfunction]
#[pyo3(signature = (parts, out, threads))]
pub fn merge_parts(
    py: Python<'_>,
    parts: Vec<String>,
    out: Option<PathBuf>,
    threads: Option<String>,
) -> PyResult<String> {
    let threads = crate::inputs::threads(threads.as_deref())?;
    let mut read = Vec::with_capacity(parts.len() + 1);
    for (k, text) in parts.iter().enumerate() {
        let part: SweepPart = serde_json::from_str(text)
            .map_err(|e| PyValueError::new_err(format!("part {k} is not a sweep part: {e}")))?;
        read.push(PartData::in_memory(part));
    }
    let dir = out.clone();
    merged(
        py,
        move || {
            if let Some(kept) = dir
                .as_deref()
                .map(|d| merge::reused_in(d, &read))
                .transpose()?
            {
                read.extend(kept);
            }
            Ok(read)
        },
        out,
        threads,
    )
}
