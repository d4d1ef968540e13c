//! Reports: what turns results into documents a reader can check.
//!
//! * [`publication`]: `lorentz report`, the publication audit of a result file (every check PASS,
//!   FAIL or SKIP with its numbers; Markdown, HTML, JSON).
//! * [`speed_error`]: speed against error across precisions (`lorentz bench --report`).
//! * [`reproduce`]: every figure and table of the user guide into one folder (`lorentz reproduce`).
//! * [`figures`]: the plotting backend and the paper's figures.

pub mod figures;
pub mod publication;
pub mod reproduce;
pub mod speed_error;
pub mod text;

/// `n` and the noun, plural unless n = 1: "1 thread", "2 threads".
///
/// ```
/// assert_eq!(lorentz_gas::report::counted(1, "thread"), "1 thread");
/// assert_eq!(lorentz_gas::report::counted(2, "thread"), "2 threads");
/// ```
pub fn counted(n: u64, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}
