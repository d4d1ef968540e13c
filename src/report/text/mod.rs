//! Results as the command line prints them. The command line writes this text to stdout, and
//! Python's `str()` of a result is the same text, so a notebook and a terminal read the same
//! lines.

use crate::Error;
use crate::statistics::comparison;

pub mod diffusion;

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

/// The command line's text of a result of kind `kind` given as its JSON (`None` for a kind
/// whose text is not here yet).
///
/// # Errors
/// JSON that is not a result of that kind.
pub fn of_json(kind: &str, json: &str) -> Result<Option<String>, Error> {
    let bad = |e: serde_json::Error| Error::Invalid(format!("a {kind} result: {e}"));
    Ok(match kind {
        "diffusion" => Some(diffusion::diffusion(
            &serde_json::from_str(json).map_err(bad)?,
        )),
        _ => None,
    })
}
