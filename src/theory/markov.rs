//! Exact diffusion coefficient of the order-k correlated random walk on the honeycomb
//! (the lattice gas of Fig. 6b), by linear algebra on the chain of symbol histories.
//!
//! # The walk
//!
//! The next exit symbol s is drawn from p(s | h), h = the previous k − 1 symbols (k = 1:
//! memoryless, p(z) = p_bs, p(l) = p(r) = (1 − p_bs)/2). From a table of sequence
//! probabilities of length k, p(s | h) = p(h s)/p(h) with p(h) = Σ_s p(h s); a history with
//! p(h) = 0 is completed with p(s | h) = 1/3 (for a table measured along a trajectory such a
//! history has stationary weight 0 and the completion does not change D).
//!
//! # D in closed form (`proofs-notes/markov-walk.md`)
//!
//! Write the hop directions as complex numbers: dᵢ₊₁ = ω(sᵢ₊₁) dᵢ with ω(z) = −1,
//! ω(l) = e^{−iπ/3}, ω(r) = e^{+iπ/3}. Then dᵢ·dᵢ₊ⱼ = Re Π ω(s), and in the stationary chain
//!
//! C_j = ⟨d̂₀·d̂_j⟩ = Re πᵀ Qʲ 𝟙,  Q(h, h') = p(s | h) ω(s)  (h' = h shifted by s),
//!
//! with π the stationary distribution of the histories. The Einstein/Green–Kubo sum is the
//! resolvent
//!
//! D = (l²/(4τ))·[1 + 2 Σ_{j≥1} C_j] = D_MZ·[1 + 2 Re πᵀ (I − Q)⁻¹ Q 𝟙],
//!
//! exact whenever I − Q is invertible (Cesàro sum when Q has eigenvalues on the unit circle
//! other than 1; I − Q singular means a ballistic component and D = ∞).
//!
//! For k = 1, Q is the number c = −p_bs + (1 − p_bs)/2 = (1 − 3p_bs)/2 and
//! D = D_MZ (1 + c)/(1 − c) = D_MZ·3(1 − p_bs)/(1 + 3p_bs) ([`persistent_d_over_d_mz`]).

use nalgebra::{Complex, DMatrix, DVector};

use crate::Error;
use crate::numbers::real::Real;
use crate::scenes::triangular::geometry::Geometry;

use super::sequences::SequenceProbabilities;
use crate::scenes::symbols::{Symbol, sequence_from_index, sequence_index, word};

/// Correlation of successive hop directions of the memoryless walk,
/// c = ⟨d̂ᵢ·d̂ᵢ₊₁⟩ = p_bs·(−1) + (1 − p_bs)·cos 60° = (1 − 3p_bs)/2.
pub fn persistent_correlation<T: Real>(p_bs: &T) -> T {
    (T::one(p_bs.ctx()) - &p_bs.clone().scale(3.0)).scale(0.5)
}

/// Exact D/D_MZ of the memoryless walk: (1 + c)/(1 − c) = 3(1 − p_bs)/(1 + 3p_bs)
/// (C_j = cʲ, 1 + 2Σcʲ = (1 + c)/(1 − c)).
///
/// # Examples
///
/// ```
/// use lorentz_gas::theory::markov::persistent_d_over_d_mz;
/// assert_eq!(persistent_d_over_d_mz(&(1.0f64 / 3.0)), 1.0);
/// assert_eq!(persistent_d_over_d_mz(&0.0f64), 3.0);
/// assert_eq!(persistent_d_over_d_mz(&1.0f64), 0.0);
/// ```
pub fn persistent_d_over_d_mz<T: Real>(p_bs: &T) -> T {
    let one = T::one(p_bs.ctx());
    (one.clone() - p_bs).scale(3.0) / &p_bs.clone().scale(3.0).add_f64(1.0)
}

/// ω(s) as an exact-as-possible complex number: −1, ½ − i√3/2, ½ + i√3/2.
fn omega(s: Symbol) -> Complex<f64> {
    let h = 3f64.sqrt() / 2.0;
    match s {
        Symbol::Z => Complex::new(-1.0, 0.0),
        Symbol::L => Complex::new(0.5, -h),
        Symbol::R => Complex::new(0.5, h),
    }
}

/// The order-k correlated walk: conditional exit probabilities on the 3^(k−1) histories and
/// their stationary distribution.
#[derive(Debug, Clone, PartialEq)]
pub struct CorrelatedWalk {
    k: usize,
    cond: Vec<[f64; 3]>,
    stationary: Vec<f64>,
}

impl CorrelatedWalk {
    /// Largest order accepted: the crate's one limit [`crate::scenes::symbols::MAX_ORDER`]
    /// (3⁶ = 729 histories, a dense complex LU).
    pub const MAX_ORDER: usize = crate::scenes::symbols::MAX_ORDER;

    /// The walk whose sequences of length k have the probabilities `p` (k = `p.len()`).
    pub fn new(p: &SequenceProbabilities) -> Result<Self, Error> {
        let k = p.len();
        Self::check_order(k)?;
        let cond = p
            .probabilities()
            .chunks(3)
            .map(|c| {
                let s = c[0] + c[1] + c[2];
                if s > 0.0 {
                    [c[0] / s, c[1] / s, c[2] / s]
                } else {
                    [1.0 / 3.0; 3]
                }
            })
            .collect();
        Self::from_conditionals(k, cond)
    }

    /// The memoryless walk (k = 1) with backscattering probability `p_bs`.
    pub fn memoryless(p_bs: f64) -> Result<Self, Error> {
        Self::new(&SequenceProbabilities::memoryless(1, p_bs)?)
    }

    /// The walk of order k from p(s | h) given for each of the 3^(k−1) histories h in
    /// [`crate::scenes::symbols::sequence_index`] order, as `[p(z|h), p(l|h), p(r|h)]`. Each row must
    /// be finite, ≥ 0 and sum to 1 within 4u.
    pub fn from_conditionals(k: usize, cond: Vec<[f64; 3]>) -> Result<Self, Error> {
        Self::check_order(k)?;
        let n = 3usize.pow(k as u32 - 1);
        if cond.len() != n {
            return Err(Error::parameter(
                "cond",
                format!("{} rows", cond.len()),
                format!(
                    "an order-{k} walk needs conditional probabilities for 3^{} = {n} histories",
                    k - 1
                ),
            ));
        }
        for (h, row) in cond.iter().enumerate() {
            let hist = word(&sequence_from_index(k - 1, h));
            if row.iter().any(|x| !x.is_finite() || *x < 0.0) {
                return Err(Error::parameter(
                    "cond",
                    format!("p(·|\"{hist}\") = {row:?}"),
                    "conditional probabilities must be finite and ≥ 0",
                ));
            }
            // A row given as three correctly rounded values sums to 1 within 3u (+u for the sum).
            let s = row[0] + row[1] + row[2];
            if (s - 1.0).abs() > 4.0 * f64::EPSILON / 2.0 {
                return Err(Error::parameter(
                    "cond",
                    format!("p(·|\"{hist}\") = {row:?}"),
                    format!("sums to {s}, not 1"),
                ));
            }
        }
        let stationary = stationary_distribution(k, &cond)?;
        Ok(CorrelatedWalk {
            k,
            cond,
            stationary,
        })
    }

    fn check_order(k: usize) -> Result<(), Error> {
        crate::scenes::symbols::check_order("order", k)
    }

    /// The order k (sequences of length k, memory of k − 1 symbols).
    pub fn order(&self) -> usize {
        self.k
    }

    /// Number of histories, 3^(k−1).
    pub fn histories(&self) -> usize {
        self.cond.len()
    }

    /// `[p(z|h), p(l|h), p(r|h)]` for history index `h`.
    pub fn conditional(&self, h: usize) -> [f64; 3] {
        self.cond[h]
    }

    /// The history index after symbol `s` follows history `h`: (3h + s) mod 3^(k−1).
    pub fn next_history(&self, h: usize, s: Symbol) -> usize {
        (3 * h + s.index()) % self.cond.len()
    }

    /// The stationary distribution π of the histories.
    pub fn stationary(&self) -> &[f64] {
        &self.stationary
    }

    /// The stationary probabilities of all sequences of length `len`:
    /// p(s₁…s_len) = π(s₁…s_{k−1}) Π_{i≥k} p(sᵢ | sᵢ₋ₖ₊₁…sᵢ₋₁), marginalised if len < k − 1.
    pub fn sequence_probabilities(&self, len: usize) -> Result<SequenceProbabilities, Error> {
        let m = self.k - 1;
        let full = len.max(m).max(1);
        if full > SequenceProbabilities::MAX_LEN {
            return Err(Error::out_of_range(
                "len",
                len,
                format!(
                    "use at most {} (the longer of it and the order's histories)",
                    SequenceProbabilities::MAX_LEN
                ),
            ));
        }
        let nh = self.cond.len();
        let w: Vec<f64> = (0..3usize.pow(full as u32))
            .map(|i| {
                let s = sequence_from_index(full, i);
                let h0 = sequence_index(&s[..m]);
                let mut x = self.stationary[h0];
                let mut h = h0;
                for &sym in &s[m..] {
                    x *= self.cond[h][sym.index()];
                    h = (3 * h + sym.index()) % nh;
                }
                x
            })
            .collect();
        let t = SequenceProbabilities::from_weights(full, w)?;
        if len < full {
            t.prefix_marginal(len)
        } else {
            Ok(t)
        }
    }

    fn q_matrix(&self) -> (DMatrix<Complex<f64>>, DVector<Complex<f64>>) {
        let n = self.cond.len();
        let mut q = DMatrix::from_element(n, n, Complex::new(0.0, 0.0));
        let mut q1 = DVector::from_element(n, Complex::new(0.0, 0.0));
        for h in 0..n {
            for s in Symbol::ALL {
                let x = omega(s) * self.cond[h][s.index()];
                q[(h, self.next_history(h, s))] += x;
                q1[h] += x;
            }
        }
        (q, q1)
    }

    /// The exact hop correlations C_j = ⟨d̂₀·d̂_j⟩ = Re πᵀQʲ𝟙 for j = 1..=j_max.
    pub fn correlations(&self, j_max: usize) -> Vec<f64> {
        let (q, _) = self.q_matrix();
        let pi = DVector::from_iterator(
            self.stationary.len(),
            self.stationary.iter().map(|&x| Complex::new(x, 0.0)),
        );
        let mut v = DVector::from_element(self.cond.len(), Complex::new(1.0, 0.0));
        (0..j_max)
            .map(|_| {
                v = &q * &v;
                pi.dot(&v).re
            })
            .collect()
    }

    /// The exact D/D_MZ = 1 + 2 Re πᵀ(I − Q)⁻¹Q𝟙.
    ///
    /// Errors when I − Q is singular or so ill-conditioned that the result exceeds
    /// 10⁻³/u ≈ 9·10¹² (its relative error bound κ(I − Q)·u would exceed 10⁻³): the walk has
    /// a ballistic component and D = ∞.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::theory::markov::CorrelatedWalk;
    /// let w = CorrelatedWalk::memoryless(1.0 / 3.0).unwrap();
    /// assert_eq!(w.d_over_d_mz().unwrap(), 1.0);
    /// ```
    pub fn d_over_d_mz(&self) -> Result<f64, Error> {
        let n = self.cond.len();
        let (q, q1) = self.q_matrix();
        let a = DMatrix::<Complex<f64>>::identity(n, n) - q;
        let ballistic = || {
            Error::Failed(format!(
                "the order-{} walk has a ballistic component (I − Q is singular): D is infinite",
                self.k
            ))
        };
        let y = a.lu().solve(&q1).ok_or_else(ballistic)?;
        let mut s = 0.0;
        for (p, yi) in self.stationary.iter().zip(y.iter()) {
            s += p * yi.re;
        }
        let d = 1.0 + 2.0 * s;
        if !d.is_finite() || d.abs() > 1e-3 / (f64::EPSILON / 2.0) {
            return Err(ballistic());
        }
        Ok(d)
    }

    /// The exact D = D_MZ(w)·[`CorrelatedWalk::d_over_d_mz`].
    pub fn d(&self, g: &Geometry<f64>) -> Result<f64, Error> {
        Ok(self.d_over_d_mz()? * g.d_mz())
    }
}

/// Stationary distribution of the history chain: solve (Pᵀ − I)π = 0 with the last equation
/// replaced by Σπ = 1 (LU). Errors when the solution is not unique (reducible chain with
/// several closed classes) — detected by a failed LU or a residual above the LU backward error
/// model 64·n·u, or a negative weight beyond it.
fn stationary_distribution(k: usize, cond: &[[f64; 3]]) -> Result<Vec<f64>, Error> {
    let n = cond.len();
    if n == 1 {
        return Ok(vec![1.0]);
    }
    let mut pt = DMatrix::<f64>::zeros(n, n);
    for h in 0..n {
        for s in 0..3 {
            pt[((3 * h + s) % n, h)] += cond[h][s];
        }
    }
    let mut a = pt.clone() - DMatrix::<f64>::identity(n, n);
    for j in 0..n {
        a[(n - 1, j)] = 1.0;
    }
    let mut b = DVector::<f64>::zeros(n);
    b[n - 1] = 1.0;
    let not_unique = || {
        Error::Failed(format!(
            "the chain of order-{k} symbol histories has no unique stationary distribution \
             (it is reducible): D depends on the initial history"
        ))
    };
    let pi = a.lu().solve(&b).ok_or_else(not_unique)?;
    let tol = 64.0 * n as f64 * f64::EPSILON / 2.0;
    let res = (&pt * &pi - &pi).amax();
    if !pi.iter().all(|x| x.is_finite() && *x >= -tol) || res > tol {
        return Err(not_unique());
    }
    let v: Vec<f64> = pi.iter().map(|&x| x.max(0.0)).collect();
    let s: f64 = v.iter().sum();
    Ok(v.into_iter().map(|x| x / s).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::theory::hierarchy::d_k;

    /// A mirror-symmetric order-2 table: p(·|z), p(·|l), p(·|r).
    pub(crate) fn order2() -> CorrelatedWalk {
        CorrelatedWalk::from_conditionals(
            2,
            vec![[0.5, 0.25, 0.25], [0.3, 0.2, 0.5], [0.3, 0.5, 0.2]],
        )
        .unwrap()
    }

    #[test]
    fn memoryless_one_third_is_machta_zwanzig() {
        // c = −fl(1/3) + 2·½fl(1/3) = 0 exactly in f64, so D/D_MZ = 1 exactly.
        let w = CorrelatedWalk::memoryless(1.0 / 3.0).unwrap();
        assert_eq!(w.d_over_d_mz().unwrap(), 1.0);
        // The same walk written as order 3 (27 sequences of probability 1/27): LU on 9 states,
        // error ≤ 64·n·u·κ with κ(I − Q) ≤ 2/(1 − |c|)… here c = 0: within 1e-14.
        let p = SequenceProbabilities::memoryless(3, 1.0 / 3.0).unwrap();
        let d = CorrelatedWalk::new(&p).unwrap().d_over_d_mz().unwrap();
        assert!((d - 1.0).abs() < 1e-14, "{d}");
    }

    #[test]
    fn persistent_walk_closed_form() {
        // k = 1: a 1×1 complex solve, ≤ 8 roundings on numbers of size ≤ (1+c)/(1−c):
        // relative error ≤ 16u·(1 + |c|)/(1 − |c|) (condition of 1/(1 − c)).
        for &p in &[0.0, 0.1, 0.25, 0.38, 0.5, 0.9] {
            let d = CorrelatedWalk::memoryless(p)
                .unwrap()
                .d_over_d_mz()
                .unwrap();
            let exact = persistent_d_over_d_mz(&p);
            let c: f64 = persistent_correlation(&p);
            let tol = 16.0 * f64::EPSILON / 2.0 * (1.0 + c.abs()) / (1.0 - c.abs()) * exact;
            assert!((d - exact).abs() <= tol, "p = {p}: {d} vs {exact}");
        }
        // p_bs = 0.38: D/D_MZ = 3·0.62/2.14 = 0.86915887850467289…
        assert!((persistent_d_over_d_mz(&0.38f64) - 1.86 / 2.14).abs() < 4.0 * f64::EPSILON);
    }

    #[test]
    fn correlations_of_the_persistent_walk_are_geometric() {
        let p = 0.38;
        let c: f64 = persistent_correlation(&p);
        let cs = CorrelatedWalk::memoryless(p).unwrap().correlations(10);
        for (j, &cj) in cs.iter().enumerate() {
            let e = c.powi(j as i32 + 1);
            assert!((cj - e).abs() <= 8.0 * (j as f64 + 1.0) * f64::EPSILON / 2.0);
        }
    }

    #[test]
    fn degenerate_walks() {
        // Always z: the particle rattles between two traps, D = 0 (Cesàro sum of (−1)^j).
        let z = CorrelatedWalk::memoryless(1.0).unwrap();
        assert!(z.d_over_d_mz().unwrap().abs() < 4.0 * f64::EPSILON);
        // Always l: the particle circles one hexagon, D = 0 (q = e^{−iπ/3}, Re q/(1 − q) = −½).
        let l = CorrelatedWalk::from_conditionals(1, vec![[0.0, 1.0, 0.0]]).unwrap();
        assert!(l.d_over_d_mz().unwrap().abs() < 8.0 * f64::EPSILON);
        // l, r alternating (order 2): a ballistic zig-zag, D = ∞ is reported as an error.
        let zig = CorrelatedWalk::from_conditionals(
            2,
            vec![[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
        )
        .unwrap();
        let e = zig.d_over_d_mz().unwrap_err().to_string();
        assert!(e.contains("ballistic"), "{e}");
    }

    #[test]
    fn input_validation() {
        assert!(CorrelatedWalk::from_conditionals(2, vec![[1.0, 0.0, 0.0]; 2]).is_err());
        let e = CorrelatedWalk::from_conditionals(2, vec![[0.5, 0.5, 0.5]; 3]).unwrap_err();
        assert!(e.to_string().contains("sums to"), "{e}");
        assert!(CorrelatedWalk::from_conditionals(1, vec![[1.5, -0.5, 0.0]]).is_err());
        assert!(CorrelatedWalk::from_conditionals(9, vec![]).is_err());
        // Two closed classes (z-forever and l-forever): no unique stationary distribution.
        let e = CorrelatedWalk::from_conditionals(
            2,
            vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]],
        )
        .unwrap_err();
        assert!(e.to_string().contains("stationary"), "{e}");
    }

    #[test]
    fn a_product_table_is_the_memoryless_walk() {
        // Order-3 table p(s₁)p(s₂)p(s₃): the 9-state chain reproduces 3(1−p)/(1+3p).
        // LU error ≤ 64·n·u·κ; κ(I − Q) ≤ ‖I − Q‖‖(I − Q)⁻¹‖ ≤ 2/(1 − |c|) for this chain.
        let p = 0.38;
        let t = SequenceProbabilities::memoryless(3, p).unwrap();
        let d = CorrelatedWalk::new(&t).unwrap().d_over_d_mz().unwrap();
        let c: f64 = persistent_correlation(&p);
        let tol = 64.0 * 9.0 * f64::EPSILON / 2.0 * 2.0 / (1.0 - c.abs());
        assert!((d - persistent_d_over_d_mz(&p)).abs() <= tol, "{d}");
    }

    #[test]
    fn stationary_tables_round_trip() {
        // The walk rebuilt from its own length-2 table is the same walk.
        let w = order2();
        let t = w.sequence_probabilities(2).unwrap();
        let w2 = CorrelatedWalk::new(&t).unwrap();
        for h in 0..3 {
            for s in 0..3 {
                assert!((w.conditional(h)[s] - w2.conditional(h)[s]).abs() < 1e-15);
            }
        }
        // Stationarity of π: p(z) = Σ_h π(h) p(z|h).
        let pi = w.stationary();
        let pz: f64 = (0..3).map(|h| pi[h] * w.conditional(h)[0]).sum();
        assert!((pz - pi[0]).abs() < 1e-15);
        // Mirror symmetry of the table ⇒ π(l) = π(r).
        assert!((pi[1] - pi[2]).abs() < 1e-15);
    }

    #[test]
    fn order2_exact_value_by_hand() {
        // Hand solution in proofs-notes/markov-walk.md for p(·|z) = (½, ¼, ¼),
        // p(·|l) = (0.3, 0.2, 0.5), p(·|r) = (0.3, 0.5, 0.2).
        // Both are backward-stable 3×3 solves: |Δ| ≤ 2·64·n·u·κ·max(1, |D|), κ of the
        // real 3×3 system from its singular values.
        let d = order2().d_over_d_mz().unwrap();
        let (ex, kappa) = order2_by_hand();
        let tol = 2.0 * 64.0 * 3.0 * f64::EPSILON / 2.0 * kappa * ex.abs().max(1.0);
        assert!((d - ex).abs() <= tol, "{d} vs {ex} (tol {tol:e})");
        assert!(kappa < 10.0);
    }

    /// The same resolvent written out by hand for a mirror-symmetric order-2 chain with
    /// p(·|z) = (a, b, b), p(·|l) = (c, e, f), p(·|r) = (c, f, e): returns (D/D_MZ, κ) with κ
    /// the 2-norm condition number of the reduced real system.
    fn order2_by_hand() -> (f64, f64) {
        let (a, b, c, e, f) = (0.5, 0.25, 0.3, 0.2, 0.5);
        // Stationary: π_z = c/(1 − a + c) (flow into z = flow out), π_l = π_r = (1 − π_z)/2.
        let pz = c / (1.0 - a + c);
        let pl = (1.0 - pz) / 2.0;
        // By symmetry y_r = conj(y_l); unknowns y_z (real) and y_l = u + iv.
        // y_h = q_h + Σ_s p(s|h) ω(s) y_{s}:  with ω_l = ½ − i√3/2, ω_r = conj.
        let h = 3f64.sqrt() / 2.0;
        // Solve with nalgebra as a 3×3 real system in (y_z, u, v).
        // y_z = −a + b + (−a) y_z + 2b Re(ω_l y_l)
        // y_l = q_l + c(−1) y_z + e ω_l y_l + f ω_r conj(y_l)
        // q_l = −c + e ω_l + f ω_r.
        // Re(ω_l y_l) = ½u + h v;  ω_l y_l = (½u + h v) + i(½v − h u);
        // ω_r conj(y_l) = (½ + ih)(u − iv) = (½u + h v) + i(h u − ½v).
        let m = nalgebra::Matrix3::new(
            1.0 + a,
            -b,
            -2.0 * b * h,
            c,
            1.0 - (e + f) * 0.5,
            -(e + f) * h,
            0.0,
            (e - f) * h,
            1.0 - (e - f) * 0.5,
        );
        let rhs = nalgebra::Vector3::new(-a + b, -c + (e + f) * 0.5, -(e - f) * h);
        let y = m.lu().solve(&rhs).unwrap();
        let s = pz * y[0] + 2.0 * pl * y[1];
        let sv = m.singular_values();
        (1.0 + 2.0 * s, sv.max() / sv.min())
    }

    #[test]
    fn hierarchy_converges_to_the_exact_walk() {
        // D_k of the walk's own length-k table: for the memoryless walk
        // D_k/D_MZ = [(k+1) + 2Σ_{j=1}^{k}(k+1−j)cʲ]/(k+1) exactly (proofs-notes/markov-walk.md).
        let g = Geometry::new(0.1f64).unwrap();
        let p = 0.38;
        let c: f64 = persistent_correlation(&p);
        let w = CorrelatedWalk::memoryless(p).unwrap();
        for k in 1..=8usize {
            let t = w.sequence_probabilities(k).unwrap();
            let dk = d_k(&g, &t) / g.d_mz();
            let kf = k as f64 + 1.0;
            let s: f64 = (1..=k).map(|j| (kf - j as f64) * c.powi(j as i32)).sum();
            let expect = (kf + 2.0 * s) / kf;
            // Each p carries ≤ (k + 4)u (products and one normalisation), the 3^k-term sum
            // adds ≤ 3^k u relative, the reference ≤ 4ku; both are ≤ 3 in size:
            // |Δ| ≤ 3(5k + 3^k + 8)u.
            let tol = 3.0 * (5.0 * k as f64 + 3f64.powi(k as i32) + 8.0) * f64::EPSILON / 2.0;
            assert!((dk - expect).abs() <= tol, "k = {k}: {dk} vs {expect}");
        }
        // And D_k → D: |D_k − D| = |2Σ_{j≤k} j cʲ/(k+1) + 2Σ_{j>k} cʲ| ≤ 2|c|/((1−|c|)²(k+1)) + …
        let t = w.sequence_probabilities(10).unwrap();
        let d10 = d_k(&g, &t) / g.d_mz();
        let d = persistent_d_over_d_mz(&p);
        let bound = 2.0 * c.abs() / ((1.0 - c.abs()).powi(2) * 11.0)
            + 2.0 * c.abs().powi(11) / (1.0 - c.abs());
        assert!((d10 - d).abs() <= bound, "{d10} vs {d}");
    }
}
