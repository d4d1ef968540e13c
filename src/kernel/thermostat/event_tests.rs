//! Certified thermostatted events: the straight kernel's at ε → 0, grazing contacts taken or
//! refused on the right side of the model, reversible, and `f64` against MPFR-200 within the
//! per-event bound (`proofs-notes/thermostat-flight.md`).

use super::tests::Mix;
use super::*;
use crate::kernel::cell::{ConvexCell, Disk, Edge, EdgeMap, LatticeBasis};
use crate::kernel::flight::{EventKind, Flight};
use crate::kernel::trap::Trap;
use rug::Float;

const U: f64 = f64::EPSILON / 2.0;

/// A free start in `cell` with a random direction.
fn start_in(cell: &ConvexCell<f64>, r: &mut Mix) -> Flight<f64> {
    let (w, h) = cell
        .corners
        .iter()
        .fold((0f64, 0f64), |(w, h), c| (w.max(c.x), h.max(c.y)));
    loop {
        let p = Vec2::new(w * r.unit(), h * r.unit());
        if cell.is_free(&p) {
            let phi = 6.3 * r.unit();
            return Flight::new(p, Vec2::new(phi.cos(), phi.sin()));
        }
    }
}

fn field(eps: f64, r: &mut Mix) -> Thermostat<f64> {
    let phi = 6.3 * r.unit();
    Thermostat {
        strength: eps,
        dir: Vec2::new(phi.cos(), phi.sin()),
    }
}

/// The per-event bound on the error of an event's time: (e₀ + extra)/|F′| twice over (the
/// factor 2 covers the second-order term of a transversal root, `thermostat-flight.md`).
fn time_bound(j: &isolate::Jet<f64>, extra: f64) -> f64 {
    2.0 * (j.err[0] + extra) / j.f1.abs()
}

/// ε = 10⁻¹⁰: the straight kernel's event, its time within (e₀ + 2ρ·εt²/2 + 16u(ρ² + r²))/|F′|
/// — the curved flight is within εt²/2 of the straight one — over 3000 random starts in the
/// trap at w = 0.1 (skipping contacts within 10⁻³ of grazing, where the bound is not small).
#[test]
fn a_vanishing_field_gives_the_straight_events() {
    let cell = Trap::new(0.1f64).unwrap().cell().clone();
    let mut r = Mix(21);
    let (mut compared, mut worst) = (0, 0f64);
    for _ in 0..3000 {
        let f = start_in(&cell, &mut r);
        let th = field(1e-10, &mut r);
        let straight = cell.next_event(&f).unwrap();
        let ev = cell.next_event_thermostat(&f, &th).unwrap();
        assert_eq!(ev.kind, straight.kind, "{f:?}");
        let j = cell.thermostat_jet(&f, &th, ev.kind, &ev.time);
        let t = ev.time;
        let rho = j.reach.max(1.0);
        let extra = rho * th.strength * t * t + 16.0 * U * (rho * rho + 1.0);
        if j.f1.abs() < 1e-3 {
            continue;
        }
        let bound = time_bound(&j, extra);
        let gap = (t - straight.time).abs();
        assert!(gap <= bound, "{gap:e} > {bound:e} for {f:?}");
        compared += 1;
        worst = worst.max(gap / bound);
    }
    assert!(compared > 2900, "{compared}");
    eprintln!("ε = 1e-10: largest |t − t_straight| / bound over {compared} events: {worst:.3}");
}

/// A box [−10, 10]² whose edges translate into the next box, holding the given disks.
fn boxed(disks: Vec<Disk<f64>>) -> ConvexCell<f64> {
    let side = |nx: f64, ny: f64, k: u8, entered: u8| Edge {
        normal: Vec2::new(nx, ny),
        offset: -10.0,
        map: EdgeMap::Translation(Vec2::new(-20.0 * nx, -20.0 * ny)),
        entered,
        disks_after: disks.iter().map(|_| None).collect(),
        step: [k as i64, 0],
    };
    let c = |x: f64, y: f64| Vec2::new(x, y);
    ConvexCell {
        corners: vec![
            c(-10.0, -10.0),
            c(10.0, -10.0),
            c(10.0, 10.0),
            c(-10.0, 10.0),
        ],
        edges: vec![
            side(1.0, 0.0, 0, 1),
            side(-1.0, 0.0, 1, 0),
            side(0.0, 1.0, 2, 3),
            side(0.0, -1.0, 3, 2),
        ],
        disks,
        lattice: LatticeBasis {
            a: 20.0,
            beta: 0.0,
            h: 20.0,
        },
    }
}

/// A disk of radius r tangent to a random flight at its point at t* = 1 (on either side, at
/// curvatures below 1/r), moved by δ towards the flight (a penetration, which must be taken,
/// before t*) or away (a miss by δ, which must be refused): δ from 10⁻¹³ (a few times the model's
/// e₀/2r ≈ 10⁻¹⁴ there) to 10⁻⁶, at ε from 0.01 to 3.
#[test]
fn grazing_contacts_are_taken_or_refused_on_the_right_side() {
    let mut r = Mix(5);
    for n in 0..400 {
        let eps = [0.01, 0.3, 3.0][n % 3];
        let radius = 0.2 + 0.1 * r.unit();
        let th = field(eps, &mut r);
        let phi = 6.3 * r.unit();
        let f = Flight::new(Vec2::new(0.0, 0.0), Vec2::new(phi.cos(), phi.sin()));
        let at = th.start(&f.vel).at(&1.0);
        let side = if n % 2 == 0 { 1.0 } else { -1.0 };
        let normal = Vec2::new(-at.vel.y * side, at.vel.x * side);
        let delta = 10f64.powf(-13.0 + 7.0 * r.unit());
        for (toward, sign) in [(true, -1.0), (false, 1.0)] {
            let k = radius + sign * delta;
            let centre = Vec2::new(at.disp.x + k * normal.x, at.disp.y + k * normal.y);
            let cell = boxed(vec![Disk::new(centre, radius)]);
            let ev = cell.next_event_thermostat(&f, &th).unwrap();
            let hit = ev.kind == EventKind::Collision(0);
            assert_eq!(hit, toward, "{n}: δ = {delta:e}, ε = {eps}, side {side}");
            if hit {
                assert!(ev.time <= 1.0 + 1e-12, "{n}: {}", ev.time);
            }
        }
    }
}

/// A flight leaving the edge it entered by almost along it, the field along that edge: the
/// lateral distance grows to |v⊥|(1 − e^{−εt})/ε only, yet the edge must be refused and the far
/// edge found at ξ = 19. The fuzz finding `seed-creeps-away-from-entry-edge-square-E9.65-x`: with
/// |F‴| bounded by ε² instead of ε²|sin θ| the march crept in steps of ~10⁻⁴, reached its step
/// limit and took the entry edge back, 10⁻¹⁰ off it.
#[test]
fn a_flight_creeping_away_from_its_entry_edge_is_not_taken_back() {
    let cell = boxed(Vec::new());
    for eps in [0.01, 0.3, 9.65] {
        // The lateral distance reaches v⊥/ε ≥ 3·10⁻¹², beyond the edge's e₀ ≤ 4·10⁻¹³ up to t = 20
        // (closer, the model cannot tell the flight from one that returns, and may take it).
        for lean in [3e-11, 1.5e-9, 1e-6] {
            let th = Thermostat {
                strength: eps,
                dir: Vec2::new(1.0, 0.0),
            };
            // On the top edge (y = 10, label 3), moving right and slightly down.
            let mut f = Flight::new(Vec2::new(-9.0, 10.0), Vec2::new(1.0, -lean));
            f.excluded_edge = Some(3);
            let ev = cell.next_event_thermostat(&f, &th).unwrap();
            assert_eq!(ev.kind, EventKind::Crossing(1), "ε = {eps}, v⊥ = {lean:e}");
            // At the root within the model: ξ = 19 within 2e₀ (|F′| = 1), and ξ(t) = t + ln A/ε
            // with |ln A| ≤ m = 1 − cos θ₀ ≤ v⊥²/2.
            let e0 = cell.thermostat_jet(&f, &th, ev.kind, &ev.time).err[0];
            let off = (ev.at.disp.x - 19.0).abs();
            assert!(off <= 2.0 * e0, "ε = {eps}: ξ off by {off:e}, e₀ = {e0:e}");
            let lag = lean * lean / (2.0 * eps) + 2.0 * e0;
            assert!((ev.time - 19.0).abs() <= lag, "{}", ev.time);
        }
    }
}

/// Reversibility at 200 bits: 20 events in the trap at w = 0.1 (the field flipping with the
/// point-reflected cells), the velocity reversed with E fixed, 20 events back (the first at
/// t = 0: the disk or edge the particle is on, now moved into) and the first flight time again:
/// the start, with the velocity reversed, to 10⁻³⁰ (chaos amplifies 2⁻²⁰⁰ by ≲ 10²⁵ over 40
/// events).
#[test]
fn thermostatted_events_are_reversible() {
    let cell = Trap::new(Float::with_val(200, 0.1)).unwrap().cell().clone();
    let cell64 = Trap::new(0.1f64).unwrap().cell().clone();
    let mut r = Mix(9);
    for eps in [0.01, 0.3, 3.0] {
        let f64s = start_in(&cell64, &mut r);
        let mut f = Flight::<Float>::convert_from_f64(200, &f64s);
        // Unit vectors at 200 bits: the closed form takes |v| = |ê| = 1.
        let norm = f.vel.norm2().sqrt();
        f.vel = Vec2::new(f.vel.x.clone() / &norm, f.vel.y.clone() / &norm);
        let v0 = f.vel.clone();
        let p0 = f.pos.clone();
        let mut th = Thermostat::new(
            Float::with_val(200, eps),
            lift_field(&field(eps, &mut r)).dir,
        );
        let first = run(&cell, &mut f, &mut th, 20);
        f.vel = -f.vel;
        let back = run(&cell, &mut f, &mut th, 20);
        assert!(!back[0].gt0(), "the first event back is now");
        let end = th.start(&f.vel).at(&first[0]);
        let x = Vec2::new(f.pos.x.clone() + &end.disp.x, f.pos.y.clone() + &end.disp.y);
        let off = x.sub(&p0).norm2().sqrt();
        let dv = Vec2::new(end.vel.x.clone() + &v0.x, end.vel.y.clone() + &v0.y);
        assert!(off.to_f64() < 1e-30, "ε = {eps}: {}", off.to_f64());
        assert!(dv.norm2().sqrt().to_f64() < 1e-30, "ε = {eps}");
    }
}

/// Runs `n` events, flipping the field at point reflections; returns their flight times.
fn run(
    cell: &ConvexCell<Float>,
    f: &mut Flight<Float>,
    th: &mut Thermostat<Float>,
    n: usize,
) -> Vec<Float> {
    let mut times = Vec::new();
    for _ in 0..n {
        let ev = cell.next_event_thermostat(f, th).unwrap();
        if cell.apply_thermostat(f, &ev) {
            th.dir = -th.dir.clone();
        }
        times.push(ev.time);
    }
    times
}

/// `f64` against MPFR-200 from the same (lifted) state and field over random starts in the trap
/// at w = 0.1 and 0.3 and ε ∈ {0.01, 0.3, 3}: the same event, its time within
/// 2(e₀⁽⁶⁴⁾ + 2ρ·4u·a)/|F′| (the cells' constants differ by the rounding of a, h, √3).
#[test]
fn f64_events_agree_with_mpfr_within_the_model() {
    let mut r = Mix(13);
    let mut worst = 0f64;
    let mut count = 0;
    for w in [0.1, 0.3] {
        let c64 = Trap::new(w).unwrap().cell().clone();
        let c200 = Trap::new(Float::with_val(200, w)).unwrap().cell().clone();
        for n in 0..600 {
            let eps = [0.01, 0.3, 3.0][n % 3];
            let f = start_in(&c64, &mut r);
            let th = field(eps, &mut r);
            let ev = c64.next_event_thermostat(&f, &th).unwrap();
            let hi = lift_field(&th);
            let fh = Flight::<Float>::convert_from_f64(200, &f);
            let eh = c200.next_event_thermostat(&fh, &hi).unwrap();
            assert_eq!(ev.kind, eh.kind, "w = {w}, {f:?} ε = {eps}");
            let j = c64.thermostat_jet(&f, &th, ev.kind, &ev.time);
            let bound = time_bound(&j, 8.0 * U * j.reach.max(1.0) * 2.5);
            let gap = (eh.time.to_f64() - ev.time).abs();
            assert!(
                gap <= bound,
                "{gap:e} > {bound:e}: w = {w}, {f:?}, ε = {eps}"
            );
            worst = worst.max(gap / bound);
            count += 1;
        }
    }
    eprintln!("f64 vs MPFR-200: largest |Δt| / bound over {count} events: {worst:.3}");
}

fn lift_field(th: &Thermostat<f64>) -> Thermostat<Float> {
    lift_field_to(th, 200)
}

fn lift_field_to(th: &Thermostat<f64>, bits: u32) -> Thermostat<Float> {
    let at = |x: f64| Float::with_val(bits, x);
    Thermostat {
        strength: at(th.strength),
        dir: Vec2::new(at(th.dir.x), at(th.dir.y)),
    }
}

/// The march is one algorithm at every precision (its step margins read from `f64` values,
/// exact at 53 bits): 5 successive events from each of 600 random starts at
/// w = 0.1 and 0.3, ε ∈ {0.01, 0.3, 3}, are the same in `f64` and MPFR-53 to the bit — kind,
/// time, displacement and velocity — the point-reflected cells flipping the field in both.
#[test]
fn f64_events_are_mpfr_53_events_bit_for_bit() {
    let mut r = Mix(15);
    let bits = |x: &Float| x.to_f64().to_bits();
    for w in [0.1, 0.3] {
        let c64 = Trap::new(w).unwrap().cell().clone();
        let c53 = Trap::new(Float::with_val(53, w)).unwrap().cell().clone();
        for n in 0..600 {
            let mut f = start_in(&c64, &mut r);
            let mut th = field([0.01, 0.3, 3.0][n % 3], &mut r);
            let mut fh = Flight::<Float>::convert_from_f64(53, &f);
            for k in 0..5 {
                let (Some(ev), Some(eh)) = (
                    c64.next_event_thermostat(&f, &th),
                    c53.next_event_thermostat(&fh, &lift_field_to(&th, 53)),
                ) else {
                    panic!("{n}.{k}: no event in one of them, w = {w}");
                };
                let lo = [
                    ev.time,
                    ev.at.disp.x,
                    ev.at.disp.y,
                    ev.at.vel.x,
                    ev.at.vel.y,
                ];
                let hi = [
                    &eh.time,
                    &eh.at.disp.x,
                    &eh.at.disp.y,
                    &eh.at.vel.x,
                    &eh.at.vel.y,
                ];
                assert_eq!(ev.kind, eh.kind, "{n}.{k}, w = {w}");
                assert_eq!(lo.map(f64::to_bits), hi.map(bits), "{n}.{k}, w = {w}");
                let flipped = c64.apply_thermostat(&mut f, &ev);
                c53.apply_thermostat(&mut fh, &eh);
                if flipped {
                    th.dir = Vec2::new(-th.dir.x, -th.dir.y);
                }
            }
        }
    }
}

/// The earliest event by a march per candidate ([`isolate::earliest`] of every disk and edge up
/// to the exit bound, the earliest kept with the kernel's ties): what the one march for all
/// candidates (`search.rs`) must find.
fn event_by_single_marches(
    cell: &ConvexCell<f64>,
    f: &Flight<f64>,
    th: &Thermostat<f64>,
) -> Option<(EventKind, f64)> {
    let start = th.start(&f.vel);
    let exit = cell::exit_bound(cell, &f.pos, &start);
    let kinds = (0..cell.edges.len() as u8)
        .map(EventKind::Crossing)
        .chain((0..cell.disks.len() as u8).map(EventKind::Collision));
    let mut best: Option<(f64, (bool, u8), EventKind)> = None;
    for kind in kinds {
        let c = contacts::Candidate::new(cell, &start, f, kind);
        let t = match isolate::earliest(&c, c.identity(), &exit) {
            isolate::Found::Root(t) => t,
            isolate::Found::Creeps if matches!(kind, EventKind::Crossing(_)) => 0.0,
            isolate::Found::Creeps => return None,
            isolate::Found::Clear => continue,
        };
        let rank = match kind {
            EventKind::Collision(m) => (false, m),
            EventKind::Crossing(k) => (true, k),
        };
        if best.is_none_or(|b| (t, rank) < (b.0, b.1)) {
            best = Some((t, rank, kind));
        }
    }
    best.map(|b| (b.2, b.0))
}

/// The one march for all candidates finds the event a march per candidate finds (the search
/// before 2026-11-30), and the event the march of the winner alone finds
/// ([`ConvexCell::next_event_thermostat_among`], the floor of `bench --oracle-floor`): the same
/// obstacle, the time within the stopping band 2e₀/|F′| of the two,
/// over 5 successive events from each of 600 random starts at w = 0.1 and 0.3, ε ∈ {0.01, 0.3, 3}
/// (so that flights leave the disk or the edge they are on, too).
#[test]
fn one_march_for_all_candidates_finds_the_event_of_a_march_per_candidate() {
    let mut r = Mix(17);
    let (mut worst, mut worst_alone) = (0f64, 0f64);
    for w in [0.1, 0.3] {
        let cell = Trap::new(w).unwrap().cell().clone();
        for n in 0..600 {
            let mut f = start_in(&cell, &mut r);
            let mut th = field([0.01, 0.3, 3.0][n % 3], &mut r);
            for k in 0..5 {
                let ev = cell.next_event_thermostat(&f, &th).unwrap();
                let (kind, t) = event_by_single_marches(&cell, &f, &th).unwrap();
                assert_eq!(ev.kind, kind, "{n}.{k}, w = {w}: {f:?}");
                let j = cell.thermostat_jet(&f, &th, ev.kind, &ev.time);
                let gap = (ev.time - t).abs();
                let bound = time_bound(&j, 0.0);
                assert!(gap <= bound, "{n}.{k}, w = {w}: {gap:e} > {bound:e}");
                worst = worst.max(gap / bound);
                // The winner alone (the floor of `bench --oracle-floor`) certifies the same root.
                let alone = cell.next_event_thermostat_among(&f, &th, std::iter::once(kind));
                let alone = alone.unwrap();
                assert_eq!(alone.kind, kind, "{n}.{k}, w = {w}: {f:?}");
                let gap = (alone.time - ev.time).abs();
                assert!(gap <= bound, "{n}.{k}, w = {w}, alone: {gap:e} > {bound:e}");
                worst_alone = worst_alone.max(gap / bound);
                if cell.apply_thermostat(&mut f, &ev) {
                    th.dir = Vec2::new(-th.dir.x, -th.dir.y);
                }
            }
        }
    }
    eprintln!("one march against a march per candidate: largest |Δt| / bound {worst:.3}");
    eprintln!("one march against the winner's alone: largest |Δt| / bound {worst_alone:.3}");
}
