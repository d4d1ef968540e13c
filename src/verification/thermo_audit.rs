//! What the tracked audit adds for thermostatted flights ([`super::arc_audit`] replays them,
//! `proofs-notes/thermostat-audit.md`): the decisions the kernel takes in plain `f64` from its
//! values, made visible to the ambiguity count, and the reference flight checked against closed
//! forms the kernel does not use, so that a wrong formula — shared by the `f64` run and its
//! tracked replay, invisible to a comparison of the two — is caught too.

use rug::Float;

use crate::kernel::cell::ConvexCell;
use crate::kernel::flight::Flight;
use crate::kernel::thermostat::Thermostat;
use crate::kernel::thermostat::cell::ThermoEvent;
use crate::kernel::vec2::Vec2;
use crate::numbers::real::Real;
use crate::numbers::tracked::Tracked;

/// The largest residual of the reference flight `ev` from the start velocity `v0` under `th`
/// (the cell's frame) against the independent closed forms of `proofs-notes/thermostat-audit.md`,
/// each in units of its tolerance: above 1 the reference is not the thermostatted flight.
///
/// With p = 1 + c₀, m = 1 − c₀ (p·m = s₀²), P = p·e^{εt}, M = m·e^{−εt}:
/// εξ = ln((P + M)/2), cos θ = (P − M)/(P + M), sin θ = 2s₀/(P + M) and
/// εη = sgn(s₀)(atan((P − M)/(2|s₀|)) − atan(c₀/|s₀|)) (the Gudermannian of εt + artanh c₀).
pub fn flight_residual(
    th: &Thermostat<Tracked>,
    v0: [&Tracked; 2],
    ev: &ThermoEvent<Tracked>,
) -> f64 {
    let bits = ev.time.v.prec();
    let f = |x: &Tracked| Float::with_val(bits, &x.v);
    let e = Vec2::new(f(&th.dir.x), f(&th.dir.y));
    let eps = f(&th.strength);
    // The closed forms are those of a unit start velocity; the state's is unit to a few u, and
    // the kernel's forms take it as it is: its speed defect δ = |v|² − 1 moves the flight by
    // at most |δ|(1 + t) (proofs-notes/thermostat-audit.md), inside the tolerance below.
    let v = Vec2::new(f(v0[0]), f(v0[1]));
    let speed2 = v.norm2();
    let defect = speed2.clone().add_f64(-1.0).to_f64().abs();
    let speed = speed2.sqrt();
    let v = Vec2::new(v.x / &speed, v.y / &speed);
    let (c0, s0) = (e.dot(&v), e.cross(&v));
    let (p, m) = if c0.lt0() {
        let m = (-c0.clone()).add_f64(1.0);
        (Real::square(&s0) / &m, m)
    } else {
        let p = c0.clone().add_f64(1.0);
        (p.clone(), Real::square(&s0) / &p)
    };
    let et = eps.clone() * &f(&ev.time);
    let big_p = p * &et.clone().exp();
    let big_m = m * &(-et).exp();
    let den = big_p.clone() + &big_m;
    let diff = big_p - &big_m;
    let xi = den.clone().scale(0.5).ln() / &eps;
    let cos = diff.clone() / &den;
    let sin = s0.clone().scale(2.0) / &den;
    let eta = if s0.gt0() || s0.lt0() {
        let a = s0.clone().abs();
        let g = (diff / &a.clone().scale(2.0)).atan() - &(c0 / &a).atan();
        let g = if s0.lt0() { -g } else { g };
        g / &eps
    } else {
        Float::new(bits)
    };
    let d = Vec2::new(f(&ev.at.disp.x), f(&ev.at.disp.y));
    let u = Vec2::new(f(&ev.at.vel.x), f(&ev.at.vel.y));
    // Lengths and velocity components of order 1, to 2^(−P/2); the 1/ε of ξ and η carries the
    // P-bit roundings of their ε-scaled forms (a flight in a weak field).
    let weak = 1.0 + 1.0 / eps.to_f64();
    let p_bits = f64::from(bits);
    let drift = 8.0 * defect * (1.0 + ev.time.v.to_f64());
    // The event's point may be a Taylor step from the march's last point, itself a Taylor step
    // from a closed-form point: two remainders of at most u/64 each of the computation replayed
    // (`Start::step_from`), far below f64's resolution.
    let taylor = <Tracked as Real>::unit_roundoff(bits) / 32.0;
    let tol = |x: &Float| {
        (1.0 + x.to_f64().abs())
            * ((-p_bits / 2.0).exp2() + (16.0 - p_bits).exp2() * weak + drift + taylor)
    };
    let res = |a: Float, b: &Float| (a - b).to_f64().abs() / tol(b);
    [
        res(e.dot(&d), &xi),
        res(e.cross(&d), &eta),
        res(e.dot(&u), &cos),
        res(e.cross(&u), &sin),
    ]
    .into_iter()
    .fold(0.0, f64::max)
}

/// The freedom of a certified march's stopping point, carried to the event: the time band and
/// how far the post-event position and velocity (x, y, vx, vy) move across it.
#[derive(Debug, Clone, Copy)]
pub struct StoppingBand {
    /// The band's half-width in time.
    pub time: f64,
    /// The largest move of each post-event coordinate over t ± `time`.
    pub state: [f64; 4],
}

/// The stopping band of the reference event `ev` of the flight `pre` under `th` in `cell`
/// (`proofs-notes/thermostat-audit.md`): a march stops where the contact function's lower bound
/// F − e₀ reaches zero, so the `f64` run and the reference may each stop anywhere in
/// [t* − (e₀ + e_F)/|F′|, t* + e_F/|F′|] (e₀ the kernel's model bound of F, e_F the running
/// bound of its rounding): they differ by at most (e₀ + 2e_F)/|F′|, with |F′| taken less its
/// error and its change across the band. `None` where that slope is not positive (a contact
/// grazing at `f64` resolution: the time itself is ambiguous).
pub fn stopping_band(
    cell: &ConvexCell<Tracked>,
    pre: &Flight<Tracked>,
    th: &Thermostat<Tracked>,
    ev: &ThermoEvent<Tracked>,
) -> Option<StoppingBand> {
    let j = cell.thermostat_jet(pre, th, ev.kind, &ev.time);
    let width = j.err[0].v.to_f64() + 2.0 * j.f.e;
    let slope = j.f1.v.to_f64().abs() - j.err[1].v.to_f64() - j.f1.e;
    let curve = j.f2.v.to_f64().abs() + j.err[2].v.to_f64() + j.f2.e;
    if slope <= 0.0 {
        return None;
    }
    let first = width / slope;
    let slope = slope - 2.0 * curve * first;
    if slope <= 0.0 {
        return None;
    }
    let time = width / slope * (1.0 + 1.0 / 64.0);
    if width == 0.0 {
        return Some(StoppingBand {
            time: 0.0,
            state: [0.0; 4],
        });
    }
    let landed = |t: Tracked| {
        let start = th.start(&pre.vel);
        let at = start.at(&t);
        let moved = ThermoEvent {
            kind: ev.kind,
            time: t,
            at,
        };
        let mut f = pre.clone();
        cell.apply_thermostat(&mut f, &moved);
        [f.pos.x.v, f.pos.y.v, f.vel.x.v, f.vel.y.v]
    };
    let bits = ev.time.v.prec();
    let shift = |k: f64| ev.time.clone() + &Tracked::from_f64(bits, k * time);
    let centre = landed(ev.time.clone());
    let mut state = [0.0f64; 4];
    for side in [landed(shift(1.0)), landed(shift(-1.0))] {
        for (k, (a, b)) in side.iter().zip(&centre).enumerate() {
            let d = Float::with_val(bits, a - b).to_f64().abs();
            // Smooth in t across so short a band: the ends' moves, with room for curvature.
            state[k] = state[k].max(d * (1.0 + 1.0 / 16.0));
        }
    }
    Some(StoppingBand { time, state })
}
