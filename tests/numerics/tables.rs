//! Tables given as data (`scenes::table`), against brute force: on random sheared lattices with
//! one to three disks of random radii (16 tables, 1500 events each), the world segment of every
//! flight, its ends included, meets no disk of the table (every image in the 5×5 block of cells
//! around it, at 192 bits); the table's exact horizon agrees with long straight flights.

use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::lattice::LatticeState;
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::table::PeriodicTable;
use lorentz_gas::scenes::table::spec::TableSpec;
use rand::Rng;
use rug::{Float, Rational};

const BITS: u32 = 192;

/// A disk of a table: its centre and radius, exactly.
pub(super) type Disk = ([Rational; 2], Rational);

/// A random table: e1 = (1, 0), e2 = (b, h), up to three disks at fractional coordinates (u, v)
/// of the cell, every number a multiple of 1/64; `None` where the disks overlap.
pub(super) fn random_table(rng: &mut impl Rng) -> Option<(PeriodicTable, Vec<Disk>)> {
    let q = |n: i64| Rational::from((n, 64));
    let (b, h) = (q(rng.random_range(-32..=32)), q(rng.random_range(40..=96)));
    let mut text = format!("[lattice]\ne1 = [\"1\", \"0\"]\ne2 = [\"{b}\", \"{h}\"]\n");
    let mut disks = Vec::new();
    for _ in 0..rng.random_range(1..=3) {
        let (u, v) = (q(rng.random_range(0..64)), q(rng.random_range(0..64)));
        let r = q(rng.random_range(2..=24));
        let c = [u.clone() + v.clone() * &b, v * &h];
        text += &format!(
            "[[disks]]\ncentre = [\"{}\", \"{}\"]\nradius = \"{r}\"\n",
            c[0], c[1]
        );
        disks.push((c, r));
    }
    let spec = TableSpec::from_toml(&text).unwrap();
    let table = PeriodicTable::new(&spec).ok()?;
    Some((table, disks))
}

/// Distance² from `c` to the segment [a, b] minus r², at the points' precision.
fn clearance(a: &Vec2<Float>, b: &Vec2<Float>, c: &Vec2<Float>, r2: &Float) -> f64 {
    let ab = b.sub(a);
    let l2 = ab.norm2();
    let t = if l2.is_zero() {
        Float::with_val(BITS, 0)
    } else {
        (c.sub(a).dot(&ab) / &l2).clamp(&0, &1)
    };
    (a.along(&t, &ab).sub(c).norm2() - r2).to_f64()
}

#[test]
fn no_flight_of_a_random_table_crosses_a_disk() {
    let mut rng = stream(97, 0);
    let mut tables = 0;
    while tables < 16 {
        let Some((table, disks)) = random_table(&mut rng) else {
            continue;
        };
        tables += 1;
        let lat = table.lattice::<Float>(BITS).unwrap();
        let f = |q: &Rational| Float::with_val(BITS, q);
        let e2 = table.spec().lattice.e2.clone().map(|n| n.value());
        let s64 = table.sample(&mut stream(98, tables));
        let mut st = LatticeState::<Float>::convert_from_f64(BITS, &s64);
        for event in 0..1_500 {
            let (ci, cj) = (st.cell.i, st.cell.j);
            let a = lat.world(&st);
            lat.step(&mut st).unwrap();
            let b = lat.world(&st);
            for (c, r) in &disks {
                let r2 = f(&(r.clone() * r));
                for di in -2..=2i64 {
                    for dj in -2..=2i64 {
                        let (i, j) = (Rational::from(ci + di), Rational::from(cj + dj));
                        let cx = c[0].clone() + i + j.clone() * &e2[0];
                        let cy = c[1].clone() + j * &e2[1];
                        let gap = clearance(&a, &b, &Vec2::new(f(&cx), f(&cy)), &r2);
                        assert!(
                            gap > -1e-40,
                            "{} event {event}: the flight crosses the disk at ({cx}, {cy}) r {r}: {gap:e}",
                            table.label()
                        );
                    }
                }
            }
        }
    }
}

/// Long straight flights from random starts: on a table whose horizon is finite none flies
/// farther than 10⁴ cell sizes without a collision; on one with a corridor, a flight started in
/// the corridor along its direction flies 10⁴ cells and more without one.
#[test]
fn the_exact_horizon_agrees_with_long_flights() {
    let mut rng = stream(99, 0);
    let (mut finite, mut open) = (0, 0);
    while finite < 6 || open < 6 {
        let Some((table, _)) = random_table(&mut rng) else {
            continue;
        };
        let lat = table.lattice::<f64>(()).unwrap();
        let longest = |st: &mut LatticeState<f64>| {
            let (mut since, mut worst) = (0.0f64, 0.0f64);
            let mut last = lat.world(st);
            for _ in 0..200_000 {
                let ev = lat.step(st).unwrap();
                let p = lat.world(st);
                since += (p.x - last.x).hypot(p.y - last.y);
                last = p;
                if since > 1e4 {
                    return since;
                }
                if matches!(
                    ev.kind,
                    lorentz_gas::kernel::flight::EventKind::Collision(_)
                ) {
                    worst = worst.max(since);
                    since = 0.0;
                }
            }
            worst.max(since)
        };
        match table.corridor() {
            None if finite < 6 => {
                finite += 1;
                for k in 0..4 {
                    let mut st = table.sample(&mut stream(100, k));
                    assert!(longest(&mut st) < 1e4, "{}", table.label());
                }
            }
            Some(c) if open < 6 => {
                open += 1;
                // A start in the middle of the widest corridor, along it: a point of the free
                // strip is found by sampling until a flight along the corridor stays free.
                let (ux, uy) = (c.vector[0], c.vector[1]);
                let n = ux.hypot(uy);
                let free = (0..2000).any(|k| {
                    let mut st = table.sample(&mut stream(101, k));
                    st.flight.vel = Vec2::new(ux / n, uy / n);
                    longest(&mut st) > 1e4
                });
                assert!(free, "{}: no free flight along {c}", table.label());
            }
            _ => {}
        }
    }
}
