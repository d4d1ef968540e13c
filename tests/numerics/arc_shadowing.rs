//! True shadowing of `f64` arc segments in a magnetic field (`proofs-notes/shadowing.md`, "In a
//! magnetic field"): the magnetic billiard map and its Jacobian, Newton on the whole segment,
//! and the clearance of arcs from the disks they do not hit.

use rug::{Float, Rational};

use super::shadowing::{assert_certified, assert_step_jacobian};

use lorentz_gas::numbers::exact::parse_exact;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::motion::MotionInput;
use lorentz_gas::scenes::sampling::{Purpose, StreamKey};
use lorentz_gas::scenes::triangular::TriangularScene;
use lorentz_gas::theory::magnetic::FieldGeometry;
use lorentz_gas::verification::shadowing::{
    self as shadowing, OrbitPoint, Shadow, ShadowConfig, Table, f64_segment_in_field,
    shadow_pseudo_orbit_in_field,
};

const BITS: u32 = 128;

fn scene(w: &str) -> TriangularScene {
    TriangularScene::exact(parse_exact(w).unwrap()).unwrap()
}

/// Segment k of `shadow --w W --field B --seed 1`: the f64 arc orbit from the diffusing start
/// of batch k of the transport run in the field.
fn arc_segment(sc: &TriangularScene, field: &Rational, k: u64, n: usize) -> Vec<OrbitPoint> {
    let b = field.to_f64();
    let g = FieldGeometry::new(sc.disk_lattice().unwrap(), b).unwrap();
    let mut rng = StreamKey::new(1, Purpose::Trajectory, k).rng();
    let (mut start, _) = g.diffusing_start(sc, &mut rng).unwrap();
    start.flight.normalise_speed();
    f64_segment_in_field(sc, &start, b, n, BITS).unwrap()
}

/// The claims of a clean shadow that follow from the theorem and the stopping rule
/// ([`assert_certified`], as for straight segments, without the straight test's empirical
/// δ ≤ 1e-13: in a field K reaches 10³–10⁶ on orbits that linger near regular islands, and δ is
/// bounded by what the theorem gives, 2K‖F(y⁰)‖₂).
fn assert_clean(sh: &Shadow, what: &str) {
    assert_certified(sh, what);
}

/// The analytic Jacobian of the magnetic map against central differences at 256 bits, with the
/// straight map's error model (`tests/numerics/shadowing.rs`): tol = 2^(S−P)(1/h + 1 + J)/c +
/// h²J³/c⁴, h = 2⁻¹¹⁶ (x ± h exact for 128-bit points), and det DT = 1 — the magnetic billiard
/// map keeps ds dp as the straight one does (`proofs-notes/liouville.md`) — within 4J times the
/// entries' error. Both signs of the field, radii from 1/10 to 10, and steps that return to the
/// disk they left (skipping arcs) are among the events.
#[test]
fn the_magnetic_map_has_the_analytic_jacobian_and_keeps_ds_dp() {
    let sc = scene("0.1");
    let bits = 256;
    let h = Float::with_val(bits, -116f64).exp2();
    let mut returns = 0;
    for field in ["1/10", "1", "-1", "10"] {
        let q = parse_exact(field).unwrap();
        let y = arc_segment(&sc, &q, 3, 40);
        let table = Table::in_field(&sc, bits, Some(&q)).unwrap();
        for k in 0..y.len() - 1 {
            returns += usize::from(y[k].disk == y[k + 1].disk);
            let what = format!("B {field}, k {k}");
            assert_step_jacobian(&table, bits, &y[k], y[k + 1].disk, &h, &what);
        }
    }
    assert!(returns > 0, "no skipping step was checked");
}

/// The fields at w = 0.1 and 0.3 (at w = 0.3, B = 10 every orbit is localized and the
/// run is refused: nothing diffuses to shadow).
#[test]
fn f64_arc_segments_are_shadowed_at_w_0_1_and_0_3() {
    for (w, fields) in [
        ("0.1", &["1/10", "1", "10"][..]),
        ("0.3", &["1/10", "-1"][..]),
    ] {
        let sc = scene(w);
        for field in fields {
            let request = ShadowConfig {
                collisions_per_segment: 300,
                segments: 3,
                seed: 1,
                reference_bits: BITS,
                motion: MotionInput {
                    field: Some(field.to_string()),
                    ..Default::default()
                },
            };
            let r = shadowing::run(&sc, &request, &crate::common::threads(1)).unwrap();
            for s in &r.segments {
                let what = format!("w = {w}, B = {field}, segment {}", s.segment);
                assert_clean(&s.shadow, &what);
                assert!(s.shadow.iterations <= 4, "{what}: quadratic convergence");
            }
        }
    }
    let request = ShadowConfig {
        collisions_per_segment: 300,
        segments: 1,
        seed: 1,
        reference_bits: BITS,
        motion: MotionInput {
            field: Some("10".into()),
            ..Default::default()
        },
    };
    let e = shadowing::run(&scene("0.3"), &request, &crate::common::threads(1))
        .unwrap_err()
        .to_string();
    assert!(e.contains("every orbit is localized"), "{e}");
}

/// An arc segment is an orbit of its own field only: shadowed as straight flights or in the
/// opposite field, the same disk sequence has no true orbit near it.
#[test]
fn an_arc_segment_is_not_shadowed_in_another_field() {
    let sc = scene("0.1");
    let q = parse_exact("1").unwrap();
    let y = arc_segment(&sc, &q, 0, 200);
    assert_clean(
        &shadow_pseudo_orbit_in_field(&sc, &y, BITS, Some(&q)).unwrap(),
        "B = 1",
    );
    for other in [None, Some(-q.clone()), Some(Rational::from((11, 10)))] {
        let sh = shadow_pseudo_orbit_in_field(&sc, &y, BITS, other.as_ref()).unwrap();
        assert!(!sh.certified, "{other:?}: certified {:?}", sh.delta);
    }
}

/// The clearance of arcs against brute force: from points of disk (0, 0), the map to a chosen
/// disk (which finds the entry into it whatever lies on the way) gives a two-point orbit with no
/// defect; the shadow must call it blocked exactly when the arc, sampled at 4000 points between
/// its ends, dips into another disk — or back into the disk it left — by more than 10⁻⁴ (steps
/// of at most 2πρ/4000 ≤ 3.2·10⁻³ along arcs of radius ρ ≤ 2 misjudge a distance by at most
/// step²/8 ≈ 1.3·10⁻⁶; arcs that come within 10⁻⁴ of a disk are left out as undecided).
#[test]
fn arcs_through_other_disks_are_blocked_as_brute_force_finds() {
    let sc = scene("0.1");
    let table = Table::new(&sc, BITS).unwrap();
    let centre = |d: [i64; 2]| {
        let c = table.centre(d);
        [c.x.to_f64(), c.y.to_f64()]
    };
    let (mut blocked, mut clear) = (0, 0);
    for field in ["1/2", "-1", "3"] {
        let q = parse_exact(field).unwrap();
        let b = q.to_f64();
        let t = Table::in_field(&sc, BITS, Some(&q)).unwrap();
        for si in 0..8 {
            for pi in -4..=4 {
                let x = OrbitPoint {
                    disk: [0, 0],
                    s: Float::with_val(BITS, si as f64 * 0.785),
                    p: Float::with_val(BITS, pi as f64 * 0.22),
                };
                for next in [
                    [0, 0],
                    [1, 0],
                    [0, 1],
                    [-1, 1],
                    [-1, 0],
                    [0, -1],
                    [1, -1],
                    [2, 0],
                ] {
                    let Some((image, _)) = t.map(&x, next) else {
                        continue;
                    };
                    let truth = brute_force(&x, &image, b, &centre);
                    let Some(truth) = truth else { continue };
                    let y = [x.clone(), image];
                    let sh = shadow_pseudo_orbit_in_field(&sc, &y, BITS, Some(&q)).unwrap();
                    let found = sh
                        .failure
                        .as_deref()
                        .is_some_and(|f| f.contains("passes through"));
                    assert_eq!(
                        found, truth,
                        "B {field}, s {si}, p {pi}, to {next:?}: {:?}",
                        sh.failure
                    );
                    if truth {
                        blocked += 1;
                    } else {
                        clear += 1;
                    }
                }
            }
        }
    }
    assert!(
        blocked >= 20 && clear >= 20,
        "blocked {blocked}, clear {clear}"
    );
}

/// Whether the arc from `x` to `image` in the field `b` enters a disk of the lattice on the way
/// (`None`: within 10⁻⁴ of one, undecided), by sampling the circle in `f64`.
fn brute_force(
    x: &OrbitPoint,
    image: &OrbitPoint,
    b: f64,
    centre: &dyn Fn([i64; 2]) -> [f64; 2],
) -> Option<bool> {
    let point = |o: &OrbitPoint| {
        let c = centre(o.disk);
        let s = o.s.to_f64();
        [c[0] + s.cos(), c[1] + s.sin()]
    };
    let (s, p) = (x.s.to_f64(), x.p.to_f64());
    let cphi = (1.0 - p * p).sqrt();
    let v = [cphi * s.cos() - p * s.sin(), cphi * s.sin() + p * s.cos()];
    let (x0, x1) = (point(x), point(image));
    let m = [x0[0] - v[1] / b, x0[1] + v[0] / b];
    let u0 = [x0[0] - m[0], x0[1] - m[1]];
    let u1 = [x1[0] - m[0], x1[1] - m[1]];
    let sg = b.signum();
    let mut theta1 = (sg * (u0[0] * u1[1] - u0[1] * u1[0])).atan2(u0[0] * u1[0] + u0[1] * u1[1]);
    if theta1 <= 0.0 {
        theta1 += 2.0 * std::f64::consts::PI;
    }
    let rho = 1.0 / b.abs();
    let mut near = Vec::new();
    for dj in -3..=3 {
        for di in -4..=4 {
            let c = centre([di, dj]);
            if [di, dj] != image.disk && (c[0] - m[0]).hypot(c[1] - m[1]) < rho + 1.5 {
                near.push(([di, dj], c));
            }
        }
    }
    let mut min = f64::INFINITY;
    let samples = 4000;
    for i in 1..samples {
        let th = sg * theta1 * i as f64 / samples as f64;
        let q = [
            m[0] + th.cos() * u0[0] - th.sin() * u0[1],
            m[1] + th.sin() * u0[0] + th.cos() * u0[1],
        ];
        for (d, c) in &near {
            let gap = (q[0] - c[0]).hypot(q[1] - c[1]) - 1.0;
            // The disk left: only a re-entry counts (the arc starts on its boundary).
            if *d == x.disk && gap > -1e-4 {
                continue;
            }
            min = min.min(gap);
        }
    }
    if min < -1e-4 {
        Some(true)
    } else if min > 1e-4 {
        Some(false)
    } else {
        None
    }
}

/// The square lattice, with and without a field (its corridors give long flights without one):
/// every f64 segment is shadowed by a certified true orbit, Newton converging quadratically, as
/// on the triangular lattice (`lorentz shadow --scene square --radius R [--field B]`).
#[test]
fn f64_segments_of_the_square_lattice_are_shadowed_with_and_without_a_field() {
    let sc = lorentz_gas::scenes::square::SquareScene::exact(parse_exact("1/4").unwrap()).unwrap();
    for field in [None, Some("1"), Some("-1/2")] {
        let request = ShadowConfig {
            collisions_per_segment: 300,
            segments: 3,
            seed: 1,
            reference_bits: BITS,
            motion: MotionInput {
                field: field.map(str::to_string),
                ..Default::default()
            },
        };
        let r = shadowing::run(&sc, &request, &crate::common::threads(1)).unwrap();
        assert!(r.scene.starts_with("square"), "{}", r.scene);
        for s in &r.segments {
            let what = format!("square r = 1/4, B = {field:?}, segment {}", s.segment);
            assert_clean(&s.shadow, &what);
            assert!(s.shadow.iterations <= 4, "{what}: quadratic convergence");
        }
    }
}
