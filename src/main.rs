//! `lorentz`: the command-line face of lorentz-gas.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rug::Float;
use serde_json::json;

use lorentz_gas::diffusion::{self, DiffusionConfig, Precision, Window};
use lorentz_gas::error::Error;
use lorentz_gas::geometry::Geometry;
use lorentz_gas::real::Real;

#[derive(Parser)]
#[command(
    name = "lorentz",
    version,
    about = "Deterministic diffusion in the periodic Lorentz gas (Klages & Dellago 2000), with error bars and MPFR shadows"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Diffusion coefficient D(w) by the Einstein formula, with standard errors from independent batches.
    Diffusion {
        /// Gap between neighbouring disks, 0 < w < 4/sqrt(3) - 2 = 0.3094.
        #[arg(long, allow_negative_numbers = true)]
        w: f64,
        /// Total collisions over all batches.
        #[arg(long, default_value_t = 2_000_000_000)]
        collisions: u64,
        /// Independent batches (trajectories); the error bar is their standard error.
        #[arg(long, default_value_t = 32)]
        batches: u32,
        /// Seed of the random streams (same seed, same bits, whatever --threads).
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Number type: f64, or MPFR bits (>= 53).
        #[arg(long, default_value = "f64")]
        precision: String,
        /// Fit window LO:HI for the MSD slope, in units of the mean hop time tau.
        #[arg(long, default_value = "10:40")]
        window: String,
        /// Second, later window fitted as a check of the linear regime.
        #[arg(long, default_value = "20:80")]
        check_window: String,
        /// Append each finished batch to this file; a rerun with the same parameters resumes.
        #[arg(long)]
        checkpoint: Option<PathBuf>,
        /// Replay this fraction of the events in MPFR as the run goes (per-event shadow audit; f64 runs).
        #[arg(long)]
        audit: Option<f64>,
        /// Reference precision of the audit, in bits (>= 128).
        #[arg(long, default_value_t = 128)]
        audit_precision: u32,
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
    },
    /// Per-event shadow audit: replay f64 events in MPFR from the exact pre-event state and judge them against the error model.
    Audit {
        /// Gap w, 0 < w < w_inf.
        #[arg(long, allow_negative_numbers = true)]
        w: f64,
        /// Collisions simulated (all trajectories).
        #[arg(long, default_value_t = 1_000_000)]
        collisions: u64,
        /// Fraction of events replayed, in (0, 1].
        #[arg(long, default_value_t = 1.0)]
        sample: f64,
        /// Reference precision in bits (>= 128).
        #[arg(long, default_value_t = 128)]
        precision: u32,
        /// Seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Worker threads (default: all cores); one trajectory per thread.
        #[arg(long)]
        threads: Option<usize>,
        /// Machine-readable output (includes every event outside the model, with its exact state).
        #[arg(long)]
        json: bool,
    },
    /// Largest Lyapunov exponent (tangent space) and the divergence of f64/64..1024-bit orbits from a 4096-bit reference.
    Lyapunov {
        /// Gap w, 0 < w < w_inf.
        #[arg(long, allow_negative_numbers = true)]
        w: f64,
        /// Collisions per tangent-space orbit.
        #[arg(long, default_value_t = 2_000_000)]
        collisions: u64,
        /// Independent tangent-space orbits.
        #[arg(long, default_value_t = 16)]
        orbits: u32,
        /// Initial conditions for the divergence measurement (0 to skip it).
        #[arg(long, default_value_t = 8)]
        starts: u32,
        /// Seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
    },
    /// Certify a segment of N collisions to D digits by precision doubling (runs at P and 2P bits agree).
    Certify {
        /// Gap w, 0 < w < w_inf.
        #[arg(long, allow_negative_numbers = true)]
        w: f64,
        /// Collisions in the segment.
        #[arg(long, default_value_t = 1000)]
        collisions: usize,
        /// Digits to certify.
        #[arg(long, default_value_t = 30)]
        digits: u32,
        /// Seed of the equilibrium start.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
    },
    /// Backscattering by injection into a single trap from the invariant flux (Kac's lemma checks included).
    Backscatter {
        /// Gap w, 0 < w < w_inf.
        #[arg(long, allow_negative_numbers = true)]
        w: f64,
        /// Particles injected.
        #[arg(long, default_value_t = 10_000_000)]
        visits: u64,
        /// Number type: f64, or MPFR bits (>= 53).
        #[arg(long, default_value = "f64")]
        precision: String,
        /// Independent batches.
        #[arg(long, default_value_t = 32)]
        batches: u32,
        /// Seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
    },
    /// Trap-hopping statistics along lattice trajectories: p_bs, p_cf, symbol sequences, hop-level Green-Kubo D.
    Hops {
        /// Gap w, 0 < w < w_inf.
        #[arg(long, allow_negative_numbers = true)]
        w: f64,
        /// Collisions in all.
        #[arg(long, default_value_t = 500_000_000)]
        collisions: u64,
        /// Independent batches.
        #[arg(long, default_value_t = 32)]
        batches: u32,
        /// Longest symbol sequence counted.
        #[arg(long, default_value_t = 4)]
        order: usize,
        /// Seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
    },
    /// D over a range of w with independent runs per point (resumable); residuals, Boltzmann fit, MZ crossing, figures.
    Sweep {
        /// First w.
        #[arg(long)]
        w_from: f64,
        /// Last w.
        #[arg(long)]
        w_to: f64,
        /// Number of points.
        #[arg(long, default_value_t = 11)]
        steps: u32,
        /// Independent runs per point (the error bar is their standard error).
        #[arg(long, default_value_t = 10)]
        runs: u32,
        /// Collisions per run.
        #[arg(long, default_value_t = 200_000_000)]
        collisions: u64,
        /// Batches per run.
        #[arg(long, default_value_t = 8)]
        batches: u32,
        /// Base seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Output directory (finished points are kept in OUT/points/ and reused on a rerun).
        #[arg(long, default_value = "results/sweep")]
        out: PathBuf,
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
    },
    /// Regenerate one of the paper's figures from this crate's numbers (PNG, SVG, CSV, JSON into --out).
    Figure {
        /// backscatter-map (Fig. 5), backscatter (Fig. 4a and inset) or hierarchy (Figs. 3, 4b, 6). Figs. 2, 7, 8: use `sweep`.
        kind: String,
        /// Gap for backscatter-map.
        #[arg(long, default_value_t = 0.1)]
        w: f64,
        /// Injections (map) or injections per point (curve).
        #[arg(long, default_value_t = 60_000)]
        samples: u64,
        /// Seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Output directory.
        #[arg(long, default_value = "results/figures")]
        out: PathBuf,
    },
    /// The corrected Machta-Zwanzig hierarchy (D_cf, D_bs, D_1, D_k), App. A p_cf, and the exact D of correlated lattice walks, on measured hop statistics.
    Theory {
        /// Gap w, 0 < w < w_inf.
        #[arg(long, allow_negative_numbers = true)]
        w: f64,
        /// Collisions in all.
        #[arg(long, default_value_t = 200_000_000)]
        collisions: u64,
        /// Independent batches.
        #[arg(long, default_value_t = 16)]
        batches: u32,
        /// Highest order k of the hierarchy and of the lattice walk.
        #[arg(long, default_value_t = 4)]
        order: usize,
        /// Seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
    },
    /// Fig. 6b by simulation: correlated lattice-gas walks of order 1..K driven by the measured symbol tables, D by the Einstein formula, next to the exact D.
    LatticeWalk {
        /// Gap w, 0 < w < w_inf.
        #[arg(long, allow_negative_numbers = true)]
        w: f64,
        /// Lorentz-gas collisions used to measure the symbol tables.
        #[arg(long, default_value_t = 100_000_000)]
        collisions: u64,
        /// Highest order.
        #[arg(long, default_value_t = 4)]
        order: usize,
        /// Seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
    },
    /// Every closed-form quantity at gap w (geometry, Santaló, Machta-Zwanzig, Boltzmann).
    Constants {
        /// Gap w > 0.
        #[arg(long, allow_negative_numbers = true)]
        w: f64,
        /// f64 or MPFR bits (>= 53).
        #[arg(long, default_value = "f64")]
        precision: String,
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
    },
    /// Single-trajectory kernel throughput (median of repetitions).
    Bench {
        /// Gap w > 0.
        #[arg(long, allow_negative_numbers = true)]
        w: f64,
        /// Collisions per repetition.
        #[arg(long, default_value_t = 20_000_000)]
        collisions: u64,
        /// Repetitions (the median is reported).
        #[arg(long, default_value_t = 7)]
        repetitions: usize,
        /// Threads (the kernel benchmark is single-trajectory; only 1 is meaningful).
        #[arg(long, default_value_t = 1)]
        threads: usize,
        /// f64 or MPFR bits (>= 53).
        #[arg(long, default_value = "f64")]
        precision: String,
        /// Seed of the starting point.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Speed against error for f64 and MPFR 53..1024 bits: Markdown, JSON, PNG and SVG into --out.
        #[arg(long)]
        report: bool,
        /// Output directory of --report.
        #[arg(long, default_value = "results")]
        out: PathBuf,
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match real_main(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// The requested thread count, or every core.
fn all_cores(threads: Option<usize>) -> usize {
    threads.unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    })
}

fn progress_bar(total: u64, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::hidden());
    }
    let pb = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
    pb.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {percent}% ({per_sec}, eta {eta})",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    pb
}

fn to_json<T: serde::Serialize>(v: &T) -> Result<String, Error> {
    serde_json::to_string_pretty(v).map_err(|e| Error::Io(e.to_string()))
}

fn real_main(cli: Cli) -> Result<(), Error> {
    match cli.cmd {
        Cmd::Diffusion {
            w,
            collisions,
            batches,
            seed,
            threads,
            precision,
            window,
            check_window,
            checkpoint,
            audit,
            audit_precision,
            json,
            quiet,
        } => {
            let cfg = DiffusionConfig {
                w,
                collisions,
                batches,
                seed,
                precision: precision.parse()?,
                window: window.parse::<Window>()?,
                check_window: check_window.parse::<Window>()?,
            };
            cfg.validate()?;
            let threads = all_cores(threads);
            let pb = progress_bar(collisions, quiet);
            let audit = audit.map(|rate| diffusion::AuditSpec {
                rate,
                bits: audit_precision,
            });
            let r =
                diffusion::run_audited(&cfg, threads, checkpoint.as_ref(), audit, &|n| pb.inc(n))?;
            pb.finish_and_clear();
            if json {
                println!("{}", to_json(&r)?);
            } else {
                print_diffusion(&r);
            }
        }
        Cmd::Audit {
            w,
            collisions,
            sample,
            precision,
            seed,
            threads,
            json,
        } => {
            let threads = all_cores(threads);
            let r = lorentz_gas::verification::audit::audit_run(
                w,
                collisions,
                sample,
                precision,
                seed,
                threads as u32,
                threads,
            )?;
            if json {
                println!("{}", to_json(&r)?);
            } else {
                print_audit(&r);
            }
        }
        Cmd::Lyapunov {
            w,
            collisions,
            orbits,
            starts,
            seed,
            threads,
            json,
        } => {
            use lorentz_gas::verification::lyapunov::{divergence, lyapunov};
            let threads = all_cores(threads);
            let l = lyapunov(w, collisions, orbits, seed, threads)?;
            let d = if starts > 0 {
                divergence(w, &[64, 128, 256, 512, 1024], 4096, 900, starts, seed)?
            } else {
                Vec::new()
            };
            if json {
                println!("{}", to_json(&json!({ "tangent": l, "divergence": d }))?);
            } else {
                println!(
                    "w = {}: largest Lyapunov exponent (tangent space, {} orbits x {} collisions)\n  {:.5} ± {:.5} per collision, {:.5} ± {:.5} per unit time",
                    w, l.orbits, l.collisions, l.per_collision, l.per_collision_err, l.per_time, l.per_time_err
                );
                if !d.is_empty() {
                    println!("divergence from a 4096-bit reference ({starts} initial conditions):");
                    println!("precision  horizon (collisions to 1e-3)   growth per collision   growth per unit time");
                    for x in &d {
                        println!(
                            "{:>9}  {:>12.1} ± {:<8.1}       {:.4} ± {:.4}        {:.4} ± {:.4}",
                            x.precision,
                            x.horizon,
                            x.horizon_err,
                            x.rate_per_collision,
                            x.rate_per_collision_err,
                            x.rate_per_time,
                            x.rate_per_time_err
                        );
                    }
                }
            }
        }
        Cmd::Certify {
            w,
            collisions,
            digits,
            seed,
            json,
        } => {
            lorentz_gas::geometry::check_diffusive_gap(w)?;
            let trap = lorentz_gas::kernel::trap::Trap::new(w)?;
            let start = lorentz_gas::sampling::equilibrium_state(
                &trap,
                &mut lorentz_gas::sampling::stream(seed, 0),
            );
            let c = lorentz_gas::verification::certify::certify(w, &start, collisions, digits)?;
            if json {
                println!("{}", to_json(&c)?);
            } else {
                println!(
                    "w = {}: {} collisions from the seed-{} start certified to {:.1} digits (runs at {} and {} bits agree; tried {:?});\nthe f64 orbit from the same start stays within 1e-3 of it for {} collisions",
                    c.w, c.collisions, seed, c.digits_agreed, c.bits, 2 * c.bits, c.tried, c.f64_faithful_collisions
                );
            }
        }
        Cmd::Backscatter {
            w,
            visits,
            precision,
            batches,
            seed,
            threads,
            json,
        } => {
            let threads = all_cores(threads);
            let r = lorentz_gas::hopping::backscatter_at(
                w,
                visits,
                batches,
                seed,
                threads,
                precision.parse()?,
                &|_| {},
            )?;
            if json {
                println!("{}", to_json(&r)?);
            } else {
                println!(
                    "injection into one trap, w = {} ({} visits, {} batches, seed {})",
                    r.w, r.visits, r.batches, r.seed
                );
                println!("p_bs = {:.5} ± {:.5}   p_l = {:.5} ± {:.5}   p_r = {:.5} ± {:.5}   p_cf = {:.5} ± {:.5}", r.p_bs, r.p_bs_err, r.p_l.value, r.p_l.err, r.p_r.value, r.p_r.err, r.p_cf.value, r.p_cf.err);
                println!(
                    "mean visit time      = {:.5} ± {:.5}   Kac tau = {:.5}",
                    r.mean_visit_time, r.mean_visit_time_err, r.mean_visit_time_exact
                );
                println!(
                    "collisions per visit = {:.4} ± {:.4}   Kac pi/(3w) = {:.4}",
                    r.mean_collisions_per_visit,
                    r.mean_collisions_per_visit_err,
                    r.mean_collisions_per_visit_exact
                );
            }
        }
        Cmd::Hops {
            w,
            collisions,
            batches,
            order,
            seed,
            threads,
            json,
        } => {
            let threads = all_cores(threads);
            let r =
                lorentz_gas::hopping::hops(w, collisions, batches, order, seed, threads, &|_| {})?;
            if json {
                println!("{}", to_json(&r)?);
            } else {
                println!("trap hopping along lattice trajectories, w = {} ({} visits, {:.2e} collisions, {} batches, seed {})", r.w, r.visits, r.collisions as f64, r.batches, r.seed);
                println!(
                    "p_bs = {:.5} ± {:.5}   p_cf = {:.6} ± {:.6}",
                    r.p_bs, r.p_bs_err, r.p_cf, r.p_cf_err
                );
                let pairs: Vec<String> = r
                    .pairs
                    .iter()
                    .map(|(k, e)| format!("p({k}) = {:.5} ± {:.5}", e.value, e.err))
                    .collect();
                for c in pairs.chunks(3) {
                    println!("{}", c.join("   "));
                }
                println!(
                    "symmetries p(s) = p(mirror s) = p(reversed mirror s): largest |z| = {:.2}",
                    r.symmetry_max_z
                );
                println!(
                    "hop-level Green-Kubo D = {:.6} ± {:.6}   (D_MZ = {:.6})",
                    r.D_GK, r.D_GK_err, r.D_MZ
                );
            }
        }
        Cmd::Sweep {
            w_from,
            w_to,
            steps,
            runs,
            collisions,
            batches,
            seed,
            threads,
            out,
            json,
            quiet,
        } => {
            let threads = all_cores(threads);
            let cfg = lorentz_gas::sweep::SweepConfig {
                w_from,
                w_to,
                steps,
                runs,
                collisions,
                batches,
                seed,
            };
            let pb = progress_bar(
                collisions
                    .saturating_mul(runs as u64)
                    .saturating_mul(steps as u64),
                quiet,
            );
            let r = lorentz_gas::sweep::sweep(&cfg, &out, threads, &|n| pb.inc(n))?;
            pb.finish_and_clear();
            if json {
                println!("{}", to_json(&r)?);
            } else {
                println!("sweep w = {w_from} .. {w_to}, {steps} points x {runs} runs x {collisions} collisions ({} points resumed)", r.resumed_points);
                println!("      w        D            +-          D_MZ       D_Bo      residual");
                for x in &r.rows {
                    println!(
                        "{:>8.4}  {:.6}  {:.6}  {:.6}  {:.6}  {:+.2e}",
                        x.w, x.D, x.D_err, x.D_MZ, x.D_Bo, x.residual
                    );
                }
                println!("Boltzmann offset (slope 3/16): Delta D = {:.5} ± {:.5}; free slope of D vs 1/n = {:.5} (3/16 = 0.1875)", r.boltzmann_offset.0, r.boltzmann_offset.1, r.boltzmann_free_fit.0);
                match r.mz_crossing {
                    Some((x, e)) => println!("D = D_MZ at w = {x:.4} ± {e:.4}"),
                    None => println!("D - D_MZ does not change sign in this range"),
                }
                println!("written: {}/sweep.{{csv,json}}, fig2-D-vs-w, fig7-boltzmann, fig8-residuals (.png, .svg)", out.display());
            }
        }
        Cmd::Figure {
            kind,
            w,
            samples,
            seed,
            out,
        } => {
            use lorentz_gas::figures::paper;
            let threads = all_cores(None);
            match kind.as_str() {
                "backscatter-map" => paper::backscatter_map(w, samples, seed, &out)?,
                "hierarchy" => {
                    let grid: Vec<f64> = (1..=15).map(|i| 0.02 * i as f64).collect();
                    paper::hierarchy(&grid, samples.max(10_000_000), seed, threads, &out)?
                }
                "backscatter" => {
                    let grid: Vec<f64> = (1..=30).map(|i| 0.01 * i as f64).filter(|w| *w < 0.3094).collect();
                    let inset: Vec<f64> = (0..=30).map(|i| 0.04 + 0.001 * i as f64).collect();
                    paper::backscatter_curve(&grid, &inset, samples.max(100_000), seed, threads, &out)?
                }
                other => return Err(Error::Invalid(format!("unknown figure '{other}': use backscatter-map, backscatter or hierarchy (Figs. 2, 7, 8: lorentz sweep)"))),
            }
            println!("written into {}", out.display());
        }
        Cmd::Theory {
            w,
            collisions,
            batches,
            order,
            seed,
            json,
        } => {
            let r = lorentz_gas::hopping::theory(
                w,
                collisions,
                batches,
                order,
                seed,
                all_cores(None),
                &|_| {},
            )?;
            if json {
                println!("{}", to_json(&r)?);
            } else {
                println!("w = {}: p_bs = {:.5} ± {:.5}, p_cf = {:.6} ± {:.6} (App. A: {:.6} corrected, {:.6} as printed)", r.w, r.p_bs.value, r.p_bs.err, r.p_cf.value, r.p_cf.err, r.p_cf_appendix_a.0, r.p_cf_appendix_a.1);
                println!(
                    "D_GK (the Lorentz gas) = {:.6} ± {:.6}   D_MZ = {:.6}",
                    r.D_GK.value, r.D_GK.err, r.D_MZ
                );
                println!(
                    "D_cf = {:.6}  D_bs = {:.6}  D_1 = {:.6}",
                    r.D_cf, r.D_bs, r.D_1
                );
                for ((k, dk, dc), (_, ex)) in r.D_k.iter().zip(&r.lattice_gas_exact) {
                    println!("k = {k}: D_k = {dk:.6}  with collisionless flights {dc:.6}   exact order-{k} lattice walk {ex:.6}");
                }
                println!(
                    "paper's (B2), (B3) as printed: {:.6}, {:.6}",
                    r.D_2_D_3_as_printed.0, r.D_2_D_3_as_printed.1
                );
            }
        }
        Cmd::LatticeWalk {
            w,
            collisions,
            order,
            seed,
            json,
        } => {
            use lorentz_gas::theory::{lattice_walk, markov::CorrelatedWalk};
            let h = lorentz_gas::hopping::hops(
                w,
                collisions,
                16,
                order.max(1),
                seed,
                all_cores(None),
                &|_| {},
            )?;
            let g = Geometry::new(w)?;
            let mut rows = Vec::new();
            for k in 1..=order.max(1) {
                let walk = CorrelatedWalk::new(&h.table(k)?)?;
                let sim = lattice_walk::simulate(
                    &walk,
                    &lattice_walk::LatticeWalkConfig::new(16, 4096, 128, seed),
                )?;
                rows.push(json!({"order": k, "D_simulated": sim.d_over_d_mz * g.d_mz(), "D_simulated_err": sim.se * g.d_mz(), "D_exact": walk.d(&g)?}));
            }
            if json {
                println!(
                    "{}",
                    to_json(
                        &json!({"w": w, "D_MZ": g.d_mz(), "D_GK": h.D_GK, "D_GK_err": h.D_GK_err, "walks": rows, "seed": seed, "version": env!("CARGO_PKG_VERSION")})
                    )?
                );
            } else {
                println!("w = {w}: D_MZ = {:.6}, hop-level Green-Kubo D of the Lorentz gas = {:.6} ± {:.6}", g.d_mz(), h.D_GK, h.D_GK_err);
                for r in &rows {
                    println!(
                        "order {}: simulated D = {:.6} ± {:.6}   exact D = {:.6}",
                        r["order"],
                        r["D_simulated"].as_f64().unwrap_or(f64::NAN),
                        r["D_simulated_err"].as_f64().unwrap_or(f64::NAN),
                        r["D_exact"].as_f64().unwrap_or(f64::NAN)
                    );
                }
            }
        }
        Cmd::Constants { w, precision, json } => match precision.parse::<Precision>()? {
            Precision::F64 => print_constants(Geometry::new(w)?, json)?,
            Precision::Bits(b) => print_constants(Geometry::new(Float::with_val(b, w))?, json)?,
        },
        Cmd::Bench {
            w,
            report: true,
            out,
            ..
        } => {
            let threads = all_cores(None);
            let (_, md) = lorentz_gas::report::speed_against_error(w, &out, threads)?;
            println!("{md}");
            println!(
                "written: {}/speed-vs-error.{{md,json,png,svg}}",
                out.display()
            );
        }
        Cmd::Bench {
            w,
            collisions,
            repetitions,
            threads,
            precision,
            seed,
            json,
            ..
        } => {
            if threads != 1 {
                return Err(Error::Invalid(
                    "bench measures one trajectory on one thread: use --threads 1".into(),
                ));
            }
            let r = lorentz_gas::bench::throughput(
                w,
                precision.parse()?,
                collisions,
                repetitions,
                seed,
            )?;
            if json {
                println!("{}", to_json(&r)?);
            } else {
                println!(
                    "w = {}  precision {}  {} collisions x {} repetitions, 1 thread\nmedian {:.3e} collisions/s = {:.2} ns/collision  (runs: {})",
                    r.w,
                    r.precision,
                    r.collisions,
                    r.repetitions,
                    r.collisions_per_second,
                    r.ns_per_collision,
                    r.samples.iter().map(|s| format!("{s:.3e}")).collect::<Vec<_>>().join(" ")
                );
            }
        }
    }
    Ok(())
}

fn print_audit(r: &lorentz_gas::verification::audit::AuditReport) {
    let s = &r.summary;
    println!(
        "shadow audit, w = {}: {} events of {} ({} collisions, {} trajectories, seed {}) replayed at {} bits in {:.1} s",
        r.w, s.audited, r.events, r.collisions, r.trajectories, r.seed, r.precision, r.seconds
    );
    println!(
        "outside the error model: {}   ambiguous at f64 resolution: {}   f64 chose another obstacle: {}",
        s.outside, s.ambiguous, s.different_choice
    );
    let q = &r.quantiles;
    println!("one-step error            median      99%         max");
    for (name, v) in [
        ("flight time", q.time_error),
        ("contact point", q.position_error),
        ("velocity", q.velocity_error),
        ("time error / bound", q.time_error_over_bound),
    ] {
        println!("{name:<22} {:>10.2e} {:>10.2e} {:>10.2e}", v[0], v[1], v[2]);
    }
    for e in s.outside_events.iter().take(5) {
        println!(
            "outside: state bits {:x?} excluded {:?}: {:?}",
            e.state_bits, e.excluded, e.check
        );
    }
}

fn sigmas(x: f64, err: f64, exact: f64) -> String {
    format!("{:+.1} sigma", (x - exact) / err)
}

fn print_diffusion(r: &diffusion::DiffusionReport) {
    println!(
        "periodic Lorentz gas, w = {}  ({} precision, seed {}, {} batches, {:.3e} collisions, {} threads, {:.1} s, {:.3e} collisions/s)",
        r.w, r.precision, r.seed, r.batches, r.collisions as f64, r.threads, r.seconds, r.collisions_per_second
    );
    println!(
        "D              = {:.6} ± {:.6}   ({:.3} %, MSD slope over [{}τ, {}τ])",
        r.D,
        r.D_err,
        100.0 * r.D_err / r.D,
        r.window.lo,
        r.window.hi
    );
    println!(
        "D (check)      = {:.6} ± {:.6}   (MSD slope over [{}τ, {}τ]; difference {:+.1} combined sigma)",
        r.D_check,
        r.D_check_err,
        r.check_window.lo,
        r.check_window.hi,
        (r.D_check - r.D) / (r.D_err.powi(2) + r.D_check_err.powi(2)).sqrt()
    );
    println!(
        "D_MZ           = {:.6}           D/D_MZ = {:.4}",
        r.D_MZ,
        r.D / r.D_MZ
    );
    println!("D_Bo           = {:.6}", r.D_Bo);
    println!(
        "mean free path = {:.7} ± {:.7}   exact {:.7}  ({})",
        r.mean_free_path,
        r.mean_free_path_err,
        r.mean_free_path_exact,
        sigmas(
            r.mean_free_path,
            r.mean_free_path_err,
            r.mean_free_path_exact
        )
    );
    println!(
        "mean hop time  = {:.6} ± {:.6}   exact {:.6}  ({})",
        r.tau_hop,
        r.tau_hop_err,
        r.tau_hop_exact,
        sigmas(r.tau_hop, r.tau_hop_err, r.tau_hop_exact)
    );
    println!(
        "collisions/hop = {:.5} ± {:.5}   exact {:.5}  ({})",
        r.collisions_per_hop,
        r.collisions_per_hop_err,
        r.collisions_per_hop_exact,
        sigmas(
            r.collisions_per_hop,
            r.collisions_per_hop_err,
            r.collisions_per_hop_exact
        )
    );
    if let Some(a) = &r.audit {
        println!(
            "self-audit     : {} events replayed in MPFR, {} outside the error model, worst time error / bound {:.2e}",
            a.audited, a.outside, a.time_error_over_bound.max
        );
    }
    if r.resumed_batches > 0 {
        println!(
            "({} batches resumed from the checkpoint)",
            r.resumed_batches
        );
    }
}

fn print_constants<T: Real>(g: Geometry<T>, json: bool) -> Result<(), Error> {
    let ctx = g.ctx();
    let rows: Vec<(&str, &str, T)> = vec![
        ("w", "gap", g.gap()),
        ("a", "lattice spacing 2 + w", g.spacing()),
        ("n", "number density 2/(sqrt3 a^2)", g.density()),
        (
            "w_inf",
            "horizon threshold 4/sqrt3 - 2",
            Geometry::<T>::w_inf(ctx),
        ),
        (
            "w_0",
            "collisionless-flight onset 2/sqrt3 - 1",
            Geometry::<T>::w_0(ctx),
        ),
        ("trap_area", "A = sqrt3 a^2/4 - pi/2", g.trap_area()),
        (
            "free_area_per_disk",
            "|Q| = 1/n - pi = 2A",
            g.free_area_per_disk(),
        ),
        ("boundary_per_disk", "|dQ| = 2 pi", g.boundary_per_disk()),
        (
            "mean_free_path",
            "Santalo pi|Q|/|dQ| = A",
            g.mean_free_path(),
        ),
        ("trap_distance", "l = a/sqrt3", g.trap_distance()),
        ("tau_hop", "tau = pi A/(3w)", g.hop_time()),
        ("collisions_per_hop", "pi/(3w)", g.collisions_per_hop()),
        ("D_MZ", "Machta-Zwanzig l^2/(4 tau)", g.d_mz()),
        ("D_Bo", "Boltzmann (3/16)(1/n - pi)", g.d_bo()),
    ];
    let horizon_finite = g.gap() < Geometry::<T>::w_inf(ctx);
    let lmax = g.max_free_path_bound();
    if json {
        let mut m = serde_json::Map::new();
        for (k, _, v) in &rows {
            m.insert((*k).into(), json!(v.to_decimal()));
        }
        m.insert(
            "max_free_path_bound".into(),
            json!(lmax.as_ref().map(|v| v.to_decimal())),
        );
        m.insert("finite_horizon".into(), json!(horizon_finite));
        m.insert("precision_bits".into(), json!(T::bits(ctx)));
        m.insert("version".into(), json!(env!("CARGO_PKG_VERSION")));
        println!("{}", to_json(&m)?);
    } else {
        for (k, d, v) in &rows {
            println!("{k:<20} {:<45} {d}", v.to_decimal());
        }
        match lmax {
            Some(l) => println!(
                "{:<20} {:<45} proven bound on any free path: sqrt3 a below w_0, 12 a below w_inf",
                "max_free_path_bound",
                l.to_decimal()
            ),
            None => println!(
                "w >= w_inf: infinite horizon, free paths are unbounded and D does not exist"
            ),
        }
    }
    Ok(())
}
