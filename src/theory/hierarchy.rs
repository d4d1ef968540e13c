//! The paper's hierarchy of corrected Machta–Zwanzig diffusion coefficients (Sec. III and
//! App. B of Klages & Dellago 2000), with the distance classes computed by walking the
//! honeycomb ([`super::honeycomb`]), not copied from the paper.
//!
//! | name | formula | paper |
//! |---|---|---|
//! | collisionless flights | D_cf = (1 + 2p_cf) D_MZ | eq. (4) |
//! | backscattering | D_bs = (3/2)(1 − p_bs) D_MZ | eq. (5) |
//! | first order | D₁ = (3/2)(1 − p_bs)(1 + 2p_cf) D_MZ | eq. (6) |
//! | order k (backscattering) | D_k = Σ_seq p(seq) \|Δr(seq)\|² / (4(k+1)τ) | eqs. (B1)–(B2), corrected |
//! | order k combined | D_k^cf = (1 + 2p_cf) D_k | "in the same way" as eq. (6) |
//!
//! Δr(seq) is the displacement after the initial hop followed by the k hops given by the
//! symbols: k + 1 hops in the time (k + 1)τ. Since l²/(4τ) = D_MZ,
//! D_k = D_MZ · M_k/(k + 1) with the second moment M_k = Σ p(seq)·|Δr(seq)|²/l² (an average of
//! exact integers). k = 1 gives eq. (5): |Δr(z)|² = 0, |Δr(l)|² = |Δr(r)|² = 3l².
//!
//! The paper's eqs. (B2) and (B3) print D₂ and D₃ without the factor (1 + 2p_cf): as printed
//! they are the backscattering coefficients [`d_k`] (generalising eq. 5), while the text
//! (Sec. III C) says they are combined with D_cf "in the same way as before", which is
//! [`d_k_combined`]. Discrepancies of the printed App. B with the honeycomb are listed in
//! `proofs-notes/paper-appendix-b.md` and reproduced by [`d2_as_printed`], [`d3_as_printed`].

use std::collections::BTreeMap;

use crate::numbers::real::Real;
use crate::scenes::triangular::geometry::Geometry;

use super::honeycomb::squared_displacement;
use super::sequences::SequenceProbabilities;
use crate::scenes::symbols::{Symbol, all_sequences, parse_symbols, sequence_index};

/// Eq. (4): D_cf = [1 − p_cf] D_MZ + p_cf · 3 D_MZ = (1 + 2p_cf) D_MZ (a collisionless flight
/// covers the next-nearest-neighbour distance l₂ = √3 l in the time τ).
pub fn d_cf<T: Real>(g: &Geometry<T>, p_cf: &T) -> T {
    (p_cf.clone().scale(2.0).add_f64(1.0)) * &g.d_mz()
}

/// Eq. (5): D_bs = (1 − p_bs) l₂²/(8τ) = (3/2)(1 − p_bs) D_MZ.
pub fn d_bs<T: Real>(g: &Geometry<T>, p_bs: &T) -> T {
    let one = T::one(g.ctx());
    ((one - p_bs).scale(1.5)) * &g.d_mz()
}

/// Eq. (6): D₁ = (3/2)(1 − p_bs)(1 + 2p_cf) D_MZ (D_MZ in eq. 5 replaced by D_cf of eq. 4).
pub fn d_1<T: Real>(g: &Geometry<T>, p_bs: &T, p_cf: &T) -> T {
    let one = T::one(g.ctx());
    (one - p_bs).scale(1.5) * &p_cf.clone().scale(2.0).add_f64(1.0) * &g.d_mz()
}

/// The second moment M_k = Σ_seq p(seq)·|Δr(seq)|²/l² over the k + 1 hops (initial hop plus
/// one per symbol), evaluated at the precision `ctx` (each p is converted exactly, each
/// |Δr|²/l² is an exact integer).
pub fn second_moment<T: Real>(ctx: T::Ctx, p: &SequenceProbabilities) -> T {
    let k = p.len();
    let mut m = T::zero(ctx);
    for (i, &pi) in p.probabilities().iter().enumerate() {
        let n = squared_displacement(&crate::scenes::symbols::sequence_from_index(k, i));
        m += &(T::from_f64(ctx, pi) * &T::from_i32(ctx, n as i32));
    }
    m
}

/// Order-k backscattering coefficient D_k = Σ p(seq)|Δr(seq)|²/(4(k+1)τ) = D_MZ·M_k/(k+1)
/// (k = 1: eq. 5; k = 2, 3: eqs. B2, B3 with corrected distance classes).
///
/// # Examples
///
/// ```
/// use lorentz_gas::scenes::triangular::geometry::Geometry;
/// use lorentz_gas::theory::{hierarchy::{d_bs, d_k}, sequences::SequenceProbabilities};
/// let g = Geometry::new(0.1f64).unwrap();
/// let p = SequenceProbabilities::memoryless(1, 0.38).unwrap();
/// assert!((d_k(&g, &p) - d_bs(&g, &0.38)).abs() < 1e-15);
/// ```
pub fn d_k<T: Real>(g: &Geometry<T>, p: &SequenceProbabilities) -> T {
    let ctx = g.ctx();
    let k1 = T::from_i32(ctx, p.len() as i32 + 1);
    second_moment::<T>(ctx, p) * &g.d_mz() / &k1
}

/// Order-k coefficient combined with collisionless flights as eq. (6) does for k = 1:
/// D_MZ replaced by D_cf, i.e. (1 + 2p_cf)·D_k.
pub fn d_k_combined<T: Real>(g: &Geometry<T>, p: &SequenceProbabilities, p_cf: &T) -> T {
    p_cf.clone().scale(2.0).add_f64(1.0) * &d_k(g, p)
}

/// All sequences of one length that end at the same squared distance from the start.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DistanceClass {
    /// |Δr|²/l², an exact integer.
    pub squared: i64,
    /// The sequences (as the paper's words, e.g. `"lzr"`), sorted.
    pub words: Vec<String>,
}

/// The distance classes of all 3^k sequences of length `k`, by increasing distance,
/// computed by walking the honeycomb in exact lattice coordinates.
pub fn distance_classes(k: usize) -> Vec<DistanceClass> {
    let mut m: BTreeMap<i64, Vec<String>> = BTreeMap::new();
    for s in all_sequences(k) {
        m.entry(squared_displacement(&s))
            .or_default()
            .push(crate::scenes::symbols::word(&s));
    }
    m.into_iter()
        .map(|(squared, mut words)| {
            words.sort();
            DistanceClass { squared, words }
        })
        .collect()
}

/// One class as printed in the paper's App. B: its probability name, the words it sums and
/// the printed distance (as a function of l and √3, evaluated by [`PaperClass::squared`]).
#[derive(Debug, Clone, PartialEq)]
pub struct PaperClass {
    /// The paper's name (`"p_1"`, `"p_41"`, …).
    pub name: &'static str,
    /// The words summed in the printed probability (the typo `pp(lrr)` read as `p(lrr)`).
    pub words: Vec<&'static str>,
    /// The printed distance.
    pub printed_distance: &'static str,
}

impl PaperClass {
    /// The printed squared distance in units of l², evaluated at the precision `ctx`.
    /// `"(2+w)√3"` (printed for l₁) is a·√3 = 3l, so its square is 9 l².
    pub fn squared<T: Real>(&self, ctx: T::Ctx) -> T {
        let s3 = T::sqrt3(ctx);
        match self.printed_distance {
            "0" => T::zero(ctx),
            "l = (2+w)√3" => T::from_f64(ctx, 9.0),
            "√7 l" => T::from_f64(ctx, 7.0),
            "2l" => T::from_f64(ctx, 4.0),
            "√3 l" => T::from_f64(ctx, 3.0),
            "3l" => T::from_f64(ctx, 9.0),
            "(1.5+√3) l" => s3.add_f64(1.5).square(),
            other => unreachable!("unknown printed distance {other}"),
        }
    }
}

/// App. B for k = 2 (time 3τ), exactly as printed.
pub fn paper_classes_k2() -> Vec<PaperClass> {
    vec![
        PaperClass {
            name: "p_1",
            words: vec!["zz", "zl", "zr", "lz", "rz"],
            printed_distance: "l = (2+w)√3",
        },
        PaperClass {
            name: "p_3",
            words: vec!["lr", "rl"],
            printed_distance: "√7 l",
        },
        PaperClass {
            name: "p_3'",
            words: vec!["ll", "rr"],
            printed_distance: "2l",
        },
    ]
}

/// App. B for k = 3 (time 4τ), exactly as printed.
pub fn paper_classes_k3() -> Vec<PaperClass> {
    vec![
        PaperClass {
            name: "p_0",
            words: vec!["lzz", "rzz", "zlz", "zrz", "zzz"],
            printed_distance: "0",
        },
        PaperClass {
            name: "p_2",
            words: vec![
                "lll", "llz", "lrz", "lzl", "lzr", "rlz", "rrr", "rrz", "rzl", "rzr", "zll", "zlr",
                "zrl", "zrr", "zzl", "zzr",
            ],
            printed_distance: "√3 l",
        },
        PaperClass {
            name: "p_41",
            words: vec!["lrl", "rlr"],
            printed_distance: "3l",
        },
        PaperClass {
            name: "p_42",
            words: vec!["llr", "lrr", "rll", "rrl"],
            printed_distance: "(1.5+√3) l",
        },
    ]
}

fn as_printed<T: Real>(g: &Geometry<T>, p: &SequenceProbabilities, classes: &[PaperClass]) -> T {
    let ctx = g.ctx();
    let k = p.len();
    let mut m = T::zero(ctx);
    for c in classes {
        let mut pc = T::zero(ctx);
        for w in &c.words {
            let s: Vec<Symbol> = parse_symbols(w).expect("paper word");
            pc += &T::from_f64(ctx, p.probabilities()[sequence_index(&s)]);
        }
        m += &(pc * &c.squared::<T>(ctx));
    }
    m * &g.d_mz() / &T::from_i32(ctx, k as i32 + 1)
}

/// Eq. (B2) exactly as printed: D₂ = (12τ)⁻¹[p₁l₁² + p₃l₃² + p₃'l₃'²] with the printed
/// l₁ = (2+w)√3 = 3l (the correct l₁ = l = (2+w)/√3 gives [`d_k`]). Panics unless k = 2.
pub fn d2_as_printed<T: Real>(g: &Geometry<T>, p: &SequenceProbabilities) -> T {
    assert_eq!(p.len(), 2, "eq. (B2) needs sequences of length 2");
    as_printed(g, p, &paper_classes_k2())
}

/// Eq. (B3) exactly as printed: D₃ = (16τ)⁻¹[p₂l₂² + p₄₁l₄₁² + p₄₂l₄₂²] with the printed
/// classes and distances (l₂ = √3 l, l₄₁ = 3l, l₄₂ = (1.5 + √3)l). Panics unless k = 3.
pub fn d3_as_printed<T: Real>(g: &Geometry<T>, p: &SequenceProbabilities) -> T {
    assert_eq!(p.len(), 3, "eq. (B3) needs sequences of length 3");
    as_printed(g, p, &paper_classes_k3())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rug::Float;

    fn class_words(k: usize) -> Vec<(i64, Vec<String>)> {
        distance_classes(k)
            .into_iter()
            .map(|c| (c.squared, c.words))
            .collect()
    }

    fn strs(v: &[&str]) -> Vec<String> {
        let mut v: Vec<String> = v.iter().map(|s| s.to_string()).collect();
        v.sort();
        v
    }

    #[test]
    fn first_order_classes() {
        assert_eq!(
            class_words(1),
            vec![(0, strs(&["z"])), (3, strs(&["l", "r"]))]
        );
    }

    #[test]
    fn second_order_classes_match_the_derivation_and_the_paper() {
        // proofs-notes/paper-appendix-b.md: 1 l² (five words), 4 l² (ll, rr), 7 l² (lr, rl).
        assert_eq!(
            class_words(2),
            vec![
                (1, strs(&["zz", "zl", "zr", "lz", "rz"])),
                (4, strs(&["ll", "rr"])),
                (7, strs(&["lr", "rl"])),
            ]
        );
        // The paper's k = 2 sets are right (only its l₁ = (2+w)√3 is a slip).
        for pc in paper_classes_k2() {
            let sq = squared_displacement(&parse_symbols(pc.words[0]).unwrap());
            for w in &pc.words {
                assert_eq!(squared_displacement(&parse_symbols(w).unwrap()), sq);
            }
        }
    }

    #[test]
    fn third_order_classes_and_the_paper_slips() {
        let c = class_words(3);
        assert_eq!(
            c,
            vec![
                (0, strs(&["lzr", "rzl", "zlz", "zrz", "zzz"])),
                (
                    3,
                    strs(&[
                        "lll", "llz", "lrz", "lzl", "lzz", "rlz", "rrr", "rrz", "rzr", "rzz",
                        "zll", "zlr", "zrl", "zrr", "zzl", "zzr"
                    ])
                ),
                (9, strs(&["llr", "lrr", "rll", "rrl"])),
                (12, strs(&["lrl", "rlr"])),
            ]
        );
        // Paper: p(lzz), p(rzz) listed as returning; they end at √3 l.
        assert_eq!(squared_displacement(&parse_symbols("lzz").unwrap()), 3);
        // Paper: p(lzr), p(rzl) listed at √3 l; they return to the origin.
        assert_eq!(squared_displacement(&parse_symbols("lzr").unwrap()), 0);
        // Paper: l₄₁ = 3l for lrl; it is 2√3 l. l₄₂ = (1.5+√3)l for llr; it is 3l.
        assert_eq!(squared_displacement(&parse_symbols("lrl").unwrap()), 12);
        assert_eq!(squared_displacement(&parse_symbols("llr").unwrap()), 9);
    }

    #[test]
    fn memoryless_sum_is_exact() {
        // Σ_seq |Δr|²/l² = (k+1)·3^k exactly (uncorrelated hops, proofs-notes/memoryless.md).
        for k in 1..=8usize {
            let total: i64 = all_sequences(k)
                .iter()
                .map(|s| squared_displacement(s))
                .sum();
            assert_eq!(total, (k as i64 + 1) * 3i64.pow(k as u32), "k = {k}");
        }
    }

    #[test]
    fn memoryless_one_third_gives_d_mz_at_every_order() {
        // f64: each factor fl(1/3) or fl(1 − fl(1/3))/2 carries relative error ≤ 1.5u, a
        // product of k of them with k − 1 roundings ≤ (2.5k − 1)u < 3ku; M_k adds 3^k rounded
        // terms, D_MZ·M/(k+1)/D_MZ four more roundings: |D_k/D_MZ − 1| ≤ (3k + 3^k + 4)u.
        let g = Geometry::new(0.1f64).unwrap();
        let g256 = Geometry::new(Float::with_val(256, 0.1)).unwrap();
        for k in 1..=6usize {
            let p = SequenceProbabilities::memoryless(k, 1.0 / 3.0).unwrap();
            let r = d_k(&g, &p) / g.d_mz();
            let n = 3f64.powi(k as i32);
            let u = f64::EPSILON / 2.0;
            assert!(
                (r - 1.0).abs() <= (3.0 * k as f64 + n + 4.0) * u,
                "k={k}: {r}"
            );
            // The 256-bit evaluation is limited only by the f64 probabilities (< 3ku each,
            // all in the same direction at worst), plus 2^-240 for the 256-bit arithmetic.
            let r256 = (d_k(&g256, &p) / g256.d_mz()).to_f64();
            assert!(
                (r256 - 1.0).abs() <= 3.0 * k as f64 * u + 1e-70,
                "k={k}: {r256}"
            );
        }
    }

    #[test]
    fn order_one_reproduces_eq5_and_eq6() {
        let g = Geometry::new(Float::with_val(256, 0.2)).unwrap();
        let pbs = 0.3;
        let p = SequenceProbabilities::memoryless(1, pbs).unwrap();
        let pb = Float::with_val(256, pbs);
        let pcf = Float::with_val(256, 0.05);
        // p(l) + p(r) = 1 − p_bs up to one rounding in (1 − p_bs)/2 (|Δ| ≤ u): eq. 5 within 2u.
        let a = d_k(&g, &p);
        let b = d_bs(&g, &pb);
        let rel = ((a.clone() - &b) / &b).abs().to_f64();
        assert!(rel <= f64::EPSILON, "{rel}");
        let c = d_k_combined(&g, &p, &pcf);
        let d = d_1(&g, &pb, &pcf);
        let rel = ((c - &d) / &d).abs().to_f64();
        assert!(rel <= f64::EPSILON, "{rel}");
        // Known value: D_cf(p_cf = 1/2) = 2 D_MZ exactly.
        let half = Float::with_val(256, 0.5);
        assert_eq!(d_cf(&g, &half), g.d_mz() * 2u32);
    }

    #[test]
    fn printed_appendix_b_values_for_memoryless_hops() {
        let g = Geometry::new(0.1f64).unwrap();
        let u = f64::EPSILON / 2.0;
        // k = 2: with the printed l₁ = (2+w)√3 = 3l, M = (5·9 + 2·7 + 2·4)/9 = 67/9.
        let p2 = SequenceProbabilities::memoryless(2, 1.0 / 3.0).unwrap();
        let r2 = d2_as_printed(&g, &p2) / g.d_mz();
        assert!((r2 - 67.0 / 27.0).abs() <= 32.0 * u, "{r2}");
        // k = 3: M = (16·3 + 2·9 + 4(1.5+√3)²)/27 = (48 + 18 + 21 + 12√3)/27 = (87 + 12√3)/27,
        // so the printed D₃/D_MZ = M/4 = (87 + 12√3)/108 ≈ 0.99798, not 1.
        let p3 = SequenceProbabilities::memoryless(3, 1.0 / 3.0).unwrap();
        let r3 = d3_as_printed(&g, &p3) / g.d_mz();
        let expect = (87.0 + 12.0 * 3f64.sqrt()) / 108.0;
        assert!((r3 - expect).abs() <= 64.0 * u, "{r3} vs {expect}");
        assert!((r3 - 1.0).abs() > 1e-3);
    }
}
