//! Finite-segment certification by precision doubling.
//!
//! A segment of N collisions from an exactly given initial condition is certified to d digits when
//! its runs at precision P and 2P agree to d digits in every contact point and velocity. Chaos
//! amplifies rounding by ~e^{λk} after k collisions, so P is chosen as
//! P = ⌈(λN + d·ln 10)/ln 2⌉ + 64 bits from the tangent-space λ, and doubled until the two runs
//! agree (`proofs-notes/certification.md`). The certified segment also shows how far the f64 orbit
//! from the same start follows the true one.

use crate::engine::work::{Work, mpfr_seconds_per_collision};
use rug::Float;
use serde::{Deserialize, Serialize};

use super::lyapunov::{LyapunovConfig, collision_track};
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::scenes::Scene;
use crate::scenes::lattice::LatticeState;

/// Collisions per orbit of the λ estimate that sets the starting precision.
pub const CERTIFY_LAMBDA_COLLISIONS: u64 = 100_000;
/// Orbits of the λ estimate (its relative error, ~10⁻³, changes P by a few bits).
pub const CERTIFY_LAMBDA_ORBITS: u32 = 4;
/// Seed of the λ estimate: fixed, so the precisions tried depend on (w, N, d) only.
pub const CERTIFY_LAMBDA_SEED: u64 = 17;
/// Guard bits added to P = ⌈(λN + d ln 10)/ln 2⌉ for the prefactor of the error growth.
pub const CERTIFY_GUARD_BITS: u32 = 64;
/// Smallest P tried.
pub const MIN_CERTIFY_BITS: u32 = 128;
/// Largest P tried (the 2P run then has 2²¹ bits): beyond it one collision costs milliseconds
/// and a segment that still disagrees is not worth certifying this way.
pub const MAX_CERTIFY_BITS: u32 = 1 << 20;
/// Memory the two stored MPFR tracks may take, checked before anything is allocated.
pub const MAX_MEMORY_BYTES: f64 = 4.0 * (1u64 << 30) as f64;

/// A certified segment.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Certificate {
    /// The scene ([`Scene::label`]).
    pub scene: String,
    /// Collisions certified.
    pub collisions: usize,
    /// Digits requested.
    pub digits_requested: u32,
    /// Digits to which the P and 2P runs agree over the whole segment (−log₁₀ of the largest
    /// deviation).
    pub digits_agreed: f64,
    /// The precision P (bits) of the certifying pair (P, 2P).
    pub bits: u32,
    /// Precisions tried, in order.
    pub tried: Vec<u32>,
    /// Collisions for which the f64 orbit from the same start stays within 10⁻³ of the certified one.
    pub f64_faithful_collisions: usize,
    /// Version, seed of the start (if drawn from a seed), precision P, command line.
    pub meta: RunMeta,
}

fn max_dev(a: &[([Float; 4], f64)], b: &[([Float; 4], f64)]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            (0..4)
                .map(|i| (x.0[i].clone() - &y.0[i]).abs().to_f64())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

/// Bytes of one stored collision (four MPFR numbers of `bits` bits, their headers, a time).
fn bytes_per_collision(bits: f64) -> f64 {
    4.0 * (32.0 + (bits / 64.0).ceil() * 8.0) + 8.0
}

/// The starting precision and the memory of its three stored tracks, for `n` collisions to
/// `digits` digits at Lyapunov exponent `lambda`.
fn needs(lambda: f64, n: f64, digits: u32) -> (f64, f64) {
    let need = (lambda * n + digits as f64 * std::f64::consts::LN_10) / std::f64::consts::LN_2
        + CERTIFY_GUARD_BITS as f64;
    let bits = need.ceil().max(MIN_CERTIFY_BITS as f64);
    // Three tracks live at once (P, 2P, and f64 or the next attempt), stored at 2P bits.
    (bits, 3.0 * n * bytes_per_collision(2.0 * bits))
}

/// The starting precision for `n` collisions to `digits` digits at Lyapunov exponent `lambda`,
/// or an error naming the largest segment that fits the limits ([`MAX_CERTIFY_BITS`],
/// [`MAX_MEMORY_BYTES`]).
pub fn starting_bits(lambda: f64, n: usize, digits: u32) -> Result<u32, Error> {
    let fits = |n: f64| {
        let (b, m) = needs(lambda, n, digits);
        b <= MAX_CERTIFY_BITS as f64 && m <= MAX_MEMORY_BYTES
    };
    let (bits, memory) = needs(lambda, n as f64, digits);
    if fits(n as f64) {
        return Ok(bits as u32);
    }
    // The largest segment that fits, by bisection (both needs grow with n).
    let (mut lo, mut hi) = (0.0f64, n as f64);
    while hi - lo > 1.0 {
        let mid = ((lo + hi) / 2.0).floor();
        if fits(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let gib = |m: f64| m / (1u64 << 30) as f64;
    let (bits_limit, memory_limit) = (
        format!("the limit of {MAX_CERTIFY_BITS} bits"),
        format!("the memory limit of {:.0} GiB", gib(MAX_MEMORY_BYTES)),
    );
    let over = |b: f64, m: f64| match (b > MAX_CERTIFY_BITS as f64, m > MAX_MEMORY_BYTES) {
        (true, true) => format!("{bits_limit} and {memory_limit}"),
        (true, false) => bits_limit.clone(),
        _ => memory_limit.clone(),
    };
    let needed = format!(
        "certifying {n} collisions to {digits} digits needs about {bits:.3e} bits (lambda N / ln 2 \
         at lambda = {lambda:.3} per collision) and {:.3e} GiB of memory, beyond {}",
        gib(memory),
        over(bits, memory)
    );
    if lo < 1.0 {
        return Err(Error::parameter(
            "digits",
            digits,
            format!("{needed}: use fewer digits"),
        ));
    }
    // The limit that stops the next collision beyond the longest segment that fits.
    let (b1, m1) = needs(lambda, lo + 1.0, digits);
    Err(Error::parameter(
        "collisions",
        n,
        format!(
            "{needed}: use at most {lo:.0} collisions (where {} binds)",
            over(b1, m1)
        ),
    ))
}

/// What a certification runs: `collisions` collisions from the start of trajectory 0 of seed
/// `seed` (the first batch of `lorentz diffusion --seed SEED`) to `digits` digits.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CertifyConfig {
    /// Collisions of the segment.
    pub collisions: usize,
    /// Digits certified (of every position and velocity at every collision).
    pub digits: u32,
    /// Seed of the equilibrium start.
    pub seed: u64,
}

impl CertifyConfig {
    /// The command line's defaults: 1000 collisions to 30 digits from the seed-1 start.
    pub fn new() -> Self {
        CertifyConfig {
            collisions: 1000,
            digits: 30,
            seed: 1,
        }
    }
}

impl Default for CertifyConfig {
    fn default() -> Self {
        Self::new()
    }
}

/// Certifies the segment `cfg` of `scene` by precision doubling. `options.progress` receives
/// collision counts of the runs made; the runs are sequential (the options' threads do not
/// apply).
///
/// # Errors
/// No collisions or digits, or a segment beyond the precision and memory limits (the error names
/// the longest segment that fits).
pub fn run<S: Scene>(
    scene: &S,
    cfg: &CertifyConfig,
    options: &RunOptions,
) -> Result<Certificate, Error> {
    options.accept("certify", &[])?;
    let start = scene.sample(&mut crate::scenes::sampling::stream(cfg.seed, 0));
    certify_with_meta(
        scene,
        &start,
        cfg.collisions,
        cfg.digits,
        Some(cfg.seed),
        options.progress,
    )
}

/// The Lyapunov exponent per collision the precision plan starts from (a short run of its own,
/// with fixed seed and the cell walk, so the plan keeps its bits).
fn planning_exponent<S: Scene>(scene: &S) -> Result<f64, Error> {
    let cfg = LyapunovConfig {
        collisions_per_batch: CERTIFY_LAMBDA_COLLISIONS,
        batches: CERTIFY_LAMBDA_ORBITS,
        seed: CERTIFY_LAMBDA_SEED,
        // The plan keeps its bits: the walk, as before long flights.
        flights: crate::engine::long_flight::Flights::Walk,
        motion: Default::default(),
    };
    let one = RunOptions {
        threads: 1,
        ..RunOptions::default()
    };
    match super::lyapunov::run(scene, &cfg, &one) {
        Ok(l) => Ok(l.per_collision),
        // The planning run's own counts are not certify's to lower: name the scene instead.
        Err(Error::TooMuchWork { estimate, .. }) => Err(Error::out_of_range(
            "scene",
            scene.label(),
            format!(
                "certify plans its precision from a Lyapunov exponent it measures first, and \
                 here {estimate}; use a scene with shorter flights (a smaller gap, a larger radius)"
            ),
        )),
        Err(e) => Err(e),
    }
}

/// The collisions before the f64 track `f` first leaves the certified one `hi` by more than 10⁻³.
fn faithful_collisions(f: &[([Float; 4], f64)], hi: &[([Float; 4], f64)]) -> usize {
    f.iter()
        .zip(hi)
        .position(|(x, y)| (0..4).any(|i| (x.0[i].clone() - &y.0[i]).abs().to_f64() > 1e-3))
        .unwrap_or(f.len())
}

fn certify_with_meta<S: Scene>(
    scene: &S,
    start: &LatticeState<f64>,
    n: usize,
    digits: u32,
    seed: Option<u64>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Certificate, Error> {
    if n == 0 {
        return Err(Error::Zero { what: "collisions" });
    }
    if digits == 0 {
        return Err(Error::Zero { what: "digits" });
    }
    let plan = f64::from(CERTIFY_LAMBDA_ORBITS) * CERTIFY_LAMBDA_COLLISIONS as f64;
    let lower = &["collisions", "digits"];
    Work::new("certify's plan", lower, plan)
        .walking(scene)
        .check(1)?;
    let mut bits = starting_bits(planning_exponent(scene)?, n, digits)?;
    // The first attempt: runs at P and 2P bits, each walking its cells.
    let per = mpfr_seconds_per_collision(bits) + mpfr_seconds_per_collision(bits.saturating_mul(2));
    Work::new("certify", lower, n as f64)
        .costing(per)
        .walking(scene)
        .check(1)?;
    let mut tried = Vec::new();
    let run = |b: u32, out: u32| -> Result<Vec<([Float; 4], f64)>, Error> {
        let lat = scene.lattice::<Float>(b)?;
        let t = collision_track(
            &lat,
            &LatticeState::<Float>::convert_from_f64(b, start),
            n,
            out,
        );
        progress(n as u64);
        t
    };
    loop {
        tried.push(bits);
        let out = 2 * bits;
        let (lo, hi) = (run(bits, out)?, run(2 * bits, out)?);
        let dev = max_dev(&lo, &hi);
        let agreed = if dev > 0.0 {
            -dev.log10()
        } else {
            f64::INFINITY
        };
        if agreed >= digits as f64 {
            let f = collision_track(&scene.lattice::<f64>(())?, start, n, out)?;
            progress(n as u64);
            let faithful = faithful_collisions(&f, &hi);
            return Ok(Certificate {
                scene: scene.label(),
                collisions: n,
                digits_requested: digits,
                digits_agreed: agreed,
                bits,
                tried,
                f64_faithful_collisions: faithful,
                meta: RunMeta::new(seed, None, bits, Some(1)),
            });
        }
        if bits >= MAX_CERTIFY_BITS
            || 3.0 * n as f64 * bytes_per_collision(4.0 * bits as f64) > MAX_MEMORY_BYTES
        {
            return Err(Error::Failed(format!(
                "could not certify {n} collisions to {digits} digits within {} bits and {:.0} GiB \
                 (the runs at {bits} and {} bits agree to {agreed:.1} digits)",
                MAX_CERTIFY_BITS,
                MAX_MEMORY_BYTES / (1u64 << 30) as f64,
                2 * bits
            )));
        }
        bits *= 2;
    }
}
