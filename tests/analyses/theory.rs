//! Monte-Carlo checks of the theory module: the lattice-gas walk (Einstein formula) and the
//! hop-level Green–Kubo estimator against the exact resolvent D of the same correlated walk.
//!
//! Every comparison is "within 4 standard errors" (batch means over independent streams),
//! plus the deterministic bias of the estimator where there is one, computed exactly from the
//! chain (`fit_bias`, truncation tail) — never a hand-tuned tolerance. A z-score whose standard
//! error comes from the spread of n batch means is Student-t with n − 1 dof, so "4σ" is the
//! Student-t quantile at the normal's two-sided 4σ tail probability 6.3·10⁻⁵
//! (`statistics::normal_sigma_equivalent_t`; 15 dof: 5.48, 31 dof: 4.62).

use lorentz_gas::scenes::symbols::{Symbol, sequence_from_index};
use lorentz_gas::scenes::triangular::geometry::Geometry;
use lorentz_gas::statistics::{mean_se, normal_sigma_equivalent_t};
use lorentz_gas::theory::green_kubo::{Truncation, green_kubo};
use lorentz_gas::theory::lattice_walk::{
    LatticeWalkConfig, direction_sequence, fit_bias, simulate, symbol_sequence,
};
use lorentz_gas::theory::markov::{CorrelatedWalk, persistent_d_over_d_mz};
use lorentz_gas::theory::sequences::{SequenceProbabilities, count_sequences};

/// A mirror-symmetric order-k walk with genuine memory (k ≥ 2), see
/// `proofs-notes/lattice-walk.md`: p(z|h) = 0.2 + 0.3·#z(h)/(k−1); the rest, q, goes to l and r
/// by the last symbol (l: 35/65 %, r: mirrored) or, after z, by the majority of l vs r in h.
fn correlated(k: usize) -> CorrelatedWalk {
    let n = 3usize.pow(k as u32 - 1);
    let cond = (0..n)
        .map(|h| {
            let s = sequence_from_index(k - 1, h);
            let nz = s.iter().filter(|&&x| x == Symbol::Z).count() as f64;
            let nl = s.iter().filter(|&&x| x == Symbol::L).count();
            let nr = s.iter().filter(|&&x| x == Symbol::R).count();
            let pz = 0.2 + 0.3 * nz / (k as f64 - 1.0);
            let q = 1.0 - pz;
            let fl = match s.last() {
                Some(Symbol::L) => 0.35,
                Some(Symbol::R) => 0.65,
                _ if nl > nr => 0.6,
                _ if nr > nl => 0.4,
                _ => 0.5,
            };
            let pl = q * fl;
            [pz, pl, 1.0 - pz - pl]
        })
        .collect();
    CorrelatedWalk::from_conditionals(k, cond).unwrap()
}

/// The order-2 table of `markov::tests` (exact D/D_MZ = 195/134, proofs-notes/markov-walk.md).
fn order2() -> CorrelatedWalk {
    CorrelatedWalk::from_conditionals(2, vec![[0.5, 0.25, 0.25], [0.3, 0.2, 0.5], [0.3, 0.5, 0.2]])
        .unwrap()
}

/// The 4σ-equivalent bound for a mean of `n` batch means.
fn t4(n: usize) -> f64 {
    normal_sigma_equivalent_t(n as f64 - 1.0, 4.0)
}

fn check_walk(name: &str, walk: &CorrelatedWalk, seed: u64) {
    let cfg = LatticeWalkConfig::new(32, 32768, 128, seed);
    let exact = walk.d_over_d_mz().unwrap();
    let bias = fit_bias(walk, &cfg).unwrap();
    let r = simulate(walk, &cfg).unwrap();
    let z = (r.d_over_d_mz - exact) / r.se;
    println!(
        "{name}: MC D/D_MZ = {:.5} ± {:.5}, exact {exact:.6}, z = {z:+.2}, fit bias {bias:.1e}",
        r.d_over_d_mz, r.se
    );
    // The fit window [64, 128] is long enough: its exact bias is below a tenth of σ.
    assert!(
        bias.abs() < 0.1 * r.se,
        "{name}: fit bias {bias} vs se {}",
        r.se
    );
    assert!(z.abs() < t4(cfg.batches), "{name}: z = {z}");
}

#[test]
fn lattice_walk_memoryless_one_third_is_machta_zwanzig() {
    let w = CorrelatedWalk::memoryless(1.0 / 3.0).unwrap();
    assert_eq!(w.d_over_d_mz().unwrap(), 1.0);
    check_walk("memoryless p_bs = 1/3", &w, 11);
    // In absolute units at w = 0.1 the walk gives D_MZ within the same 4σ.
    let g = Geometry::new(0.1f64).unwrap();
    // 32 batches of 1024 walkers: with 8 batches "4σ" would be t₇ = 8.47.
    let cfg = LatticeWalkConfig::new(32, 1024, 64, 12);
    let r = simulate(&w, &cfg).unwrap();
    let (d, se) = r.d(&g);
    assert!(
        (d - g.d_mz()).abs() < t4(cfg.batches) * se,
        "{d} ± {se} vs D_MZ {}",
        g.d_mz()
    );
}

#[test]
fn lattice_walk_order1_persistent() {
    let w = CorrelatedWalk::memoryless(0.38).unwrap();
    let exact = persistent_d_over_d_mz(&0.38f64);
    // 1×1 solve: |Δ| ≤ 16u(1 + |c|)/(1 − |c|)·D with c = (1 − 3·0.38)/2 = −0.07.
    let tol = 16.0 * f64::EPSILON / 2.0 * (1.07 / 0.93) * exact;
    assert!((w.d_over_d_mz().unwrap() - exact).abs() <= tol);
    check_walk("order 1, p_bs = 0.38", &w, 21);
}

#[test]
fn lattice_walk_order2() {
    let w = order2();
    let d = w.d_over_d_mz().unwrap();
    // Backward-stable 3×3 complex LU: |Δ| ≤ 64·n·u·κ·D with n = 3, κ(I − Q) < 10.
    assert!(
        (d - 195.0 / 134.0).abs() <= 64.0 * 3.0 * f64::EPSILON / 2.0 * 10.0 * d,
        "{d}"
    );
    check_walk("order 2 (195/134)", &w, 31);
}

#[test]
fn lattice_walk_order3_and_order4() {
    check_walk("order 3", &correlated(3), 41);
    check_walk("order 4", &correlated(4), 51);
}

#[test]
fn simulated_symbol_frequencies_match_the_stationary_table() {
    // 16 independent sequences of 2^16 exits; per-sequence frequencies of each length-2 word
    // → mean ± SE, compared with the chain's stationary table within 4σ.
    let w = correlated(3);
    let table = w.sequence_probabilities(2).unwrap();
    let seqs: Vec<Vec<Symbol>> = (0..16)
        .map(|b| symbol_sequence(&w, 61, b, 1 << 16))
        .collect();
    for i in 0..9 {
        let f: Vec<f64> = seqs
            .iter()
            .map(|s| {
                let c = count_sequences(s, 2);
                c[i] as f64 / c.iter().sum::<u64>() as f64
            })
            .collect();
        let (m, se) = mean_se(&f);
        let p = table.probabilities()[i];
        assert!(
            (m - p).abs() < t4(f.len()) * se,
            "word {i}: {m} ± {se} vs {p}"
        );
    }
    // Rebuilding the walk from an order-3 table recovers the walk's conditionals p(s | h):
    // exactly (to rounding) from its own stationary table, and within 4σ from each simulated
    // sequence's measured table — the walk rebuilt per sequence, its 9 × 3 conditionals
    // averaged over the 16 sequences (mean ± SE, Student-t with 15 dof). Each is a ratio of
    // counts over ~7000 visits of its history, whose O(1/n) bias is below a tenth of the SE.
    let exact = CorrelatedWalk::new(&w.sequence_probabilities(3).unwrap()).unwrap();
    assert_eq!(exact.histories(), w.histories());
    for h in 0..w.histories() {
        for s in 0..3 {
            let (a, b) = (exact.conditional(h)[s], w.conditional(h)[s]);
            assert!(
                (a - b).abs() <= 16.0 * f64::EPSILON,
                "history {h}, symbol {s}: {a} vs {b}"
            );
        }
    }
    let rebuilt: Vec<CorrelatedWalk> = seqs
        .iter()
        .map(|q| {
            let t = SequenceProbabilities::from_counts(3, &count_sequences(q, 3)).unwrap();
            CorrelatedWalk::new(&t).unwrap()
        })
        .collect();
    for h in 0..w.histories() {
        for s in 0..3 {
            let c: Vec<f64> = rebuilt.iter().map(|r| r.conditional(h)[s]).collect();
            let (m, se) = mean_se(&c);
            let want = w.conditional(h)[s];
            assert!(
                (m - want).abs() < t4(c.len()) * se,
                "history {h}, symbol {s}: recovered {m} ± {se} vs the walk's {want}"
            );
        }
    }
}

fn check_gk(name: &str, walk: &CorrelatedWalk, seed: u64) {
    let seqs: Vec<Vec<u8>> = (0..16)
        .map(|b| direction_sequence(walk, seed, b, 1 << 17))
        .collect();
    let r = green_kubo(&seqs, Truncation::Automatic { c: 6.0 }).unwrap();
    assert_eq!(r.batch_values.len(), 16);
    let k = t4(seqs.len());
    let c = walk.correlations(r.truncation);
    let truncated = 1.0 + 2.0 * c.iter().sum::<f64>();
    let exact = walk.d_over_d_mz().unwrap();
    let tail = exact - truncated;
    let z = (r.d_over_d_mz - truncated) / r.se;
    println!(
        "{name}: GK D/D_MZ = {:.5} ± {:.5} (J = {}), exact truncated {truncated:.6}, \
         exact {exact:.6}, tail {tail:.1e}, z = {z:+.2}",
        r.d_over_d_mz, r.se, r.truncation
    );
    // Unbiased for the truncated sum; against D the exactly known tail is added.
    assert!(z.abs() < k, "{name}: z = {z} (bound {k:.2})");
    assert!((r.d_over_d_mz - exact).abs() < k * r.se + tail.abs());
    assert_eq!(r.correlations.len(), r.truncation);
}

#[test]
fn green_kubo_matches_the_exact_walk() {
    check_gk(
        "GK memoryless 1/3",
        &CorrelatedWalk::memoryless(1.0 / 3.0).unwrap(),
        71,
    );
    check_gk(
        "GK order 1, 0.38",
        &CorrelatedWalk::memoryless(0.38).unwrap(),
        72,
    );
    check_gk("GK order 2", &order2(), 73);
    check_gk("GK order 4", &correlated(4), 74);
}

/// The error bar is over independent sequences only: one sequence is refused (its gᵢ are
/// correlated), and a fixed window J = 24 over 16 sequences covers the exact truncated sum.
#[test]
fn green_kubo_fixed_window_needs_independent_sequences() {
    let w = order2();
    let one = direction_sequence(&w, 81, 0, 1 << 16);
    let e = green_kubo(&[one], Truncation::Fixed(24)).unwrap_err();
    assert!(e.to_string().contains("at least 2"), "{e}");
    let seqs: Vec<Vec<u8>> = (0..16)
        .map(|b| direction_sequence(&w, 81, b, 1 << 16))
        .collect();
    let r = green_kubo(&seqs, Truncation::Fixed(24)).unwrap();
    let c = w.correlations(24);
    let truncated = 1.0 + 2.0 * c.iter().sum::<f64>();
    let z = (r.d_over_d_mz - truncated) / r.se;
    println!(
        "GK fixed J = 24: {:.5} ± {:.5} vs {truncated:.6}, z = {z:+.2}",
        r.d_over_d_mz, r.se
    );
    assert!(z.abs() < t4(seqs.len()), "z = {z}");
}
