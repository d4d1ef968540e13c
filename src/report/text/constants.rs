//! The text `lorentz constants` prints (every closed form of a scene): the command line writes
//! it to stdout, and Python's `str()` of the result is the same text. Text shows the digits the
//! working precision guarantees; JSON carries every digit.

use super::line;
use crate::theory::constants::{Constant, ConstantsReport};

/// One constant's line: name, the digits shown, formula.
fn row(out: &mut String, c: &Constant) {
    line!(out, "{:<20} {:<45} {}", c.name, c.shown, c.formula);
}

/// The text of a `constants` result, line by line as the command line prints it.
pub fn constants(r: &ConstantsReport) -> String {
    let mut out = String::new();
    if let Some(q) = &r.w_exact {
        line!(out, "{:<20} {:<45} gap as typed, exactly", "w_exact", q);
    }
    if let Some(q) = &r.radius_exact {
        line!(
            out,
            "{:<20} {:<45} radius as typed, exactly",
            "radius_exact",
            q
        );
    }
    for c in &r.rows {
        row(&mut out, c);
    }
    match (&r.max_free_path_bound, &r.superdiffusion) {
        (Some(c), _) => row(&mut out, c),
        (None, Some(sd)) => {
            line!(
                out,
                "infinite horizon: free paths are unbounded, D does not exist; {} corridors and the superdiffusion constants (proofs-notes/corridors.md):",
                sd.corridors.len()
            );
            for c in &sd.rows {
                row(&mut out, c);
            }
            line!(
                out,
                "corridor (m, n)      angle (deg)     period          width"
            );
            for c in &sd.corridors {
                line!(
                    out,
                    "({:>4}, {:>4})         {:>10.4}      {:<15.10} {:.10}",
                    c.direction[0],
                    c.direction[1],
                    c.angle_degrees,
                    c.period,
                    c.width
                );
            }
        }
        (None, None) => {}
    }
    out
}
