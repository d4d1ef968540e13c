//! Results as the command line prints them. The command line writes this text to stdout, and
//! Python's `str()` of a result is the same text, so a notebook and a terminal read the same
//! lines.

use crate::Error;
use crate::statistics::comparison;

pub mod audit;
pub mod backscatter;
pub mod certify;
pub mod diffusion;
pub mod escape;
pub mod field;
pub mod hops;
pub mod lattice_walk;
pub mod shadow;
pub mod superdiffusion;
pub mod theory;

/// `writeln!` into a `String` (which cannot fail).
macro_rules! line {
    ($out:expr, $($arg:tt)*) => {{
        use std::fmt::Write as _;
        let _ = writeln!($out, $($arg)*);
    }};
}
pub(crate) use line;

/// "+1.5σ, bound 4.6σ: agree" for a value against its exact one, with the Student-t bound of `n`
/// batches.
pub fn sigmas(x: f64, err: f64, exact: f64, n: usize) -> String {
    let c = comparison::of(x - exact, err, comparison::batch_dof(n));
    let verdict = if c.agrees() { "agree" } else { "DISAGREE" };
    format!("{:+.1}σ, bound {:.1}σ: {verdict}", c.z, c.bound)
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
    let bad = |e: serde_json::Error| Error::Invalid(format!("a {kind} result: {e}"));
    let text = match kind {
        "diffusion" => diffusion::diffusion(&serde_json::from_str(json).map_err(bad)?),
        "field" => field::field(&serde_json::from_str(json).map_err(bad)?),
        "hops" => hops::hops(&serde_json::from_str(json).map_err(bad)?),
        "theory" => theory::theory(&serde_json::from_str(json).map_err(bad)?),
        "lattice-walk" => lattice_walk::lattice_walk(&serde_json::from_str(json).map_err(bad)?),
        "backscatter" => backscatter::backscatter(&serde_json::from_str(json).map_err(bad)?),
        "escape" => escape::escape(&serde_json::from_str(json).map_err(bad)?),
        "superdiffusion" => {
            superdiffusion::superdiffusion(&serde_json::from_str(json).map_err(bad)?)
        }
        "shadow" => shadow::shadow(&serde_json::from_str(json).map_err(bad)?),
        "certify" => certify::certify(&serde_json::from_str(json).map_err(bad)?),
        "audit" => audit::audit(&serde_json::from_str(json).map_err(bad)?),
        _ => return Ok(None),
    };
    Ok(Some(text))
}
