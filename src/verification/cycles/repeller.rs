//! The three-disk repeller by cycles: every fundamental-domain prime cycle up to a length,
//! certified in the full space, and the cycle expansions of its escape rate, Lyapunov exponent,
//! KS entropy and partial dimension.

use super::expansion::{CycleWeight, Expansion, Truncation, convergence_table};
use super::symbols::{full_space, prime_words, word_text};
use super::*;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::parallel::par_batches;
use crate::numbers::exact::ExactInput;

/// Longest fundamental-domain cycle expanded (3 × 16 = 48 collisions in the full space).
pub const MAX_FUNDAMENTAL_LENGTH: usize = 16;

/// Default working precision of the cycles (bits).
pub const DEFAULT_CYCLE_BITS: u32 = 256;
/// Default longest fundamental-domain cycle.
pub const DEFAULT_MAX_LENGTH: usize = 8;

/// What [`run`] is asked for.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RepellerConfig {
    /// Distance R between the disk centres, R > 2a, exactly as typed (a decimal or a fraction,
    /// rounded once at the working precision).
    pub side: String,
    /// Disk radius a > 0, exactly as typed.
    pub radius: String,
    /// Longest fundamental-domain cycle N, 1 to [`MAX_FUNDAMENTAL_LENGTH`].
    pub max_length: usize,
    /// MPFR working precision of the cycles and their certificates (bits),
    /// [`MIN_CYCLE_BITS`] to [`MAX_CYCLE_BITS`].
    pub bits: u32,
}

impl RepellerConfig {
    /// The repeller of side `side` and radius `radius` (exact text) with the command line's
    /// defaults: N = [`DEFAULT_MAX_LENGTH`] at [`DEFAULT_CYCLE_BITS`] bits.
    pub fn new(side: &str, radius: &str) -> Self {
        RepellerConfig {
            side: side.trim().to_string(),
            radius: radius.trim().to_string(),
            max_length: DEFAULT_MAX_LENGTH,
            bits: DEFAULT_CYCLE_BITS,
        }
    }

    /// The disks, R and a parsed exactly ([`parse_exact`](crate::numbers::exact::parse_exact)).
    ///
    /// # Errors
    /// Text that is not an exact decimal or fraction, a NaN or an infinity, a ≤ 0 or R ≤ 2a.
    pub fn disks(&self) -> Result<Disks, Error> {
        let exact = |what: &'static str, text: &str, range: &str| -> Result<Rational, Error> {
            let e = ExactInput::parse(text).map_err(|e| e.named(what))?;
            e.exact
                .ok_or_else(|| Error::out_of_range(what, e.value, range))
        };
        let radius = exact("radius", &self.radius, "use a finite radius a > 0")?;
        let side = exact(
            "side",
            &self.side,
            "use a finite side R > 2a (disjoint disks)",
        )?;
        let disks = Disks::three_disk(side, radius);
        disks.validate()?;
        Ok(disks)
    }

    /// Checks every parameter; errors name the valid range.
    ///
    /// # Errors
    /// Disks that touch, a length or precision out of range.
    pub fn validate(&self) -> Result<(), Error> {
        self.disks()?;
        Error::unless_in(
            "max_length",
            self.max_length,
            1..=MAX_FUNDAMENTAL_LENGTH,
            " (the longest fundamental-domain cycle)",
        )?;
        Error::unless_in("bits", self.bits, MIN_CYCLE_BITS..=MAX_CYCLE_BITS, " bits")?;
        Ok(())
    }
}

/// A fundamental-domain prime cycle and its certified full-space cycle.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FundamentalCycle {
    /// The binary word p̃ (0: reflection, 1: rotation).
    pub word: String,
    /// Order h of the symmetry the full-space cycle closes with (its length is h·n_p̃).
    pub order: usize,
    /// T_p̃ = T_p/h.
    pub period: f64,
    /// Λ_p̃ = (−1)^(number of 0s) × the expanding eigenvalue of the first n_p̃ Jacobians
    /// (a reflection is −I in Birkhoff coordinates); Λ_p̃^h = Λ_p.
    pub stability: f64,
    /// The certified full-space cycle.
    pub cycle: Cycle,
    /// n_p̃, T_p̃, Λ_p̃ at the working precision.
    #[serde(skip)]
    weight: Option<CycleWeight>,
}

/// The certified cycles and the convergence tables of both expansions.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RepellerReport {
    /// What was run.
    pub config: RepellerConfig,
    /// Cycles certified (all, when the report is complete).
    pub certified: usize,
    /// The fundamental-domain prime cycles, by length.
    pub cycles: Vec<FundamentalCycle>,
    /// The spectral determinant's truncations N = 1 … max_length.
    pub spectral_determinant: Vec<Truncation>,
    /// The dynamical zeta function's truncations.
    pub zeta_function: Vec<Truncation>,
    /// Version, precision, threads, command line.
    pub meta: RunMeta,
}

/// The fundamental-domain cycle of `word` on the repeller `disks`, certified at `bits`.
///
/// # Errors
/// As [`certify_cycle`].
pub fn fundamental_cycle(disks: &Disks, word: &[u8], bits: u32) -> Result<FundamentalCycle, Error> {
    let (seq, order) = full_space(word);
    let cycle = certify_cycle(disks, &seq, bits)?;
    let zeros = word.iter().filter(|&&s| s == 0).count();
    let mut lam = cycle.partial_stability(word.len());
    if zeros % 2 == 1 {
        lam = -lam;
    }
    let period = match &cycle.period_exact {
        Some(t) => t.clone() / order as u32,
        None => Float::with_val(bits, f64::NAN),
    };
    Ok(FundamentalCycle {
        word: word_text(word),
        order,
        period: period.to_f64(),
        stability: lam.to_f64(),
        weight: Some(CycleWeight {
            length: word.len(),
            period,
            stability: lam,
        }),
        cycle,
    })
}

/// Certifies every fundamental-domain prime cycle up to `config.max_length` and expands. The
/// result does not depend on `options.threads`.
///
/// # Errors
/// A parameter out of range, or a cycle that is not certified (the message names it).
pub fn run(config: &RepellerConfig, options: &RunOptions) -> Result<RepellerReport, Error> {
    options.validate()?;
    options.refuse_unused("cycles", &[])?;
    config.validate()?;
    let disks = config.disks()?;
    let words = prime_words(config.max_length);
    let cycles = par_batches(options.threads, words.len() as u32, |k| {
        let c = fundamental_cycle(&disks, &words[k as usize], config.bits)?;
        (options.progress)(1);
        Ok(c)
    })?;
    if let Some(bad) = cycles.iter().find(|c| !c.cycle.certified) {
        return Err(Error::Failed(format!(
            "cycle {} is not certified: {}",
            bad.word,
            bad.cycle.failure.as_deref().unwrap_or("unknown")
        )));
    }
    let weights: Vec<CycleWeight> = cycles.iter().filter_map(|c| c.weight.clone()).collect();
    let n = config.max_length;
    Ok(RepellerReport {
        config: config.clone(),
        certified: cycles.len(),
        spectral_determinant: convergence_table(&weights, n, Expansion::SpectralDeterminant)?,
        zeta_function: convergence_table(&weights, n, Expansion::ZetaFunction)?,
        cycles,
        meta: RunMeta::new(None, None, config.bits, Some(options.threads)),
    })
}
