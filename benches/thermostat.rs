//! `cargo bench -p lorentz-gas-benches --bench thermostat`: what one event of a thermostatted
//! flight costs, and its parts, beside the straight kernel's event on the same flights (divan
//! reports medians per event).
//!
//! The flights are those of a walk in the trap of w = 0.2 under E = 0.3 at 30° (the field of the
//! issue's speed target), recorded before each event, so that most start on the disk just left as
//! in a run. The parts are the closed-form point at the event's time (three correctly rounded
//! calls), Taylor steps of the lengths the march takes (εs = 3·10⁻⁴, about 10⁻³ before a root, and
//! εs = 10⁻⁵), and the whole certified event. `docs/performance.md` and the Cost section of
//! `proofs-notes/thermostat-flight.md` read the budget of an event from them.

use divan::Bencher;
use lorentz_gas::kernel::cell::ConvexCell;
use lorentz_gas::kernel::flight::{EventKind, Flight};
use lorentz_gas::kernel::thermostat::Thermostat;
use lorentz_gas::kernel::trap::Trap;
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::triangular::equilibrium_state;
use rug::Rational;

fn main() {
    divan::main();
}

/// Events recorded, and timed per call.
const EVENTS: usize = 512;

/// A recorded start: the flight before an event, whether its frame sees −E, and the event's time.
struct Case {
    flight: Flight<f64>,
    flipped: bool,
    time: f64,
    kind: EventKind,
}

/// The trap cell, the field (as seen in a cell and in a point-reflected one) and the flights of
/// a walk of [`EVENTS`] events from an equilibrium start.
fn walk(w: f64) -> (ConvexCell<f64>, [Thermostat<f64>; 2], Vec<Case>) {
    let trap = Trap::new(w).unwrap();
    let cell = trap.cell().clone();
    let th = Thermostat::<f64>::exact(&Rational::from((3, 10)), &Rational::from(30), ()).unwrap();
    let flip = Thermostat {
        strength: th.strength,
        dir: -th.dir.clone(),
    };
    let fields = [th, flip];
    let mut f = equilibrium_state(&trap, &mut stream(7, 0)).flight;
    let mut flipped = false;
    let mut cases = Vec::with_capacity(EVENTS);
    while cases.len() < EVENTS {
        let ev = cell
            .next_event_thermostat(&f, &fields[flipped as usize])
            .unwrap();
        cases.push(Case {
            flight: f.clone(),
            flipped,
            time: ev.time,
            kind: ev.kind,
        });
        flipped ^= cell.apply_thermostat(&mut f, &ev);
    }
    (cell, fields, cases)
}

/// Times `each` on every recorded event of the walk at w = 0.2 (the cell, the field in the
/// event's frame, the event).
fn per_event(b: Bencher, each: impl Fn(&ConvexCell<f64>, &Thermostat<f64>, &Case)) {
    let (cell, fields, cases) = walk(0.2);
    b.counter(divan::counter::ItemsCount::new(EVENTS))
        .bench_local(|| {
            for c in &cases {
                each(&cell, &fields[c.flipped as usize], divan::black_box(c));
            }
        });
}

/// The straight kernel's next event from the same states (its walk would go elsewhere: this is
/// the cost of one event of the straight kernel, not a rate of its engine).
#[divan::bench]
fn straight_event(b: Bencher) {
    per_event(b, |cell, _, c| {
        divan::black_box(cell.next_event(&c.flight));
    });
}

/// One certified thermostatted event: the march over all candidates and the event's point.
#[divan::bench]
fn thermostat_event(b: Bencher) {
    per_event(b, |cell, th, c| {
        divan::black_box(cell.next_event_thermostat(&c.flight, th));
    });
}

/// The winner-only floor: the same event with the one candidate the full search found (its
/// march, its certificates and the event's point; the other candidates neither screened nor
/// certified). No way of ruling the others out in advance costs less with these certificates.
#[divan::bench]
fn winner_only_event(b: Bencher) {
    per_event(b, |cell, th, c| {
        let only = std::iter::once(c.kind);
        divan::black_box(cell.next_event_thermostat_among(&c.flight, th, only));
    });
}

/// A flight's start ([`Thermostat::start`]) and its closed-form point at the event's time.
#[divan::bench]
fn closed_form_point(b: Bencher) {
    per_event(b, |_, th, c| {
        divan::black_box(th.start(&c.flight.vel).at(&c.time));
    });
}

/// A Taylor step of length s = σ/ε from the event's point (the order the step's remainder needs
/// at σ: 4 at 3·10⁻⁴, 3 at 10⁻⁵).
#[divan::bench(args = [3e-4, 1e-5])]
fn taylor_step(b: Bencher, sigma: f64) {
    let (_, fields, cases) = walk(0.2);
    let points: Vec<_> = cases
        .iter()
        .map(|c| {
            let th = &fields[c.flipped as usize];
            (th.start(&c.flight.vel), c.time)
        })
        .map(|(s, t)| {
            let p = s.at(&t);
            (s, p)
        })
        .collect();
    let s = sigma / fields[0].strength;
    b.counter(divan::counter::ItemsCount::new(EVENTS))
        .bench_local(|| {
            for (start, p) in &points {
                divan::black_box(start.step_from(divan::black_box(p), &s));
            }
        });
}
