//! The MSD curve of a run on the logarithmic grid ([`super::MsdGrid::Log`]) or at the user's
//! times: the mean squared displacement, the velocity autocorrelation (per component too at the
//! user's times) and the running Green–Kubo integral, each the mean over the batches with its
//! standard error, and D by Green–Kubo over the fit window, compared with the Einstein D of the
//! same trajectories.

use serde::{Deserialize, Serialize};

use super::{BatchResult, Window};
use crate::Error;
use crate::statistics::comparison::paired;
use crate::statistics::mean_se;

/// The MSD curve: at each grid time the mean over the batches and its standard error.
#[allow(non_snake_case)]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MsdCurveReport {
    /// The grid's times: ⟨ℓ⟩/8 … 7⟨ℓ⟩/8, then four per octave; or the user's, from 0.
    pub times: Vec<f64>,
    /// ⟨|Δr(t)|²⟩ (length²).
    pub msd: Vec<f64>,
    /// Its standard errors.
    pub msd_err: Vec<f64>,
    /// The velocity autocorrelation ⟨v(0)·v(t)⟩ (1 at t = 0).
    pub vacf: Vec<f64>,
    /// Its standard errors.
    pub vacf_err: Vec<f64>,
    /// The running Green–Kubo integral ½∫₀ᵗ ⟨v(0)·v(s)⟩ ds = ½⟨v(0)·Δr(t)⟩ (length²/time),
    /// which tends to D.
    pub green_kubo: Vec<f64>,
    /// Its standard errors.
    pub green_kubo_err: Vec<f64>,
    /// ⟨v_x(0)v_x(t)⟩, ½ at t = 0 (the user's times only; absent on the logarithmic grid).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub vacf_x: Vec<f64>,
    /// Its standard errors.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub vacf_x_err: Vec<f64>,
    /// ⟨v_y(0)v_y(t)⟩, ½ at t = 0 (likewise).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub vacf_y: Vec<f64>,
    /// Its standard errors.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub vacf_y_err: Vec<f64>,
}

/// D by Green–Kubo from the MSD curve, against the Einstein D (in a report's top level; absent
/// without the curve).
#[allow(non_snake_case)]
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct GreenKuboD {
    /// D by Green–Kubo: each batch's running integral averaged over the grid times inside the
    /// fit window, then the mean over the batches (`None` if no grid time lies in the window).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub D_green_kubo: Option<f64>,
    /// Its standard error.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub D_green_kubo_err: Option<f64>,
    /// The Einstein D minus D by Green–Kubo, paired over the batches.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub D_minus_D_green_kubo: Option<f64>,
    /// Its standard error (of the per-batch differences; batches − 1 dof).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub D_minus_D_green_kubo_err: Option<f64>,
}

/// The curve of `done` at the grid's `times`, and D by Green–Kubo in `window` (in units of
/// `tau`) against the batches' Einstein values `batch_d`. `None` and no D without a grid.
///
/// # Errors
/// If a batch lacks the curve the grid asks for.
pub(super) fn summarise(
    times: Option<Vec<f64>>,
    done: &[BatchResult],
    tau: f64,
    window: &Window,
    batch_d: &[f64],
) -> Result<(Option<MsdCurveReport>, GreenKuboD), Error> {
    let Some(times) = times else {
        return Ok((None, GreenKuboD::default()));
    };
    let mut curves = Vec::with_capacity(done.len());
    for b in done {
        match &b.curve {
            Some(c) if c.msd.len() == times.len() => curves.push(c),
            _ => {
                return Err(Error::Invalid(format!(
                    "batch {} has no MSD curve on this run's grid of {} times",
                    b.index,
                    times.len()
                )));
            }
        }
    }
    let column = |f: &dyn Fn(usize, usize) -> f64| -> (Vec<f64>, Vec<f64>) {
        (0..times.len())
            .map(|k| mean_se(&(0..curves.len()).map(|b| f(b, k)).collect::<Vec<_>>()))
            .unzip()
    };
    let (msd, msd_err) = column(&|b, k| curves[b].msd[k]);
    let (vacf, vacf_err) = column(&|b, k| curves[b].vacf[k]);
    let (green_kubo, green_kubo_err) = column(&|b, k| curves[b].green_kubo[k]);
    // The components where every batch has them (the user's times).
    let components = curves
        .iter()
        .all(|c| c.vacf_x.len() == times.len() && c.vacf_y.len() == times.len());
    let ((vacf_x, vacf_x_err), (vacf_y, vacf_y_err)) = if components {
        (
            column(&|b, k| curves[b].vacf_x[k]),
            column(&|b, k| curves[b].vacf_y[k]),
        )
    } else {
        Default::default()
    };
    let (lo, hi) = (window.lo as f64 * tau, window.hi as f64 * tau);
    let inside: Vec<usize> = (0..times.len())
        .filter(|&k| times[k] >= lo && times[k] <= hi)
        .collect();
    let mut d = GreenKuboD::default();
    if !inside.is_empty() && curves.len() >= 2 {
        let gk: Vec<f64> = curves
            .iter()
            .map(|c| inside.iter().map(|&k| c.green_kubo[k]).sum::<f64>() / inside.len() as f64)
            .collect();
        let (value, err) = mean_se(&gk);
        let diff = paired(batch_d, &gk)?;
        d = GreenKuboD {
            D_green_kubo: Some(value),
            D_green_kubo_err: Some(err),
            D_minus_D_green_kubo: Some(diff.difference),
            D_minus_D_green_kubo_err: Some(diff.err),
        };
    }
    let curve = MsdCurveReport {
        times,
        msd,
        msd_err,
        vacf,
        vacf_err,
        green_kubo,
        green_kubo_err,
        vacf_x,
        vacf_x_err,
        vacf_y,
        vacf_y_err,
    };
    Ok((Some(curve), d))
}
