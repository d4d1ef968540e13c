//! Results as the command line prints them. The command line writes this text to stdout, and
//! Python's `str()` of a result is the same text, so a notebook and a terminal read the same
//! lines.

use crate::Error;
use crate::statistics::comparison;

pub mod audit;
pub mod backscatter;
pub mod bench;
pub mod certify;
pub mod constants;
pub mod current;
pub mod cycles;
pub mod diffusion;
pub mod driven_sweep;
pub mod escape;
pub mod field;
pub mod field_sweep;
pub mod figure;
pub mod free_paths;
pub mod hops;
pub mod lattice_cycles;
pub mod lattice_walk;
pub mod lyapunov;
pub mod publication;
pub mod reproduce;
pub mod scene_diffusion;
pub mod section;
pub mod shadow;
pub mod superdiffusion;
pub mod survival;
pub mod sweep;
pub mod theory;
pub mod trajectory;

/// `writeln!` into a `String` (which cannot fail).
macro_rules! line {
    ($out:expr, $($arg:tt)*) => {{
        use std::fmt::Write as _;
        let _ = writeln!($out, $($arg)*);
    }};
}
pub(crate) use line;

/// ", long flights jumped" where the run jumped them (the title lines of `lyapunov`,
/// `superdiffusion` and `free-paths`), else nothing.
pub fn jumped(flights: crate::engine::long_flight::Flights) -> &'static str {
    if flights == crate::engine::long_flight::Flights::Jump {
        ", long flights jumped"
    } else {
        ""
    }
}

/// A batch run's first line: `title`, then its [`provenance`] (with a newline).
pub fn first_line(
    title: impl std::fmt::Display,
    m: &crate::engine::metadata::RunMeta,
    counts: (u64, f64, Option<f64>),
    with_path: bool,
) -> String {
    format!("{title}  {}\n", provenance(m, counts, with_path))
}

/// The provenance a batch run's first line ends with: `(P precision, E engine, seed S, B
/// batches, N collisions, K threads, T s, R collisions/s)`, the engine with its SIMD path if
/// `with_path`, the rate left out where it is `None`.
pub fn provenance(
    m: &crate::engine::metadata::RunMeta,
    (collisions, seconds, rate): (u64, f64, Option<f64>),
    with_path: bool,
) -> String {
    let engine = match (&m.simd, with_path) {
        (Some(p), true) => format!("{} ({p})", m.engine),
        _ => m.engine.clone(),
    };
    let rate = rate.map_or(String::new(), |r| format!(", {r:.3e} collisions/s"));
    format!(
        "({} precision, {engine} engine, seed {}, {} batches, {:.3e} collisions, {}, {seconds:.1} s{rate})",
        m.precision,
        m.seed.unwrap_or_default(),
        m.batches.unwrap_or_default(),
        collisions as f64,
        crate::report::counted(m.threads.unwrap_or_default() as u64, "thread"),
    )
}

/// `x ± e` at six decimals, as the printed lines show estimates — or, where six decimals would
/// show a nonzero error as 0.000000 (below 5·10⁻⁷), to the place of the error
/// ([`with_error`](crate::report::publication::headline::with_error)): an error bar is printed as
/// zero only when it is zero.
///
/// # Examples
///
/// ```
/// use lorentz_gas::report::text::estimate;
/// assert_eq!(estimate(0.1, 0.00023), "0.100000 ± 0.000230");
/// assert_eq!(estimate(1.2e-7, 3.4e-8), "1.2000e-7 ± 3.4e-8");
/// assert_eq!(estimate(0.0, 0.0), "0.000000 ± 0.000000");
/// ```
pub fn estimate(x: f64, e: f64) -> String {
    if e != 0.0 && e.abs() < 5e-7 {
        crate::report::publication::headline::with_error(x, e)
    } else {
        format!("{x:.6} ± {e:.6}")
    }
}

/// What a printed diffusion coefficient (never negative) needs beside it when it came out
/// negative: that it is noise around 0, or — beyond `bound` errors — a sign of a fault.
pub fn negative_note(x: f64, e: f64, bound: f64) -> &'static str {
    if x >= 0.0 || x.is_nan() {
        ""
    } else if e > 0.0 && -x <= bound * e {
        "  [negative: D ≥ 0, so this is noise around 0 within its error; more collisions resolve it]"
    } else {
        "  [negative beyond its error: D ≥ 0, so the run is at fault; please report it]"
    }
}

/// "+1.5σ, bound 4.6σ: agree" for a value against its exact one, with the Student-t bound of `n`
/// batches.
pub fn sigmas(x: f64, err: f64, exact: f64, n: usize) -> String {
    let c = comparison::of(x - exact, err, comparison::batch_dof(n));
    format!("{:+.1}σ, bound {:.1}σ: {}", c.z, c.bound, c.verdict())
}

/// "+1.5σ; no verdict: …" for a value measured where its estimator has not converged (no
/// agreement claimed, and no disagreement either: the distance is the approach's).
pub fn sigmas_unconverged(x: f64, err: f64, exact: f64, n: usize, why: &str) -> String {
    let c = comparison::of(x - exact, err, comparison::batch_dof(n));
    format!("{:+.1}σ; no verdict: {why}", c.z)
}

/// The command line's text of a result of kind `kind` given as its JSON (`None` for a kind
/// whose text is not here yet).
///
/// # Errors
/// JSON that is not a result of that kind.
pub fn of_json(kind: &str, json: &str) -> Result<Option<String>, Error> {
    let text = match kind {
        "diffusion" => render(kind, json, diffusion::diffusion)?,
        "field" => render(kind, json, field::field)?,
        "current" => render(kind, json, current::current)?,
        "table-diffusion" => render(kind, json, scene_diffusion::scene_diffusion)?,
        "hops" => render(kind, json, hops::hops)?,
        "theory" => render(kind, json, theory::theory)?,
        "lattice-walk" => render(kind, json, lattice_walk::lattice_walk)?,
        "backscatter" => render(kind, json, backscatter::backscatter)?,
        "escape" => render(kind, json, escape::escape)?,
        "escape-survival" => render(kind, json, survival::survival)?,
        "superdiffusion" => render(kind, json, superdiffusion::superdiffusion)?,
        "free-paths" => render(kind, json, free_paths::free_paths)?,
        "lyapunov" => render(kind, json, lyapunov::lyapunov)?,
        "lyapunov-driven" => render(kind, json, lyapunov::driven)?,
        "sweep" => render(kind, json, sweep::sweep)?,
        "field-sweep" => render(kind, json, field_sweep::field_sweep)?,
        "driven-sweep" => render(kind, json, driven_sweep::driven_sweep)?,
        "bench" => render(kind, json, bench::throughput)?,
        "bench-electric" => render(kind, json, bench::electric)?,
        "bench-long-flights" => render(kind, json, bench::long_flights)?,
        "shadow" => render(kind, json, shadow::shadow)?,
        "certify" => render(kind, json, certify::certify)?,
        "audit" => render(kind, json, audit::audit)?,
        "section" => render(kind, json, section::section)?,
        "cycles" => render(kind, json, cycles::cycles)?,
        "lattice-cycles" => render(kind, json, lattice_cycles::lattice_cycles)?,
        _ => return Ok(None),
    };
    Ok(Some(text))
}

/// `text` of the result `json` of kind `kind`, read back into its report type.
fn render<R: serde::de::DeserializeOwned>(
    kind: &str,
    json: &str,
    text: fn(&R) -> String,
) -> Result<String, Error> {
    let r =
        serde_json::from_str(json).map_err(|e| Error::Invalid(format!("a {kind} result: {e}")))?;
    Ok(text(&r))
}
