//! The text `lorentz sweep` prints (the table of D(w) and its fits): the command line writes it to
//! stdout, and Python's `str()` of a sweep result is the same text.

use super::line;
use crate::estimators::sweep::SweepReport;

/// The text of a sweep's table and fits (`lorentz sweep` and `lorentz merge` print it before the
/// files they wrote).
pub fn sweep(r: &SweepReport) -> String {
    let mut out = String::new();
    let c = &r.config;
    let (from, to) = c
        .gap_grid()
        .map_or(("?", "?"), |g| (g.w_from.as_str(), g.w_to.as_str()));
    line!(
        out,
        "sweep w = {} .. {}, {} points x {} runs x {} collisions in {} batches per run ({} points resumed)",
        from,
        to,
        c.steps(),
        c.runs(),
        c.collisions,
        c.batches,
        r.resumed_points
    );
    line!(
        out,
        "error of D: from the batches inside the runs (dof = runs x (batches - 1)); runs F (p): spread of the runs against those errors, F(runs - 1, dof)"
    );
    line!(
        out,
        "       w         D            +-       dof   runs F     (p)     D_MZ       D_Bo      residual"
    );
    for x in &r.rows {
        // One run per point has no spread to test: say so rather than print NaN.
        let f_test = if x.runs_f.is_finite() {
            format!("{:>6.2}  ({:.3})", x.runs_f, x.runs_p_value)
        } else {
            format!("{:>15}", "n/a (1 run)")
        };
        line!(
            out,
            "{:>8}  {:.6}  {:.6}  {:>6}   {f_test}   {:.6}  {:.6}  {:+.2e}",
            x.w,
            x.D,
            x.D_err,
            x.D_err_dof,
            x.D_MZ,
            x.D_Bo,
            x.residual
        );
    }
    fits(&mut out, r);
    out
}

/// The fits of the sweep: the straight line, the polynomials, the Boltzmann offset and where D
/// crosses D_MZ.
fn fits(out: &mut String, r: &SweepReport) {
    let l = &r.linear_fit;
    line!(
        out,
        "straight line D = {:.6} + {:.6} w: chi2/dof = {:.2}/{} (residuals: Fig. 8)",
        l.intercept,
        l.slope,
        l.chi2,
        l.dof
    );
    line!(
        out,
        "polynomials in w, chi2/dof by degree: {}",
        r.polynomial_chi2
            .iter()
            .map(|p| format!("{}: {:.1}/{}", p.degree, p.chi2, p.dof))
            .collect::<Vec<_>>()
            .join("  ")
    );
    let b = &r.boltzmann_offset;
    line!(
        out,
        "Boltzmann offset (slope 3/16): Delta D = {:.5} ± {:.5} (chi2/dof = {:.1}/{}; error scaled by sqrt(chi2/dof) when above 1: ± {:.5})",
        b.mean,
        b.err,
        b.chi2,
        b.dof,
        r.boltzmann_offset_err_scaled
    );
    let f = &r.boltzmann_free_fit;
    line!(
        out,
        "free slope of D against 1/n = {:.5} ± {:.5} (3/16 = 0.1875; chi2/dof = {:.1}/{})",
        f.slope,
        f.var_slope.sqrt(),
        f.chi2,
        f.dof
    );
    match &r.mz_crossing {
        Some(x) => line!(
            out,
            "D = D_MZ at w = {:.4} ± {:.4} (local weighted quadratic through {} points, chi2/dof = {:.2}/{}; error scaled by sqrt(chi2/dof) when above 1: ± {:.4})",
            x.w,
            x.err,
            x.points,
            x.chi2,
            x.dof,
            x.err_scaled
        ),
        None => line!(out, "D - D_MZ does not change sign in this range"),
    }
}
