//! The divergence of finite-precision orbits: the same initial condition run at f64 and at
//! 64 … 1024 bits against a 4096-bit reference. The deviation grows like u_P·e^{λk}, so the
//! number of collisions before it passes 10⁻³ (the divergence horizon) grows linearly in the
//! number of bits, and the fitted growth rate is the Lyapunov exponent again
//! (`proofs-notes/lyapunov.md`).

use rug::Float;
use serde::{Deserialize, Serialize};

use super::lyapunov::collision_track;
use crate::Error;
use crate::engine::long_flight::Flights;
use crate::engine::options::RunOptions;
use crate::scenes::Scene;
use crate::scenes::lattice::LatticeState;
use crate::scenes::sampling::stream;
use crate::statistics::{linear_fit, mean_se};

/// Precisions (bits) whose divergence from the reference `lorentz lyapunov` measures, next to f64.
pub const DIVERGENCE_BITS: [u32; 5] = [64, 128, 256, 512, 1024];

/// Reference precision of the divergence measurement: four times the largest precision measured,
/// so the reference's own divergence horizon (~3000 collisions) lies beyond every horizon measured.
pub const DIVERGENCE_REFERENCE_BITS: u32 = 4096;

/// Collisions followed in the divergence measurement: beyond the 1024-bit horizon (~785
/// collisions at w = 0.1) with a margin.
pub const DIVERGENCE_COLLISIONS: usize = 900;

/// Starts of the divergence measurement when none are asked for: 8, or 0 where long flights jump
/// ([`Flights::resolve`]): the measurement replays the cell walk at up to 4096 bits, whose cost
/// grows with the flight's length (at r = 10⁻⁴ some 5000 cells a collision), which would turn a
/// run of seconds into hours.
///
/// # Errors
/// `flights` refused for `scene`.
pub fn default_starts<S: Scene>(scene: &S, flights: Flights) -> Result<u32, Error> {
    Ok(match flights.resolve(scene)? {
        Flights::Jump => 0,
        _ => 8,
    })
}

/// The divergence of one precision from the reference.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Divergence {
    /// "f64" or bits.
    pub precision: String,
    /// Initial conditions measured (the errors are over them).
    pub starts: u32,
    /// Collisions until the deviation first exceeds 10⁻³ (mean over initial conditions).
    pub horizon: f64,
    /// Its standard error over the starts (NaN for one start: no spread to estimate it from).
    pub horizon_err: f64,
    /// Fitted growth rate of ln(deviation) per collision (mean ± SE over initial conditions).
    pub rate_per_collision: f64,
    /// Its standard error.
    pub rate_per_collision_err: f64,
    /// Fitted growth rate per unit time.
    pub rate_per_time: f64,
    /// Its standard error.
    pub rate_per_time_err: f64,
}

/// What a divergence measurement runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DivergenceConfig {
    /// Precisions (bits) measured next to f64, each below `reference_bits`.
    pub bits: Vec<u32>,
    /// The reference precision.
    pub reference_bits: u32,
    /// Collisions followed.
    pub collisions: usize,
    /// Equilibrium initial conditions (the error is over them).
    pub starts: u32,
    /// Seed: start k is drawn from stream (seed, k).
    pub seed: u64,
}

impl DivergenceConfig {
    /// The command line's defaults: [`DIVERGENCE_BITS`] against [`DIVERGENCE_REFERENCE_BITS`] for
    /// [`DIVERGENCE_COLLISIONS`] collisions from 8 starts, seed 1.
    pub fn new() -> Self {
        DivergenceConfig {
            bits: DIVERGENCE_BITS.to_vec(),
            reference_bits: DIVERGENCE_REFERENCE_BITS,
            collisions: DIVERGENCE_COLLISIONS,
            starts: 8,
            seed: 1,
        }
    }
}

impl DivergenceConfig {
    /// Checks the configuration before any work. One start is accepted (its horizon is that
    /// start's own, which a test of one orbit needs), but its error fields are NaN: nothing to
    /// spread over; the command line asks for 2 or more.
    pub fn validate(&self) -> Result<(), Error> {
        if self.starts == 0 {
            return Err(Error::Zero { what: "starts" });
        }
        if self.collisions == 0 {
            return Err(Error::Zero { what: "collisions" });
        }
        Ok(())
    }
}

impl Default for DivergenceConfig {
    fn default() -> Self {
        Self::new()
    }
}

/// Runs `cfg.starts` equilibrium initial conditions of `scene` at f64 and at each of `cfg.bits`,
/// against a reference at `cfg.reference_bits`, for `cfg.collisions` collisions; fits
/// ln(deviation) against collision number (and time) where 10⁴·u_P < deviation < 10⁻³.
/// `options.progress` receives finished initial conditions; the starts run one after another.
///
/// # Errors
/// A precision at or above the reference's.
pub fn run<S: Scene>(
    scene: &S,
    cfg: &DivergenceConfig,
    options: &RunOptions,
) -> Result<Vec<Divergence>, Error> {
    options.accept("divergence", &[])?;
    cfg.validate()?;
    let (bits, ref_bits, n, starts, seed) = (
        &cfg.bits[..],
        cfg.reference_bits,
        cfg.collisions,
        cfg.starts,
        cfg.seed,
    );
    let progress = options.progress;
    if let Some(&b) = bits.iter().find(|&&b| b >= ref_bits) {
        return Err(Error::parameter(
            "reference_bits",
            ref_bits,
            format!("the divergence's precisions must lie below the reference's ({b} bits given)"),
        ));
    }
    let l64 = scene.lattice::<f64>(())?;
    let lref = scene.lattice::<Float>(ref_bits)?;
    let mut precs: Vec<Option<u32>> = vec![None];
    precs.extend(bits.iter().map(|&b| Some(b)));
    let mut per: Vec<Vec<(f64, f64, f64)>> = vec![Vec::new(); precs.len()];
    for k in 0..starts {
        progress(1);
        let s64 = scene.sample(&mut stream(seed, k as u64));
        let r = collision_track(
            &lref,
            &LatticeState::<Float>::convert_from_f64(ref_bits, &s64),
            n,
            ref_bits,
        )?;
        for (pi, p) in precs.iter().enumerate() {
            let track = match p {
                None => collision_track(&l64, &s64, n, ref_bits)?,
                Some(b) => {
                    let lat = scene.lattice::<Float>(*b)?;
                    collision_track(
                        &lat,
                        &LatticeState::<Float>::convert_from_f64(*b, &s64),
                        n,
                        ref_bits,
                    )?
                }
            };
            per[pi].push(horizon_and_rates(&track, &r, *p, n, ref_bits));
        }
    }
    Ok(precs
        .iter()
        .zip(per)
        .map(|(p, v)| summary(cfg, *p, &v))
        .collect())
}

/// The separation of the orbit `track` at precision `p` (`None`: f64) from the reference `r`,
/// collision by collision: the horizon (the first collision at which it exceeds 10⁻³, or `n`)
/// and its growth rates per collision and per unit time, fitted to ln(separation) between 10⁴·u
/// and 10⁻³ before the horizon (NaN with fewer than 5 such points).
fn horizon_and_rates(
    track: &[([Float; 4], f64)],
    r: &[([Float; 4], f64)],
    p: Option<u32>,
    n: usize,
    ref_bits: u32,
) -> (f64, f64, f64) {
    let u = (-(p.unwrap_or(53) as f64)).exp2();
    let mut dev = Vec::with_capacity(n);
    for (a, b) in track.iter().zip(r) {
        let mut d = Float::with_val(ref_bits, 0);
        for i in 0..4 {
            d += (a.0[i].clone() - &b.0[i]).abs();
        }
        dev.push((d.to_f64(), b.1));
    }
    let horizon = dev.iter().position(|d| d.0 > 1e-3).unwrap_or(n) as f64;
    let (mut xs, mut ts, mut ys) = (Vec::new(), Vec::new(), Vec::new());
    for (i, d) in dev.iter().enumerate() {
        if d.0 > 1e4 * u && d.0 < 1e-3 && (i as f64) < horizon {
            xs.push(i as f64);
            ts.push(d.1);
            ys.push(d.0.ln());
        }
    }
    if xs.len() >= 5 {
        (horizon, linear_fit(&xs, &ys).1, linear_fit(&ts, &ys).1)
    } else {
        (horizon, f64::NAN, f64::NAN)
    }
}

/// The divergence at precision `p` over the starts' (horizon, rate per collision, rate per
/// time), each with its standard error (the rates over the starts that have one).
fn summary(cfg: &DivergenceConfig, p: Option<u32>, v: &[(f64, f64, f64)]) -> Divergence {
    let h: Vec<f64> = v.iter().map(|x| x.0).collect();
    let rc: Vec<f64> = v.iter().map(|x| x.1).filter(|x| x.is_finite()).collect();
    let rt: Vec<f64> = v.iter().map(|x| x.2).filter(|x| x.is_finite()).collect();
    let (hm, he) = mean_se(&h);
    let (cm, ce) = mean_se(&rc);
    let (tm, te) = mean_se(&rt);
    Divergence {
        precision: p.map(|b| b.to_string()).unwrap_or_else(|| "f64".into()),
        starts: cfg.starts,
        horizon: hm,
        horizon_err: he,
        rate_per_collision: cm,
        rate_per_collision_err: ce,
        rate_per_time: tm,
        rate_per_time_err: te,
    }
}
