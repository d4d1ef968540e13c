//! The magnetic tangent map (`verification::arc_tangent`) against finite differences of certified
//! trajectories: two orbits whose starts differ by ε (exact rationals) are run to time T by
//! `estimators::trajectory` at 40 certified digits, and (x_ε(T) − x(T))/ε must be the tangent
//! vector's δq(T). Error model: the second-order term ε·|d²x/dq²| ≲ ε·g² for a growth g ≲ 10³
//! over the few collisions run, and f64 rounding amplified by g: far below 10⁻⁶ relative, while a
//! missing term of the collision map (the field's acceleration, of relative size |ω δt|) is
//! of order 1.

use nalgebra::Vector4;
use rug::{Float, Rational};

use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::trajectory::{self, TrajectoryInput};
use lorentz_gas::kernel::arc::arc_time;
use lorentz_gas::kernel::flight::Flight;
use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::numbers::exact::{nearest_f64, parse_exact};
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::lattice::LatticeState;
use lorentz_gas::scenes::triangular::TriangularScene;
use lorentz_gas::verification::arc_tangent::{arc_flight, arc_tangent_step};

/// δq(T) in world coordinates of the tangent vector that starts as (δq, 0) in world coordinates.
fn tangent(
    scene: &TriangularScene,
    start: (&str, &str),
    dir: (f64, f64),
    t: f64,
    b: f64,
    dq: (f64, f64),
) -> (f64, f64) {
    let q = |s: &str| parse_exact(s).unwrap();
    let lat = scene.lattice::<f64>(()).unwrap();
    let (cell, pos) = scene.locate::<f64>((), &q(start.0), &q(start.1)).unwrap();
    let n = dir.0.hypot(dir.1);
    let sg = if cell.down { -1.0 } else { 1.0 };
    let vel = Vec2::new(sg * dir.0 / n, sg * dir.1 / n);
    let mut s = LatticeState {
        cell,
        flight: Flight::new(pos, vel),
    };
    let mut tv = Vector4::new(sg * dq.0, sg * dq.1, 0.0, 0.0);
    let mut elapsed = 0.0;
    loop {
        let ev = lat.next_event_in_field(&s, &b).expect("an event");
        let dt = arc_time(&s.flight.vel, &ev.chord, &b);
        if elapsed + dt > t {
            arc_flight(&mut tv, t - elapsed, b);
            break;
        }
        arc_tangent_step(&mut tv, &s.flight, &ev, dt, lat.cell(), b);
        lat.apply_in_field(&mut s, &ev);
        elapsed += dt;
    }
    let sg = if s.cell.down { -1.0 } else { 1.0 };
    (sg * tv[0], sg * tv[1])
}

/// The certified world position at time `t` (40 digits) and the collisions on the way.
fn position(
    scene: &TriangularScene,
    start: (&Rational, &Rational),
    dir: (&str, &str),
    t: &str,
    b: &str,
) -> (Float, Float, u64) {
    let q = |s: &str| parse_exact(s).unwrap();
    let input = TrajectoryInput {
        x: start.0.clone(),
        y: start.1.clone(),
        dx: q(dir.0),
        dy: q(dir.1),
        time: q(t),
        digits: 40,
        record_events: false,
        field: Some(q(b)),
        electric: None,
    };
    let r = trajectory::run(scene, &input, &RunOptions::default()).unwrap();
    let [x, y, _] = r.values;
    (x, y, r.collisions)
}

#[test]
fn the_magnetic_tangent_map_is_the_derivative_of_the_flow() {
    let eps = Rational::from((1, 1_000_000_000_000_000u64)); // 10⁻¹⁵
    let cases = [
        ("0.2", ("1.1", "0.4"), ("-2", "1"), "2", "1/2"),
        ("0.1", ("1.05", "0.6"), ("1", "0"), "1.5", "-3"),
        ("0.3", ("1.05", "0.6"), ("1", "1/3"), "2", "2"),
        ("0.25", ("1.2", "-0.5"), ("-1", "-4"), "1", "10"),
    ];
    let mut collisions = 0;
    for (w, start, dir, t, b) in cases {
        let scene = TriangularScene::exact(parse_exact(w).unwrap()).unwrap();
        let (x0, y0) = (parse_exact(start.0).unwrap(), parse_exact(start.1).unwrap());
        let (px, py, n) = position(&scene, (&x0, &y0), dir, t, b);
        collisions += n;
        let d = (
            nearest_f64(&parse_exact(dir.0).unwrap()),
            nearest_f64(&parse_exact(dir.1).unwrap()),
        );
        let (tf, bf) = (
            nearest_f64(&parse_exact(t).unwrap()),
            nearest_f64(&parse_exact(b).unwrap()),
        );
        for (ex, ey) in [(1.0, 0.0), (0.0, 1.0)] {
            let xs = x0.clone() + eps.clone() * ex as i32;
            let ys = y0.clone() + eps.clone() * ey as i32;
            let (qx, qy, m) = position(&scene, (&xs, &ys), dir, t, b);
            assert_eq!(m, n, "w={w} B={b}: the perturbed orbit met other disks");
            let e = Float::with_val(256, &eps);
            let fd = (((qx - &px) / &e).to_f64(), ((qy - &py) / &e).to_f64());
            let tg = tangent(&scene, start, d, tf, bf, (ex, ey));
            let err = (fd.0 - tg.0).hypot(fd.1 - tg.1) / tg.0.hypot(tg.1);
            assert!(
                err < 1e-6,
                "w={w} B={b} δq=({ex},{ey}): finite difference {fd:?}, tangent map {tg:?} (relative {err:e})"
            );
        }
    }
    // The collision map is exercised, not only free flights and crossings.
    assert!(collisions >= 8, "{collisions} collisions");
}

/// The tangent vector carried from collision to collision (`CollisionTangent`: one free flight
/// per arc, its rotation from the arc's velocities, its time from the arc's chord) against the
/// map applied event by event (`arc_tangent_step`, checked against finite differences above):
/// over 2000 collisions on the triangular lattice (point-reflecting crossings) and the square
/// one (translations), each collision's growth and each arc's time agree to 10⁻⁹ relative.
/// Error model: both are the same map in f64, differing by rounding (a few ulps per arc),
/// amplified by at most the condition of one collision map (≲ 10³ at grazing incidence).
#[test]
fn carried_from_collision_to_collision_the_tangent_map_is_the_event_by_event_one() {
    use lorentz_gas::scenes::square::SquareScene;
    use lorentz_gas::verification::arc_tangent::{CollisionTangent, TangentCell};
    fn check<S: Scene>(scene: &S, b: f64) {
        let lat = scene.lattice::<f64>(()).unwrap();
        let cell = TangentCell::new(lat.cell(), b);
        use rand::SeedableRng;
        let mut s = scene.sample(&mut rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(7));
        while lat.next_event_in_field(&s, &b).is_none() {
            s.flight.vel = Vec2::new(-s.flight.vel.y, s.flight.vel.x);
        }
        let v0 = Vector4::new(-s.flight.vel.y, s.flight.vel.x, 0.3, -0.2);
        let (mut each, mut carried) = (v0, CollisionTangent::new(v0));
        let (mut time, mut n) = (0.0, 0);
        while n < 2000 {
            let Some(ev) = lat.next_event_in_field(&s, &b) else {
                panic!("{}: no next event", scene.label());
            };
            let dt = arc_time(&s.flight.vel, &ev.chord, &b);
            arc_tangent_step(&mut each, &s.flight, &ev, dt, lat.cell(), b);
            time += dt;
            if let Some((growth, t)) = carried.event(&s.flight, &ev, &cell, b) {
                let g = each.norm();
                each /= g;
                let at = format!("{} B={b}, collision {n}", scene.label());
                assert!(
                    (growth - g).abs() <= 1e-9 * g,
                    "{at}: growth {growth} vs {g}"
                );
                assert!((t - time).abs() <= 1e-9 * time, "{at}: time {t} vs {time}");
                let d = (carried.vector() - each).norm();
                assert!(d <= 1e-9, "{at}: vectors differ by {d:e}");
                (time, n) = (0.0, n + 1);
            }
            lat.apply_in_field(&mut s, &ev);
        }
    }
    check(&TriangularScene::new(0.1).unwrap(), 1.0);
    check(&TriangularScene::new(0.2).unwrap(), -2.5);
    check(&SquareScene::new(0.3).unwrap(), 0.7);
}
