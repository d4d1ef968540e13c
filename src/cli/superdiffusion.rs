//! `lorentz superdiffusion`: an infinite horizon's flight tails, velocity autocorrelation, t ln t
//! growth and limit law, each against the exact corridor constants.

use lorentz_gas::Error;
use lorentz_gas::estimators::superdiffusion::{self, SuperdiffusionConfig, SuperdiffusionReport};

use super::args::{CheckpointArgs, OutputArgs, RunArgs, SceneArgs, parse_count, parse_count_u32};
use super::output::{emit, sigmas, sigmas_unconverged};
use super::progress::Progress;

/// The gap superdiffusion needs (the shared help of `--w` gives the whole range w > 0).
const GAP_HELP: &str = "Gap w of the triangular scene, a decimal or a fraction such as 1/10: w > \
    w_inf = 4/sqrt(3) - 2 = 0.3094... (an infinite horizon)";

#[derive(clap::Args)]
#[command(mut_arg("w", |a| a.help(GAP_HELP)))]
pub struct Args {
    /// The scene (an infinite horizon: `--scene triangular --w W` with W > w_inf = 0.3094..., or
    /// `--scene square --radius R`).
    #[command(flatten)]
    scene: SceneArgs,
    /// Collisions in all, shared between the batches.
    #[arg(long, default_value = "2e8", value_parser = parse_count, allow_negative_numbers = true)]
    collisions: u64,
    /// Independent batches (one trajectory each), at least 16; the error bars are over them.
    #[arg(long, default_value = "32", value_parser = parse_count_u32, allow_negative_numbers = true)]
    batches: u32,
    /// The longest lag is 2^OCTAVES mean free times (1 to 20).
    #[arg(long, default_value = "12", value_parser = parse_count_u32, allow_negative_numbers = true)]
    octaves: u32,
    /// Lags per octave (1 to 16).
    #[arg(long, default_value = "4", value_parser = parse_count_u32, allow_negative_numbers = true)]
    points_per_octave: u32,
    /// The tail fits s P(tau > s) = C + B/s and s^2 mu(tau > s) = C + B/s use the times s from
    /// this many mean free times on (where every batch saw 100 longer flights).
    #[arg(long, default_value = "8", allow_negative_numbers = true)]
    tail_fit_from: f64,
    /// The lags of the plateau of t C(t), FROM:TO in mean free times; by default 2^(OCTAVES-6)
    /// to 2^(OCTAVES-4) (64:256 at 12 octaves).
    #[arg(long, value_parser = parse_window, allow_hyphen_values = true)]
    vacf_fit: Option<[f64; 2]>,
    /// The lags of the fit of <dx^2>/t = a ln t + b, FROM:TO in mean free times; by default
    /// 2^(OCTAVES-3) to 2^OCTAVES (512:4096 at 12 octaves).
    #[arg(long, value_parser = parse_window, allow_hyphen_values = true)]
    msd_fit: Option<[f64; 2]>,
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    checkpoint: CheckpointArgs,
    #[command(flatten)]
    output: OutputArgs,
}

/// A window FROM:TO of two positive numbers.
fn parse_window(text: &str) -> Result<[f64; 2], String> {
    let bad = || {
        format!("'{text}' is not a window FROM:TO: use two numbers such as 64:256, 1 <= FROM < TO")
    };
    let (a, b) = text.split_once(':').ok_or_else(bad)?;
    let a: f64 = a.trim().parse().map_err(|_| bad())?;
    let b: f64 = b.trim().parse().map_err(|_| bad())?;
    if !(a >= 1.0 && a < b && b.is_finite()) {
        return Err(bad());
    }
    Ok([a, b])
}

pub fn run(a: Args) -> Result<(), Error> {
    let windows = SuperdiffusionConfig::new(a.scene.spec()?).with_octaves(a.octaves);
    let cfg = SuperdiffusionConfig {
        collisions: a.collisions,
        batches: a.batches,
        points_per_octave: a.points_per_octave,
        tail_fit_from: a.tail_fit_from,
        vacf_fit: a.vacf_fit.unwrap_or(windows.vacf_fit),
        msd_fit: a.msd_fit.unwrap_or(windows.msd_fit),
        seed: a.run.seed(),
        ..windows
    };
    cfg.validate()?;
    let pb = Progress::new(a.collisions, "collisions", a.output.quiet);
    let opts = a.checkpoint.apply(pb.options(a.run.threads()));
    let r = superdiffusion::run(&cfg, &opts)?;
    drop(opts);
    drop(pb);
    emit(a.output.json, &r, print)
}

fn print(r: &SuperdiffusionReport) {
    let n = r.meta.batches.unwrap_or(2) as usize;
    println!(
        "{}: superdiffusion ({} batches x {} collisions, mean free path l = {:.6})",
        r.scene, n, r.collisions_per_batch, r.mean_free_path
    );
    let widths: Vec<String> = r
        .corridors
        .iter()
        .map(|c| format!("{:.6}", c.width))
        .collect();
    println!(
        "exact ({} corridors, widths {}): D_sup = {:.6e}  C_flow = {:.6e}  C_map = {:.6e}  <dx^2> ~ {:.6e} t ln t",
        r.corridors.len(),
        widths.join(", "),
        r.d_sup_exact,
        r.c_flow_exact,
        r.c_map_exact,
        r.msd_log_slope_exact
    );
    print_estimates(r, n);
    print_lags(r);
    print_law(r);
}

/// The fitted constants, each against its exact value.
fn print_estimates(r: &SuperdiffusionReport, n: usize) {
    println!("measured, each against its exact value:");
    let l = r.mean_free_path;
    let line = |what: &str, x: f64, e: f64, exact: f64, range: [f64; 2], from: f64| {
        let start = range[0] / l;
        // The window's first lag is a grid time, rounded from the mean free times asked for.
        let verdict = if start < from * (1.0 - 1e-9) {
            let why = format!(
                "the window starts at {}l, below the {from}l from which this estimator has converged",
                if (start - start.round()).abs() < 1e-9 {
                    format!("{start:.0}")
                } else {
                    format!("{start:.3}")
                }
            );
            sigmas_unconverged(x, e, exact, n, &why)
        } else {
            sigmas(x, e, exact, n)
        };
        println!(
            "  {what:<36} {x:.6e} ± {e:.1e}  over t in [{:.4}, {:.4}]  ({verdict})",
            range[0], range[1],
        )
    };
    let from = superdiffusion::CONVERGED_FROM;
    match (
        r.c_flow_tail,
        r.c_flow_tail_err,
        r.c_map_tail,
        r.c_map_tail_err,
        r.tail_fit,
    ) {
        (Some(f), Some(fe), Some(m), Some(me), Some(range)) => {
            line(
                "C_flow  (s P(tau > s) = C + B/s)",
                f,
                fe,
                r.c_flow_exact,
                range,
                from.tails,
            );
            line(
                "C_map   (s^2 mu(tau > s) = C + B/s)",
                m,
                me,
                r.c_map_exact,
                range,
                from.tails,
            );
        }
        _ => println!(
            "  C_flow, C_map: not fitted (every batch needs 100 flights longer than --tail-fit-from mean free paths at two lags; use more collisions)"
        ),
    }
    line(
        "D_sup   (t C_xx(t), weighted mean)",
        r.d_sup_vacf,
        r.d_sup_vacf_err,
        r.d_sup_exact,
        r.vacf_fit,
        from.vacf,
    );
    line(
        "2D_sup  (slope of <dx^2>/t in ln t)",
        r.msd_log_slope,
        r.msd_log_slope_err,
        r.msd_log_slope_exact,
        r.msd_fit,
        from.msd,
    );
    println!(
        "  intercept of <dx^2>/t in ln t      {:.6e} ± {:.1e}",
        r.msd_log_intercept, r.msd_log_intercept_err
    );
    println!(
        "  (the last two errors: batch {:.1e} and {:.1e}, with the bound on flights longer than the longest seen, L = {:.1}: {:.1e} and {:.1e})",
        r.d_sup_vacf_err_batch,
        r.msd_log_slope_err_batch,
        r.longest_flight,
        r.d_sup_vacf_err_unsampled,
        r.msd_log_slope_err_unsampled
    );
}

/// One line per lag, each quantity over its exact value.
fn print_lags(r: &SuperdiffusionReport) {
    println!(
        "per lag (relative to the exact value; batch errors, and in [ ] the bound on unsampled flights):"
    );
    println!(
        "      t/l            t   s P(tau>s)/C_flow  s^2 mu(tau>s)/C_map   t C(t)/D_sup   local slope/2D_sup"
    );
    let rel = |x: f64, e: f64, exact: f64| format!("{:>7.4} ± {:<7.4}", x / exact, e / exact);
    for l in &r.lags {
        let slope = match (l.msd_local_slope, l.msd_local_slope_err) {
            (Some(s), Some(e)) => format!(
                "{} [{:.4}]",
                rel(s, e, r.msd_log_slope_exact),
                l.msd_local_slope_unsampled.unwrap_or(0.0) / r.msd_log_slope_exact
            ),
            _ => String::new(),
        };
        println!(
            "  {:>7} {:>12.4}   {}  {}  {}  {}",
            l.t_over_ell,
            l.t,
            rel(l.s_p_flow, l.s_p_flow_err, r.c_flow_exact),
            rel(l.s2_p_map, l.s2_p_map_err, r.c_map_exact),
            format!(
                "{} [{:.4}]",
                rel(l.t_c, l.t_c_err, r.d_sup_exact),
                l.t_c_unsampled / r.d_sup_exact
            ),
            slope
        );
    }
}

/// One line per octave of the limit law.
fn print_law(r: &SuperdiffusionReport) {
    println!("limit law of u = dx / sqrt(D_sup t ln t) (-> N(0, 1)):");
    println!(
        "             t   (IQR/1.349)^2 (-> 1)   <u^2> (-> 2)       Kolmogorov distance   samples"
    );
    for l in &r.limit_law {
        println!(
            "  {:>12.4}   {:>7.4} ± {:<7.4}      {:>7.4} ± {:<7.4}   {:.4}                {}",
            l.t,
            l.variance_ratio,
            l.variance_ratio_err,
            l.second_moment_ratio,
            l.second_moment_ratio_err,
            l.ks_distance,
            l.samples
        );
    }
}
