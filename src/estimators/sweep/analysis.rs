//! The analysis of a finished sweep: each point's D from its runs with the runs' F test, the
//! straight line in w and its residuals (Fig. 8), the Boltzmann offset against 1/n (Fig. 7), the
//! crossing D = D_MZ, and polynomial χ².

use super::{
    CROSSING_POINTS_PER_SIDE, Crossing, MAX_POLYNOMIAL_DEGREE, PolynomialChi2, SweepConfig,
    SweepPoint, SweepReport, SweepRow,
};
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::numbers::precision::Precision;
use crate::scenes::triangular::geometry::Geometry;
use crate::statistics::f_p_value;
use crate::statistics::fits::{
    weighted_line_fit, weighted_mean, weighted_polynomial_chi2, weighted_quadratic_fit,
};

/// One point's D, its error from the batch errors inside the runs, and the runs' χ².
fn combine(cfg: &SweepConfig, p: &SweepPoint) -> Result<SweepRow, Error> {
    let g = Geometry::new(p.w)?;
    let r = p.runs.len() as f64;
    let d = p.runs.iter().map(|x| x.D).sum::<f64>() / r;
    let d_err = p.runs.iter().map(|x| x.D_err * x.D_err).sum::<f64>().sqrt() / r;
    let dof1 = p.runs.len() as u32 - 1;
    let dof2 = p.runs.len() as u64 * (cfg.batches as u64 - 1);
    let between = p.runs.iter().map(|x| (x.D - d).powi(2)).sum::<f64>() / dof1 as f64;
    let within = p.runs.iter().map(|x| x.D_err * x.D_err).sum::<f64>() / r;
    let f = between / within;
    Ok(SweepRow {
        w: p.w,
        inv_n: 1.0 / g.density(),
        D: d,
        D_err: d_err,
        D_err_dof: dof2,
        runs_f: f,
        runs_f_dof1: dof1,
        runs_f_dof2: dof2,
        runs_p_value: f_p_value(f, dof1 as f64, dof2 as f64),
        D_MZ: g.d_mz(),
        D_Bo: g.d_bo(),
        residual: 0.0,
        run_D: p.runs.iter().map(|x| x.D).collect(),
        run_D_err: p.runs.iter().map(|x| x.D_err).collect(),
    })
}

/// The crossing of D − D_MZ, from a weighted least-squares quadratic through up to
/// [`CROSSING_POINTS_PER_SIDE`] points on each side of the first sign change (a straight line when
/// only two points exist). The root is the one nearest the sign change; its error is
/// (gᵀ Σ g)^½ / |f′(w*)| with g = (1, t*, t*²) and Σ the fit's covariance.
pub fn mz_crossing(rows: &[SweepRow]) -> Result<Option<Crossing>, Error> {
    let f: Vec<f64> = rows.iter().map(|r| r.D - r.D_MZ).collect();
    let Some(k) = (0..f.len().saturating_sub(1)).find(|&k| f[k].signum() != f[k + 1].signum())
    else {
        return Ok(None);
    };
    let lo = (k + 1).saturating_sub(CROSSING_POINTS_PER_SIDE);
    let hi = (k + 1 + CROSSING_POINTS_PER_SIDE).min(rows.len());
    let sel = &rows[lo..hi];
    let x: Vec<f64> = sel.iter().map(|r| r.w).collect();
    let y: Vec<f64> = sel.iter().map(|r| r.D - r.D_MZ).collect();
    let e: Vec<f64> = sel.iter().map(|r| r.D_err).collect();
    // Centre on the linear interpolation between the two points that change sign.
    let x0 = rows[k].w + (rows[k + 1].w - rows[k].w) * f[k] / (f[k] - f[k + 1]);
    let (t, err, chi2, dof) = if sel.len() >= 3 {
        let q = weighted_quadratic_fit(&x, &y, &e, x0)?;
        let (t, err) = q.root_near_zero().ok_or_else(|| {
            Error::Failed("the local quadratic of D - D_MZ has no real root".into())
        })?;
        (t, err, q.chi2, q.dof)
    } else {
        let l = weighted_line_fit(&x, &y, &e)?;
        let (w, err) = l.root();
        (w - x0, err, l.chi2, l.dof)
    };
    let scale = if dof > 0 {
        (chi2 / dof as f64).max(1.0).sqrt()
    } else {
        1.0
    };
    Ok(Some(Crossing {
        w: x0 + t,
        err,
        err_scaled: err * scale,
        chi2,
        dof,
        points: sel.len(),
    }))
}

/// The analysis of the finished `points` of `cfg` (`resumed` of them reused), on `threads`.
pub(crate) fn analyse(
    cfg: &SweepConfig,
    points: &[SweepPoint],
    resumed: u32,
    threads: usize,
) -> Result<SweepReport, Error> {
    let mut rows = points
        .iter()
        .map(|p| combine(cfg, p))
        .collect::<Result<Vec<_>, _>>()?;
    let col = |f: &dyn Fn(&SweepRow) -> f64| rows.iter().map(f).collect::<Vec<f64>>();
    let (ws, ds, es, inv_n) = (
        col(&|r| r.w),
        col(&|r| r.D),
        col(&|r| r.D_err),
        col(&|r| r.inv_n),
    );
    let lin = weighted_line_fit(&ws, &ds, &es)?;
    let boltz = weighted_mean(&col(&|r| r.D_Bo - r.D), &es)?;
    let scale = if boltz.dof > 0 {
        (boltz.chi2 / boltz.dof as f64).max(1.0).sqrt()
    } else {
        1.0
    };
    let free = weighted_line_fit(&inv_n, &ds, &es)?;
    for r in &mut rows {
        r.residual = r.D - lin.at(r.w);
    }
    let crossing = mz_crossing(&rows)?;
    let polynomial_chi2 = polynomial_chi2(&ws, &ds, &es)?;
    Ok(SweepReport {
        polynomial_chi2,
        config: cfg.clone(),
        rows,
        linear_fit: lin,
        boltzmann_offset: boltz,
        boltzmann_offset_err_scaled: boltz.err * scale,
        boltzmann_free_fit: free,
        mz_crossing: crossing,
        resumed_points: resumed,
        meta: RunMeta::new(
            Some(cfg.seed),
            Some(cfg.runs() as u64 * cfg.batches as u64),
            Precision::F64,
            Some(threads),
        ),
    })
}

/// χ² and degrees of freedom of weighted polynomials through (x, y ± e) of degree 1 …
/// [`MAX_POLYNOMIAL_DEGREE`], as far as the points allow (two more distinct x than the degree).
///
/// # Errors
/// Errors that are not positive, or points that do not determine a polynomial.
pub fn polynomial_chi2(x: &[f64], y: &[f64], e: &[f64]) -> Result<Vec<PolynomialChi2>, Error> {
    let mut distinct = x.to_vec();
    distinct.sort_by(f64::total_cmp);
    distinct.dedup();
    let mut out = Vec::new();
    for degree in 1..=MAX_POLYNOMIAL_DEGREE {
        if distinct.len() < degree + 2 {
            break;
        }
        let (chi2, dof) = weighted_polynomial_chi2(x, y, e, degree)?;
        out.push(PolynomialChi2 { degree, chi2, dof });
    }
    Ok(out)
}
