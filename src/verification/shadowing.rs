//! True shadowing of `f64` orbit segments: Grebogi–Hammel–Yorke–Sauer refinement by Newton's
//! method on the whole segment, in MPFR (`proofs-notes/shadowing.md`).
//!
//! An `f64` segment of N collisions is a pseudo-orbit y⁰ = (x₀, …, x_{N−1}) in Birkhoff
//! coordinates x_k = (s_k, p_k) on the recorded disks c_k (s the polar angle of the contact
//! point, p = sin φ of the outgoing velocity). With T_k the exact billiard map from disk c_k to
//! the *recorded* next disk c_{k+1}, the one-step defects are
//!
//! F_k(y) = T_k(x_k) − x_{k+1},  k = 0 … N−2  (the s component reduced to (−π, π]).
//!
//! A true orbit with the same disk sequence is a zero of F: ℝ^{2N} → ℝ^{2(N−1)}. Newton's method
//! with the minimum-norm correction solves the block-bidiagonal linear system
//!
//! A_k e_k − e_{k+1} = −F_k(y),  A_k = DT_k(x_k) (analytic, at the working precision),
//!
//! as e = −Jᵀ(JJᵀ)⁻¹F: JJᵀ is block tridiagonal with diagonal blocks A_kA_kᵀ + I and
//! off-diagonal blocks −A_{k+1}ᵀ, so a block LDLᵀ sweep solves it in O(N) (no dense N×N
//! solve). Its pivots S_{k+1} = A_{k+1}(I − S_k⁻¹)A_{k+1}ᵀ + I are all ≥ I, so the sweep is
//! stable however hyperbolic the A_k are.
//!
//! **The proof.** At the final iterate y*, with ε = ‖F(y*)‖₂ (evaluated again at twice the
//! working precision) and K ≥ ‖J⁺‖₂ = 1/σ_min(J) (certified by Sylvester's law of inertia: the
//! block LDLᵀ of JJᵀ − μI has positive definite pivots, so λ_min(JJᵀ) > μ and K = 1/√μ), the
//! Newton–Kantorovich argument for a right inverse gives a zero of F within 2Kε of y* provided
//! 4MK²ε ≤ 1, M a Lipschitz constant of DF (i.e. a bound on ‖D²T‖) on that ball. Everything
//! but M is computed (up to MPFR rounding, for which explicit allowances are added); M is
//! *estimated* from the secants of DT along the Newton path and compared with the allowance
//! 1/(4K²ε), which is typically 10³⁰ times larger. δ = max_k ‖x*_k − x⁰_k‖₂ (Euclidean in
//! (s, p)) is then the distance from the `f64` segment to a true orbit up to 2Kε.

use rug::Float;
use serde::Serialize;

use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::parallel::par_batches;
use crate::kernel::flight::EventKind;
use crate::kernel::vec2::Vec2;
use crate::scenes::lattice::LatticeState;
use crate::scenes::sampling::stream;
use crate::scenes::Scene;
use crate::Error;

/// Smallest working precision: 128 bits leave ~75 bits between the `f64` defects (~2⁻⁵³) and
/// the rounding level, room for the quadratic convergence to show and for the proof's margins.
pub const MIN_SHADOW_BITS: u32 = 128;
/// Largest working precision accepted (the cost of one map grows like bits^1.6).
pub const MAX_SHADOW_BITS: u32 = 1 << 16;
/// Longest segment: the range. The cost is O(N) per Newton iteration (about 0.1 s per
/// 10⁴ collisions at 128 bits), so longer segments would work; 10⁴ keeps the memory and time of
/// `--segments` runs predictable.
pub const MAX_COLLISIONS: usize = 10_000;
/// Most Newton iterations: quadratic convergence from ~10⁻¹⁵ reaches the 128-bit rounding level
/// in 2–3 iterations; more than [`MAX_ITERATIONS`] means the linearisation is too poor
/// (near-grazing collisions).
pub const MAX_ITERATIONS: usize = 12;
/// Converged when every defect is below 2^(CONVERGENCE_SLACK_BITS − P)·max(1, 1/cos φ_min):
/// one evaluation of T rounds ~20 operations, amplified by 1/cos φ at the arrival.
pub const CONVERGENCE_SLACK_BITS: i32 = 24;

/// A collision point: the disk (lattice indices (i, j), centre a(i + βj, 0) + (0, hj)) and the
/// Birkhoff coordinates s = θ (polar angle of the contact point) and p = sin φ (outgoing
/// velocity, φ from the outward normal, counter-clockwise).
#[derive(Debug, Clone)]
pub struct OrbitPoint {
    /// Lattice indices (i, j) of the disk.
    pub disk: [i64; 2],
    /// Polar angle θ of the contact point (radians).
    pub s: Float,
    /// sin φ of the outgoing velocity.
    pub p: Float,
}

/// The billiard table at the working precision: the lattice basis and the disk radius, every
/// constant computed from the scene's exact parameters.
#[derive(Debug, Clone)]
pub struct Table {
    a: Float,
    beta: Float,
    h: Float,
    r: Float,
    bits: u32,
}

/// 2×2 matrix, row-major.
type M2 = [Float; 4];

/// One step of the map with its Jacobian.
struct Step {
    s: Float,
    p: Float,
    jac: M2,
    /// cos φ at the arrival.
    cos_in: Float,
    /// Free flight τ.
    tau: Float,
}

/// Why a step of the map could not be taken.
#[derive(Debug, Clone)]
enum StepFailure {
    /// |p| ≥ 1: the outgoing velocity is tangent to the disk (or beyond).
    Grazing(Float),
    /// The line of flight misses the recorded next disk.
    Miss,
}

impl Table {
    /// The table of `scene` at `bits` of precision.
    ///
    /// # Errors
    /// If `bits` is outside MPFR's range or the scene refuses it.
    pub fn new<S: Scene>(scene: &S, bits: u32) -> Result<Self, Error> {
        let lat = scene.lattice::<Float>(bits)?;
        let c = lat.cell();
        Ok(Table {
            a: c.lattice.a.clone(),
            beta: c.lattice.beta.clone(),
            h: c.lattice.h.clone(),
            r: c.radius.clone(),
            bits,
        })
    }

    /// The working precision.
    pub fn bits(&self) -> u32 {
        self.bits
    }

    /// Centre of disk (i, j): (a(i + βj), hj).
    pub fn centre(&self, d: [i64; 2]) -> Vec2<Float> {
        let (i, j) = (self.f(d[0] as f64), self.f(d[1] as f64));
        let x = self.a.clone() * &(i + &(self.beta.clone() * &j));
        Vec2::new(x, self.h.clone() * &j)
    }

    fn f(&self, x: f64) -> Float {
        Float::with_val(self.bits, x)
    }

    /// The billiard map T from `x` to the disk `next` at the table's precision, and its
    /// Jacobian ∂(s′, p′)/∂(s, p) (row-major), by the chain rule through the flight. `None` if
    /// |p| ≥ 1 (grazing) or the line of flight misses `next`. Another disk in the way is not
    /// checked here (see [`shadow_pseudo_orbit`]).
    pub fn map(&self, x: &OrbitPoint, next: [i64; 2]) -> Option<(OrbitPoint, [Float; 4])> {
        let st = self.step(x, next).ok()?;
        Some((
            OrbitPoint {
                disk: next,
                s: st.s,
                p: st.p,
            },
            st.jac,
        ))
    }

    /// Contact point and outgoing velocity of the collision state `x`.
    fn phase(&self, x: &OrbitPoint) -> Result<(Vec2<Float>, Vec2<Float>), StepFailure> {
        let b = self.bits;
        let (s, p) = (Float::with_val(b, &x.s), Float::with_val(b, &x.p));
        let c2 = Float::with_val(b, 1) - &p.clone().square();
        if !c2.is_sign_positive() || c2.is_zero() {
            return Err(StepFailure::Grazing(Float::with_val(b, 0)));
        }
        let cphi = c2.sqrt();
        let (sn, cs) = s.sin_cos(Float::new(b));
        let c = self.centre(x.disk);
        let pos = Vec2::new(c.x + &(self.r.clone() * &cs), c.y + &(self.r.clone() * &sn));
        let vel = Vec2::new(
            cphi.clone() * &cs - &(p.clone() * &sn),
            cphi * &sn + &(p * &cs),
        );
        Ok((pos, vel))
    }

    /// The billiard map from `x` to the disk `next` and its analytic Jacobian in (s, p)
    /// (chain rule through the flight; `proofs-notes/shadowing.md`).
    fn step(&self, x: &OrbitPoint, next: [i64; 2]) -> Result<Step, StepFailure> {
        let b = self.bits;
        let s = Float::with_val(b, &x.s);
        let p = Float::with_val(b, &x.p);
        let cphi2 = Float::with_val(b, 1) - &p.clone().square();
        if !cphi2.is_sign_positive() || cphi2.is_zero() {
            return Err(StepFailure::Grazing(Float::with_val(b, 0)));
        }
        let cphi = cphi2.sqrt();
        let (sn, cs) = s.sin_cos(Float::new(b));
        let n = Vec2::new(cs.clone(), sn.clone());
        let t = Vec2::new(-sn, cs);
        let v = Vec2::new(
            cphi.clone() * &n.x + &(p.clone() * &t.x),
            cphi.clone() * &n.y + &(p.clone() * &t.y),
        );
        let c0 = self.centre(x.disk);
        let c1 = self.centre(next);
        let x0 = c0.along(&self.r, &n);
        let d = x0.sub(&c1);
        let beta = d.dot(&v);
        let gamma = d.norm2() - &self.r.clone().square();
        let disc = beta.clone().square() - &gamma;
        if !beta.is_sign_negative() || !disc.is_sign_positive() || disc.is_zero() {
            return Err(StepFailure::Miss);
        }
        let sq = disc.clone().sqrt();
        // τ = −β − √Δ = γ/(√Δ − β), free of cancellation (β < 0, γ > 0).
        let tau = gamma / &(sq.clone() - &beta);
        let x1 = x0.along(&tau, &v);
        let n1 = Vec2::new(
            (x1.x.clone() - &c1.x) / &self.r,
            (x1.y.clone() - &c1.y) / &self.r,
        );
        let s1 = Float::with_val(b, n1.y.atan2_ref(&n1.x));
        let p1 = n1.cross(&v);
        let cos_in = sq.clone() / &self.r;
        let nn = n1.norm2();
        // Directional derivatives along e_s and e_p.
        let mut jac: M2 = std::array::from_fn(|_| Float::new(b));
        for dir in 0..2 {
            let (ds, dp) = if dir == 0 { (1.0, 0.0) } else { (0.0, 1.0) };
            let (ds, dp) = (self.f(ds), self.f(dp));
            // dn = t ds, dt = −n ds, dcφ = −p dp / cφ.
            let dn = Vec2::new(t.x.clone() * &ds, t.y.clone() * &ds);
            let dt = Vec2::new(-(n.x.clone() * &ds), -(n.y.clone() * &ds));
            let dc = -(p.clone() * &dp) / &cphi;
            let dv = Vec2::new(
                dc.clone() * &n.x
                    + &(cphi.clone() * &dn.x)
                    + &(dp.clone() * &t.x)
                    + &(p.clone() * &dt.x),
                dc * &n.y + &(cphi.clone() * &dn.y) + &(dp * &t.y) + &(p.clone() * &dt.y),
            );
            let dx0 = Vec2::new(dn.x.clone() * &self.r, dn.y.clone() * &self.r);
            let dbeta = dx0.dot(&v) + &d.dot(&dv);
            let dgamma = d.dot(&dx0) * 2u32;
            let ddisc = beta.clone() * &dbeta * 2u32 - &dgamma;
            let dtau = -dbeta - &(ddisc / &(sq.clone() * 2u32));
            let dx1 = Vec2::new(
                dx0.x.clone() + &(dtau.clone() * &v.x) + &(tau.clone() * &dv.x),
                dx0.y.clone() + &(dtau * &v.y) + &(tau.clone() * &dv.y),
            );
            let dn1 = Vec2::new(dx1.x / &self.r, dx1.y / &self.r);
            jac[dir] = n1.cross(&dn1) / &nn;
            jac[2 + dir] = dn1.cross(&v) + &n1.cross(&dv);
        }
        Ok(Step {
            s: s1,
            p: p1,
            jac,
            cos_in,
            tau,
        })
    }
}

/// `d` reduced to (−π, π] (differences of polar angles).
fn reduce_angle(d: Float) -> Float {
    let b = d.prec();
    let two_pi = Float::with_val(b, rug::float::Constant::Pi) * 2u32;
    let k = (d.clone() / &two_pi).round();
    d - &(k * &two_pi)
}

fn m_mul(a: &M2, b: &M2) -> M2 {
    let e = |i: usize, j: usize| a[2 * i].clone() * &b[j] + &(a[2 * i + 1].clone() * &b[2 + j]);
    [e(0, 0), e(0, 1), e(1, 0), e(1, 1)]
}

fn m_t(a: &M2) -> M2 {
    [a[0].clone(), a[2].clone(), a[1].clone(), a[3].clone()]
}

/// Inverse of a symmetric 2×2 matrix if it is positive definite (leading entry and determinant
/// positive), else `None`.
fn m_inv_spd(a: &M2) -> Option<M2> {
    let det = a[0].clone() * &a[3] - &(a[1].clone() * &a[2]);
    if !a[0].is_sign_positive() || a[0].is_zero() || !det.is_sign_positive() || det.is_zero() {
        return None;
    }
    Some([
        a[3].clone() / &det,
        -(a[1].clone() / &det),
        -(a[2].clone() / &det),
        a[0].clone() / &det,
    ])
}

type V2 = [Float; 2];

fn mv(a: &M2, v: &V2) -> V2 {
    [
        a[0].clone() * &v[0] + &(a[1].clone() * &v[1]),
        a[2].clone() * &v[0] + &(a[3].clone() * &v[1]),
    ]
}

fn mtv(a: &M2, v: &V2) -> V2 {
    mv(&m_t(a), v)
}

fn norm2(v: &V2) -> Float {
    (v[0].clone().square() + &v[1].clone().square()).sqrt()
}

/// Frobenius norm of a 2×2 matrix (≥ its spectral norm), in f64.
fn m_norm(a: &M2) -> f64 {
    a.iter().map(|x| x.to_f64().powi(2)).sum::<f64>().sqrt()
}

/// Inverses of the block LDLᵀ pivots of JJᵀ − μI, J the block-bidiagonal matrix of the rows
/// (A_k, −I): S₀ = A₀A₀ᵀ + (1 − μ)I, S_k = A_kA_kᵀ + (1 − μ)I − A_k S_{k−1}⁻¹ A_kᵀ. `None` if
/// a pivot is not positive definite — by Sylvester's law of inertia, exactly when JJᵀ − μI is not.
fn pivot_inverses(a: &[M2], mu: &Float) -> Option<Vec<M2>> {
    let one_mu = Float::with_val(mu.prec(), 1) - mu;
    let mut inv: Vec<M2> = Vec::with_capacity(a.len());
    for (k, ak) in a.iter().enumerate() {
        let mut s = m_mul(ak, &m_t(ak));
        s[0] += &one_mu;
        s[3] += &one_mu;
        if k > 0 {
            let q = m_mul(&m_mul(ak, &inv[k - 1]), &m_t(ak));
            for (x, y) in s.iter_mut().zip(&q) {
                *x -= y;
            }
        }
        inv.push(m_inv_spd(&s)?);
    }
    Some(inv)
}

/// The minimum-norm solution e of A_k e_k − e_{k+1} = −F_k (k = 0 … m−1, m + 1 unknown
/// blocks): e = Jᵀz with (JJᵀ)z = −F solved by the block LDLᵀ sweep. `None` if JJᵀ is not
/// numerically positive definite.
fn min_norm_correction(a: &[M2], f: &[V2]) -> Option<Vec<V2>> {
    let m = a.len();
    let bits = f[0][0].prec();
    let inv = pivot_inverses(a, &Float::with_val(bits, 0))?;
    let mut y: Vec<V2> = Vec::with_capacity(m);
    for k in 0..m {
        let mut r = [-f[k][0].clone(), -f[k][1].clone()];
        if k > 0 {
            let t = mv(&a[k], &mv(&inv[k - 1], &y[k - 1]));
            r[0] += &t[0];
            r[1] += &t[1];
        }
        y.push(r);
    }
    let mut z: Vec<V2> = vec![[Float::new(bits), Float::new(bits)]; m];
    for k in (0..m).rev() {
        let mut w = y[k].clone();
        if k + 1 < m {
            let t = mtv(&a[k + 1], &z[k + 1]);
            w[0] += &t[0];
            w[1] += &t[1];
        }
        z[k] = mv(&inv[k], &w);
    }
    let mut e: Vec<V2> = Vec::with_capacity(m + 1);
    for j in 0..=m {
        let mut ej = if j < m {
            mtv(&a[j], &z[j])
        } else {
            [Float::with_val(bits, 0), Float::with_val(bits, 0)]
        };
        if j > 0 {
            ej[0] -= &z[j - 1][0];
            ej[1] -= &z[j - 1][1];
        }
        e.push(ej);
    }
    Some(e)
}

/// Geometric bisection steps of the λ_min(JJᵀ) bracket: from [2⁻⁸⁰, ~1] the ratio of the
/// bracket falls below 2^(80/2¹⁰) < 1.06, so K is certified to within 3 %.
const BISECTION_STEPS: usize = 10;
/// Smallest λ_min(JJᵀ) tried: K ≤ 2⁴⁰. A larger K means a near-singular linearisation (a
/// grazing collision), where the argument is worthless anyway.
const MU_FLOOR_LOG2: i32 = -80;

/// A certified K ≥ ‖J⁺‖₂ = 1/√λ_min(JJᵀ): the largest μ of a geometric bisection for which the
/// LDLᵀ pivots of JJᵀ − μI are positive definite, lowered by an allowance for the rounding of
/// JJᵀ and of the sweep (2^(16−P)·(1 + max‖A_k‖²), Weyl's inequality with a generous backward
/// error of the block sweep). `None` if even μ = 2⁻⁸⁰ fails.
fn inverse_bound(a: &[M2], bits: u32) -> Option<f64> {
    let ok = |mu: f64| pivot_inverses(a, &Float::with_val(bits, mu)).is_some();
    // λ_min ≤ any diagonal entry of JJᵀ (a Rayleigh quotient): 1 + the smallest row norm².
    let hi0 = a
        .iter()
        .map(|x| 1.0 + (x[0].to_f64().powi(2) + x[1].to_f64().powi(2)))
        .fold(f64::INFINITY, f64::min);
    let mut lo = (MU_FLOOR_LOG2 as f64).exp2();
    let mut hi = hi0 * 1.01;
    if !ok(lo) {
        return None;
    }
    for _ in 0..BISECTION_STEPS {
        let mid = (lo * hi).sqrt();
        if ok(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let amax = a.iter().map(m_norm).fold(0.0, f64::max);
    let mu = lo - (16.0 - bits as f64).exp2() * (1.0 + amax * amax);
    (mu > 0.0).then(|| 1.0 / mu.sqrt())
}

/// Defects, Jacobians and the geometry of one evaluation of F along a pseudo-orbit.
struct Evaluation {
    f: Vec<V2>,
    jac: Vec<M2>,
    tau: Vec<Float>,
    /// Smallest cos φ over the collisions and its event.
    cos_min: (f64, usize),
}

/// Evaluates F at `y` on `table` (at the table's precision).
fn evaluate(table: &Table, y: &[OrbitPoint]) -> Result<Evaluation, (usize, StepFailure)> {
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

/// The shadow of one pseudo-orbit: convergence, δ and the ingredients of the proof.
///
/// Norms: a collision point is x = (s, p) ∈ ℝ² with the Euclidean norm (s reduced mod 2π);
/// a segment lives in ℝ^{2N} with the ℓ² norm, F in ℝ^{2(N−1)} likewise.
#[derive(Debug, Clone, Serialize)]
pub struct Shadow {
    /// Collisions N in the segment.
    pub collisions: usize,
    /// Working precision P (bits).
    pub precision_bits: u32,
    /// Newton reached the rounding level (max_k ‖F_k‖ ≤ 2^(24−P)·max(1, 1/cos φ_min)) and the
    /// orbit found is a billiard orbit (no flight passes through another disk).
    pub converged: bool,
    /// Newton corrections applied.
    pub iterations: usize,
    /// δ = max_k ‖x*_k − x⁰_k‖₂ in (s, p) between the shadow and the pseudo-orbit.
    pub delta: Option<f64>,
    /// max_k ‖F_k‖₂ at the last iterate (re-evaluated at 2P bits when converged).
    pub residual: Option<f64>,
    /// ε = ‖F(y*)‖₂ (2P bits) plus the rounding allowance √(N−1)·2^(24−2P)·max(1, 1/cos φ_min).
    pub residual_l2: Option<f64>,
    /// max_k ‖F_k(y⁰)‖₂: the one-step defect of the pseudo-orbit.
    pub pseudo_orbit_defect: Option<f64>,
    /// 2K‖F(y⁰)‖₂: the shadowing lemma's bound on δ (K at y*, an estimate of K at y⁰).
    pub a_priori_bound: Option<f64>,
    /// K ≥ ‖J⁺‖₂ at y*, certified by the inertia of JJᵀ − μI.
    pub inverse_bound: Option<f64>,
    /// 2Kε: an exact orbit lies within this of y* (given the Lipschitz condition below).
    pub correction_bound: Option<f64>,
    /// 1/(4K²ε): the Newton–Kantorovich argument holds if ‖D²T‖ ≤ this on the ball.
    pub lipschitz_allowance: Option<f64>,
    /// Secant estimate of ‖D²T‖: max_k ‖DT(x*_k) − DT(x⁰_k)‖_F / ‖x*_k − x⁰_k‖ (not a bound).
    pub second_derivative_estimate: Option<f64>,
    /// max_k ‖DT(x*_k)‖_F.
    pub max_jacobian_norm: Option<f64>,
    /// Smallest cos φ over the collisions of the last iterate.
    pub min_cos_phi: Option<f64>,
    /// The event of the smallest cos φ.
    pub min_cos_phi_event: Option<usize>,
    /// Smallest distance of a flight of y* from the surface of any other disk.
    pub min_clearance: Option<f64>,
    /// Converged, K certified, 4·(100·M_est)·K²ε ≤ 1, and the ball of radius 2Kε (times
    /// 1 + max‖DT‖) stays away from grazing and from other disks.
    pub certified: bool,
    /// `None`, or why the segment was not shadowed (or not certified).
    pub failure: Option<String>,
    /// The last iterate (the true orbit when converged), at P bits.
    #[serde(skip)]
    pub orbit: Vec<OrbitPoint>,
}

impl Shadow {
    fn failed(n: usize, bits: u32, iterations: usize, y: Vec<OrbitPoint>, why: String) -> Self {
        Shadow {
            collisions: n,
            precision_bits: bits,
            converged: false,
            iterations,
            delta: None,
            residual: None,
            residual_l2: None,
            pseudo_orbit_defect: None,
            a_priori_bound: None,
            inverse_bound: None,
            correction_bound: None,
            lipschitz_allowance: None,
            second_derivative_estimate: None,
            max_jacobian_norm: None,
            min_cos_phi: None,
            min_cos_phi_event: None,
            min_clearance: None,
            certified: false,
            failure: Some(why),
            orbit: y,
        }
    }
}

fn describe(k: usize, e: &StepFailure, y: &[OrbitPoint]) -> String {
    match e {
        StepFailure::Grazing(c) => format!(
            "grazing collision at event {k}: cos phi = {:.3e} (|sin phi| = {:.17}; the map's derivative grows like 1/cos phi)",
            c.to_f64(),
            y[k].p.to_f64().abs()
        ),
        StepFailure::Miss => format!(
            "the flight from event {k} misses the recorded disk ({}, {}): a near-tangent flight, the f64 disk sequence has no true orbit within reach",
            y[k + 1].disk[0],
            y[k + 1].disk[1]
        ),
    }
}

/// The public form of the defects: max-free list of ‖F_k(y)‖₂ for k = 0 … N−2 on the table of
/// `scene` at `bits` (the points are taken exactly if their precision is ≤ `bits`).
///
/// # Errors
/// If `y` has fewer than 2 points, or a step grazes or misses its recorded disk.
pub fn defects<S: Scene>(scene: &S, y: &[OrbitPoint], bits: u32) -> Result<Vec<f64>, Error> {
    if y.len() < 2 {
        return Err(Error::TooFew {
            what: "collisions",
            min: 2,
            got: y.len() as u64,
        });
    }
    let table = Table::new(scene, bits)?;
    let ev = evaluate(&table, y).map_err(|(k, e)| Error::Invalid(describe(k, &e, y)))?;
    Ok(ev.f.iter().map(|v| norm2(v).to_f64()).collect())
}

/// Smallest clearance (distance − r) of the flights of `y` from every disk other than their
/// endpoints' disks, and the first flight that passes through one (k, disk, clearance).
fn clearance(
    table: &Table,
    y: &[OrbitPoint],
    tau: &[Float],
) -> (f64, Option<(usize, [i64; 2], f64)>) {
    let (a, beta, h, r) = (
        table.a.to_f64(),
        table.beta.to_f64(),
        table.h.to_f64(),
        table.r.to_f64(),
    );
    let mut min = f64::INFINITY;
    for k in 0..y.len() - 1 {
        let Ok((x0, v)) = table.phase(&y[k]) else {
            continue;
        };
        let x1 = x0.along(&tau[k], &v);
        let (p0, p1) = (x0.to_f64(), x1.to_f64());
        let (xmin, xmax) = (p0[0].min(p1[0]) - r, p0[0].max(p1[0]) + r);
        let (ymin, ymax) = (p0[1].min(p1[1]) - r, p0[1].max(p1[1]) + r);
        let (j0, j1) = ((ymin / h).floor() as i64 - 1, (ymax / h).ceil() as i64 + 1);
        for j in j0..=j1 {
            let sh = beta * j as f64;
            let (i0, i1) = (
                (xmin / a - sh).floor() as i64 - 1,
                (xmax / a - sh).ceil() as i64 + 1,
            );
            for i in i0..=i1 {
                let d = [i, j];
                if d == y[k].disk || d == y[k + 1].disk {
                    continue;
                }
                let c = table.centre(d);
                let rel = c.sub(&x0);
                let mut u = rel.dot(&v);
                if u.is_sign_negative() {
                    u = Float::with_val(table.bits, 0);
                } else if u > tau[k] {
                    u = tau[k].clone();
                }
                let q = x0.along(&u, &v);
                let gap = c.sub(&q).norm2().sqrt() - &table.r;
                let g = gap.to_f64();
                if g <= 0.0 {
                    return (g.min(min), Some((k, d, g)));
                }
                min = min.min(g);
            }
        }
    }
    (min, None)
}

/// Shadows the pseudo-orbit `orbit` (N ≥ 2 collision points with their disks) by a true orbit of
/// `scene` with the same disk sequence, at `bits` ≥ [`MIN_SHADOW_BITS`] of precision.
///
/// A pseudo-orbit that cannot be shadowed (grazing, a missed or blocked flight, no convergence)
/// is an `Ok` with `converged = false` and the reason in `failure`.
///
/// # Errors
/// If N < 2, N > [`MAX_COLLISIONS`], or `bits` is outside [[`MIN_SHADOW_BITS`], [`MAX_SHADOW_BITS`]].
pub fn shadow_pseudo_orbit<S: Scene>(
    scene: &S,
    orbit: &[OrbitPoint],
    bits: u32,
) -> Result<Shadow, Error> {
    check_request(orbit.len(), bits)?;
    let n = orbit.len();
    let table = Table::new(scene, bits)?;
    let lift = |x: &OrbitPoint| OrbitPoint {
        disk: x.disk,
        s: Float::with_val(bits, &x.s),
        p: Float::with_val(bits, &x.p),
    };
    let y0: Vec<OrbitPoint> = orbit.iter().map(lift).collect();
    let mut y = y0.clone();
    let Converged {
        first,
        last,
        iterations,
    } = match newton(&table, &mut y, bits) {
        Ok(c) => c,
        Err((iterations, why)) => return Ok(Shadow::failed(n, bits, iterations, y, why)),
    };
    let mut sh = Shadow::failed(n, bits, iterations, Vec::new(), String::new());
    sh.failure = None;
    sh.converged = true;
    // The defect at twice the precision (the points are exact at 2P).
    let table2 = Table::new(scene, 2 * bits)?;
    let ev2 = match evaluate(&table2, &y) {
        Ok(ev) => ev,
        Err((k, e)) => {
            let why = describe(k, &e, &y);
            return Ok(Shadow::failed(n, bits, iterations, y, why));
        }
    };
    let (eps, f0_l2) = record_defects(&mut sh, &ev2, &first, &last, bits);
    let m_est = record_distance(&mut sh, &y, &y0, &first, &last, bits);
    let amax = last.jac.iter().map(m_norm).fold(0.0, f64::max);
    sh.max_jacobian_norm = Some(amax);
    sh.min_cos_phi = Some(last.cos_min.0);
    sh.min_cos_phi_event = Some(last.cos_min.1);
    let (gap, blocked) = clearance(&table, &y, &last.tau);
    sh.min_clearance = Some(gap);
    if let Some((k, d, g)) = blocked {
        sh.converged = false;
        sh.failure = Some(format!(
            "the flight from event {k} passes through disk ({}, {}) (clearance {g:.3e}): a near-tangent flight past a second disk, the f64 disk sequence is not that of a true orbit",
            d[0], d[1]
        ));
        sh.orbit = y;
        return Ok(sh);
    }
    let estimates = Estimates {
        eps,
        f0_l2,
        m_est,
        amax,
        gap,
    };
    certify(&mut sh, &last, bits, &estimates);
    sh.orbit = y;
    Ok(sh)
}

/// Newton's method converged: the first and the last evaluation, and the iterations taken.
struct Converged {
    first: Evaluation,
    last: Evaluation,
    iterations: usize,
}

/// Newton's method on `y` (minimum-norm corrections) until the defect is within the tolerance
/// at `bits`; on failure, the iterations done and the reason.
fn newton(table: &Table, y: &mut [OrbitPoint], bits: u32) -> Result<Converged, (usize, String)> {
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
fn record_defects(
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
fn record_distance(
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
struct Estimates {
    eps: f64,
    f0_l2: f64,
    m_est: f64,
    amax: f64,
    gap: f64,
}

/// The Newton–Kantorovich certificate from the bound K on ‖J⁺‖ at the converged orbit (`last`),
/// or the reason there is none.
fn certify(sh: &mut Shadow, last: &Evaluation, bits: u32, est: &Estimates) {
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

/// Refuses a segment length or precision outside the supported ranges, naming them.
pub fn check_request(n: usize, bits: u32) -> Result<(), Error> {
    if !(2..=MAX_COLLISIONS).contains(&n) {
        return Err(Error::Invalid(format!(
            "collisions = {n} is out of range: use 2 to {MAX_COLLISIONS} (a segment needs one step; longer segments: split them)"
        )));
    }
    if !(MIN_SHADOW_BITS..=MAX_SHADOW_BITS).contains(&bits) {
        return Err(Error::Invalid(format!(
            "precision = {bits} bits is out of range: use {MIN_SHADOW_BITS} to {MAX_SHADOW_BITS}"
        )));
    }
    Ok(())
}

/// Most events run by [`f64_segment`] per collision recorded before it gives up (a finite-horizon
/// table has a collision every few events).
const EVENTS_PER_COLLISION: usize = 1000;

/// The first `n` collisions of the `f64` orbit from `start`, as Birkhoff points at `bits`: the
/// disk's lattice indices from the f64 world centre (rounded to the lattice, checked to 10⁻⁶),
/// s and p from the f64 contact point and velocity lifted exactly and the disk centre at `bits`
/// (so the points are the f64 states projected to the exact table's phase space).
///
/// # Errors
/// If a collision's disk is not a lattice point, or `n` collisions take more than 1000n events.
pub fn f64_segment<S: Scene>(
    scene: &S,
    start: &LatticeState<f64>,
    n: usize,
    bits: u32,
) -> Result<Vec<OrbitPoint>, Error> {
    let lat = scene.lattice::<f64>(())?;
    let latp = scene.lattice::<Float>(bits)?;
    let basis = &lat.cell().lattice;
    let mut st = start.clone();
    let mut out = Vec::with_capacity(n);
    let mut events = 0usize;
    while out.len() < n {
        let ev = lat.step(&mut st)?;
        events += 1;
        if events > EVENTS_PER_COLLISION * (n + 1) {
            return Err(Error::Invalid(format!(
                "no collision in {events} events: the table has an open corridor"
            )));
        }
        let EventKind::Collision(m) = ev.kind else {
            continue;
        };
        let f = &st.flight;
        let c64 = &lat.cell().disks[m as usize];
        let cw = lat.world(&LatticeState {
            cell: st.cell,
            flight: crate::kernel::flight::Flight::new(c64.clone(), f.vel.clone()),
        });
        let j = (cw.y / basis.h).round();
        let i = (cw.x / basis.a - basis.beta * j).round();
        let (ex, ey) = (basis.a * (i + basis.beta * j) - cw.x, basis.h * j - cw.y);
        if ex.hypot(ey) > 1e-6 * (1.0 + cw.x.abs() + cw.y.abs()) {
            return Err(Error::Invalid(format!(
                "disk centre ({}, {}) is not a lattice point",
                cw.x, cw.y
            )));
        }
        let cp = &latp.cell().disks[m as usize];
        let mut nx = Float::with_val(bits, f.pos.x) - &cp.x;
        let mut ny = Float::with_val(bits, f.pos.y) - &cp.y;
        let (vx, vy) = (
            Float::with_val(bits, f.vel.x),
            Float::with_val(bits, f.vel.y),
        );
        let norm = (nx.clone().square() + &ny.clone().square()).sqrt()
            * &(vx.clone().square() + &vy.clone().square()).sqrt();
        // n × v is invariant under the frame's point reflection (both flip); θ is not.
        let p = (nx.clone() * &vy - &(ny.clone() * &vx)) / &norm;
        if st.cell.down {
            nx = -nx;
            ny = -ny;
        }
        let s = Float::with_val(bits, ny.atan2_ref(&nx));
        out.push(OrbitPoint {
            disk: [i as i64, j as i64],
            s,
            p,
        });
    }
    Ok(out)
}

/// Most segments per run: each keeps its result (and, while it runs, its orbit) in memory.
pub const MAX_SEGMENTS: u32 = 10_000;

/// One shadowed segment of a seeded run.
#[derive(Debug, Clone, Serialize)]
pub struct SegmentShadow {
    /// Segment index k: its start is the equilibrium state of `sampling::stream(seed, k)` (the
    /// start of batch k of `lorentz diffusion --seed SEED`), run to its first collision.
    pub segment: u32,
    /// The seed.
    pub start_seed: u64,
    /// The shadow.
    #[serde(flatten)]
    pub shadow: Shadow,
}

/// Shadows of `segments` seeded segments, with a summary.
#[derive(Debug, Clone, Serialize)]
pub struct ShadowReport {
    /// The scene ([`Scene::label`]).
    pub scene: String,
    /// Segments that converged.
    pub converged: u32,
    /// Segments whose shadow is certified (see [`Shadow::certified`]).
    pub certified: u32,
    /// What was run: collisions per segment, segments, seed, working precision.
    pub config: ShadowConfig,
    /// Median δ over the converged segments.
    pub median_delta: Option<f64>,
    /// Largest δ over the converged segments.
    pub max_delta: Option<f64>,
    /// The segments, in order.
    pub segments: Vec<SegmentShadow>,
    /// Version, seed, segments, precision, threads, command line.
    pub meta: RunMeta,
}

/// What [`run`] is asked for.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ShadowConfig {
    /// Collisions N of each segment, 2 to [`MAX_COLLISIONS`].
    pub collisions_per_segment: usize,
    /// Segments, 1 to [`MAX_SEGMENTS`].
    pub segments: u32,
    /// Seed of the start streams.
    pub seed: u64,
    /// MPFR working precision P of the true orbit (bits), [`MIN_SHADOW_BITS`] to
    /// [`MAX_SHADOW_BITS`].
    pub reference_bits: u32,
}

/// Shadows `segments` segments of `collisions_per_segment` collisions each; segment k starts from the
/// equilibrium state of stream (seed, k). The result does not depend on `options.threads`;
/// `options.progress` receives collision counts.
///
/// # Errors
/// If a parameter is out of range ([`check_request`], 1 ≤ segments ≤ [`MAX_SEGMENTS`]).
pub fn run<S: Scene>(
    scene: &S,
    request: &ShadowConfig,
    options: &RunOptions,
) -> Result<ShadowReport, Error> {
    options.validate()?;
    let (threads, progress) = (options.threads, options.progress);
    let &ShadowConfig {
        collisions_per_segment: collisions,
        segments,
        seed,
        reference_bits: bits,
    } = request;
    check_request(collisions, bits)?;
    if !(1..=MAX_SEGMENTS).contains(&segments) {
        return Err(Error::Invalid(format!(
            "segments = {segments} is out of range: use 1 to {MAX_SEGMENTS}"
        )));
    }
    let out = par_batches(threads, segments, |k| {
        let start = scene.sample(&mut stream(seed, k as u64));
        let orbit = f64_segment(scene, &start, collisions, bits)?;
        let mut shadow = shadow_pseudo_orbit(scene, &orbit, bits)?;
        shadow.orbit = Vec::new();
        progress(collisions as u64);
        Ok(SegmentShadow {
            segment: k,
            start_seed: seed,
            shadow,
        })
    })?;
    let mut deltas: Vec<f64> = out
        .iter()
        .filter(|s| s.shadow.converged)
        .filter_map(|s| s.shadow.delta)
        .collect();
    deltas.sort_by(f64::total_cmp);
    let median_delta = (!deltas.is_empty()).then(|| {
        let m = deltas.len();
        if m % 2 == 1 {
            deltas[m / 2]
        } else {
            0.5 * (deltas[m / 2 - 1] + deltas[m / 2])
        }
    });
    Ok(ShadowReport {
        scene: scene.label(),
        config: *request,
        converged: out.iter().filter(|s| s.shadow.converged).count() as u32,
        certified: out.iter().filter(|s| s.shadow.certified).count() as u32,
        median_delta,
        max_delta: deltas.last().copied(),
        segments: out,
        meta: RunMeta::new(Some(seed), Some(segments as u64), bits, Some(threads)),
    })
}
