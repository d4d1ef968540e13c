//! `lorentz cycles --w W`: every C6v class of prime cycles up to a length, certified, and the
//! convergence table of D by the cycle-averaging formula beside D from the MSD.

use rug::{Float, Rational};
use serde::{Deserialize, Serialize};

use super::averages::{Averages, WindingWeight, averages};
use super::letters::{Class, LETTERS, classes, images, winding, word_text};
use super::{LatticeDisks, Stage, certify_word};
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::parallel::par_batches;
use crate::numbers::exact::ExactInput;
use crate::scenes::triangular::geometry::Geometry;
use crate::verification::cycles::expansion::EXPANSION_BITS;
use crate::verification::cycles::{Cycle, MAX_CYCLE_BITS, MIN_CYCLE_BITS};

/// Longest cycle of the lattice expanded (the classes grow as 12ⁿ/(12n)).
pub const MAX_LATTICE_LENGTH: usize = 7;
/// Default longest cycle.
pub const DEFAULT_LATTICE_LENGTH: usize = 5;
/// Default working precision of the lattice's cycles (bits).
pub const DEFAULT_LATTICE_BITS: u32 = 128;
/// Default collisions of the MSD run beside the table.
pub const DEFAULT_MSD_COLLISIONS: u64 = 200_000_000;

/// What [`run`] is asked for.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeConfig {
    /// The gap w, 0 < w < w∞, exactly as typed.
    pub w: String,
    /// Longest prime cycle N (collisions), 1 to [`MAX_LATTICE_LENGTH`].
    pub max_length: usize,
    /// MPFR working precision of the cycles, [`MIN_CYCLE_BITS`] to [`MAX_CYCLE_BITS`].
    pub bits: u32,
    /// Collisions of the MSD run whose D stands beside the table (0: none).
    pub msd_collisions: u64,
}

impl LatticeConfig {
    /// The lattice at gap `w` (exact text) with the command line's defaults.
    pub fn new(w: &str) -> Self {
        LatticeConfig {
            w: w.trim().to_string(),
            max_length: DEFAULT_LATTICE_LENGTH,
            bits: DEFAULT_LATTICE_BITS,
            msd_collisions: DEFAULT_MSD_COLLISIONS,
        }
    }

    /// The gap, parsed exactly.
    ///
    /// # Errors
    /// Text that is not an exact number.
    pub fn gap(&self) -> Result<Rational, Error> {
        let e = ExactInput::parse(&self.w).map_err(|e| e.named("w"))?;
        e.exact
            .ok_or_else(|| Error::out_of_range("w", e.value, "use 0 < w < w_inf = 0.309402"))
    }

    /// The disks at the exact gap.
    ///
    /// # Errors
    /// Text that is not an exact number, or a gap outside 0 < w < w∞.
    pub fn disks(&self) -> Result<LatticeDisks, Error> {
        LatticeDisks::new(&self.gap()?)
    }

    /// Checks every parameter; errors name the valid range.
    ///
    /// # Errors
    /// A gap, length or precision out of range.
    pub fn validate(&self) -> Result<(), Error> {
        self.disks()?;
        Error::unless_in(
            "max_length",
            self.max_length,
            1..=MAX_LATTICE_LENGTH,
            " (the longest prime cycle, in collisions)",
        )?;
        Error::unless_in("bits", self.bits, MIN_CYCLE_BITS..=MAX_CYCLE_BITS, " bits")?;
        if self.msd_collisions != 0 {
            Error::unless_in(
                "msd_collisions",
                self.msd_collisions,
                1_000_000..=100_000_000_000,
                " (0: no MSD run)",
            )?;
        }
        Ok(())
    }
}

/// A certified class representative and the cycles its class stands for.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LatticeCycle {
    /// The word (letters A–F nearest, a–f second neighbours).
    pub word: String,
    /// Its winding n̂_p = Σδ_k in lattice indices (i, j).
    pub winding: [i64; 2],
    /// The class's words (the representative first), each a prime cycle of the expansion.
    pub images: Vec<String>,
    /// Their windings, in the order of `images`.
    pub image_windings: Vec<[i64; 2]>,
    /// The certified cycle (T_p, Λ_p, their bounds, the certificate).
    pub cycle: Cycle,
}

/// A class representative that is not certified.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RefusedWord {
    /// The word.
    pub word: String,
    /// Cycles in its class.
    pub images: usize,
    /// Where it was stopped.
    pub stage: Stage,
    /// Why.
    pub reason: String,
}

/// One truncation of the expansion.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LatticeTruncation {
    /// Longest prime cycle N in the expansion.
    pub max_length: usize,
    /// Certified prime cycles (images included) of length ≤ N.
    pub certified: usize,
    /// Prime cycles of length ≤ N not certified (pruned by the screen or the kernel, or not
    /// found).
    pub refused: usize,
    /// The averages of the truncated zeta function.
    #[serde(flatten)]
    pub averages: Averages,
    /// ⟨T⟩_ζ/⟨n⟩_ζ, against the exact mean free time.
    #[serde(deserialize_with = "crate::estimators::field::nan_if_null")]
    pub mean_free_time: f64,
    /// D_N − D_{N−1} (NaN, `null` in JSON, at N = 1).
    #[serde(deserialize_with = "crate::estimators::field::nan_if_null")]
    pub change: f64,
}

/// D from the MSD at the same gap.
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct MsdReference {
    /// Collisions of the run.
    pub collisions: u64,
    /// D from the MSD slope.
    pub D: f64,
    /// Its standard error.
    pub D_err: f64,
    /// (D_N − D) / its standard error at the largest N.
    #[serde(deserialize_with = "crate::estimators::field::nan_if_null")]
    pub difference_sigma: f64,
}

/// The certified cycles of the lattice and the convergence table of D.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LatticeReport {
    /// What was run.
    pub config: LatticeConfig,
    /// The letters' lattice displacements, in the order A–F, a–f.
    pub letters: Vec<[i64; 2]>,
    /// The exact mean free time ⟨ℓ⟩ = √3a²/4 − π/2 (speed 1).
    pub mean_free_time_exact: f64,
    /// The certified class representatives, by length.
    pub cycles: Vec<LatticeCycle>,
    /// The representatives not certified.
    pub refused: Vec<RefusedWord>,
    /// One row per truncation N = 1 … max_length.
    pub table: Vec<LatticeTruncation>,
    /// D from the MSD (`None` when not run).
    pub msd: Option<MsdReference>,
    /// Version, precision, threads.
    pub meta: RunMeta,
}

/// The outcome of one class: certified or refused.
fn class_outcome(
    disks: &LatticeDisks,
    class: &Class,
    bits: u32,
) -> Result<Result<LatticeCycle, RefusedWord>, Error> {
    let out = certify_word(disks, &class.representative, bits)?;
    let word = word_text(&class.representative);
    if let Some((stage, reason)) = out.refused {
        return Ok(Err(RefusedWord {
            word,
            images: class.size,
            stage,
            reason,
        }));
    }
    let members = images(&class.representative);
    Ok(Ok(LatticeCycle {
        word,
        winding: winding(&class.representative),
        images: members.iter().map(|w| word_text(w)).collect(),
        image_windings: members.iter().map(|w| winding(w)).collect(),
        cycle: out.cycle.expect("a certified word has its cycle"),
    }))
}

/// The zeta function's weights of every certified cycle (each image its own prime cycle).
fn weights(disks: &LatticeDisks, cycles: &[LatticeCycle]) -> Vec<WindingWeight> {
    let b = EXPANSION_BITS;
    let mut out = Vec::new();
    for c in cycles {
        let period = Float::with_val(b, c.cycle.period_exact.as_ref().expect("certified"));
        let lam = c.cycle.partial_stability(c.cycle.jacobians.len()).abs();
        for w in &c.image_windings {
            let x = disks.centre_f64(*w);
            out.push(WindingWeight {
                length: c.cycle.jacobians.len(),
                period: period.clone(),
                stability: Float::with_val(b, &lam),
                displacement: [Float::with_val(b, x[0]), Float::with_val(b, x[1])],
            });
        }
    }
    out
}

/// Certifies one word of every C6v class of prime cycles up to `config.max_length`, expands the
/// zeta function over all certified cycles and tabulates D against N, beside D from the MSD
/// when `config.msd_collisions` > 0. The cycles do not depend on `options.threads`; progress
/// counts prime cycles (each class its size).
///
/// # Errors
/// A parameter out of range, or the MSD run's.
pub fn run(config: &LatticeConfig, options: &RunOptions) -> Result<LatticeReport, Error> {
    options.validate()?;
    options.refuse_unused("cycles", &[])?;
    config.validate()?;
    let disks = config.disks()?;
    let all = classes(config.max_length);
    let chunks = all.len().min(4096);
    let parts = par_batches(options.threads, chunks as u32, |k| {
        let mine: Vec<_> = (k as usize..all.len()).step_by(chunks).collect();
        let out: Result<Vec<_>, Error> = mine
            .iter()
            .map(|&i| class_outcome(&disks, &all[i], config.bits))
            .collect();
        (options.progress)(mine.iter().map(|&i| all[i].size as u64).sum());
        out
    })?;
    let mut outcomes: Vec<Option<Result<LatticeCycle, RefusedWord>>> = vec![None; all.len()];
    for (k, part) in parts.into_iter().enumerate() {
        for (m, o) in part.into_iter().enumerate() {
            outcomes[k + m * chunks] = Some(o);
        }
    }
    let (mut cycles, mut refused) = (Vec::new(), Vec::new());
    for o in outcomes.into_iter().flatten() {
        match o {
            Ok(c) => cycles.push(c),
            Err(r) => refused.push(r),
        }
    }
    let table = table(&disks, &cycles, &refused, config.max_length);
    let msd = msd_reference(config, options, table.last())?;
    let geometry = Geometry::new(Float::with_val(256, &config.gap()?))?;
    Ok(LatticeReport {
        config: config.clone(),
        letters: LETTERS.to_vec(),
        mean_free_time_exact: geometry.mean_free_path().to_f64(),
        cycles,
        refused,
        table,
        msd,
        meta: RunMeta::new(None, None, config.bits, Some(options.threads)),
    })
}

/// The convergence table: the averages at N = 1 … `max_length` with the cycle counts.
fn table(
    disks: &LatticeDisks,
    cycles: &[LatticeCycle],
    refused: &[RefusedWord],
    max_length: usize,
) -> Vec<LatticeTruncation> {
    let rows = averages(&weights(disks, cycles), max_length);
    let mut out: Vec<LatticeTruncation> = Vec::new();
    for (k, a) in rows.into_iter().enumerate() {
        let n = k + 1;
        let certified = cycles
            .iter()
            .filter(|c| c.cycle.jacobians.len() <= n)
            .map(|c| c.images.len())
            .sum();
        let refused = refused
            .iter()
            .filter(|r| r.word.chars().count() <= n)
            .map(|r| r.images)
            .sum();
        let change = out
            .last()
            .map_or(f64::NAN, |p| a.diffusion - p.averages.diffusion);
        out.push(LatticeTruncation {
            max_length: n,
            certified,
            refused,
            mean_free_time: a.mean_period / a.mean_length,
            averages: a,
            change,
        });
    }
    out
}

/// D from the MSD at the config's gap, and the last row's distance from it in its standard
/// errors.
fn msd_reference(
    config: &LatticeConfig,
    options: &RunOptions,
    last: Option<&LatticeTruncation>,
) -> Result<Option<MsdReference>, Error> {
    use crate::estimators::diffusion::{self, DiffusionConfig};
    use crate::scenes::spec::Table;
    if config.msd_collisions == 0 {
        return Ok(None);
    }
    let cfg = DiffusionConfig {
        collisions: config.msd_collisions,
        ..DiffusionConfig::on(Table::triangular(&config.w)?)
    };
    let quiet = |_: u64| {};
    let opts = RunOptions {
        threads: options.threads,
        stop: options.stop.clone(),
        progress: &quiet,
        ..RunOptions::default()
    };
    let r = diffusion::run(&cfg, &opts)?;
    let d_n = last.map_or(f64::NAN, |l| l.averages.diffusion);
    Ok(Some(MsdReference {
        collisions: config.msd_collisions,
        D: r.D,
        D_err: r.D_err,
        difference_sigma: (d_n - r.D) / r.D_err,
    }))
}
