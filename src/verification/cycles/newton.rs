//! Newton's method on the closed cycle and its Newton–Kantorovich certificate.

use super::*;
use crate::verification::shadowing::{
    Evaluation, StepFailure, V2, evaluate, m_mul, m_norm, mv, norm2,
};

/// Most Newton iterations (damped steps count once).
const MAX_ITERATIONS: usize = 40;
/// Converged when every defect is below 2^(SLACK − P)/cos φ_min (as the shadows).
const SLACK: f64 = 24.0;
/// The secant estimate of ‖D²T‖ is multiplied by this before it enters the certificate.
const LIPSCHITZ_SAFETY: f64 = 100.0;

/// The defects F_k = T_k(x_k) − x_{k+1 mod n} of the cycle `y` with the Jacobians and flights
/// (the shadows' evaluation of the open chain x₀ … x_{n−1}, x₀′, x₀′ the state x₀ on the disk
/// `close`: x₀'s own on an open table, x₀'s shifted by the winding on a lattice).
fn evaluate_cycle(table: &Table, y: &[OrbitPoint], close: [i64; 2]) -> Result<Evaluation, String> {
    let mut chain = y.to_vec();
    chain.push(OrbitPoint {
        disk: close,
        ..y[0].clone()
    });
    evaluate(table, &chain).map_err(|(k, e)| match e {
        StepFailure::Grazing(_) => format!("grazing collision at collision {k}"),
        StepFailure::Miss => format!(
            "the flight from collision {k} misses disk {:?}",
            chain[k + 1].disk
        ),
    })
}

fn max_defect(ev: &Evaluation) -> f64 {
    ev.f.iter().map(|v| norm2(v).to_f64()).fold(0.0, f64::max)
}

fn identity(bits: u32) -> M2 {
    std::array::from_fn(|i| Float::with_val(bits, u32::from(i % 3 == 0)))
}

/// The solution e of the cyclic system A_k e_k − e_{k+1 mod n} = r_k: with e₀ free,
/// e_{k+1} = A_k e_k − r_k closes when (I − M)e₀ = c, M = A_{n−1}⋯A₀ and c the image of e₀ = 0.
/// `None` if I − M is singular (a parabolic cycle).
fn solve_cyclic(a: &[M2], r: &[V2]) -> Option<Vec<V2>> {
    let bits = r[0][0].prec();
    let zero = || Float::new(bits);
    let mut c: V2 = [zero(), zero()];
    let mut m = identity(bits);
    for (ak, rk) in a.iter().zip(r) {
        let t = mv(ak, &c);
        c = [t[0].clone() - &rk[0], t[1].clone() - &rk[1]];
        m = m_mul(ak, &m);
    }
    let b: M2 = [
        Float::with_val(bits, 1) - &m[0],
        -m[1].clone(),
        -m[2].clone(),
        Float::with_val(bits, 1) - &m[3],
    ];
    let det = b[0].clone() * &b[3] - &(b[1].clone() * &b[2]);
    if det.is_zero() || !det.is_finite() {
        return None;
    }
    let mut e = Vec::with_capacity(a.len());
    e.push([
        (b[3].clone() * &c[0] - &(b[1].clone() * &c[1])) / &det,
        (b[0].clone() * &c[1] - &(b[2].clone() * &c[0])) / &det,
    ]);
    for k in 0..a.len() - 1 {
        let t = mv(&a[k], &e[k]);
        e.push([t[0].clone() - &r[k][0], t[1].clone() - &r[k][1]]);
    }
    Some(e)
}

/// Damped Newton on the cycle `y` until the defect is at the rounding level of `bits`: each step
/// is halved until the evaluation succeeds and the largest defect falls.
fn newton(
    table: &Table,
    y: &mut Vec<OrbitPoint>,
    bits: u32,
    close: [i64; 2],
) -> Result<(Evaluation, usize), (usize, String)> {
    let mut ev = evaluate_cycle(table, y, close).map_err(|w| (0, w))?;
    let mut it = 0;
    loop {
        let res = max_defect(&ev);
        let tol = (SLACK - f64::from(bits)).exp2() / ev.cos_min.0.min(1.0);
        if res <= tol {
            return Ok((ev, it));
        }
        if it == MAX_ITERATIONS || !res.is_finite() {
            return Err((
                it,
                format!("no convergence after {it} Newton iterations (max defect {res:.3e})"),
            ));
        }
        let r: Vec<V2> =
            ev.f.iter()
                .map(|v| [-v[0].clone(), -v[1].clone()])
                .collect();
        let e = solve_cyclic(&ev.jac, &r)
            .ok_or_else(|| (it, "the linearised cycle is singular (I − M)".to_string()))?;
        let mut step = Float::with_val(bits, 1);
        loop {
            let trial: Vec<OrbitPoint> = y
                .iter()
                .zip(&e)
                .map(|(x, d)| OrbitPoint {
                    disk: x.disk,
                    s: x.s.clone() + &(d[0].clone() * &step),
                    p: x.p.clone() + &(d[1].clone() * &step),
                })
                .collect();
            match evaluate_cycle(table, &trial, close) {
                Ok(next) if max_defect(&next) < res || step < 1e-3 => {
                    *y = trial;
                    ev = next;
                    break;
                }
                Err(why) if step < 1e-3 => return Err((it, why)),
                _ => step /= 2u32,
            }
        }
        it += 1;
    }
}

/// K ≥ ‖DF⁻¹‖₂ for DF the cyclic block matrix of the Jacobians `a` (rows (…, A_k, −I, …)): the
/// inverse X computed column by column, and ‖DF⁻¹‖₂ ≤ ‖X‖_F/(1 − ρ) with
/// ρ ≥ ‖I − X·DF‖_F (plus an allowance for its rounding). `None` if ρ ≥ 1/2.
fn inverse_bound(a: &[M2], bits: u32) -> Option<f64> {
    let n = a.len();
    let zero = || Float::new(bits);
    // Columns of X as vectors of n blocks.
    let mut cols: Vec<Vec<V2>> = Vec::with_capacity(2 * n);
    for j in 0..2 * n {
        let mut r: Vec<V2> = (0..n).map(|_| [zero(), zero()]).collect();
        r[j / 2][j % 2] = Float::with_val(bits, 1);
        cols.push(solve_cyclic(a, &r)?);
    }
    let x_norm = cols
        .iter()
        .flatten()
        .flatten()
        .map(|x| x.to_f64().powi(2))
        .sum::<f64>()
        .sqrt();
    // X·DF: column 2j + c is Σ_m X[:, 2j+m] A_j[m][c] − X[:, 2(j−1)+c]; compare with I.
    let mut rho2 = 0.0f64;
    for j in 0..n {
        let prev = (j + n - 1) % n;
        for c in 0..2 {
            for i in 0..2 * n {
                let (bi, ci) = (i / 2, i % 2);
                let v = cols[2 * j][bi][ci].clone() * &a[j][c]
                    + &(cols[2 * j + 1][bi][ci].clone() * &a[j][2 + c])
                    - &cols[2 * prev + c][bi][ci];
                let target = f64::from(u8::from(i == 2 * j + c));
                rho2 += (v - target).to_f64().powi(2);
            }
        }
    }
    let amax = a.iter().map(m_norm).fold(0.0, f64::max);
    let rounding = (2 * n) as f64 * (20.0 - f64::from(bits)).exp2() * x_norm * (2.0 + amax);
    let rho = rho2.sqrt() + rounding;
    (rho < 0.5).then(|| x_norm / (1.0 - rho))
}

/// The secant estimate of ‖D²T‖: max_k ‖A_k(x′_k) − A_k(x_k)‖_F/‖x′_k − x_k‖ between the cycle
/// `y` (Jacobians `jac`) and the points `other` (Jacobians `other_jac`).
fn secant(y: &[OrbitPoint], jac: &[M2], other: &[OrbitPoint], other_jac: &[M2]) -> f64 {
    let mut m = 0.0f64;
    for k in 0..y.len() {
        let d = norm2(&[other[k].s.clone() - &y[k].s, other[k].p.clone() - &y[k].p]).to_f64();
        if d > 0.0 {
            let diff: M2 = std::array::from_fn(|i| other_jac[k][i].clone() - &jac[k][i]);
            m = m.max(m_norm(&diff) / d);
        }
    }
    m
}

/// M: the largest secant estimate of ‖D²T‖ from the starting guess and from perturbations of
/// size 2⁻²⁰ along s, along p and along both (a ball far larger than the certified one, and
/// several directions: at a symmetric cycle DT may be stationary along one of them), times
/// [`LIPSCHITZ_SAFETY`].
fn lipschitz(
    table: &Table,
    (y, close): (&[OrbitPoint], [i64; 2]),
    ev: &Evaluation,
    first: &Evaluation,
    y0: &[OrbitPoint],
) -> f64 {
    let delta = Float::with_val(table.bits(), -20f64).exp2();
    let mut m = secant(y, &ev.jac, y0, &first.jac);
    for (ds, dp) in [(1u32, 0u32), (0, 1), (1, 2)] {
        let near: Vec<OrbitPoint> = y
            .iter()
            .enumerate()
            .map(|(k, x)| OrbitPoint {
                disk: x.disk,
                s: x.s.clone() + &(delta.clone() * ds),
                p: x.p.clone() - &(delta.clone() * (dp * (1 + (k % 3) as u32))),
            })
            .collect();
        if let Ok(e) = evaluate_cycle(table, &near, close) {
            m = m.max(secant(y, &ev.jac, &near, &e.jac));
        }
    }
    LIPSCHITZ_SAFETY * m
}

/// Finds the cycle of `disks` through the disk sequence `seq` by Newton's method at `bits`,
/// certifies it (Newton–Kantorovich) and has the kernel check its flights.
///
/// A cycle that does not converge, is not certified or is pruned is an `Ok` with the reason in
/// `failure` (and `pruned`).
///
/// # Errors
/// A bad geometry, a sequence with a disk following itself or an unknown disk, or `bits` out of
/// [[`MIN_CYCLE_BITS`], [`MAX_CYCLE_BITS`]].
pub fn certify_cycle(disks: &Disks, seq: &[usize], bits: u32) -> Result<Cycle, Error> {
    check_sequence(disks, seq, bits)?;
    let y0 = initial_guess(disks, seq, bits);
    let mut cycle = certify_closed(disks, y0, [seq[0] as i64, 0], bits)?;
    cycle.disks = seq.to_vec();
    Ok(cycle)
}

/// Newton's method at `bits` from the collision states `y0` on `geometry`'s disks, the cycle
/// closing on the disk `close` (the first disk, or on a lattice the first shifted by the
/// winding), its Newton–Kantorovich certificate and the kernel's check of its flights. The
/// cycle's `disks` are left empty for the caller to name.
///
/// # Errors
/// The defect at twice the precision cannot be evaluated.
pub(crate) fn certify_closed<G: CycleTable>(
    geometry: &G,
    y0: Vec<OrbitPoint>,
    close: [i64; 2],
    bits: u32,
) -> Result<Cycle, Error> {
    let table = geometry.table(bits)?;
    let first = evaluate_cycle(&table, &y0, close);
    let mut y = y0.clone();
    let mut cycle = Cycle::unfinished(&[], bits);
    let (ev, iterations) = match newton(&table, &mut y, bits, close) {
        Ok(done) => done,
        Err((it, why)) => {
            cycle.iterations = it;
            cycle.failure = Some(why);
            return Ok(cycle);
        }
    };
    cycle.iterations = iterations;
    cycle.min_cos_phi = ev.cos_min.0;
    let contacts = super::prune::kernel_check(&table, geometry, (&y, close), &ev.tau);
    cycle.min_clearance = contacts.min_clearance;
    cycle.pruned = contacts.blocked;
    let eps = residual(&geometry.table(2 * bits)?, (&y, close), &ev, bits)?;
    let m = match &first {
        Ok(f) => lipschitz(&table, (&y, close), &ev, f, &y0),
        Err(_) => lipschitz(&table, (&y, close), &ev, &ev, &y),
    };
    cycle.orbit = y;
    cycle.jacobians = ev.jac.clone();
    certify(&mut cycle, &ev, eps, m, geometry.radius_f64());
    Ok(cycle)
}

/// ε = ‖F(y*)‖₂ at twice the precision (on `table2`) plus √n·2^(24−2P)/cos φ_min.
fn residual(
    table2: &Table,
    (y, close): (&[OrbitPoint], [i64; 2]),
    ev: &Evaluation,
    bits: u32,
) -> Result<f64, Error> {
    let ev2 = evaluate_cycle(table2, y, close).map_err(Error::Failed)?;
    let l2 = ev2
        .f
        .iter()
        .map(|v| norm2(v).to_f64().powi(2))
        .sum::<f64>()
        .sqrt();
    let n = y.len() as f64;
    Ok(l2 + n.sqrt() * (SLACK - 2.0 * f64::from(bits)).exp2() / ev.cos_min.0.min(1.0))
}

/// Fills the period, Λ and the certificate of `cycle` from the converged evaluation `ev`, the
/// defect bound `eps`, the Lipschitz constant `m` and the disk radius `a`.
fn certify(cycle: &mut Cycle, ev: &Evaluation, eps: f64, m: f64, a: f64) {
    let bits = cycle.precision_bits;
    let n = ev.jac.len() as f64;
    let round = (20.0 - f64::from(bits)).exp2();
    let period = ev.tau.iter().fold(Float::new(bits), |t, x| t + x);
    let prod = ev.jac.iter().fold(identity(bits), |p, ak| m_mul(ak, &p));
    let lambda = expanding_eigenvalue(&prod);
    let norms: f64 = ev.jac.iter().map(m_norm).product();
    let amax = ev.jac.iter().map(m_norm).fold(0.0, f64::max);
    cycle.period = period.to_f64();
    cycle.stability = lambda.to_f64();
    cycle.period_exact = Some(period);
    cycle.residual = eps;
    cycle.lipschitz = m;
    let Some(k) = inverse_bound(&ev.jac, bits) else {
        cycle.failure = Some(
            "converged but not certified: the computed inverse of DF has residual >= 1/2".into(),
        );
        return;
    };
    let radius = 2.0 * k * eps;
    let l = cycle.stability.abs();
    cycle.inverse_bound = k;
    cycle.radius = radius;
    cycle.uniqueness_radius = 1.0 / (k * m);
    // |Δτ_k| ≤ |ΔX_k| + |ΔX_{k+1}|, |ΔX| = a|Δs| ≤ a·radius.
    cycle.period_bound = 2.0 * n * a * radius + n * round * cycle.period;
    // ‖ΔM‖_F ≤ n·∏‖A_j‖_F·M·radius; |ΔΛ| ≤ √2‖ΔM‖_F·Λ/(Λ − 1/Λ); plus rounding.
    cycle.stability_bound =
        (std::f64::consts::SQRT_2 * n * norms * (m * radius + round)) * l / (l - 1.0 / l);
    let reach = radius * (1.0 + amax);
    let kantorovich = 2.0 * m * k * k * eps <= 1.0;
    cycle.certified = kantorovich
        && reach < cycle.min_cos_phi
        && reach < cycle.min_clearance
        && cycle.pruned.is_none()
        && l > 1.0;
    if let Some(why) = &cycle.pruned {
        cycle.failure = Some(format!("pruned: {why}"));
    } else if !cycle.certified {
        cycle.failure = Some(format!(
            "converged but not certified: K = {k:.3e}, eps = {eps:.3e}, M = {m:.3e} (2MK^2 eps <= 1: {kantorovich}), reach {reach:.3e} against cos phi {:.3e} and clearance {:.3e}",
            cycle.min_cos_phi, cycle.min_clearance
        ));
    }
}

impl Cycle {
    /// A cycle of `seq` at `bits` before Newton's method.
    fn unfinished(seq: &[usize], bits: u32) -> Self {
        Cycle {
            disks: seq.to_vec(),
            precision_bits: bits,
            iterations: 0,
            period: f64::NAN,
            period_bound: f64::INFINITY,
            stability: f64::NAN,
            stability_bound: f64::INFINITY,
            residual: f64::INFINITY,
            inverse_bound: f64::INFINITY,
            radius: f64::INFINITY,
            uniqueness_radius: 0.0,
            lipschitz: f64::INFINITY,
            min_cos_phi: 0.0,
            min_clearance: f64::NEG_INFINITY,
            certified: false,
            pruned: None,
            failure: None,
            orbit: Vec::new(),
            jacobians: Vec::new(),
            period_exact: None,
        }
    }
}
