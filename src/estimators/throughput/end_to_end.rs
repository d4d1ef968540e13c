//! A field run end to end beside the bare arc engine (`lorentz bench --field B
//! --diffusion-beside`): repetition i of `lorentz diffusion --field B` runs right after
//! repetition i of the engine, on the same threads, with as many collisions, so that the paired
//! ratio says what the analysis around the engine costs on this machine (issue 58's target:
//! at least 0.7).

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::Engine;
use crate::engine::options::RunOptions;
use crate::estimators::diffusion::DiffusionConfig;

use super::{ThroughputConfig, median};

/// The diffusion analysis in the field, timed beside the arc engine in the same run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct EndToEnd {
    /// Collisions of each run (the engine's per repetition, all threads).
    pub collisions: u64,
    /// Batches of each run.
    pub batches: u32,
    /// Every run's collisions per wall-clock second (all threads; everything from the
    /// configuration to the result: classification samples, starts, observers, estimates).
    pub samples: Vec<f64>,
    /// Their median per thread.
    pub collisions_per_second_per_thread: f64,
    /// Their median over the engine's.
    pub over_engine: f64,
    /// The median over repetitions of each pair's ratio (diffusion over engine).
    pub paired_ratio: f64,
}

/// The runs of [`EndToEnd`]: the configuration and the rates so far.
pub(super) struct DiffusionRuns {
    cfg: DiffusionConfig,
    engine: Engine,
    threads: usize,
    rates: Vec<f64>,
}

impl DiffusionRuns {
    /// With `cfg.diffusion_beside` and a `field`: `lorentz diffusion` on `cfg`'s table in the
    /// field (its double), `collisions` collisions on the benchmark's threads and engine,
    /// otherwise the command's defaults; `None` otherwise.
    ///
    /// # Errors
    /// A field whose double has no exact text (not finite).
    pub(super) fn beside(
        cfg: &ThroughputConfig,
        field: Option<f64>,
        collisions: u64,
        options: &RunOptions,
    ) -> Result<Option<Self>, Error> {
        let Some(b) = field.filter(|_| cfg.diffusion_beside) else {
            return Ok(None);
        };
        let text =
            crate::numbers::exact::exact_text_of(b).ok_or(Error::NotFinite { what: "field" })?;
        let table = cfg.table.in_field(&text);
        let samples = crate::estimators::diffusion::DEFAULT_LOCALIZATION_SAMPLES;
        Ok(Some(DiffusionRuns {
            cfg: DiffusionConfig::sized(table, Some(collisions), None, samples),
            engine: options.engine,
            threads: options.threads,
            rates: Vec::new(),
        }))
    }

    /// One run, timed.
    ///
    /// # Errors
    /// What the analysis returns.
    pub(super) fn time(&mut self) -> Result<(), Error> {
        let opts = RunOptions {
            engine: self.engine,
            threads: self.threads,
            ..RunOptions::default()
        };
        let t0 = Instant::now();
        let r = crate::estimators::field::run(&self.cfg, &opts)?;
        self.rates
            .push(r.collisions as f64 / t0.elapsed().as_secs_f64());
        Ok(())
    }

    /// The runs against the engine's repetitions `engine` (collisions per second, all threads).
    pub(super) fn report(self, engine: &[f64]) -> EndToEnd {
        let ratios: Vec<f64> = self.rates.iter().zip(engine).map(|(d, e)| d / e).collect();
        let m = median(&self.rates);
        EndToEnd {
            collisions: self.cfg.collisions,
            batches: self.cfg.batches,
            collisions_per_second_per_thread: m / self.threads as f64,
            over_engine: m / median(engine),
            paired_ratio: median(&ratios),
            samples: self.rates,
        }
    }
}
