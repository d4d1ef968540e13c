//! Newton's method on the whole segment: the evaluations of F and DT, convergence, the recorded defects and distances, and the certification.

use super::*;

/// Defects, Jacobians and the geometry of one evaluation of F along a pseudo-orbit.
pub(crate) struct Evaluation {
    pub(crate) f: Vec<V2>,
    pub(crate) jac: Vec<M2>,
    pub(crate) tau: Vec<Float>,
    /// Smallest cos φ over the collisions and its event.
    pub(crate) cos_min: (f64, usize),
}

/// Evaluates F at `y` on `table` (at the table's precision).
pub(crate) fn evaluate(
    table: &Table,
    y: &[OrbitPoint],
) -> Result<Evaluation, (usize, StepFailure)> {
    let m = y.len() - 1;
    let mut ev = Evaluation {
        f: Vec::with_capacity(m),
        jac: Vec::with_capacity(m),
        tau: Vec::with_capacity(m),
        cos_min: (f64::INFINITY, 0),
    };
    for (k, x) in y.iter().enumerate() {
        let c2 = Float::with_val(table.bits, 1) - &Float::with_val(table.bits, &x.p).square();
        let c = if c2.is_sign_positive() {
            c2.sqrt().to_f64()
        } else {
            0.0
        };
        if c < ev.cos_min.0 {
            ev.cos_min = (c, k);
        }
    }
    for k in 0..m {
        let st = table.step(&y[k], y[k + 1].disk).map_err(|e| (k, e))?;
        if st.cos_in.to_f64() < ev.cos_min.0 {
            ev.cos_min = (st.cos_in.to_f64(), k + 1);
        }
        ev.f.push([reduce_angle(st.s - &y[k + 1].s), st.p - &y[k + 1].p]);
        ev.jac.push(st.jac);
        ev.tau.push(st.tau);
    }
    Ok(ev)
}

/// Newton's method converged: the first and the last evaluation, and the iterations taken.
pub(super) struct Converged {
    pub(super) first: Evaluation,
    pub(super) last: Evaluation,
    pub(super) iterations: usize,
}

/// Newton's method on `y` (minimum-norm corrections) until the defect is within the tolerance
/// at `bits`; on failure, the iterations done and the reason.
pub(super) fn newton(
    table: &Table,
    y: &mut [OrbitPoint],
    bits: u32,
) -> Result<Converged, (usize, String)> {
    let mut first: Option<Evaluation> = None;
    let mut iterations = 0;
    loop {
        let ev = evaluate(table, y).map_err(|(k, e)| (iterations, describe(k, &e, y)))?;
        let residual = ev.f.iter().map(|v| norm2(v).to_f64()).fold(0.0, f64::max);
        let tol = (CONVERGENCE_SLACK_BITS as f64 - bits as f64).exp2() / ev.cos_min.0.min(1.0);
        if first.is_none() {
            first = Some(Evaluation {
                f: ev.f.clone(),
                jac: ev.jac.clone(),
                tau: Vec::new(),
                cos_min: ev.cos_min,
            });
        }
        if residual <= tol {
            let first = first.expect("evaluated at least once");
            return Ok(Converged {
                first,
                last: ev,
                iterations,
            });
        }
        if iterations == MAX_ITERATIONS || !residual.is_finite() {
            let why = format!(
                "no convergence after {iterations} Newton iterations (max defect {residual:.3e}); smallest cos phi = {:.3e} at event {} (near-grazing: the linearisation is poor)",
                ev.cos_min.0, ev.cos_min.1
            );
            return Err((iterations, why));
        }
        let Some(e) = min_norm_correction(&ev.jac, &ev.f) else {
            let why = format!(
                "the linearised system is numerically singular; smallest cos phi = {:.3e} at event {}",
                ev.cos_min.0, ev.cos_min.1
            );
            return Err((iterations, why));
        };
        for (x, d) in y.iter_mut().zip(&e) {
            x.s += &d[0];
            x.p += &d[1];
        }
        iterations += 1;
    }
}

/// Records the defects of the converged orbit (`ev2`, at twice the precision) and of the
/// pseudo-orbit (`first`) in `sh`; returns the defect bound ε and the pseudo-orbit's L² defect.
pub(super) fn record_defects(
    sh: &mut Shadow,
    ev2: &Evaluation,
    first: &Evaluation,
    last: &Evaluation,
    bits: u32,
) -> (f64, f64) {
    let n = sh.collisions;
    let norms2: Vec<f64> = ev2.f.iter().map(|v| norm2(v).to_f64()).collect();
    let sec = 1.0 / last.cos_min.0.min(1.0);
    let rho =
        ((n - 1) as f64).sqrt() * (CONVERGENCE_SLACK_BITS as f64 - 2.0 * bits as f64).exp2() * sec;
    let eps = norms2.iter().map(|x| x * x).sum::<f64>().sqrt() + rho;
    sh.residual = Some(norms2.iter().cloned().fold(0.0, f64::max));
    sh.residual_l2 = Some(eps);
    let f0 = &first.f;
    sh.pseudo_orbit_defect = Some(f0.iter().map(|v| norm2(v).to_f64()).fold(0.0, f64::max));
    let f0_l2 = f0
        .iter()
        .map(|v| norm2(v).to_f64().powi(2))
        .sum::<f64>()
        .sqrt();
    (eps, f0_l2)
}

/// Records δ (the largest distance of `y` from the pseudo-orbit `y0`) in `sh` with the secant
/// estimate of ‖D²T‖, which it returns.
pub(super) fn record_distance(
    sh: &mut Shadow,
    y: &[OrbitPoint],
    y0: &[OrbitPoint],
    first: &Evaluation,
    last: &Evaluation,
    bits: u32,
) -> f64 {
    let n = y.len();
    let mut delta = 0.0f64;
    let mut m_est = 0.0f64;
    let floor = (40.0 - bits as f64).exp2();
    for k in 0..n {
        let d = norm2(&[
            reduce_angle(y[k].s.clone() - &y0[k].s),
            y[k].p.clone() - &y0[k].p,
        ])
        .to_f64();
        delta = delta.max(d);
        if k < n - 1 && d > floor {
            let diff: M2 = std::array::from_fn(|i| last.jac[k][i].clone() - &first.jac[k][i]);
            m_est = m_est.max(m_norm(&diff) / d);
        }
    }
    sh.delta = Some(delta);
    sh.second_derivative_estimate = Some(m_est);
    m_est
}

/// What the certificate weighs: the defect bound ε, the pseudo-orbit's L² defect, the estimate
/// of ‖D²T‖, the largest Jacobian norm and the smallest clearance.
pub(super) struct Estimates {
    pub(super) eps: f64,
    pub(super) f0_l2: f64,
    pub(super) m_est: f64,
    pub(super) amax: f64,
    pub(super) gap: f64,
}

/// The Newton–Kantorovich certificate from the bound K on ‖J⁺‖ at the converged orbit (`last`),
/// or the reason there is none.
pub(super) fn certify(sh: &mut Shadow, last: &Evaluation, bits: u32, est: &Estimates) {
    let Estimates {
        eps,
        f0_l2,
        m_est,
        amax,
        gap,
    } = *est;
    match inverse_bound(&last.jac, bits) {
        None => {
            sh.failure = Some(format!(
                "converged but not certified: ||J+|| > 2^40 (smallest cos phi = {:.3e} at event {})",
                last.cos_min.0, last.cos_min.1
            ));
        }
        Some(k) => {
            sh.inverse_bound = Some(k);
            let radius = 2.0 * k * eps;
            sh.correction_bound = Some(radius);
            sh.a_priori_bound = Some(2.0 * k * f0_l2);
            let allowance = 1.0 / (4.0 * k * k * eps);
            sh.lipschitz_allowance = Some(allowance);
            let reach = radius * (1.0 + amax);
            sh.certified = 100.0 * m_est <= allowance && reach < last.cos_min.0 && reach < gap;
            if !sh.certified {
                sh.failure = Some(format!(
                    "converged but not certified: K = {k:.3e}, eps = {eps:.3e}, estimated ||D2T|| = {m_est:.3e} against the allowance {allowance:.3e}, ball reach {reach:.3e} against cos phi {:.3e} and clearance {gap:.3e}",
                    last.cos_min.0
                ));
            }
        }
    }
}
