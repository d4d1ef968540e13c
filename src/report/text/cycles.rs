//! The text `lorentz cycles` prints (the three-disk repeller by certified cycles): the command
//! line writes it to stdout, and Python's `str()` of the result is the same text.

use super::line;
use crate::verification::cycles::expansion::Truncation;
use crate::verification::cycles::repeller::RepellerReport;

/// The truncation error `e` of the value `x` as the table shows it: `—` where there is none
/// (N = 1), `<` the double's resolution at `x` where the two doubles are equal.
fn error(e: f64, x: f64) -> String {
    if !e.is_finite() {
        "—".into()
    } else if e == 0.0 {
        format!("<{:.0e}", f64::EPSILON * x.abs().max(f64::MIN_POSITIVE))
    } else {
        format!("{e:.1e}")
    }
}

/// One row of the convergence table: γ, λ, h_KS and d of the spectral determinant at N, each
/// with its truncation error, and γ of the zeta function beside them.
fn row(d: &Truncation, z: &Truncation) -> String {
    format!(
        "{:>2}  {:>17.15} {:>8}  {:>17.15} {:>8}  {:>17.15} {:>8}  {:>17.15} {:>8}  |  {:>17.15} {:>8}",
        d.max_length,
        d.escape_rate,
        error(d.escape_rate_error, d.escape_rate),
        d.lyapunov,
        error(d.lyapunov_error, d.lyapunov),
        d.entropy,
        error(d.entropy_error, d.entropy),
        d.partial_dimension,
        error(d.partial_dimension_error, d.partial_dimension),
        z.escape_rate,
        error(z.escape_rate_error, z.escape_rate),
    )
}

/// The text of a `cycles` result, line by line as the command line prints it.
pub fn cycles(r: &RepellerReport) -> String {
    let mut out = String::new();
    let c = &r.config;
    let full: usize = r.cycles.iter().map(|p| 6 / p.order.max(1)).sum();
    let radius = r.cycles.iter().map(|p| p.cycle.radius).fold(0.0, f64::max);
    line!(
        out,
        "three-disk repeller, side R = {}, radius a = {}: {} of {} fundamental-domain prime cycles \
         of length 1 to {} certified ({} full-space prime cycles; Newton-Kantorovich at {} bits, \
         largest certificate radius {:.1e})",
        c.side,
        c.radius,
        r.certified,
        r.cycles.len(),
        c.max_length,
        full,
        c.bits,
        radius
    );
    line!(
        out,
        "cycle expansion truncated at length N: the spectral determinant (error |x_N - x_(N-1)|), \
         the zeta function's escape rate beside it"
    );
    line!(
        out,
        "{:>2}  {:>17} {:>8}  {:>17} {:>8}  {:>17} {:>8}  {:>17} {:>8}  |  {:>17} {:>8}",
        "N",
        "escape rate gamma",
        "error",
        "Lyapunov lambda",
        "error",
        "h_KS",
        "error",
        "partial dim. d",
        "error",
        "zeta: gamma",
        "error"
    );
    for (d, z) in r.spectral_determinant.iter().zip(&r.zeta_function) {
        line!(out, "{}", row(d, z));
    }
    if let Some(d) = r.spectral_determinant.last() {
        line!(
            out,
            "N = {}: gamma = {:.15} (truncation error {}), lambda = {:.15}, h_KS = lambda - gamma \
             = {:.15} (rates per unit time at speed 1), partial dimension d = {:.15}",
            d.max_length,
            d.escape_rate,
            error(d.escape_rate_error, d.escape_rate),
            d.lyapunov,
            d.entropy,
            d.partial_dimension
        );
    }
    out
}
