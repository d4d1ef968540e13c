//! `lorentz_gas::estimators::trajectory` against an independent reference written here: plain world
//! coordinates at 2000 bits, the first disk hit found by brute force over every lattice point
//! within reach (textbook quadratic formula), specular reflection, time accumulated until T.
//! It shares no code with the crate's kernel, cells or lattice walk.

use rug::ops::Pow;
use rug::{Float, Integer, Rational};

use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::trajectory::{TrajectoryInput, TrajectoryReport, decimal};
use lorentz_gas::numbers::exact::parse_exact;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::square::SquareScene;
use lorentz_gas::scenes::triangular::TriangularScene;

/// Precision of the reference: far beyond the few hundred bits ten to twenty collisions lose.
const REF_BITS: u32 = 2000;

/// A table-driven case: lattice, size, start, direction, time and a last field of the test's own.
type Case<'a, T> = (
    &'a str,
    &'a str,
    (&'a str, &'a str),
    (&'a str, &'a str),
    &'a str,
    T,
);

/// The disk lattice of the reference, in world coordinates.
enum Disks {
    /// Radius r at every integer point.
    Square { r: Float },
    /// Radius 1 at a(i + j/2, j√3/2), a = 2 + w.
    Triangular { a: Float, h: Float },
}

impl Disks {
    fn square(r: &str) -> Self {
        Disks::Square {
            r: Float::with_val(REF_BITS, &parse_exact(r).unwrap()),
        }
    }
    fn triangular(w: &str) -> Self {
        let a = Float::with_val(REF_BITS, &parse_exact(w).unwrap()) + 2u32;
        let h = a.clone() * Float::with_val(REF_BITS, 3u32).sqrt() / 2u32;
        Disks::Triangular { a, h }
    }
    fn radius(&self) -> Float {
        match self {
            Disks::Square { r } => r.clone(),
            Disks::Triangular { .. } => Float::with_val(REF_BITS, 1u32),
        }
    }
    /// Every disk centre within `reach` of (px, py) (a superset: a bounding box of lattice
    /// indices), with its index.
    fn near(&self, px: &Float, py: &Float, reach: &Float) -> Vec<((i64, i64), Float, Float)> {
        let floor = |f: Float| f.floor().to_f64() as i64;
        let ceil = |f: Float| f.ceil().to_f64() as i64;
        let mut out = Vec::new();
        match self {
            Disks::Square { .. } => {
                for i in floor(px.clone() - reach)..=ceil(px.clone() + reach) {
                    for j in floor(py.clone() - reach)..=ceil(py.clone() + reach) {
                        out.push((
                            (i, j),
                            Float::with_val(REF_BITS, i),
                            Float::with_val(REF_BITS, j),
                        ));
                    }
                }
            }
            Disks::Triangular { a, h } => {
                let j0 = floor((py.clone() - reach) / h) - 1;
                let j1 = ceil((py.clone() + reach) / h) + 1;
                for j in j0..=j1 {
                    let half_j = Float::with_val(REF_BITS, j) / 2u32;
                    let i0 = floor((px.clone() - reach) / a - &half_j) - 1;
                    let i1 = ceil((px.clone() + reach) / a - &half_j) + 1;
                    for i in i0..=i1 {
                        let cx = a.clone() * (Float::with_val(REF_BITS, i) + &half_j);
                        let cy = h.clone() * j;
                        out.push(((i, j), cx, cy));
                    }
                }
            }
        }
        out
    }
}

/// The reference flow: (x, y, distance, collisions) at time `t`.
fn reference(disks: &Disks, start: (&str, &str), dir: (&str, &str), t: &str) -> ([Float; 3], u64) {
    let f = |s: &str| Float::with_val(REF_BITS, &parse_exact(s).unwrap());
    let (mut px, mut py) = (f(start.0), f(start.1));
    let (dx, dy) = (f(dir.0), f(dir.1));
    let norm = (dx.clone() * &dx + dy.clone() * &dy).sqrt();
    let (mut vx, mut vy) = (dx / &norm, dy / &norm);
    let r = disks.radius();
    let r2 = r.clone() * &r;
    let mut remaining = f(t);
    let mut last: Option<(i64, i64)> = None;
    let mut collisions = 0;
    loop {
        let reach = remaining.clone() + &r + 1u32;
        let mut best: Option<(Float, Float, Float, (i64, i64))> = None;
        for (ij, cx, cy) in disks.near(&px, &py, &reach) {
            if last == Some(ij) {
                continue;
            }
            // |p + t v − c|² = r²: t² + 2bt + c₀ = 0 with b = v·(p − c), c₀ = |p − c|² − r².
            let (ox, oy) = (px.clone() - &cx, py.clone() - &cy);
            let b = vx.clone() * &ox + vy.clone() * &oy;
            let c0 = ox.clone() * &ox + oy.clone() * &oy - &r2;
            let disc = b.clone() * &b - &c0;
            if disc <= 0 {
                continue;
            }
            let hit = -b - disc.sqrt();
            if hit <= 0 {
                continue;
            }
            if best.as_ref().is_none_or(|(bt, ..)| hit < *bt) {
                best = Some((hit, cx, cy, ij));
            }
        }
        match best {
            Some((hit, cx, cy, ij)) if hit <= remaining => {
                px += vx.clone() * &hit;
                py += vy.clone() * &hit;
                let (nx, ny) = (px.clone() - &cx, py.clone() - &cy);
                let k = (vx.clone() * &nx + vy.clone() * &ny) * 2u32 / &r2;
                vx -= k.clone() * &nx;
                vy -= k * &ny;
                remaining -= &hit;
                last = Some(ij);
                collisions += 1;
            }
            _ => {
                px += vx.clone() * &remaining;
                py += vy.clone() * &remaining;
                let d = (px.clone() * &px + py.clone() * &py).sqrt();
                return ([px, py, d], collisions);
            }
        }
    }
}

fn input(start: (&str, &str), dir: (&str, &str), t: &str, digits: u32) -> TrajectoryInput {
    TrajectoryInput {
        x: parse_exact(start.0).unwrap(),
        y: parse_exact(start.1).unwrap(),
        dx: parse_exact(dir.0).unwrap(),
        dy: parse_exact(dir.1).unwrap(),
        time: parse_exact(t).unwrap(),
        digits,
        record_events: false,
        field: None,
        electric: None,
    }
}

/// One certified trajectory of `scene` (events recorded if `events`).
fn trajectory<S: Scene>(
    scene: &S,
    input: &TrajectoryInput,
    events: bool,
) -> Result<TrajectoryReport, lorentz_gas::Error> {
    let input = TrajectoryInput {
        record_events: events,
        ..input.clone()
    };
    lorentz_gas::estimators::trajectory::run(scene, &input, &RunOptions::default())
}

/// Integer digits of |q| (0 below 1): the printed digits end at 10^(lead − certified).
fn lead(q: &Float) -> i64 {
    if q.is_zero() {
        0
    } else {
        (q.to_f64().abs().log10().floor() as i64 + 1).max(0)
    }
}

/// Every printed value is within one unit of its last digit of the reference, the collision
/// count is the reference's, and the certified digits never exceed the agreement less the guard.
fn check(report: &TrajectoryReport, reference: &([Float; 3], u64), what: &str) {
    let (values, collisions) = reference;
    assert_eq!(report.collisions, *collisions, "{what}: collisions");
    assert!(report.certified_digits >= report.digits_requested, "{what}");
    assert!(
        report.certified_digits as f64 <= report.digits_agreed - 1.0,
        "{what}: certified {} digits, but P and 2P agree to {:.2}",
        report.certified_digits,
        report.digits_agreed
    );
    for (k, (printed, exact)) in [&report.x, &report.y, &report.distance]
        .into_iter()
        .zip(values)
        .enumerate()
    {
        let p = Float::with_val(REF_BITS, Float::parse(printed).unwrap());
        let digits_after_point = printed.split_once('.').map_or(0, |(_, f)| f.len()) as i64;
        assert_eq!(
            digits_after_point,
            report.certified_digits as i64 - lead(exact),
            "{what}: value {k} prints {printed}"
        );
        let unit = Float::with_val(REF_BITS, Float::i_pow_u(10, 0))
            / Float::with_val(REF_BITS, Integer::from(10).pow(digits_after_point as u32));
        let err = (p - exact).abs();
        assert!(
            err <= unit,
            "{what}: value {k} = {printed} is off the reference {} by {} (more than one unit, {})",
            exact.to_string_radix(10, Some(40)),
            err.to_f64(),
            unit.to_f64()
        );
    }
}

#[test]
fn siam_problem_2_distance_at_t_10_to_100_digits() {
    let scene = SquareScene::exact(parse_exact("1/3").unwrap()).unwrap();
    let (start, dir, t) = (("1/2", "1/10"), ("1", "0"), "10");
    let r = trajectory(&scene, &input(start, dir, t, 100), false).unwrap();
    let reference = reference(&Disks::square("1/3"), start, dir, t);
    check(&r, &reference, "SIAM problem 2");
    // The first 100 digits, each correctly rounded from its own computation.
    assert_eq!(decimal(&r.values[2], 100), decimal(&reference.0[2], 100));
    assert!(r.distance.starts_with("0.99526"), "{}", r.distance);
}

#[test]
fn variants_agree_with_the_brute_force_reference() {
    let cases: [Case<u32>; 6] = [
        ("square", "1/4", ("1/2", "1/3"), ("3", "4"), "7", 50),
        ("square", "0.2", ("0.3", "-0.45"), ("-1", "2"), "15", 40),
        ("square", "1/3", ("0.5", "0.1"), ("1", "0"), "12.5", 60),
        (
            "triangular",
            "1/10",
            ("1.05", "0.6"),
            ("1", "0.3"),
            "10",
            50,
        ),
        ("triangular", "0.1", ("2.1", "1.1"), ("-2", "-7"), "6", 80),
        ("triangular", "0.2", ("-1.1", "-0.6"), ("-2", "1"), "8", 30),
    ];
    for (name, param, start, dir, t, digits) in cases {
        let what = format!("{name} {param} from {start:?} along {dir:?} for {t}");
        let inp = input(start, dir, t, digits);
        let (r, disks) = if name == "square" {
            let s = SquareScene::exact(parse_exact(param).unwrap()).unwrap();
            (trajectory(&s, &inp, false), Disks::square(param))
        } else {
            let s = TriangularScene::exact(parse_exact(param).unwrap()).unwrap();
            (trajectory(&s, &inp, false), Disks::triangular(param))
        };
        let r = r.unwrap_or_else(|e| panic!("{what}: {e}"));
        assert!(r.collisions > 0, "{what}: no collision");
        check(&r, &reference(&disks, start, dir, t), &what);
    }
}

#[test]
fn events_are_recorded_in_order_up_to_time_t() {
    let scene = TriangularScene::exact(parse_exact("1/10").unwrap()).unwrap();
    let r = trajectory(
        &scene,
        &input(("1.05", "0.6"), ("1", "0.3"), "10", 20),
        true,
    )
    .unwrap();
    assert_eq!(r.events.len() as u64, r.collisions + r.crossings);
    let times: Vec<f64> = r.events.iter().map(|e| e.time.parse().unwrap()).collect();
    assert!(times.windows(2).all(|w| w[0] <= w[1]));
    assert!(times.last().is_some_and(|&t| t <= 10.0));
}

/// In a field every recorded event gives the centre of the arc that follows it: the event point
/// and the next one are both at 1/|B| from that centre (to the 20 printed digits, 1e-15 here),
/// and the velocity after the event is a unit vector tangent to the circle, turning
/// counter-clockwise for B > 0 ((p − c) × v = +1/|B|·sign B). Without a field there is no
/// centre. Broken on purpose (the centre on the other side, (x, y) − (−vy, vx)/B), the next
/// event is 2/|B| off the circle and the test fails.
#[test]
fn events_in_a_field_give_the_centre_of_the_following_arc() {
    let scene = TriangularScene::exact(parse_exact("1/10").unwrap()).unwrap();
    for b in ["1/2", "-3/2"] {
        let mut inp = input(("1.05", "0.6"), ("1", "0.3"), "10", 20);
        inp.field = Some(parse_exact(b).unwrap());
        let r = trajectory(&scene, &inp, true).unwrap();
        let bf: f64 = parse_exact(b).unwrap().to_f64();
        let radius = 1.0 / bf.abs();
        let num = |s: &str| s.parse::<f64>().unwrap();
        assert!(r.events.len() > 5, "{b}: {} events", r.events.len());
        for pair in r.events.windows(2) {
            let (e, next) = (&pair[0], &pair[1]);
            let (cx, cy) = e.centre.as_ref().map(|(x, y)| (num(x), num(y))).unwrap();
            let (px, py, vx, vy) = (num(&e.x), num(&e.y), num(&e.vx), num(&e.vy));
            assert!(((px - cx).hypot(py - cy) - radius).abs() < 1e-12, "{b}");
            assert!(
                ((num(&next.x) - cx).hypot(num(&next.y) - cy) - radius).abs() < 1e-12,
                "{b}"
            );
            assert!((vx.hypot(vy) - 1.0).abs() < 1e-15);
            let cross = (px - cx) * vy - (py - cy) * vx;
            assert!((cross - radius * bf.signum()).abs() < 1e-12, "{b}: {cross}");
        }
    }
    let straight = trajectory(
        &scene,
        &input(("1.05", "0.6"), ("1", "0.3"), "10", 20),
        true,
    );
    assert!(straight.unwrap().events.iter().all(|e| e.centre.is_none()));
}

#[test]
fn starts_inside_a_disk_and_zero_directions_are_refused() {
    let square = SquareScene::exact(parse_exact("1/3").unwrap()).unwrap();
    let e = trajectory(&square, &input(("2.1", "-0.9"), ("1", "0"), "1", 10), false)
        .unwrap_err()
        .to_string();
    assert!(e.contains("inside the disk at (2, -1)"), "{e}");
    let e = trajectory(&square, &input(("0.5", "0.1"), ("0", "0"), "1", 10), false)
        .unwrap_err()
        .to_string();
    assert!(e.contains("direction = 0,0: a zero direction"), "{e}");
    let tri = TriangularScene::exact(parse_exact("0.1").unwrap()).unwrap();
    let e = trajectory(&tri, &input(("2.5", "0.1"), ("1", "0"), "1", 10), false)
        .unwrap_err()
        .to_string();
    assert!(e.contains("inside the disk at (2.1, 0)"), "{e}");
    for (t, d) in [("0", 10), ("-1", 10), ("1", 0), ("1", 10_001)] {
        assert!(
            trajectory(&square, &input(("0.5", "0.1"), ("1", "0"), t, d), false,).is_err(),
            "time {t}, digits {d} accepted"
        );
    }
}

/// A start on the edge between two square cells is located on one side of it (the nearest
/// lattice point, halves away from zero): world x = ½ lies in cell 1 at local x = −½, world
/// x = −½ in cell −1 at local x = +½. Both are the same physical start modulo the lattice vector
/// (1, 0), so the two trajectories are translates of each other: x differs by exactly 1 and y is
/// the same — one flown from the left side of the edge, the other from its right side, where a
/// flight leaving the cell must cross at time 0. The same along y. Each run is also checked
/// against the brute-force reference, and the two printed values (each within one unit of its
/// last digit of the exact value) agree within two units.
#[test]
fn a_start_on_a_cell_boundary_gives_the_same_trajectory_from_either_side() {
    let scene = SquareScene::exact(parse_exact("1/3").unwrap()).unwrap();
    let disks = Disks::square("1/3");
    // (start on the positive edge, the same start on the negative edge, direction, offset)
    type Case<'a> = (
        (&'a str, &'a str),
        (&'a str, &'a str),
        (&'a str, &'a str),
        (i64, i64),
    );
    let cases: [Case; 4] = [
        (("1/2", "1/10"), ("-1/2", "1/10"), ("1", "0"), (1, 0)),
        (("1/2", "1/10"), ("-1/2", "1/10"), ("-1", "3/10"), (1, 0)),
        (("3/10", "1/2"), ("3/10", "-1/2"), ("1/5", "1"), (0, 1)),
        (("3/10", "1/2"), ("3/10", "-1/2"), ("-2/5", "-1"), (0, 1)),
    ];
    for (plus, minus, dir, (di, dj)) in cases {
        let what = format!("from {plus:?} and {minus:?} along {dir:?}");
        // The two starts are located in the neighbouring cells' frames, on opposite sides.
        let side = |start: (&str, &str)| {
            let (x, y) = (parse_exact(start.0).unwrap(), parse_exact(start.1).unwrap());
            let (cell, p) = scene.locate::<Float>(256, &x, &y).unwrap();
            // The coordinate across the edge (±½, a dyadic) is exact in the cell's frame.
            let (index, local, world) = if di == 1 {
                (cell.i, &p.x, x)
            } else {
                (cell.j, &p.y, y)
            };
            assert_eq!(
                Rational::from(index) + local.to_rational().unwrap(),
                world,
                "{what}: located elsewhere"
            );
            (
                cell.i,
                cell.j,
                p.x.to_f64() * di as f64 + p.y.to_f64() * dj as f64,
            )
        };
        let (ip, jp, local_p) = side(plus);
        let (im, jm, local_m) = side(minus);
        assert_eq!((ip - im, jp - jm), (2 * di, 2 * dj), "{what}: cells");
        assert_eq!(
            (local_p, local_m),
            (-0.5, 0.5),
            "{what}: the two sides of the edge"
        );
        let run = |start| {
            let r = trajectory(&scene, &input(start, dir, "8", 40), false)
                .unwrap_or_else(|e| panic!("{what}: {e}"));
            check(&r, &reference(&disks, start, dir, "8"), &what);
            r
        };
        let (a, b) = (run(plus), run(minus));
        assert!(a.collisions > 0, "{what}: no collision");
        assert_eq!(a.collisions, b.collisions, "{what}: collisions");
        let unit = Float::with_val(REF_BITS, Float::i_exp(1, 0))
            / Float::with_val(
                REF_BITS,
                Integer::from(10).pow(a.certified_digits.min(b.certified_digits)),
            );
        for (k, shift) in [(0, di), (1, dj)] {
            let gap = (a.values[k].clone() - &b.values[k] - shift).abs();
            assert!(
                gap <= unit.clone() * 2u32,
                "{what}: value {k} differs between the two sides by {} (beyond the shift {shift})",
                gap.to_f64()
            );
        }
    }
}

/// `p` turned by the angle φ about `c`.
fn turn((px, py): (&Float, &Float), (cx, cy): (&Float, &Float), phi: &Float) -> (Float, Float) {
    let (s, c) = (phi.clone().sin(), phi.clone().cos());
    let (ox, oy) = (px.clone() - cx, py.clone() - cy);
    (
        cx.clone() + c.clone() * &ox - s.clone() * &oy,
        cy.clone() + s * &ox + c * &oy,
    )
}

/// The reference flow in the field `b` (≠ 0): the particle turns at the angular velocity b about
/// its cyclotron centre C = p + Jv/b; the next collision is the earliest point, along the
/// circle, where it meets a disk's circle moving into the disk (the textbook intersection of two
/// circles, angles by atan2); then specular reflection. No event: it circles until T.
fn reference_arc(
    disks: &Disks,
    start: (&str, &str),
    dir: (&str, &str),
    t: &str,
    b: &str,
) -> ([Float; 3], u64) {
    let f = |s: &str| Float::with_val(REF_BITS, &parse_exact(s).unwrap());
    let (mut px, mut py) = (f(start.0), f(start.1));
    let (dx, dy) = (f(dir.0), f(dir.1));
    let norm = (dx.clone() * &dx + dy.clone() * &dy).sqrt();
    let (mut vx, mut vy) = (dx / &norm, dy / &norm);
    let (w, r) = (f(b), disks.radius());
    let rho = Float::with_val(REF_BITS, 1u32) / w.clone().abs();
    let tau = Float::with_val(REF_BITS, rug::float::Constant::Pi) * 2u32;
    let mut remaining = f(t);
    let mut collisions = 0;
    loop {
        let (cx, cy) = (px.clone() - vy.clone() / &w, py.clone() + vx.clone() / &w);
        // Disks the arc can meet before T: within the remaining path (or the circle) of p.
        let path = if remaining < rho.clone() * 2u32 {
            remaining.clone()
        } else {
            rho.clone() * 2u32
        };
        let mut best: Option<(Float, Float, Float, Float, Float)> = None;
        for (_, ex, ey) in disks.near(&px, &py, &(path + &r)) {
            let (ux, uy) = (ex.clone() - &cx, ey.clone() - &cy);
            let d = (ux.clone() * &ux + uy.clone() * &uy).sqrt();
            let a = (rho.clone() * &rho - r.clone() * &r + d.clone() * &d) / (d.clone() * 2u32);
            let h2 = rho.clone() * &rho - a.clone() * &a;
            if h2 <= 0 {
                continue;
            }
            let h = h2.sqrt();
            let (ux, uy) = (ux / &d, uy / &d);
            for sgn in [-1i32, 1] {
                let qx = cx.clone() + a.clone() * &ux - h.clone() * &uy * sgn;
                let qy = cy.clone() + a.clone() * &uy + h.clone() * &ux * sgn;
                // The angle from p to q about C in the sense of the motion, in [0, 2π).
                let (ox, oy) = (px.clone() - &cx, py.clone() - &cy);
                let (qx0, qy0) = (qx.clone() - &cx, qy.clone() - &cy);
                let cross = ox.clone() * &qy0 - oy.clone() * &qx0;
                let dot = ox * &qx0 + oy * &qy0;
                let mut theta = cross.atan2(&dot);
                if w < 0 {
                    theta = -theta;
                }
                if theta < 0 {
                    theta += &tau;
                }
                let time = theta.clone() * &rho;
                // Moving into the disk at q: (q − e)·v(q) < 0.
                let (wx, wy) = turn(
                    (&vx, &vy),
                    (&Float::new(REF_BITS), &Float::new(REF_BITS)),
                    &(w.clone() * &time),
                );
                let into = (qx.clone() - &ex) * &wx + (qy.clone() - &ey) * &wy;
                if into >= 0 || time.is_zero() {
                    continue;
                }
                if best.as_ref().is_none_or(|(bt, ..)| time < *bt) {
                    best = Some((time, qx, qy, ex.clone(), ey.clone()));
                }
            }
        }
        match best {
            Some((time, qx, qy, ex, ey)) if time <= remaining => {
                let phi = w.clone() * &time;
                let zero = Float::new(REF_BITS);
                let (ux, uy) = turn((&vx, &vy), (&zero, &zero), &phi);
                let (nx, ny) = ((qx.clone() - &ex) / &r, (qy.clone() - &ey) / &r);
                let k = (ux.clone() * &nx + uy.clone() * &ny) * 2u32;
                (vx, vy) = (ux - k.clone() * &nx, uy - k * &ny);
                (px, py) = (qx, qy);
                remaining -= &time;
                collisions += 1;
            }
            _ => {
                let (x, y) = turn((&px, &py), (&cx, &cy), &(w.clone() * &remaining));
                let d = (x.clone() * &x + y.clone() * &y).sqrt();
                return ([x, y, d], collisions);
            }
        }
    }
}

#[test]
fn trajectories_in_a_field_agree_with_the_circle_intersection_reference() {
    let cases: [Case<&str>; 7] = [
        ("triangular", "1/10", ("1.05", "0"), ("0", "1"), "10", "1"),
        (
            "triangular",
            "0.3",
            ("1.05", "0.6"),
            ("1", "1/3"),
            "12",
            "-1/2",
        ),
        ("triangular", "0.2", ("1.1", "0.4"), ("-2", "1"), "6", "7/2"),
        (
            "triangular",
            "0.1",
            ("1.05", "0.6"),
            ("1", "0"),
            "8",
            "1/1000",
        ),
        // A pinned orbit across the gap: radius 1/10 about the gap's middle, no collision.
        ("triangular", "0.3", ("1.15", "-0.1"), ("1", "0"), "3", "10"),
        ("square", "1/4", ("1/2", "1/3"), ("3", "4"), "9", "2/3"),
        ("square", "0.2", ("0.3", "-0.45"), ("-1", "2"), "7", "-3"),
    ];
    let mut collided = Vec::new();
    for (scene, p, start, dir, t, b) in cases {
        let mut inp = input(start, dir, t, 30);
        inp.field = Some(parse_exact(b).unwrap());
        let (r, disks) = if scene == "square" {
            let s = SquareScene::exact(parse_exact(p).unwrap()).unwrap();
            (trajectory(&s, &inp, false).unwrap(), Disks::square(p))
        } else {
            let s = TriangularScene::exact(parse_exact(p).unwrap()).unwrap();
            (trajectory(&s, &inp, false).unwrap(), Disks::triangular(p))
        };
        let what = format!("{scene} {p}, start {start:?}, direction {dir:?}, T = {t}, B = {b}");
        let reference = reference_arc(&disks, start, dir, t, b);
        check(&r, &reference, &what);
        collided.push(reference.1);
        assert_eq!(
            r.motion.field.as_deref(),
            Some(parse_exact(b).unwrap().to_string().as_str())
        );
    }
    // Collisions in every case but the pinned orbit: the reflections are compared too.
    assert_eq!(
        collided.iter().filter(|&&n| n == 0).count(),
        1,
        "{collided:?}"
    );
    assert!(collided.iter().sum::<u64>() >= 20, "{collided:?}");
}
