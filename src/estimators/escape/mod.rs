//! D(w) from the escape rate out of an open strip (Gaspard–Baras): a third estimator of the
//! diffusion coefficient, independent of the Einstein MSD slope and of hop-level Green–Kubo.
//!
//! Particles start from the invariant measure restricted to the strip 0 ≤ x ≤ L
//! ([`crate::scenes::strip`]) and are followed until their x leaves [0, L] or until the cut-off
//! t_max. On diffusive scales the density obeys ∂ₜρ = D∂ₓ²ρ with ρ = 0 at x = 0, L, so the
//! survival is S(t) = Σ_{n odd} 8/(n²π²) e^{−n²γt} with γ = Dπ²/L² (`proofs-notes/escape-rate.md`).
//!
//! Per width L:
//! * t_max = [`T_MAX_E_FOLDS`]/γ_guess with γ_guess = D_MZ π²/L² (Machta–Zwanzig, closed form).
//! * The tail starts at t₀, the time at which the empirical survival has fallen to
//!   [`TAIL_START_SURVIVAL`] (≈ one e-fold into the lowest mode: there the n = 3 mode, which decays
//!   9× faster, changes the hazard rate by less than 10⁻⁴ relative).
//! * γ̂ is the maximum-likelihood rate of a censored exponential on the tail: the particles alive
//!   at t₀ (memoryless), γ̂ = n_abs / Σ (min(tᵢ, t_max) − t₀). Its error is reported twice: the
//!   Fisher value γ̂/√n_abs and the batch value (ratio estimator over [`BATCHES_PER_WIDTH`]
//!   independent batches, se² = B/(B−1) Σ_b (n_b − γ̂E_b)² / (ΣE_b)²), which is the one used.
//! * The tail is checked to be exponential: γ̂ on [t₀, t₁] and on [t₁, t_max] (t₁ = t₀ + 1/γ̂,
//!   one e-fold later) are reported with their difference in combined σ.
//! * D_eff(L) = γ̂ L²/π².
//!
//! Across widths: D_eff(L) = D + c/L ([`FINITE_SIZE_FORM`]: the absorbing lines act as if shifted
//! outwards by a microscopic length b, γ = Dπ²/(L + 2b)², so D_eff = D(1 − 4b/L + O(L⁻²)) — the
//! Milne extrapolation length of a walk with finite steps), fitted by weighted least squares in
//! 1/L; D_escape is the intercept, its error scaled by √(χ²/dof) when that exceeds 1.
//!
//! Streams: batch b of width number k uses `StreamKey::new(seed, Purpose::Escape, b).in_run(k)`;
//! every batch is a fixed set of particles, so the result does not depend on the thread count.

use std::time::Instant;

use serde::{Deserialize, Serialize};

mod chunks;
mod rate;
pub mod survival;

use chunks::Chunks;
pub use rate::{Lifetime, RateEstimate, tail_start, window_counts, window_rate};

use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::{RunOption, RunOptions};
use crate::engine::parallel::{par_batches_watched, share};
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::scenes::spec::Table;
use crate::scenes::strip::Strip;
use crate::scenes::triangular::TriangularScene;
use crate::scenes::triangular::geometry::Geometry;
use crate::statistics::fits::weighted_line_fit;

/// Independent batches per width: the error of γ̂ is their batch error (dozens give a reliable
/// standard error; a fixed number keeps the bits independent of the thread count).
pub const BATCHES_PER_WIDTH: u32 = 32;

/// The tail starts where the empirical survival has fallen to this fraction: with
/// S ≈ (8/π²)e^{−γt} that is γt₀ ≈ ln(0.81/0.25) ≈ 1.2, where the n = 3 mode's share of the
/// hazard rate, 8·(1/9)e^{−8γt₀}, is below 10⁻⁴.
pub const TAIL_START_SURVIVAL: f64 = 0.25;

/// Cut-off time in e-folds of the Machta–Zwanzig guess of γ: D/D_MZ ≥ 0.89 on the whole diffusive
/// range (docs/guide/diffusion.md table; smallest near w = 0.055), so at most ≈ 0.81e^{−7.2} ≈ 0.06 % of the particles are censored, yet the MLE uses them.
pub const T_MAX_E_FOLDS: f64 = 8.0;

/// Narrowest strip, in lattice spacings a: a strip of fewer traps across has no diffusive regime.
pub const MIN_WIDTH_SPACINGS: f64 = 4.0;

/// Narrowest strip, in mean free paths ⟨ℓ⟩: diffusion needs many flights between the two lines.
pub const MIN_WIDTH_FREE_PATHS: f64 = 10.0;

/// Widest strip: lifetimes grow like L², at L = 2000 each particle needs ~10⁷–10⁸ collisions.
pub const MAX_WIDTH: f64 = 2000.0;

/// Fewest particles per width: each of the [`BATCHES_PER_WIDTH`] batches needs ~25 tail
/// absorptions for its share of the ratio estimator to be near normal.
pub const MIN_PARTICLES: u64 = 100 * BATCHES_PER_WIDTH as u64;

/// Most particles per width: every lifetime is kept in memory until the tail start is chosen
/// (16 bytes each, 320 MB per width at this bound).
pub const MAX_PARTICLES: u64 = 20_000_000;

/// Default widths in lattice spacings a = 2 + w: large against the trap size, ratio 3 between the
/// extremes for the extrapolation in 1/L, two degrees of freedom for its χ².
pub const DEFAULT_WIDTH_SPACINGS: [f64; 4] = [8.0, 12.0, 16.0, 24.0];

/// The finite-size form fitted across widths.
pub const FINITE_SIZE_FORM: &str = "D_eff(L) = gamma(L) L^2/pi^2 = D + c/L (absorbing lines effectively shifted outwards by b = -c/(4D) each side: gamma = D pi^2/(L + 2b)^2)";

/// Everything that defines an escape-rate run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EscapeConfig {
    /// The triangular gas at a gap 0 < w < w∞, without a field (in JSON `w` and `w_exact`; a
    /// record of before with `w` alone reads as that double).
    #[serde(flatten)]
    pub table: Table,
    /// Strip widths L (lengths, disk radius 1).
    pub widths: Vec<f64>,
    /// Particles per width.
    pub particles_per_width: u64,
    /// Seed of the random streams.
    pub seed: u64,
}

impl EscapeConfig {
    /// The default run on `table`: [`default_widths`] at its gap (none on a table without one,
    /// which [`validate`](Self::validate) refuses), 2·10⁵ particles per width, seed 1.
    pub fn new(table: Table) -> Self {
        let widths = table
            .gap_for("escape")
            .map_or_else(|_| Vec::new(), default_widths);
        EscapeConfig {
            table,
            widths,
            particles_per_width: 200_000,
            seed: 1,
        }
    }

    /// The narrowest accepted width at `w`: max(4a, 10⟨ℓ⟩).
    pub fn min_width(w: f64) -> Result<f64, Error> {
        let g = Geometry::new(w)?;
        Ok((MIN_WIDTH_SPACINGS * g.spacing()).max(MIN_WIDTH_FREE_PATHS * g.mean_free_path()))
    }

    /// The gap as its nearest double (what the strips run at); another table is an error.
    pub fn gap(&self) -> Result<f64, Error> {
        crate::estimators::straight_gap(&self.table, "escape")
    }

    /// Checks every parameter; errors name the valid range.
    ///
    /// # Errors
    /// Another scene ([`Error::Lacks`] trap symbols), a field, a gap outside (0, w∞) as typed,
    /// and the widths and particles out of range.
    pub fn validate(&self) -> Result<(), Error> {
        self.table.motion_taken_by("escape")?;
        let w = crate::estimators::diffusive_gap(&self.table, "escape")?;
        let min = Self::min_width(w)?;
        for &l in &self.widths {
            if !(l.is_finite() && l >= min && l <= MAX_WIDTH) {
                return Err(Error::out_of_range(
                    "widths",
                    l,
                    format!(
                        "use widths L from {min:.3} to {MAX_WIDTH} at w = {} (at least \
                         {MIN_WIDTH_SPACINGS} lattice spacings and {MIN_WIDTH_FREE_PATHS} mean \
                         free paths)",
                        w
                    ),
                ));
            }
        }
        let mut distinct = self.widths.clone();
        distinct.sort_by(f64::total_cmp);
        distinct.dedup();
        let widths = || {
            (self.widths.iter())
                .map(f64::to_string)
                .collect::<Vec<_>>()
                .join(",")
        };
        if distinct.len() < 3 {
            return Err(Error::parameter(
                "widths",
                widths(),
                format!(
                    "{} distinct width(s) given: the extrapolation in 1/L needs at least 3 \
                     distinct widths (2 for the line, 1 degree of freedom for its chi^2)",
                    distinct.len()
                ),
            ));
        }
        if distinct.len() != self.widths.len() {
            return Err(Error::parameter(
                "widths",
                widths(),
                "widths must be distinct",
            ));
        }
        Error::unless_in(
            "particles_per_width",
            self.particles_per_width,
            MIN_PARTICLES..=MAX_PARTICLES,
            "",
        )?;
        Ok(())
    }
}

/// The default widths at `w`: [`DEFAULT_WIDTH_SPACINGS`] times the spacing a = 2 + w.
pub fn default_widths(w: f64) -> Vec<f64> {
    DEFAULT_WIDTH_SPACINGS
        .iter()
        .map(|k| k * (2.0 + w))
        .collect()
}

/// One width's result.
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct EscapeWidth {
    /// Strip width L.
    pub L: f64,
    /// L in lattice spacings a.
    pub L_over_a: f64,
    /// The Machta–Zwanzig guess D_MZ π²/L² that sets t_max.
    pub gamma_guess: f64,
    /// Cut-off time.
    pub t_max: f64,
    /// Particles followed.
    pub particles: u64,
    /// Particles absorbed before t_max.
    pub absorbed: u64,
    /// Start t₀ of the fitted tail.
    pub tail_start: f64,
    /// Particles alive at t₀.
    pub tail_particles: u64,
    /// Absorptions in the tail (t₀, t_max].
    pub tail_absorbed: u64,
    /// Escape rate γ̂ (censored-exponential MLE on the tail).
    pub gamma: f64,
    /// Its batch standard error (the one used).
    pub gamma_err: f64,
    /// Its Fisher standard error γ̂/√n_abs (for comparison).
    pub gamma_err_mle: f64,
    /// D_eff = γ̂L²/π².
    pub D_eff: f64,
    /// Its standard error.
    pub D_eff_err: f64,
    /// Split of the tail check, t₁ = t₀ + 1/γ̂.
    pub tail_split: f64,
    /// γ̂ on (t₀, t₁].
    pub gamma_early: f64,
    /// Its batch standard error.
    pub gamma_early_err: f64,
    /// γ̂ on (t₁, t_max].
    pub gamma_late: f64,
    /// Its batch standard error.
    pub gamma_late_err: f64,
    /// (γ_late − γ_early) in combined σ: near 0 for an exponential tail.
    pub tail_check_sigma: f64,
    /// Events (collisions and crossings) over all particles.
    pub events: u64,
}

/// The result of an escape-rate run (the CLI's `--json`).
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct EscapeReport {
    /// Gap w.
    pub w: f64,
    /// D extrapolated to L → ∞ (intercept of the finite-size fit).
    pub D_escape: f64,
    /// Its standard error (scaled by √(χ²/dof) if that exceeds 1).
    pub D_escape_err: f64,
    /// Slope c of D_eff against 1/L.
    pub slope: f64,
    /// Its standard error (scaled like D_escape_err).
    pub slope_err: f64,
    /// Effective outward shift b = −c/(4D) of each absorbing line (γ = Dπ²/(L + 2b)²).
    pub boundary_shift: f64,
    /// Its standard error (linear propagation with the fit covariance).
    pub boundary_shift_err: f64,
    /// χ² of the finite-size fit.
    pub chi2: f64,
    /// Its degrees of freedom (widths − 2).
    pub dof: usize,
    /// χ²/dof.
    pub chi2_per_dof: f64,
    /// `true` if the errors were scaled by √(χ²/dof) > 1.
    pub errors_scaled: bool,
    /// The finite-size form fitted.
    pub finite_size_form: String,
    /// Machta–Zwanzig value, for comparison.
    pub D_MZ: f64,
    /// Tail start rule: the survival fraction at t₀.
    pub tail_start_survival: f64,
    /// Cut-off in e-folds of the Machta–Zwanzig γ.
    pub t_max_e_folds: f64,
    /// Independent batches per width.
    pub batches_per_width: u32,
    /// Per-width results, in the order given.
    pub widths: Vec<EscapeWidth>,
    /// Events over all widths.
    pub events: u64,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// The configuration that produced the result (what `lorentz report` re-runs).
    pub config: EscapeConfig,
    /// Version, seed, batches, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// One batch: the lifetimes of its particles and the events they took.
struct BatchOut {
    lifetimes: Vec<Lifetime>,
    events: u64,
}

/// The per-width analysis of the lifetimes of its batches.
///
/// # Errors
/// If the survival at t_max exceeds the tail-start fraction (D far below D_MZ) or a window is
/// empty.
pub fn analyse_width(
    width: f64,
    spacing: f64,
    gamma_guess: f64,
    t_max: f64,
    batches: &[Vec<Lifetime>],
) -> Result<EscapeWidth, Error> {
    let all: Vec<Lifetime> = batches.iter().flatten().copied().collect();
    let particles = all.len() as u64;
    let absorbed = all.iter().filter(|l| l.absorbed).count() as u64;
    let t0 = tail_start(&all, TAIL_START_SURVIVAL);
    if t0 >= t_max {
        return Err(Error::Failed(format!(
            "at L = {width} more than {TAIL_START_SURVIVAL} of the particles survive to t_max = \
             {t_max:.1}: the escape is much slower than the Machta-Zwanzig guess"
        )));
    }
    let tail = window_rate(batches, t0, t_max)?;
    let t1 = t0 + 1.0 / tail.gamma;
    if t1 >= t_max {
        return Err(Error::Failed(format!(
            "at L = {width} the tail (t0 = {t0:.1}, t_max = {t_max:.1}) is shorter than two e-folds"
        )));
    }
    let early = window_rate(batches, t0, t1)?;
    let late = window_rate(batches, t1, t_max)?;
    let scale = width * width / (std::f64::consts::PI * std::f64::consts::PI);
    Ok(EscapeWidth {
        L: width,
        L_over_a: width / spacing,
        gamma_guess,
        t_max,
        particles,
        absorbed,
        tail_start: t0,
        tail_particles: tail.alive,
        tail_absorbed: tail.absorbed,
        gamma: tail.gamma,
        gamma_err: tail.err,
        gamma_err_mle: tail.err_mle,
        D_eff: tail.gamma * scale,
        D_eff_err: tail.err * scale,
        tail_split: t1,
        gamma_early: early.gamma,
        gamma_early_err: early.err,
        gamma_late: late.gamma,
        gamma_late_err: late.err,
        tail_check_sigma: (late.gamma - early.gamma) / early.err.hypot(late.err),
        events: 0,
    })
}

/// The per-width analyses of the batches `outs` (width by width, [`BATCHES_PER_WIDTH`] each).
fn analyse_widths(
    widths: &[f64],
    outs: &[BatchOut],
    g: &Geometry<f64>,
    t_max: &[f64],
) -> Result<Vec<EscapeWidth>, Error> {
    let pi2 = std::f64::consts::PI * std::f64::consts::PI;
    let mut out = Vec::with_capacity(widths.len());
    for (k, chunk) in outs.chunks(BATCHES_PER_WIDTH as usize).enumerate() {
        let l = widths[k];
        let batches: Vec<Vec<Lifetime>> = chunk.iter().map(|o| o.lifetimes.clone()).collect();
        let guess = g.d_mz() * pi2 / (l * l);
        let mut wr = analyse_width(l, g.spacing(), guess, t_max[k], &batches)?;
        wr.events = chunk.iter().map(|o| o.events).sum();
        out.push(wr);
    }
    Ok(out)
}

/// Runs the configured computation. `options.progress` receives particle counts as they finish;
/// `threads`, `progress`, `resume` and `checkpoint_every` of the options apply (the strips run on
/// the scalar kernel). With `options.resume` (a file), each batch's finished particles are
/// appended to it every `options.checkpoint_every` and when the batch ends, and a rerun continues
/// from them to the uninterrupted bits.
///
/// # Errors
/// An invalid configuration or options, before any work.
pub fn run(cfg: &EscapeConfig, options: &RunOptions) -> Result<EscapeReport, Error> {
    cfg.validate()?;
    options.accept("escape", &[RunOption::Resume, RunOption::CheckpointEvery])?;
    let (threads, progress) = (options.threads, options.progress);
    let start = Instant::now();
    let w = cfg.gap()?;
    let scene = TriangularScene::new(w)?;
    let g = Geometry::new(w)?;
    let d_mz = g.d_mz();
    // A particle started uniformly in a strip of width L leaves after L²/(12 D) on average,
    // ⟨ℓ⟩ per collision (D ≈ D_MZ).
    let per_particle: f64 = cfg
        .widths
        .iter()
        .map(|&l| l * l / (12.0 * d_mz * g.mean_free_path()))
        .sum();
    crate::engine::work::Work::new(
        "escape",
        &["particles_per_width", "widths"],
        cfg.particles_per_width as f64 * per_particle,
    )
    .or_raise("w")
    .check(threads)?;
    let pi2 = std::f64::consts::PI * std::f64::consts::PI;
    let strips: Vec<Strip> = cfg
        .widths
        .iter()
        .map(|&l| Strip::new(&scene, l))
        .collect::<Result<_, _>>()?;
    let t_max: Vec<f64> = cfg
        .widths
        .iter()
        .map(|&l| T_MAX_E_FOLDS * l * l / (d_mz * pi2))
        .collect();
    let nb = BATCHES_PER_WIDTH;
    let tasks = nb * cfg.widths.len() as u32;
    let quota = |task: u32| share(cfg.particles_per_width, nb, task % nb);
    let t_max_of = |task: u32| t_max[(task / nb) as usize];
    let every = options.checkpoint_every;
    let kept = Chunks::open(
        options.resume.as_deref(),
        cfg,
        tasks,
        quota,
        t_max_of,
        every,
    )?;
    progress(kept.particles_done());
    let outs = par_batches_watched(threads, tasks, options.stop.as_ref(), |task| {
        let (k, b) = (task / nb, task % nb);
        let rng = StreamKey::new(cfg.seed, Purpose::Escape, b as u64)
            .in_run(k as u64)
            .rng();
        let strip = &strips[k as usize];
        let stop = options.stop.as_ref();
        let (n, t_max) = (quota(task), t_max_of(task));
        let done = kept.follow((task, strip), rng, (n, t_max), progress, stop)?;
        Ok(BatchOut {
            lifetimes: done.lifetimes,
            events: done.events,
        })
    })?;
    let widths = analyse_widths(&cfg.widths, &outs, &g, &t_max)?;
    let mut report = finite_size_fit(cfg, widths, d_mz)?;
    report.seconds = start.elapsed().as_secs_f64();
    report.meta = RunMeta::new(Some(cfg.seed), Some(tasks as u64), "f64", Some(threads));
    Ok(report)
}

/// The report of the analysed `widths`: D and the boundary shift from the weighted fit of
/// D_eff(L) = D + c/L, its errors scaled by χ²/dof where that exceeds 1 (seconds and metadata
/// left for the caller).
fn finite_size_fit(
    cfg: &EscapeConfig,
    widths: Vec<EscapeWidth>,
    d_mz: f64,
) -> Result<EscapeReport, Error> {
    let x: Vec<f64> = widths.iter().map(|r| 1.0 / r.L).collect();
    let y: Vec<f64> = widths.iter().map(|r| r.D_eff).collect();
    let s: Vec<f64> = widths.iter().map(|r| r.D_eff_err).collect();
    let fit = weighted_line_fit(&x, &y, &s)?;
    let chi2_per_dof = fit.chi2_per_dof();
    let errors_scaled = chi2_per_dof > 1.0;
    let scale2 = if errors_scaled { chi2_per_dof } else { 1.0 };
    let (d, c) = (fit.intercept, fit.slope);
    let (var_d, var_c, cov) = (
        fit.var_intercept * scale2,
        fit.var_slope * scale2,
        fit.cov * scale2,
    );
    // b = −c/(4D): ∂b/∂c = −1/(4D), ∂b/∂D = c/(4D²).
    let (db_dc, db_dd) = (-0.25 / d, 0.25 * c / (d * d));
    let var_b = db_dc * db_dc * var_c + db_dd * db_dd * var_d + 2.0 * db_dc * db_dd * cov;
    Ok(EscapeReport {
        w: cfg.gap()?,
        D_escape: d,
        D_escape_err: var_d.sqrt(),
        slope: c,
        slope_err: var_c.sqrt(),
        boundary_shift: -c / (4.0 * d),
        boundary_shift_err: var_b.max(0.0).sqrt(),
        chi2: fit.chi2,
        dof: fit.dof,
        chi2_per_dof,
        errors_scaled,
        finite_size_form: FINITE_SIZE_FORM.to_string(),
        D_MZ: d_mz,
        tail_start_survival: TAIL_START_SURVIVAL,
        t_max_e_folds: T_MAX_E_FOLDS,
        batches_per_width: BATCHES_PER_WIDTH,
        events: widths.iter().map(|r| r.events).sum(),
        widths,
        seconds: 0.0,
        config: cfg.clone(),
        meta: RunMeta::new(Some(cfg.seed), None, "f64", None),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn censored_exponential_mle_on_exact_lifetimes() {
        // Three absorbed at 1, 2, 3 and one censored at 4, window (0, 4]: γ̂ = 3/(1+2+3+4).
        let l = |time, absorbed| Lifetime { time, absorbed };
        let v = vec![l(1.0, true), l(2.0, true), l(3.0, true), l(4.0, false)];
        assert_eq!(window_counts(&v, 0.0, 4.0), (3, 10.0));
        // Window (1.5, 2.5]: alive at 1.5 are 2, 3, 4; one absorption; exposure 0.5 + 1 + 1.
        assert_eq!(window_counts(&v, 1.5, 2.5), (1, 2.5));
        assert_eq!(tail_start(&v, 0.25), 4.0);
        assert_eq!(tail_start(&v, 0.5), 3.0);
    }
}
