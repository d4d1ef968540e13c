//! The corridors of the infinite horizon and the superdiffusion constants
//! (`proofs-notes/corridors.md`): the list against brute force, the constants' identities, the
//! small-scatterer limit (Caglioti–Golse) and a Monte Carlo of the flight tail.

use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::square::SquareScene;
use lorentz_gas::theory::corridors::{LatticeGas, superdiffusion};
use rug::{Float, Rational};

fn square(r: (i64, i64)) -> LatticeGas {
    LatticeGas::Square {
        r: Rational::from(r),
    }
}

fn triangular(w: (i64, i64)) -> LatticeGas {
    LatticeGas::Triangular {
        w: Rational::from(w),
    }
}

/// The free width in direction (m, n) by brute force: the lattice points of a window projected
/// on the normal of the direction, the smallest gap between distinct projections (the spacing
/// of the rows), less the disks' diameter. Independent of the A/|v| formula.
fn brute_width(gas: &LatticeGas, [m, n]: [i64; 2]) -> f64 {
    let (a, r, e2) = match gas {
        LatticeGas::Square { r } => (1.0, r.to_f64(), [0.0, 1.0]),
        LatticeGas::Triangular { w } => (2.0 + w.to_f64(), 1.0, [0.5, 3f64.sqrt() / 2.0]),
    };
    let v = [a * (m as f64 + n as f64 * e2[0]), a * n as f64 * e2[1]];
    let len = v[0].hypot(v[1]);
    let normal = [-v[1] / len, v[0] / len];
    let k = 40;
    let mut proj: Vec<f64> = Vec::new();
    for i in -k..=k {
        for j in -k..=k {
            let p = [a * (i as f64 + j as f64 * e2[0]), a * j as f64 * e2[1]];
            proj.push(p[0] * normal[0] + p[1] * normal[1]);
        }
    }
    proj.sort_by(f64::total_cmp);
    let gap = proj
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|&g| g > 1e-9)
        .fold(f64::INFINITY, f64::min);
    gap - 2.0 * r
}

/// Every primitive direction up to four times the search's norm: open (brute width > 0)
/// exactly when listed, with the listed width.
#[test]
fn the_corridor_list_is_complete_and_its_widths_are_right() {
    let cases = [
        (square((1, 10)), 20),
        (square((1, 4)), 4),
        (square((1, 3)), 4),
        (square((2, 5)), 2),
        (triangular((7, 20)), 3),
        (triangular((2, 5)), 3),
        (triangular((1, 2)), 3),
        (triangular((5, 2)), 6),
        (triangular((1, 10)), 0),
    ];
    for (gas, expected) in cases {
        let s = superdiffusion::<f64>((), &gas).unwrap();
        assert_eq!(s.corridors.len(), expected, "{gas:?}");
        for m in 0..=12i64 {
            for n in -12..=12i64 {
                if (m == 0 && n <= 0) || rug::Integer::from(m).gcd(&rug::Integer::from(n)) != 1 {
                    continue;
                }
                let brute = brute_width(&gas, [m, n]);
                let listed = s.corridors.iter().find(|c| c.direction == [m, n]);
                match listed {
                    Some(c) => assert!(
                        (c.width - brute).abs() < 1e-9 && brute > 0.0,
                        "{gas:?} {m},{n}: listed width {} against {brute}",
                        c.width
                    ),
                    None => assert!(
                        brute <= 1e-9,
                        "{gas:?} {m},{n}: a corridor of width {brute} is missing"
                    ),
                }
            }
        }
    }
}

/// C_map = ℓ·C_flow (ℓ = π|Q|/|∂Q|, Santaló), Σ_xx + Σ_yy = C_flow, and both lattices'
/// symmetry makes Σ isotropic; at 256 bits to 70 digits.
#[test]
fn the_constants_satisfy_their_identities_at_256_bits() {
    for gas in [
        square((1, 10)),
        square((1, 3)),
        triangular((1, 2)),
        triangular((5, 2)),
    ] {
        let s = superdiffusion::<Float>(256, &gas).unwrap();
        let tol = Float::with_val(256, 1e-70);
        let close = |a: &Float, b: &Float| Float::with_val(256, a - b).abs() <= tol;
        let ell = Float::with_val(
            256,
            Float::with_val(256, rug::float::Constant::Pi) * &s.free_area,
        ) / &s.boundary;
        assert!(
            close(&s.c_map, &Float::with_val(256, &ell * &s.c_flow)),
            "{gas:?}"
        );
        assert!(
            close(&Float::with_val(256, &s.d_sup_xx + &s.d_sup_yy), &s.c_flow),
            "{gas:?}"
        );
        assert!(close(&s.d_sup_xx, &s.d_sup_yy), "{gas:?}: not isotropic");
        assert!(
            Float::with_val(256, s.d_sup_xy.clone().abs()) <= tol,
            "{gas:?}"
        );
    }
}

/// The square lattice, r = 1/4, by hand: the axes (|v| = 1, W = 1/2) and the diagonals
/// (|v| = √2, W = 1/√2 − 1/2), |Q| = 1 − π/16.
#[test]
fn the_square_lattice_at_a_quarter_by_hand() {
    let s = superdiffusion::<f64>((), &square((1, 4))).unwrap();
    let wd = 0.5f64.sqrt() - 0.5;
    let sum = 2.0 * 0.25 + 2.0 * 2f64.sqrt() * wd * wd;
    let q = 1.0 - std::f64::consts::PI / 16.0;
    assert!((s.c_flow - sum / (std::f64::consts::PI * q)).abs() < 1e-15);
    assert!((s.c_map - sum / (std::f64::consts::PI / 2.0)).abs() < 1e-15);
    assert!((s.d_sup_xx - s.c_flow / 2.0).abs() < 1e-15);
}

/// Small scatterers: in units of the mean free path ℓ the flow's tail is κ/t with
/// κ = C_flow/ℓ → 2/π² (Caglioti & Golse; Boca & Zaharescu). The sum over primitive vectors
/// in a disk of radius R = 1/(2r) approaches its integral with a relative error of order
/// log R/R (the error term of counting primitive lattice points), so |κπ²/2 − 1| must stay
/// below 2r·ln(1/r) (a factor 4 above the R log R term's coefficient, log R/R = 2r ln(1/(2r)))
/// and shrink as r does.
#[test]
fn small_scatterers_give_the_boltzmann_grad_tail() {
    let mut last = f64::INFINITY;
    for r in [(1, 50), (1, 200), (1, 1000)] {
        let gas = square(r);
        let rf = r.0 as f64 / r.1 as f64;
        let s = superdiffusion::<f64>((), &gas).unwrap();
        let ell = s.free_area / (2.0 * rf);
        let kappa = s.c_flow / ell;
        let dev = (kappa * std::f64::consts::PI.powi(2) / 2.0 - 1.0).abs();
        assert!(
            dev < 2.0 * rf * (1.0 / rf).ln(),
            "r = {rf}: kappa = {kappa}, deviation {dev}"
        );
        assert!(
            dev < last,
            "r = {rf}: deviation {dev} did not shrink from {last}"
        );
        last = dev;
    }
}

/// The flow's free-flight tail measured: starts from the invariant measure of the square
/// lattice at r = 1/4, each followed until its first collision (or s_max); in each of 16
/// batches s·P(τ > s) is fitted by C + B/s over s = 10, 20, 40, 80 (the next order of the
/// tail), and the mean of C over the batches agrees with C_flow within the Student-t 4σ bound.
#[test]
fn the_measured_flight_tail_has_the_exact_constant() {
    let gas = square((1, 4));
    let exact = superdiffusion::<f64>((), &gas).unwrap().c_flow;
    let scene = SquareScene::exact(Rational::from((1, 4))).unwrap();
    let lat = scene.lattice::<f64>(()).unwrap();
    let ss = [10.0, 20.0, 40.0, 80.0];
    let (batches, per) = (16u32, 50_000u32);
    let mut cs = Vec::new();
    for b in 0..batches {
        let mut rng = stream(17, b as u64);
        let mut beyond = [0u32; 4];
        for _ in 0..per {
            let mut st = scene.sample(&mut rng);
            let mut t = 0.0;
            while t <= ss[3] {
                let ev = lat.step(&mut st).unwrap();
                t += ev.time;
                if matches!(
                    ev.kind,
                    lorentz_gas::kernel::flight::EventKind::Collision(_)
                ) {
                    break;
                }
            }
            for (k, s) in ss.iter().enumerate() {
                beyond[k] += u32::from(t > *s);
            }
        }
        // Least squares of y = s·P(τ > s) on x = 1/s.
        let xs: Vec<f64> = ss.iter().map(|s| 1.0 / s).collect();
        let ys: Vec<f64> = ss
            .iter()
            .zip(beyond)
            .map(|(s, n)| s * n as f64 / per as f64)
            .collect();
        let (mx, my) = (xs.iter().sum::<f64>() / 4.0, ys.iter().sum::<f64>() / 4.0);
        let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
        let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
        cs.push(my - sxy / sxx * mx);
    }
    let n = cs.len() as f64;
    let mean = cs.iter().sum::<f64>() / n;
    let se = (cs.iter().map(|c| (c - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
    let z = (mean - exact) / se;
    assert!(
        z.abs() < crate::common::t4(batches),
        "measured C_flow = {mean} ± {se}, exact {exact}: z = {z}"
    );
    assert!(se < 0.1 * exact, "the error {se} says nothing");
}

/// The issue's geometries against C_flow written out by hand, corridor by corridor: the
/// triangular gas beyond w_inf has the three directions of the lattice (|v| = a,
/// W = a√3/2 − 2); the square lattice at r = 0.4 the two axes; at 1/3 the axes and diagonals;
/// at 0.1 the twenty directions with p² + q² ∈ {1, 2, 5, 10, 13, 17} (2, 2, 4, 4, 4, 4 of them).
#[test]
fn the_issues_geometries_by_hand() {
    let pi = std::f64::consts::PI;
    for w in [0.35f64, 0.4, 0.5] {
        let a = 2.0 + w;
        let width = a * 3f64.sqrt() / 2.0 - 2.0;
        let q = a * a * 3f64.sqrt() / 2.0 - pi;
        let hand = 3.0 * a * width * width / (pi * q);
        let gas = LatticeGas::Triangular {
            w: Rational::from_f64(w).unwrap(),
        };
        let s = superdiffusion::<f64>((), &gas).unwrap();
        assert!(
            (s.c_flow / hand - 1.0).abs() < 1e-13,
            "w = {w}: {} against {hand}",
            s.c_flow
        );
    }
    let squares: [(f64, &[(f64, f64)]); 3] = [
        (0.4, &[(1.0, 2.0)]),
        (1.0 / 3.0, &[(1.0, 2.0), (2.0, 2.0)]),
        (
            0.1,
            &[
                (1.0, 2.0),
                (2.0, 2.0),
                (5.0, 4.0),
                (10.0, 4.0),
                (13.0, 4.0),
                (17.0, 4.0),
            ],
        ),
    ];
    for (r, dirs) in squares {
        let sum: f64 = dirs
            .iter()
            .map(|&(n2, mult)| mult * n2.sqrt() * (1.0 / n2.sqrt() - 2.0 * r).powi(2))
            .sum();
        let hand = sum / (pi * (1.0 - pi * r * r));
        let exact = if r == 1.0 / 3.0 {
            Rational::from((1, 3))
        } else {
            Rational::from_f64(r).unwrap()
        };
        let s = superdiffusion::<f64>((), &LatticeGas::Square { r: exact }).unwrap();
        assert!(
            (s.c_flow / hand - 1.0).abs() < 1e-13,
            "r = {r}: {} against {hand}",
            s.c_flow
        );
    }
}

/// The horizon is decided exactly: gaps 10⁻¹⁸ either side of w∞ = 4/√3 − 2 (both round to the
/// double nearest w∞, so no comparison of doubles can tell them apart) are a finite horizon
/// without corridors and an infinite one with three.
#[test]
fn the_horizon_is_decided_exactly_at_w_inf() {
    use lorentz_gas::numbers::exact::parse_exact;
    use lorentz_gas::scenes::triangular::TriangularScene;
    let below = parse_exact("0.309401076758503057036595122008").unwrap();
    let above = parse_exact("0.309401076758503059036595122008").unwrap();
    assert_eq!(below.to_f64(), above.to_f64());
    assert!(
        TriangularScene::exact(below.clone())
            .unwrap()
            .finite_horizon()
    );
    assert!(
        !TriangularScene::exact(above.clone())
            .unwrap()
            .finite_horizon()
    );
    let count = |w: Rational| {
        superdiffusion::<f64>((), &LatticeGas::Triangular { w })
            .unwrap()
            .corridors
            .len()
    };
    assert_eq!(count(below), 0);
    assert_eq!(count(above), 3);
}

/// Long flights through the corridors stay inside the error model: every event of f64 runs
/// beyond the horizon — the triangular gas at w = 1/2 (corridors of width 0.165) and the square
/// lattice at r = 1/100 (mean free path ≈ 50, 64 cell crossings per collision) — replayed at
/// 128 bits, none outside the model, none where f64 chose another obstacle.
#[test]
fn audits_of_long_flights_find_nothing_outside_the_error_model() {
    use lorentz_gas::scenes::triangular::TriangularScene;
    use lorentz_gas::verification::shadow_audit::{self, AuditConfig};
    let cfg = |scene: String, collisions: u64| AuditConfig {
        scene,
        collisions,
        batches: 2,
        sample: 1.0,
        reference_bits: 128,
        seed: 3,
        motion: Default::default(),
        flights: lorentz_gas::engine::long_flight::Flights::Walk,
    };
    let tri = TriangularScene::exact(Rational::from((1, 2))).unwrap();
    assert!(!tri.finite_horizon());
    let r =
        shadow_audit::run(&tri, &cfg(tri.label(), 100_000), &crate::common::threads(2)).unwrap();
    assert!(r.summary.audited > 100_000);
    assert_eq!(
        (r.summary.outside, r.summary.different_choice),
        (0, 0),
        "{:?}",
        r.summary
    );
    let sq = SquareScene::exact(Rational::from((1, 100))).unwrap();
    let r = shadow_audit::run(&sq, &cfg(sq.label(), 10_000), &crate::common::threads(2)).unwrap();
    assert!(r.summary.audited > 100_000, "{}", r.summary.audited);
    assert_eq!(
        (r.summary.outside, r.summary.different_choice),
        (0, 0),
        "{:?}",
        r.summary
    );
}
