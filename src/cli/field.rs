//! `lorentz diffusion --field B`: the diffusion tensor in a magnetic field.

use lorentz_gas::Error;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::diffusion::DiffusionConfig;
use lorentz_gas::estimators::field::{self, FieldConfig, FieldReport};
use lorentz_gas::statistics::comparison;
use lorentz_gas::theory::magnetic::SHARE_TOLERANCE;

use super::output::{emit, sigmas};
use super::progress::Progress;

/// The field run of a diffusion configuration (validated).
pub fn config(diffusion: DiffusionConfig, field: &str, samples: u64) -> Result<FieldConfig, Error> {
    let cfg = FieldConfig {
        diffusion,
        field: field.trim().to_string(),
        localization_samples: samples,
    };
    cfg.validate()?;
    Ok(cfg)
}

/// Runs it with the options the command line gave and prints or writes the report.
pub fn run(cfg: &FieldConfig, opts: RunOptions, quiet: bool, json: bool) -> Result<(), Error> {
    let pb = Progress::new(cfg.diffusion.collisions, "collisions", quiet);
    let progress = pb.callback();
    let opts = RunOptions {
        progress: &progress,
        ..opts
    };
    let r = field::run(cfg, &opts)?;
    drop(progress);
    drop(pb);
    emit(json, &r, print)
}

fn print(r: &FieldReport) {
    let m = &r.meta;
    println!(
        "periodic Lorentz gas in a magnetic field, w = {}, B = {} (cyclotron radius {:.6})  ({} precision, {} engine, seed {}, {} batches, {:.3e} collisions, {:.1} s)",
        r.w,
        r.config.field,
        r.cyclotron_radius,
        m.precision,
        m.engine,
        m.seed.unwrap_or_default(),
        m.batches.unwrap_or_default(),
        r.collisions as f64,
        r.seconds
    );
    let n = r.batch_D_xx.len();
    println!(
        "localized share = {:.6} ± {:.6}   exact {:.6} (pinned {:.6}, skipping {:.6}; {})",
        r.localized_fraction,
        r.localized_fraction_err,
        r.localized_fraction_exact,
        r.pinned_fraction_exact,
        r.skipping_fraction_exact,
        binomial(r)
    );
    if r.all_localized {
        println!(
            "every orbit is localized (2ρ ≤ A − 2r): D_xx = D_xy = 0 exactly, no trajectory run"
        );
        return;
    }
    println!(
        "D_xx          = {:.6} ± {:.6}   (whole phase space; the diffusing part's × {:.6})",
        r.D_xx,
        r.D_xx_err,
        1.0 - r.localized_fraction_exact
    );
    println!(
        "D_xy (Hall)   = {:.6} ± {:.6}   (from the Lévy area; whole phase space)",
        r.D_xy, r.D_xy_err
    );
    let t = &r.diffusing;
    let c = &r.diffusing_check;
    println!(
        "diffusing part: D_xx {:.6} ± {:.6}, D_yy {:.6} ± {:.6}, Hall D_xy {:.6} ± {:.6}, symmetric D_xy {:.6} ± {:.6}   (MSD slopes over [{}τ, {}τ], τ = {:.4})",
        t.D_xx,
        t.D_xx_err,
        t.D_yy,
        t.D_yy_err,
        t.D_xy,
        t.D_xy_err,
        t.D_xy_symmetric,
        t.D_xy_symmetric_err,
        r.window.lo,
        r.window.hi,
        r.tau
    );
    println!(
        "check window  : D_xx {:.6} ± {:.6}, Hall D_xy {:.6} ± {:.6}   (over [{}τ, {}τ])",
        c.D_xx, c.D_xx_err, c.D_xy, c.D_xy_err, r.check_window.lo, r.check_window.hi
    );
    println!(
        "mean free time = {:.6} ± {:.6}   Kac {:.6}  ({})",
        r.mean_free_time,
        r.mean_free_time_err,
        r.mean_free_time_exact,
        sigmas(
            r.mean_free_time,
            r.mean_free_time_err,
            r.mean_free_time_exact,
            n
        )
    );
    let kac = comparison::of(
        r.mean_free_time - r.mean_free_time_exact,
        r.mean_free_time_err,
        comparison::batch_dof(n),
    );
    if !kac.agrees() {
        eprintln!(
            "warning: the diffusing part's mean free time is {:.1} standard errors from Kac's: \
             what is neither pinned nor skipping is not one ergodic component here (regular \
             islands of orbits that stay near their start), and {n} batches do not sample the \
             components in proportion; use more --batches",
            kac.z.abs()
        );
    }
}

/// The sampled share against the exact one, at the binomial 4σ bound (the exact share's
/// quadrature tolerance added to the error, so that an exact share of 1 − 10⁻¹³ and a sampled 1
/// agree).
fn binomial(r: &FieldReport) -> String {
    let f = r.localized_fraction_exact;
    let n = r.config.localization_samples as f64;
    let err = (f * (1.0 - f)).max(0.0).sqrt() / n.sqrt() + SHARE_TOLERANCE;
    let c = comparison::of(r.localized_fraction - f, err, f64::INFINITY);
    format!(
        "{:+.1}σ, bound {:.1}σ: {}",
        c.z,
        c.bound,
        if c.agrees() { "agree" } else { "DISAGREE" }
    )
}
