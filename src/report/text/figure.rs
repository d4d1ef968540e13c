//! The text `lorentz figure` prints (the files a figure of the paper wrote): the command line
//! writes it to stdout, and Python's `str()` of the result is the same text.

use std::path::Path;

use super::line;
use crate::report::figures::paper::FigureReport;

/// The text of a `figure` result written into `out`.
pub fn figure(r: &FigureReport, out: &Path) -> String {
    let mut text = String::new();
    line!(
        text,
        "written into {}: {}",
        out.display(),
        r.files.join(", ")
    );
    text
}
