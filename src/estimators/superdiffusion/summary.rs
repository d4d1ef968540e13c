//! From the batches' sums to the report: per-lag tables with batch errors, the batch-by-batch
//! fits (tails C + B/s, the VACF's plateau, the MSD's slope in ln t) and the limit law's
//! quartiles.

use serde::{Deserialize, Serialize};

use super::{Batch, SuperdiffusionConfig};
use crate::Error;
use crate::observers::lag_moments::{HISTOGRAM_BINS, HISTOGRAM_RANGE};
use crate::statistics::fits::weighted_line_fit;
use crate::statistics::mean_se;
use crate::theory::corridors::Superdiffusion;

/// The quartiles of N(0, 1) are ±0.6744897501960817.
const NORMAL_QUARTILE: f64 = 0.674_489_750_196_081_7;

/// The tail fits use an s only while every batch saw at least this many longer flights (binomial
/// noise of 10 % per batch at most).
pub const TAIL_MIN_FLIGHTS: u64 = 100;

/// One lag t (a tail time s = t).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LagRow {
    /// The lag (and tail time) t.
    pub t: f64,
    /// t in mean free times.
    pub t_over_ell: f64,
    /// s·P(τ > s) under the flow (→ C_flow).
    pub s_p_flow: f64,
    /// Its batch error.
    pub s_p_flow_err: f64,
    /// What flights longer than the longest seen (L) would add: |s·P(τ > s)|·s/L (each flight
    /// counts with weight τ − s).
    pub s_p_flow_unsampled: f64,
    /// s²·μ(τ > s) under the map (→ C_map).
    pub s2_p_map: f64,
    /// Its batch error.
    pub s2_p_map_err: f64,
    /// Flights longer than s, all batches.
    pub flights_longer: u64,
    /// t·C_xx(t) (→ D_sup).
    pub t_c: f64,
    /// Its batch error.
    pub t_c_err: f64,
    /// What flights longer than the longest seen (L) would add: |t·C_xx(t)|·t/L.
    pub t_c_unsampled: f64,
    /// ⟨Δx²⟩ at lag t.
    pub msd_x: f64,
    /// Its batch error.
    pub msd_x_err: f64,
    /// The slope of ⟨Δx²⟩/t in ln t over the octave [t/2, t] (→ 2 D_sup; `None` for the lags whose
    /// half is not on the grid).
    pub msd_local_slope: Option<f64>,
    /// Its batch error.
    pub msd_local_slope_err: Option<f64>,
    /// The unsampled-flight term of the local slope, |slope|·t/L.
    pub msd_local_slope_unsampled: Option<f64>,
}

/// The scaled displacement u = Δx/√(D_sup t ln t) at one lag (u → N(0, 1)).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LawRow {
    /// The lag t.
    pub t: f64,
    /// (interquartile range / 1.349)² of u: the limit law's variance, → 1.
    pub variance_ratio: f64,
    /// Its batch error.
    pub variance_ratio_err: f64,
    /// ⟨u²⟩ = ⟨Δx²⟩/(D_sup t ln t): → 2, the MSD's factor 2 (the long flights outside the
    /// Gaussian limit).
    pub second_moment_ratio: f64,
    /// Its batch error.
    pub second_moment_ratio_err: f64,
    /// Kolmogorov distance of the pooled histogram of u from N(0, 1) at the bin edges.
    pub ks_distance: f64,
    /// Samples of u (two per window: Δx and Δy).
    pub samples: u64,
}

pub(super) struct Input<'a> {
    pub cfg: &'a SuperdiffusionConfig,
    pub sd: &'a Superdiffusion<f64>,
    pub ell: f64,
    pub steps: &'a [usize],
    pub times: &'a [f64],
    pub histogram_at: &'a [usize],
}

pub(super) struct Summary {
    pub c_flow: Option<MeanSe>,
    pub c_map: Option<MeanSe>,
    pub tail_fit: Option<[f64; 2]>,
    pub d_sup: Estimate,
    pub vacf_fit: [f64; 2],
    pub slope: Estimate,
    pub intercept: (f64, f64),
    pub msd_fit: [f64; 2],
    pub longest: f64,
    pub lags: Vec<LagRow>,
    pub law: Vec<LawRow>,
}

/// A value with its batch error and the bound on what the flights longer than any seen would add.
pub(super) struct Estimate {
    pub value: f64,
    pub batch: f64,
    pub unsampled: f64,
}

impl Estimate {
    /// The two errors in quadrature.
    pub fn err(&self) -> f64 {
        self.batch.hypot(self.unsampled)
    }
}

/// The batches' values of one quantity at every lag.
struct Columns {
    /// `per[b][k]`: batch b at lag k.
    per: Vec<Vec<f64>>,
}

impl Columns {
    fn new(batches: &[Batch], lags: usize, f: impl Fn(&Batch, usize) -> f64) -> Self {
        Columns {
            per: batches
                .iter()
                .map(|b| (0..lags).map(|k| f(b, k)).collect())
                .collect(),
        }
    }
    fn at(&self, k: usize) -> Vec<f64> {
        self.per.iter().map(|b| b[k]).collect()
    }
    fn mean_se(&self, k: usize) -> (f64, f64) {
        mean_se(&self.at(k))
    }
}

/// Every batch's value of each per-lag quantity.
struct Tables {
    map: Columns,
    flow: Columns,
    vacf: Columns,
    msd: Columns,
    over_t: Columns,
}

impl Tables {
    fn new(inp: &Input, batches: &[Batch]) -> Self {
        let (n, times, steps) = (inp.steps.len(), inp.times, inp.steps);
        let msd_at =
            |b: &Batch, k: usize| 0.5 * b.lags.squared[k] / b.lags.windows(steps[k]) as f64;
        Tables {
            map: Columns::new(batches, n, |b, k| {
                times[k] * times[k] * b.tails.longer[k] as f64 / b.tails.flights as f64
            }),
            flow: Columns::new(batches, n, |b, k| {
                times[k] * b.tails.excess[k] / b.tails.time
            }),
            vacf: Columns::new(batches, n, |b, k| {
                times[k] * 0.5 * b.lags.velocity[k] / b.lags.windows(steps[k]) as f64
            }),
            msd: Columns::new(batches, n, msd_at),
            over_t: Columns::new(batches, n, |b, k| msd_at(b, k) / times[k]),
        }
    }
}

/// The tail constants (C_map, C_flow) fitted as C + B/s over the grid times from
/// `tail_fit_from`·ℓ at which every batch saw [`TAIL_MIN_FLIGHTS`] longer flights, and the range
/// (all `None` with fewer than two such times).
type Tails = (Option<MeanSe>, Option<MeanSe>, Option<[f64; 2]>);

fn tail_constants(inp: &Input, batches: &[Batch], t: &Tables) -> Result<Tails, Error> {
    let times = inp.times;
    let points: Vec<usize> = (0..times.len())
        .filter(|&k| {
            times[k] >= inp.cfg.tail_fit_from * inp.ell
                && batches
                    .iter()
                    .all(|b| b.tails.longer[k] >= TAIL_MIN_FLIGHTS)
        })
        .collect();
    if points.len() < 2 {
        return Ok((None, None, None));
    }
    let inv = |k: usize| 1.0 / times[k];
    Ok((
        Some(batch_fit(&t.map, &points, inv)?.0),
        Some(batch_fit(&t.flow, &points, inv)?.0),
        Some([times[points[0]], times[points[points.len() - 1]]]),
    ))
}

/// One row per lag.
fn lag_rows(inp: &Input, batches: &[Batch], t: &Tables, longest: f64) -> Vec<LagRow> {
    let (times, steps) = (inp.times, inp.steps);
    (0..steps.len())
        .map(|k| {
            let (s_p_flow, s_p_flow_err) = t.flow.mean_se(k);
            let (s2_p_map, s2_p_map_err) = t.map.mean_se(k);
            let (t_c, t_c_err) = t.vacf.mean_se(k);
            let (msd_x, msd_x_err) = t.msd.mean_se(k);
            let half = steps.iter().position(|&m| 2 * m == steps[k]);
            let local = half.map(|h| {
                let per: Vec<f64> = t
                    .over_t
                    .per
                    .iter()
                    .map(|b| (b[k] - b[h]) / std::f64::consts::LN_2)
                    .collect();
                mean_se(&per)
            });
            let unsampled = |v: f64| v.abs() * times[k] / longest;
            LagRow {
                t: times[k],
                t_over_ell: steps[k] as f64,
                s_p_flow,
                s_p_flow_err,
                s_p_flow_unsampled: unsampled(s_p_flow),
                s2_p_map,
                s2_p_map_err,
                flights_longer: batches.iter().map(|b| b.tails.longer[k]).sum(),
                t_c,
                t_c_err,
                t_c_unsampled: unsampled(t_c),
                msd_x,
                msd_x_err,
                msd_local_slope: local.map(|l| l.0),
                msd_local_slope_err: local.map(|l| l.1),
                msd_local_slope_unsampled: local.map(|l| unsampled(l.0)),
            }
        })
        .collect()
}

pub(super) fn summarise(inp: &Input, batches: &[Batch]) -> Result<Summary, Error> {
    let (times, steps) = (inp.times, inp.steps);
    let t = Tables::new(inp, batches);
    let (c_map, c_flow, tail_fit) = tail_constants(inp, batches, &t)?;
    let longest = batches.iter().map(|b| b.tails.longest).fold(0.0, f64::max);
    let window = |w: [f64; 2]| -> Vec<usize> {
        (0..steps.len())
            .filter(|&k| (w[0]..=w[1]).contains(&(steps[k] as f64)))
            .collect()
    };
    let (vacf_points, msd_points) = (window(inp.cfg.vacf_fit), window(inp.cfg.msd_fit));
    let top = |p: &[usize]| times[*p.last().expect("validated: two lags in a window")];
    let (d, d_err) = batch_mean(&t.vacf, &vacf_points)?;
    let d_sup = Estimate {
        value: d,
        batch: d_err,
        unsampled: d.abs() * top(&vacf_points) / longest,
    };
    let (intercept, a) = batch_fit(&t.over_t, &msd_points, |k| times[k].ln())?;
    let slope = Estimate {
        value: a.0,
        batch: a.1,
        unsampled: a.0.abs() * top(&msd_points) / longest,
    };
    let law = inp
        .histogram_at
        .iter()
        .enumerate()
        .map(|(h, &k)| law_row(batches, h, times[k], inp.sd.d_sup_xx, &t.msd.at(k)))
        .collect();
    Ok(Summary {
        c_flow,
        c_map,
        tail_fit,
        d_sup,
        vacf_fit: [times[vacf_points[0]], top(&vacf_points)],
        slope,
        intercept,
        msd_fit: [times[msd_points[0]], top(&msd_points)],
        longest,
        lags: lag_rows(inp, batches, &t, longest),
        law,
    })
}

/// The batch standard deviation of a column at each of `points`: the common weights.
fn sigmas(c: &Columns, points: &[usize]) -> Vec<f64> {
    let nb = c.per.len() as f64;
    points.iter().map(|&k| c.mean_se(k).1 * nb.sqrt()).collect()
}

/// A mean over batches and its standard error.
type MeanSe = (f64, f64);

/// y = c₀ + c₁x(k) fitted batch by batch with common weights over `points`: ((c₀, se), (c₁, se))
/// over the batches.
fn batch_fit(
    c: &Columns,
    points: &[usize],
    x: impl Fn(usize) -> f64,
) -> Result<(MeanSe, MeanSe), Error> {
    let xs: Vec<f64> = points.iter().map(|&k| x(k)).collect();
    let sig = sigmas(c, points);
    let mut c0 = Vec::with_capacity(c.per.len());
    let mut c1 = Vec::with_capacity(c.per.len());
    for b in &c.per {
        let ys: Vec<f64> = points.iter().map(|&k| b[k]).collect();
        let f = weighted_line_fit(&xs, &ys, &sig)?;
        c0.push(f.intercept);
        c1.push(f.slope);
    }
    Ok((mean_se(&c0), mean_se(&c1)))
}

/// The weighted mean over `points`, batch by batch with common weights: (mean, se) over batches.
fn batch_mean(c: &Columns, points: &[usize]) -> Result<(f64, f64), Error> {
    let w: Vec<f64> = sigmas(c, points).iter().map(|s| 1.0 / (s * s)).collect();
    if w.iter().any(|w| !w.is_finite()) {
        return Err(Error::Failed(
            "a lag whose batches all agree exactly: no error to weigh by".into(),
        ));
    }
    let sw: f64 = w.iter().sum();
    let per: Vec<f64> = c
        .per
        .iter()
        .map(|b| points.iter().zip(&w).map(|(&k, w)| w * b[k]).sum::<f64>() / sw)
        .collect();
    Ok(mean_se(&per))
}

/// The standard normal distribution function.
fn normal_cdf(x: f64) -> f64 {
    0.5 * statrs::function::erf::erfc(-x / std::f64::consts::SQRT_2)
}

/// The value where a histogram's distribution function reaches `p` (linear inside a bin).
fn quantile(h: &[u64], p: f64) -> f64 {
    let total: u64 = h.iter().sum();
    let width = 2.0 * HISTOGRAM_RANGE / HISTOGRAM_BINS as f64;
    let target = p * total as f64;
    let mut below = 0.0;
    for (i, &c) in h.iter().enumerate() {
        let next = below + c as f64;
        if next >= target && c > 0 {
            let frac = (target - below) / c as f64;
            return -HISTOGRAM_RANGE + (i as f64 + frac) * width;
        }
        below = next;
    }
    HISTOGRAM_RANGE
}

/// (IQR/1.349)² of a histogram of u.
fn iqr_variance(h: &[u64]) -> f64 {
    let s = (quantile(h, 0.75) - quantile(h, 0.25)) / (2.0 * NORMAL_QUARTILE);
    s * s
}

fn law_row(batches: &[Batch], h: usize, t: f64, d_sup: f64, msd: &[f64]) -> LawRow {
    let per: Vec<f64> = batches
        .iter()
        .map(|b| iqr_variance(&b.lags.histograms[h]))
        .collect();
    let (variance_ratio, variance_ratio_err) = mean_se(&per);
    let scale = d_sup * t * t.ln();
    let second: Vec<f64> = msd.iter().map(|m| m / scale).collect();
    let (second_moment_ratio, second_moment_ratio_err) = mean_se(&second);
    let mut pooled = vec![0u64; HISTOGRAM_BINS];
    for b in batches {
        for (p, c) in pooled.iter_mut().zip(&b.lags.histograms[h]) {
            *p += c;
        }
    }
    let total: u64 = pooled.iter().sum();
    let width = 2.0 * HISTOGRAM_RANGE / HISTOGRAM_BINS as f64;
    let mut below = 0u64;
    let mut ks: f64 = 0.0;
    for (i, &c) in pooled.iter().enumerate().take(HISTOGRAM_BINS - 1) {
        below += c;
        let edge = -HISTOGRAM_RANGE + (i + 1) as f64 * width;
        ks = ks.max((below as f64 / total as f64 - normal_cdf(edge)).abs());
    }
    LawRow {
        t,
        variance_ratio,
        variance_ratio_err,
        second_moment_ratio,
        second_moment_ratio_err,
        ks_distance: ks,
        samples: total,
    }
}
