//! The text `lorentz reproduce` prints (the steps of a reproduction of the user guide): the
//! command line writes it to stdout, and Python's `str()` of the result is the same text.

use std::path::Path;

use super::line;
use crate::report::reproduce::ReproduceReport;

/// The text of a `reproduce` result written into `out`: one line per step (seconds, whether it
/// was resumed, what it reproduces) and the front page.
pub fn reproduce(r: &ReproduceReport, out: &Path) -> String {
    let mut text = String::new();
    for s in &r.steps {
        line!(
            text,
            "{:<12} {:>8.1} s{}  {}",
            s.name,
            s.seconds,
            if s.resumed { " (resumed)" } else { "" },
            s.title
        );
    }
    line!(text, "written: {}/index.html", out.display());
    text
}
