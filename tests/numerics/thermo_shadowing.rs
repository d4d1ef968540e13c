//! True shadowing of `f64` thermostatted segments (`lorentz shadow --electric`,
//! `proofs-notes/shadowing.md`, "Under the thermostat"): the thermostatted billiard map and its
//! Jacobian, Newton on the whole segment, and the clearance of the curved flights. No bit of a
//! thermostatted flight is pinned: the map is checked against central differences and the
//! phase-space contraction, the shadows against the Newton–Kantorovich bound.

use rug::{Float, Rational};

use super::shadowing::{assert_central_differences, assert_certified};

use lorentz_gas::numbers::exact::parse_exact;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::motion::MotionInput;
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::thermostat::CellFields;
use lorentz_gas::scenes::triangular::TriangularScene;
use lorentz_gas::verification::curved::ExactMotion;
use lorentz_gas::verification::shadowing::{
    self as shadowing, CONVERGENCE_SLACK_BITS, OrbitPoint, ShadowConfig, Table,
    f64_segment_in_thermostat,
};

const BITS: u32 = 128;

fn scene(w: &str) -> TriangularScene {
    TriangularScene::exact(parse_exact(w).unwrap()).unwrap()
}

fn motion(e: &str, angle: &str) -> ExactMotion {
    ExactMotion::Thermostat {
        field: parse_exact(e).unwrap(),
        angle: parse_exact(angle).unwrap(),
    }
}

/// Segment k of `shadow --w W --electric E --electric-angle A --seed 1` at `bits`.
fn segment(sc: &TriangularScene, m: &ExactMotion, k: u64, n: usize, bits: u32) -> Vec<OrbitPoint> {
    let ExactMotion::Thermostat { field, angle } = m else {
        unreachable!()
    };
    let th = lorentz_gas::kernel::thermostat::Thermostat::<f64>::exact(field, angle, ());
    let fields = CellFields::new(th.unwrap());
    let start = sc.sample(&mut stream(1, k));
    f64_segment_in_thermostat(sc, &start, &fields, n, bits).unwrap()
}

/// The contact point of `x` on `table` (world coordinates).
fn contact(table: &Table, x: &OrbitPoint, bits: u32) -> [Float; 2] {
    let c = table.centre(x.disk);
    let (sn, cs) = x.s.clone().sin_cos(Float::new(bits));
    let r = table.radius();
    [c.x + &(cs * r), c.y + &(sn * r)]
}

/// The analytic Jacobian of the thermostatted map against central differences at 256 bits with
/// the straight map's error model (`tests/numerics/shadowing.rs`:
/// tol = 2^(S−P)(1/h + 1 + J)/c + h²J³/c⁴, h = 2⁻¹¹⁶), and its determinant against the phase-space contraction: the section
/// form ds dp is the flux of the flow's volume, which a flight multiplies by e^{−∫α} and ∫α = E·ΔX
/// (the field's work), so det DT = e^{−E·(X₁ − X₀)} from the contact points alone — within 4J
/// times the entries' error. Fields from 10⁻² to 10, both signs, oblique angles. Broken on
/// purpose: with the arrival's velocity variation dropped (δv⁻ = v̇δτ only) the central
/// differences fail (checked once, then restored).
#[test]
fn the_thermostatted_map_has_the_analytic_jacobian_and_contracts_by_the_work() {
    let sc = scene("0.1");
    let bits = 256;
    let h = Float::with_val(bits, -116f64).exp2();
    let rounding = (CONVERGENCE_SLACK_BITS as f64 - bits as f64).exp2();
    for (e, angle) in [("1/100", "0"), ("0.3", "30"), ("-3", "45"), ("10", "-60")] {
        let m = motion(e, angle);
        let y = segment(&sc, &m, 3, 30, bits);
        let table = Table::in_motion(&sc, bits, Some(&m)).unwrap();
        let ExactMotion::Thermostat { field, angle: a } = &m else {
            unreachable!()
        };
        let turn = Float::with_val(bits, rug::float::Constant::Pi) * Rational::from(a / 180u32);
        let (sn, cs) = turn.sin_cos(Float::new(bits));
        let (ex, ey) = (cs * field, sn * field);
        for k in 0..y.len() - 1 {
            let what = format!("E {e} at {angle} deg, k {k}");
            let (image, jac) = table.map(&y[k], y[k + 1].disk).unwrap();
            let cos = |p: &Float| {
                (Float::with_val(bits, 1) - p.clone().square())
                    .sqrt()
                    .to_f64()
            };
            let c = cos(&y[k].p).min(cos(&image.p)).min(1.0);
            let big_j = jac.iter().map(|v| v.to_f64().abs()).fold(0.0, f64::max);
            let entry_err = rounding * (1.0 + big_j) / c;
            let tol = rounding * (1.0 / h.to_f64() + 1.0 + big_j) / c
                + h.to_f64().powi(2) * big_j.powi(3) / c.powi(4);
            assert_central_differences(&table, &y[k], y[k + 1].disk, &jac, &h, tol, &what);
            let [x0, y0] = contact(&table, &y[k], bits);
            let [x1, y1] = contact(&table, &image, bits);
            let work = ex.clone() * &(x1 - &x0) + &(ey.clone() * &(y1 - &y0));
            let det = jac[0].clone() * &jac[3] - &(jac[1].clone() * &jac[2]);
            let want = (-work).exp();
            let err = (det - &want).abs().to_f64();
            assert!(
                err <= 4.0 * big_j * entry_err * (1.0 + want.to_f64()),
                "{what}: det DT − e^(−E·ΔX) = {err:e}"
            );
        }
    }
}

/// The fields E ∈ {0.01, 0.3, 3} at w = 0.1 and 0.3: every segment converges and is
/// certified, with δ within the Newton–Kantorovich bound 2K‖F(y⁰)‖₂ and the pseudo-orbit's
/// defects within reach of δ ([`assert_certified`]). Broken on purpose: with the thermostat
/// dropped from the shadow's table (straight true flights against thermostatted f64 segments)
/// no segment is certified (checked once, then restored).
#[test]
fn f64_thermostatted_segments_are_shadowed_at_w_0_1_and_0_3() {
    for w in ["0.1", "0.3"] {
        let sc = scene(w);
        for e in ["0.01", "0.3", "3"] {
            let request = ShadowConfig {
                collisions_per_segment: 200,
                segments: 2,
                seed: 1,
                reference_bits: BITS,
                motion: MotionInput::default().with_electric(e, "30"),
            };
            let r = shadowing::run(&sc, &request, &crate::common::threads(1)).unwrap();
            for s in &r.segments {
                let what = format!("w {w}, E {e}, segment {}", s.segment);
                assert_certified(&s.shadow, &what);
                assert!(s.shadow.min_clearance.unwrap() > 0.0, "{what}");
            }
        }
    }
}
