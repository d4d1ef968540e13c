//! The one metadata block every result carries: what produced it and how to reproduce it.
//!
//! Every report type of the crate has a `meta: RunMeta` field (the `"meta"` object of each JSON
//! result), filled by [`RunMeta::new`] in one place: crate version, seed, batches, precision,
//! engine, thread count and the command line of the process.

use serde::{Deserialize, Serialize};

/// Engine of results computed one trajectory at a time on the generic kernel (the default of
/// [`RunMeta::new`]; [`RunMeta::with_engine`] records the SIMD engine where it ran).
pub const ENGINE_SCALAR: &str = "scalar";

/// Provenance of one result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunMeta {
    /// Crate version that computed the result.
    pub version: String,
    /// Seed of the random streams (`None` for deterministic computations).
    pub seed: Option<u64>,
    /// The number of independent batches (sets of trajectories, each with its own random streams)
    /// whose scatter the result's error bars are computed from: `--batches` where a command has
    /// it; runs × batches per run for a sweep (per point); widths × batches per width for
    /// `escape`; segments for `shadow`. `None` where nothing is averaged over batches.
    pub batches: Option<u64>,
    /// Number type: `"f64"` or MPFR bits (`"128"`), the serde form of
    /// [`Precision`](crate::numbers::precision::Precision); for `audit` and `shadow`, the MPFR
    /// precision of the reference.
    pub precision: String,
    /// Engine that ran the trajectories: `"scalar"` or `"simd"`.
    pub engine: String,
    /// The SIMD engine's instruction path (`"avx512"`, `"avx2"`, `"portable"`); absent for the
    /// scalar engine.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub simd: Option<String>,
    /// Worker threads (never changes the result, only the time).
    pub threads: Option<usize>,
    /// The command line of the process that produced the result.
    pub command_line: Vec<String>,
    /// In a checkpoint's header only: the pilot that planned the run's size (a diffusion run
    /// planned for a relative error), so that a resumed planned run need not run it again.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pilot: Option<serde_json::Value>,
}

impl RunMeta {
    /// Metadata for a result of this process.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::engine::metadata::RunMeta;
    /// let m = RunMeta::new(Some(7), Some(32), "f64", Some(2));
    /// assert_eq!(m.version, env!("CARGO_PKG_VERSION"));
    /// assert_eq!(m.engine, "scalar");
    /// assert!(!m.command_line.is_empty());
    /// ```
    pub fn new(
        seed: Option<u64>,
        batches: Option<u64>,
        precision: impl std::fmt::Display,
        threads: Option<usize>,
    ) -> Self {
        RunMeta {
            version: env!("CARGO_PKG_VERSION").to_string(),
            seed,
            batches,
            precision: precision.to_string(),
            engine: ENGINE_SCALAR.to_string(),
            simd: None,
            threads,
            command_line: std::env::args().collect(),
            pilot: None,
        }
    }

    /// The same metadata with the engine that actually ran.
    pub fn with_engine(mut self, e: crate::engine::Resolved) -> Self {
        self.engine = e.name().to_string();
        self.simd = e.simd().map(|p| p.to_string());
        self
    }
}
