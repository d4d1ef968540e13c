//! The cycle averages of the diffusion coefficient (Cvitanović, Gaspard & Schreiber, Chaos 2,
//! 85 (1992); ChaosBook, "Deterministic diffusion"): the dynamical zeta function
//! 1/ζ(β, s) = ∏_p (1 − z^{n_p} e^{β·n̂_p − sT_p}/|Λ_p|) expanded in z to order N by the
//! curvature expansion (`expansion::exp_series`) shared with the three-disk repeller, its coefficients
//! jets carrying ∂_s and ∂²_β at (β, s) = (0, 0) (`proofs-notes/lattice-cycles.md`).

use rug::Float;
use rug::ops::Pow;
use serde::{Deserialize, Serialize};

use crate::verification::cycles::expansion::{Coefficient, EXPANSION_BITS, exp_series};

/// A function of (s, β_x, β_y) near 0 to the order the averages need: its value, ∂_s, ∂_βx,
/// ∂_βy, ∂²_βx and ∂²_βy (products and sums of such jets stay exact to that order).
#[derive(Debug, Clone)]
pub struct Jet(pub [Float; 6]);

impl Coefficient for Jet {
    fn zero() -> Self {
        Jet(std::array::from_fn(|_| Float::new(EXPANSION_BITS)))
    }
    fn one() -> Self {
        let mut j = Self::zero();
        j.0[0] += 1u32;
        j
    }
    fn plus(&self, o: &Self) -> Self {
        Jet(std::array::from_fn(|i| self.0[i].clone() + &o.0[i]))
    }
    fn times(&self, o: &Self) -> Self {
        let [f, fs, fx, fy, fxx, fyy] = &self.0;
        let [g, gs, gx, gy, gxx, gyy] = &o.0;
        let second = |f2: &Float, f1: &Float, g1: &Float, g2: &Float| {
            f2.clone() * g + &(f1.clone() * g1 * 2u32) + &(f.clone() * g2)
        };
        Jet([
            f.clone() * g,
            fs.clone() * g + &(f.clone() * gs),
            fx.clone() * g + &(f.clone() * gx),
            fy.clone() * g + &(f.clone() * gy),
            second(fxx, fx, gx, gxx),
            second(fyy, fy, gy, gyy),
        ])
    }
    fn ratio(&self, k: i64, m: u32) -> Self {
        Jet(std::array::from_fn(|i| self.0[i].clone() * k / m))
    }
}

impl Jet {
    /// The jet of w·e^{β·x − sT} at 0: (w, −Tw, x₁w, x₂w, x₁²w, x₂²w).
    pub fn weight(w: &Float, period: &Float, x: [&Float; 2]) -> Self {
        Jet([
            w.clone(),
            -(period.clone() * w),
            x[0].clone() * w,
            x[1].clone() * w,
            x[0].clone().square() * w,
            x[1].clone().square() * w,
        ])
    }
}

/// A prime cycle as the zeta function weighs it: length n_p, period T_p, |Λ_p| and the winding
/// n̂_p as a displacement in the plane.
#[derive(Debug, Clone)]
pub struct WindingWeight {
    /// Topological length n_p.
    pub length: usize,
    /// Period T_p.
    pub period: Float,
    /// |Λ_p|.
    pub stability: Float,
    /// n̂_p in the plane (x, y).
    pub displacement: [Float; 2],
}

/// The cycle averages of the zeta function truncated at length N.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Averages {
    /// 1/ζ(0, 0) truncated (→ 0 for a closed system: the flux is conserved).
    #[serde(deserialize_with = "crate::estimators::field::nan_if_null")]
    pub zeta: f64,
    /// ⟨T⟩_ζ = Σ′(−1)^{k+1}(T_{p₁} + … + T_{p_k})/|Λ_{p₁}⋯Λ_{p_k}| = ∂_s(1/ζ).
    #[serde(deserialize_with = "crate::estimators::field::nan_if_null")]
    pub mean_period: f64,
    /// ⟨n⟩_ζ, the same with the lengths n_p = −∂_z(1/ζ) at z = 1.
    #[serde(deserialize_with = "crate::estimators::field::nan_if_null")]
    pub mean_length: f64,
    /// ⟨n̂²⟩_ζ, the same with (n̂_{p₁} + … + n̂_{p_k})² = −Δ_β(1/ζ).
    #[serde(deserialize_with = "crate::estimators::field::nan_if_null")]
    pub mean_square_winding: f64,
    /// D = ⟨n̂²⟩_ζ/(2d⟨T⟩_ζ), d = 2.
    #[serde(deserialize_with = "crate::estimators::field::nan_if_null")]
    pub diffusion: f64,
}

/// The averages of the zeta function over `cycles` truncated at lengths 1 … `max_length`.
pub fn averages(cycles: &[WindingWeight], max_length: usize) -> Vec<Averages> {
    let mut c: Vec<Jet> = (0..=max_length).map(|_| Jet::zero()).collect();
    for p in cycles.iter().filter(|p| p.length <= max_length) {
        for r in 1..=max_length / p.length {
            let w = Float::with_val(EXPANSION_BITS, (&p.stability).pow(r as u32))
                .abs()
                .recip();
            let t = Float::with_val(EXPANSION_BITS, &p.period) * r as u32;
            let x = p
                .displacement
                .clone()
                .map(|d| Float::with_val(EXPANSION_BITS, d) * r as u32);
            let term = Jet::weight(&w, &t, [&x[0], &x[1]]).ratio(1, r as u32);
            c[r * p.length] = c[r * p.length].plus(&term);
        }
    }
    let a = exp_series(&c);
    let mut f = Jet::zero();
    let mut n_mean = Float::new(EXPANSION_BITS);
    (1..=max_length)
        .map(|m| {
            f = f.plus(&a[m]);
            n_mean -= a[m].0[0].clone() * m as u32;
            let zeta = (a[0].0[0].clone() + &f.0[0]).to_f64();
            let mean_period = f.0[1].to_f64();
            // 0 − x, not −x: an expansion whose cycles all return (every winding 0) gives +0,
            // not the −0 that printed as "-0.00000000".
            let square = 0.0 - (f.0[4].clone() + &f.0[5]).to_f64();
            Averages {
                zeta,
                mean_period,
                mean_length: n_mean.to_f64(),
                mean_square_winding: square,
                diffusion: square / (4.0 * mean_period),
            }
        })
        .collect()
}
