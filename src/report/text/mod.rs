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
pub mod diffusion;
pub mod escape;
pub mod field;
pub mod field_sweep;
pub mod figure;
pub mod free_paths;
pub mod hops;
pub mod lattice_walk;
pub mod lyapunov;
pub mod publication;
pub mod reproduce;
pub mod scene_diffusion;
pub mod shadow;
pub mod superdiffusion;
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
        "table-diffusion" => render(kind, json, scene_diffusion::scene_diffusion)?,
        "hops" => render(kind, json, hops::hops)?,
        "theory" => render(kind, json, theory::theory)?,
        "lattice-walk" => render(kind, json, lattice_walk::lattice_walk)?,
        "backscatter" => render(kind, json, backscatter::backscatter)?,
        "escape" => render(kind, json, escape::escape)?,
        "superdiffusion" => render(kind, json, superdiffusion::superdiffusion)?,
        "free-paths" => render(kind, json, free_paths::free_paths)?,
        "lyapunov" => render(kind, json, lyapunov::lyapunov)?,
        "sweep" => render(kind, json, sweep::sweep)?,
        "field-sweep" => render(kind, json, field_sweep::field_sweep)?,
        "bench" => render(kind, json, bench::throughput)?,
        "bench-long-flights" => render(kind, json, bench::long_flights)?,
        "shadow" => render(kind, json, shadow::shadow)?,
        "certify" => render(kind, json, certify::certify)?,
        "audit" => render(kind, json, audit::audit)?,
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
