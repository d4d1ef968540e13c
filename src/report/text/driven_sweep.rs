//! The text `lorentz sweep --electric` prints (the driven gas over gaps and fields, the
//! mobility's analysis and J(−E) = −J(E)): the command line writes it to stdout, then the files it
//! wrote, and Python's `str()` of the result is the same text.

use super::{estimate, line};
use crate::estimators::sweep::driven::{DrivenSweepReport, MobilityAnalysis};

/// The sweep's table, the mobility's analysis per gap and the symmetry checks.
pub fn driven_sweep(r: &DrivenSweepReport) -> String {
    let mut out = header(r);
    let row = |c: [&str; 7]| {
        format!(
            "{:>8}  {:>9}  {:<20}  {:<20}  {:<20}  {:<21}  {}",
            c[0], c[1], c[2], c[3], c[4], c[5], c[6]
        )
    };
    let head = ["w", "E", "mobility J/E", "J_perp", "λ₊", "λ₋", "λ₊+λ₋+⟨α⟩"];
    line!(out, "{}", row(head));
    for x in &r.rows {
        let s = &x.steady;
        let cells = [
            x.w.to_string(),
            x.electric.to_string(),
            estimate(s.mobility, s.mobility_err),
            estimate(s.J_perp, s.J_perp_err),
            estimate(s.lambda_plus, s.lambda_plus_err),
            estimate(s.lambda_minus, s.lambda_minus_err),
            estimate(s.sum_rule, s.sum_rule_err),
        ];
        line!(out, "{}", row(cells.each_ref().map(String::as_str)));
    }
    for m in &r.mobility {
        analysis(&mut out, m);
    }
    for o in &r.odd {
        let m = &o.mobility_even;
        line!(
            out,
            "J(-E) = -J(E) at w = {}, |E| = {}: J/E(E) - J/E(-E) = {} ({:+.2} sigma, bound {:.2}) {}",
            o.w,
            o.electric,
            estimate(m.difference, m.err),
            m.z,
            m.bound,
            if m.agrees() { "ok" } else { "FAIL" }
        );
    }
    out
}

/// One gap's Einstein extrapolations and polynomial χ².
fn analysis(out: &mut String, m: &MobilityAnalysis) {
    let fits = [
        ("D + a|E|", &m.einstein_linear),
        ("D + cE²", &m.einstein_quadratic),
    ];
    for (form, fit) in fits {
        if let Some(f) = fit {
            line!(
                out,
                "w = {}: J/E = {form} gives D = {} (chi2 {:.2} for {} dof)",
                m.w,
                estimate(f.intercept, f.var_intercept.sqrt()),
                f.chi2,
                f.dof
            );
        }
    }
    if !m.polynomial_chi2.is_empty() {
        let chi2: Vec<String> = (m.polynomial_chi2.iter())
            .map(|p| format!("{}: {:.1}/{}", p.degree, p.chi2, p.dof))
            .collect();
        line!(
            out,
            "w = {}: chi2/dof of polynomials in |E| by degree (smooth if a low degree absorbs the points): {}",
            m.w,
            chi2.join(", ")
        );
    }
}

/// The first line: the grid, the run sizes and the seed.
fn header(r: &DrivenSweepReport) -> String {
    let c = &r.config;
    format!(
        "sweep of the driven gas: {} point(s), {} collisions in {} batches per point, seed {} ({} points resumed)\n",
        r.rows.len(),
        c.collisions,
        c.batches,
        c.seed,
        r.resumed_points
    )
}
