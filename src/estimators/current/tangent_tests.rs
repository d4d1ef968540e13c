//! The tangent maps against finite differences of the exact dynamics: orbits started 10⁻⁴⁰ apart
//! in x, y and the velocity angle, flown at 256 bits through the same events, compared at one
//! time inside a late flight with the `f64` tangent maps carried along the base orbit.

use super::*;
use crate::kernel::flight::EventKind;
use crate::kernel::thermostat::cell::ThermoEvent;
use crate::scenes::Scene;
use crate::scenes::lattice::LatticeState;
use crate::scenes::thermostat::CellFields;
use crate::scenes::triangular::TriangularScene;
use rand::SeedableRng;
use rug::{Float, Rational};

const BITS: u32 = 256;
/// Events of each orbit before the flight in which the orbits are compared.
const EVENTS: usize = 12;

type Lat = crate::scenes::lattice::Lattice<Float, <TriangularScene as Scene>::Kernel<Float>>;

/// The world position and velocity angle at the time `time` of the orbit from `s`.
fn at_time(
    lat: &Lat,
    fields: &CellFields<Float>,
    mut s: LatticeState<Float>,
    time: &Float,
) -> [Float; 3] {
    let mut t = Float::with_val(BITS, 0);
    loop {
        let ev: ThermoEvent<Float> = lat.next_event_thermostat(&s, fields).unwrap();
        if t.clone() + &ev.time > *time {
            let start = fields.in_cell(&s.cell).start(&s.flight.vel);
            let at = start.at(&(time.clone() - &t));
            let sg = s.cell.sign();
            let p = lat.world(&s);
            let x = p.x + &(at.disp.x * sg);
            let y = p.y + &(at.disp.y * sg);
            let phi = (at.vel.y * sg).atan2(&(at.vel.x * sg));
            return [x, y, phi];
        }
        t += &ev.time;
        lat.apply_thermostat(&mut s, &ev);
    }
}

/// The `f64` tangent maps along the orbit from `s` up to `time` applied to `u`, and the orbit's
/// event count on the way.
fn carried(
    lat: &Lat,
    fields: &CellFields<Float>,
    world: &Thermostat<f64>,
    mut s: LatticeState<Float>,
    time: f64,
    mut u: [f64; 3],
) -> ([f64; 3], usize) {
    let (mut t, mut events) = (0.0, 0);
    let velocity = |s: &LatticeState<Float>| {
        let sg = s.cell.sign();
        Vec2::new(sg * s.flight.vel.x.to_f64(), sg * s.flight.vel.y.to_f64())
    };
    loop {
        let v = velocity(&s);
        let ev = lat.next_event_thermostat(&s, fields).unwrap();
        let dt = ev.time.to_f64();
        if t + dt > time {
            flight_map(&mut u, &world.start(&v), time - t);
            return (u, events);
        }
        flight_map(&mut u, &world.start(&v), dt);
        lat.apply_thermostat(&mut s, &ev);
        if let EventKind::Collision(m) = ev.kind {
            let (n, r) = super::super::track::contact_normal(lat, &s, m);
            collision_map(&mut u, world, (&n, r), &velocity(&s));
        }
        t += dt;
        events += 1;
    }
}

/// The base orbit's start: a sampled state, its velocity (cos φ, sin φ) at 256 bits; and the
/// time inside its flight after [`EVENTS`] events.
fn base(lat: &Lat, fields: &CellFields<Float>, seed: u64) -> (LatticeState<Float>, Float) {
    let scene = TriangularScene::exact(Rational::from((1, 10))).unwrap();
    let s64 = scene.sample(&mut rand::rngs::StdRng::seed_from_u64(seed));
    let mut s = LatticeState::<Float>::convert_from_f64(BITS, &s64);
    let phi = s.flight.vel.y.clone().atan2(&s.flight.vel.x);
    s.flight.vel = Vec2::new(phi.clone().cos(), phi.sin());
    let mut probe = s.clone();
    let mut t = Float::with_val(BITS, 0);
    for _ in 0..EVENTS {
        let ev = lat.next_event_thermostat(&probe, fields).unwrap();
        t += &ev.time;
        lat.apply_thermostat(&mut probe, &ev);
    }
    let last = lat.next_event_thermostat(&probe, fields).unwrap();
    t += last.time / 2u32;
    (s, t)
}

/// `s` moved by `h` along the phase-space direction `k` (x, y or the velocity angle).
fn moved(s: &LatticeState<Float>, k: usize, h: &Float) -> LatticeState<Float> {
    let mut p = s.clone();
    match k {
        0 => p.flight.pos.x += h,
        1 => p.flight.pos.y += h,
        _ => {
            let phi = p.flight.vel.y.clone().atan2(&p.flight.vel.x) + h;
            p.flight.vel = Vec2::new(phi.clone().cos(), phi.sin());
        }
    }
    p
}

#[test]
fn tangent_maps_are_the_derivatives_of_the_flow() {
    let scene = TriangularScene::exact(Rational::from((1, 10))).unwrap();
    let lat = scene.lattice::<Float>(BITS).unwrap();
    for (field, angle, seed) in [("3/10", "0", 1), ("1/100", "30", 2), ("3", "-75", 3)] {
        let th = Thermostat::<Float>::exact(&field.parse().unwrap(), &angle.parse().unwrap(), BITS);
        let fields = CellFields::new(th.unwrap());
        let world =
            Thermostat::<f64>::exact(&field.parse().unwrap(), &angle.parse().unwrap(), ()).unwrap();
        let (s, time) = base(&lat, &fields, seed);
        assert!(!s.cell.down);
        let h = Float::with_val(BITS, Float::i_exp(1, -133));
        let at = at_time(&lat, &fields, s.clone(), &time);
        for k in 0..3 {
            let moved_at = at_time(&lat, &fields, moved(&s, k, &h), &time);
            let fd: Vec<f64> = (0..3)
                .map(|i| ((moved_at[i].clone() - &at[i]) / &h).to_f64())
                .collect();
            let mut u = [0.0; 3];
            u[k] = 1.0;
            let (u, events) = carried(&lat, &fields, &world, s.clone(), time.to_f64(), u);
            assert_eq!(events, EVENTS, "E = {field}");
            let size = u.iter().map(|a| a * a).sum::<f64>().sqrt();
            // f64 maps, ~40 roundings an event over 12 events: about 5e-14 relative (1e-15
            // seen); 1e-12 leaves a factor 20 for errors made early growing along the unstable
            // direction, and is 10¹⁰ below a wrong term (a dropped φ̇δt: 6e-2).
            for i in 0..3 {
                assert!(
                    (fd[i] - u[i]).abs() <= 1e-12 * size,
                    "E = {field} at {angle}°, ∂/∂{k} component {i}: difference {fd:?} vs tangent {u:?}"
                );
            }
        }
    }
}
