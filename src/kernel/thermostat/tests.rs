//! The closed-form flight: a solution of the equations of motion, accurate to its error model in
//! `f64`, the straight flight at ε → 0, reversible, and free of cancellation at large εt.

use super::isolate::{first_root, root_error};
use super::*;
use rug::Float;

const BITS: u32 = 200;
const U: f64 = f64::EPSILON / 2.0;

fn big(x: f64) -> Float {
    Float::with_val(BITS, x)
}

fn th64(eps: f64, angle: f64) -> Thermostat<f64> {
    Thermostat {
        strength: eps,
        dir: Vec2::new(angle.cos(), angle.sin()),
    }
}

/// The same field, lifted exactly to MPFR at `bits`.
fn lift_to(th: &Thermostat<f64>, bits: u32) -> Thermostat<Float> {
    let at = |x: f64| Float::with_val(bits, x);
    Thermostat {
        strength: at(th.strength),
        dir: Vec2::new(at(th.dir.x), at(th.dir.y)),
    }
}

/// The same field, lifted exactly to MPFR at [`BITS`].
fn lift(th: &Thermostat<f64>) -> Thermostat<Float> {
    lift_to(th, BITS)
}

/// Flight `n` of a random sample: ε from 10⁻⁶ to 10³, any field direction, a flight time up to 3,
/// and every fourth start within 10⁻¹² of anti-alignment (where p = 1 + c is tiny).
fn random_flight(r: &mut Mix, n: usize) -> (Thermostat<f64>, Vec2<f64>, f64) {
    let th = th64(10f64.powf(9.0 * r.unit() - 6.0), 6.3 * r.unit());
    let phi = if n.is_multiple_of(4) {
        th.dir.y.atan2(th.dir.x) + std::f64::consts::PI + 1e-12 * (r.unit() - 0.5)
    } else {
        6.3 * r.unit()
    };
    let t = 3.0 * r.unit();
    (th, Vec2::new(phi.cos(), phi.sin()), t)
}

/// A small deterministic generator (SplitMix64) for the random flights.
pub(super) struct Mix(pub u64);
impl Mix {
    pub(super) fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The unit vector at the angle `phi`, at 200 bits (the closed form assumes |v| = 1).
fn unit(phi: f64) -> Vec2<Float> {
    let phi = big(phi);
    Vec2::new(phi.clone().cos(), phi.sin())
}

fn unit_field(eps: f64, angle: f64) -> Thermostat<Float> {
    Thermostat {
        strength: big(eps),
        dir: unit(angle),
    }
}

fn dist(a: &Vec2<Float>, b: &Vec2<f64>) -> f64 {
    let dx = Float::with_val(BITS, &a.x - b.x);
    let dy = Float::with_val(BITS, &a.y - b.y);
    Float::with_val(BITS, dx.square() + dy.square())
        .sqrt()
        .to_f64()
}

/// At 200 bits the closed form solves ṙ = v, v̇ = E − (E·v)v with |v| = 1: central differences
/// of step h = 10⁻²⁰ (truncation h²·ε²/6 ≤ 2·10⁻³⁷ for ε ≤ 100, rounding 2⁻²⁰⁰/h ≈ 10⁻⁴⁰) against
/// the formulas' velocity and acceleration, within 10⁻³⁵.
#[test]
fn the_closed_form_solves_the_equations_of_motion() {
    let mut r = Mix(7);
    for _ in 0..50 {
        let th = unit_field(10f64.powf(4.0 * r.unit() - 2.0), 6.3 * r.unit());
        let v = unit(6.3 * r.unit());
        let start = th.start(&v);
        let t = big(3.0 * r.unit());
        let h = Float::with_val(BITS, 1e-20);
        let (a, b) = (start.at(&(t.clone() + &h)), start.at(&(t.clone() - &h)));
        let at = start.at(&t);
        let h2 = h.clone() * 2u32;
        let vel = Vec2::new(
            (a.disp.x.clone() - &b.disp.x) / &h2,
            (a.disp.y.clone() - &b.disp.y) / &h2,
        );
        let acc = Vec2::new(
            (a.vel.x.clone() - &b.vel.x) / &h2,
            (a.vel.y.clone() - &b.vel.y) / &h2,
        );
        // v̇ = ε(ê − (ê·v)v).
        let ev = th.dir.dot(&at.vel);
        let law = Vec2::new(
            (th.dir.x.clone() - &(ev.clone() * &at.vel.x)) * &th.strength,
            (th.dir.y.clone() - &(ev * &at.vel.y)) * &th.strength,
        );
        for (x, y) in [(&vel, &at.vel), (&acc, &at.acc), (&law, &at.acc)] {
            let d = (x.sub(y)).norm2().sqrt().to_f64();
            assert!(d < 1e-35, "{d}");
        }
        assert!((at.vel.norm2().to_f64() - 1.0).abs() < 1e-55);
    }
}

/// `f64` against MPFR-200 over random flights (ε from 10⁻⁶ to 10³, εt up to 3000, a quarter
/// within 10⁻¹² of anti-alignment): the displacement and the velocity within
/// [`Start::error`]'s model.
#[test]
fn f64_flights_are_within_the_error_model() {
    let mut r = Mix(11);
    let mut worst: f64 = 0.0;
    for n in 0..4000 {
        let (th, v, t) = random_flight(&mut r, n);
        let start = th.start(&v);
        let at = start.at(&t);
        let (mx, mv) = start.error(&t);
        let hi = lift(&th);
        let exact = hi.start(&Vec2::new(big(v.x), big(v.y))).at(&big(t));
        let dx = dist(&exact.disp, &at.disp);
        let dv = dist(&exact.vel, &at.vel);
        assert!(dx <= mx, "{n}: δX = {dx:e} > {mx:e} at t = {t}");
        assert!(dv <= mv, "{n}: δv = {dv:e} > {mv:e}");
        worst = worst.max(dx / mx).max(dv / mv);
    }
    eprintln!("largest error / model over 4000 flights: {worst:.3}");
}

/// The kernel's contract on the start's speed: |v|² − 1 within 8u (the engine's states are
/// within a few u) is flown within [`Start::error`]'s model against the MPFR-200 flight of the
/// exactly normalised direction, over 2000 random flights (a quarter near anti-alignment); a
/// speed off by 10⁻⁹ is not (the fuzz seed `seed-unnormalised-speed-tiny-disk-square-E0.001-x`
/// came from such a start: the speed a collision with a disk of radius 10⁻¹⁰ left, which
/// `apply_thermostat` now brings back to 1).
#[test]
fn starts_within_a_few_units_of_unit_speed_fly_within_the_model() {
    let mut r = Mix(17);
    let within = |th: &Thermostat<f64>, v: Vec2<f64>, t: f64| {
        let start = th.start(&v);
        let at = start.at(&t);
        let (mx, mv) = start.error(&t);
        let hi = Vec2::new(big(v.x), big(v.y));
        let norm = hi.norm2().sqrt();
        let dir = Vec2::new(hi.x.clone() / &norm, hi.y.clone() / &norm);
        let exact = lift(th).start(&dir).at(&big(t));
        let (dx, dv) = (dist(&exact.disp, &at.disp), dist(&exact.vel, &at.vel));
        (dx <= mx && dv <= mv, dx / mx)
    };
    let mut outside = 0;
    for n in 0..2000 {
        let (th, v, t) = random_flight(&mut r, n);
        // |v|² − 1 = 2k·u, k from −4 to 4 (the scale factor 1 + ku rounds to a multiple of u).
        let k = (8.0 * r.unit()).floor() - 4.0;
        let scale = 1.0 + k * f64::EPSILON / 2.0;
        let (ok, ratio) = within(&th, Vec2::new(v.x * scale, v.y * scale), t);
        assert!(ok, "{n}: |v|² − 1 ≈ {k}·2u: δX at {ratio:.2} of the model");
        let far = 1.0 + 1e-9;
        outside += usize::from(!within(&th, Vec2::new(v.x * far, v.y * far), t.max(0.5)).0);
    }
    assert!(
        outside > 1000,
        "a speed off by 10⁻⁹ outside the model in {outside} of 2000"
    );
}

/// With correctly rounded elementary functions (CORE-MATH in `f64`, MPFR) the `f64` flight is the
/// MPFR flight at 53 bits to the bit — the displacement, the velocity and ξ — over random flights
/// as above (near anti-alignment included): the shadow audit replays what ran. (With `f64`'s
/// libm `atan` in place of CORE-MATH's, 1 of the 4 000 flights differed.)
#[test]
fn f64_flights_are_mpfr_53_flights_bit_for_bit() {
    let mut r = Mix(12);
    let at53 = |x: f64| Float::with_val(53, x);
    let bits = |p: &FlightPoint<Float>| {
        [&p.disp.x, &p.disp.y, &p.vel.x, &p.vel.y, &p.along].map(|q| q.to_f64().to_bits())
    };
    let mut differ = 0;
    for n in 0..4000 {
        let (th, v, t) = random_flight(&mut r, n);
        let lo = th.start(&v).at(&t);
        let hi = lift_to(&th, 53)
            .start(&Vec2::new(at53(v.x), at53(v.y)))
            .at(&at53(t));
        let lo_bits = [lo.disp.x, lo.disp.y, lo.vel.x, lo.vel.y, lo.along].map(f64::to_bits);
        if lo_bits != bits(&hi) {
            differ += 1;
        }
    }
    assert_eq!(differ, 0, "{differ} of 4000 flights differ from MPFR-53");
}

/// ε → 0 is the straight flight: |X(t) − tv| ≤ εt²/2 (the curvature is at most ε), here with
/// ε = 10⁻⁹ to rounding.
#[test]
fn a_vanishing_field_is_the_straight_flight() {
    let mut r = Mix(3);
    for _ in 0..200 {
        let eps = 1e-9;
        let th = th64(eps, 6.3 * r.unit());
        let phi = 6.3 * r.unit();
        let v = Vec2::new(phi.cos(), phi.sin());
        let t = 3.0 * r.unit();
        let at = th.start(&v).at(&t);
        let off = at.disp.sub(&Vec2::new(v.x * t, v.y * t)).norm2().sqrt();
        assert!(off <= eps * t * t / 2.0 + 64.0 * U * t, "{off:e}");
    }
}

/// Reversibility: the flight from the end point with the velocity reversed, for the same time,
/// returns to the start with the velocity reversed (ε fixed), to the error model twice over.
#[test]
fn a_reversed_flight_retraces_itself() {
    let mut r = Mix(5);
    for _ in 0..1000 {
        let th = th64(10f64.powf(4.0 * r.unit() - 2.0), 6.3 * r.unit());
        let phi = 6.3 * r.unit();
        let v = Vec2::new(phi.cos(), phi.sin());
        let t = 2.0 * r.unit();
        let go = th.start(&v).at(&t);
        let back = th.start(&(-go.vel.clone())).at(&t);
        let dx = (back.disp.x + go.disp.x).hypot(back.disp.y + go.disp.y);
        let dv = (back.vel.x + v.x).hypot(back.vel.y + v.y);
        // The reversed start's angle error 16u(1 + εt) is amplified by e^{εt} at most along the way back.
        let amp = (th.strength * t).exp();
        assert!(dx <= 2.0 * 64.0 * U * t + 16.0 * U * (1.0 + th.strength * t) * amp * t);
        assert!(
            dv <= 2.0 * 16.0 * U * (1.0 + th.strength * t) * amp,
            "{dv:e}"
        );
    }
}

/// The contraction integrates to εξ; ξ = (1/ε) ln(cosh εt + c sinh εt) at 200 bits.
#[test]
fn the_integrated_contraction_is_the_work_of_the_field() {
    let th = unit_field(0.7, 0.4);
    let v = unit(2.2);
    let t = big(1.3);
    let at = th.start(&v).at(&t);
    let c = th.dir.dot(&v);
    let et = th.strength.clone() * &t;
    let closed = (et.clone().cosh() + &(c * et.sinh())).ln();
    let diff = (contraction(&th, &at) - &closed).to_f64().abs();
    assert!(diff < 1e-55, "{diff:e}");
}

#[test]
fn quadratic_roots_are_the_smallest_positive_ones() {
    // 1 − 3s + 2s²: roots 1/2, 1.
    assert_eq!(first_root(&1.0f64, &-3.0, &2.0), Some(0.5));
    // 1 + s − s²/4 ... − s²: positive root (1 + √5)/2.
    let r = first_root(&1.0f64, &1.0, &-1.0).unwrap();
    assert!((r - (1.0 + 5f64.sqrt()) / 2.0).abs() < 1e-15);
    // No positive root: increasing and convex, or a positive minimum.
    assert_eq!(first_root(&1.0f64, &1.0, &1.0), None);
    assert_eq!(first_root(&1.0f64, &-1.0, &1.0), None);
}

/// The smallest positive root of a + bs + cs² at [`BITS`] (the coefficients exact), if any.
fn exact_root(a: f64, b: f64, c: f64) -> Option<Float> {
    let (a, b, c) = (big(a), big(b), big(c));
    if c == 0 {
        return (b < 0).then(|| Float::with_val(BITS, &a / -b));
    }
    let disc = Float::with_val(BITS, b.square_ref()) - Float::with_val(BITS, &a * &c) * 4u32;
    if disc < 0 {
        return None;
    }
    let root = disc.sqrt();
    let two_c = Float::with_val(BITS, &c * 2u32);
    let nb = Float::with_val(BITS, -&b);
    [
        Float::with_val(BITS, &nb - &root),
        Float::with_val(BITS, &nb + &root),
    ]
    .into_iter()
    .map(|n| n / &two_c)
    .filter(|r| *r > 0)
    .min_by(|x, y| x.partial_cmp(y).unwrap())
}

/// A march step — the root of the lower bound L less twice [`root_error`] — is below the exact
/// root of L, over random quadratics and ones within 10⁻¹⁶ … 10⁻² of a double root (the
/// discriminant lost in its rounding), where a fixed relative margin of a few units fails.
#[test]
fn a_step_stays_below_the_exact_root() {
    let mut r = Mix(14);
    let (mut checked, mut near) = (0, 0);
    for n in 0..20_000 {
        let a = 10f64.powf(-12.0 * r.unit());
        let b = -10f64.powf(3.0 * r.unit() - 1.5);
        let c = if n % 2 == 0 {
            // A double root at −b/(2c): c = b²/(4a), moved by a relative 10⁻¹⁶ … 10⁻².
            let k = 10f64.powf(-16.0 + 14.0 * r.unit()) * (r.unit() - 0.5);
            b * b / (4.0 * a) * (1.0 + k)
        } else {
            4.0 * (r.unit() - 0.5) * b * b / a
        };
        let (Some(s), Some(exact)) = (first_root(&a, &b, &c), exact_root(a, b, c)) else {
            continue;
        };
        let step = s - s * 2.0 * root_error(&a, &b, &c);
        assert!(
            big(step) <= exact,
            "{n}: step {step:e} past the root {exact} of {a:e} {b:e} {c:e}"
        );
        checked += 1;
        near += usize::from(n % 2 == 0);
    }
    assert!(checked > 10_000 && near > 3000, "{checked} {near}");
}

#[test]
fn exact_fields_have_exact_axes() {
    use rug::Rational;
    let q = |n: i32, d: i32| Rational::from((n, d));
    let th = Thermostat::<Float>::exact(&q(1, 10), &q(-270, 1), 128).unwrap();
    assert_eq!((th.dir.x.to_f64(), th.dir.y.to_f64()), (0.0, 1.0));
    assert_eq!(th.strength, Float::with_val(128, q(1, 10)));
    let th = Thermostat::<f64>::exact(&q(1, 1), &q(30, 1), ()).unwrap();
    assert!((th.dir.x - 0.75f64.sqrt()).abs() < 2.0 * U && (th.dir.y - 0.5).abs() < 2.0 * U);
}

/// The start's point skips the elementary functions (exact at ±0): the same bits, signed zeros
/// included, as calling them, in `f64` and MPFR, over random starts (anti-aligned ones too).
#[test]
fn the_start_point_is_the_calls_at_zero_bit_for_bit() {
    let mut r = Mix(13);
    let bits = |p: &FlightPoint<f64>| {
        [
            p.disp.x, p.disp.y, p.vel.x, p.vel.y, p.acc.x, p.acc.y, p.along,
        ]
        .map(f64::to_bits)
    };
    let words = |p: &FlightPoint<Float>| {
        [
            &p.disp.x, &p.disp.y, &p.vel.x, &p.vel.y, &p.acc.x, &p.acc.y, &p.along,
        ]
        .map(|q| (q.to_f64().to_bits(), q.is_sign_negative()))
    };
    for n in 0..2000 {
        let (th, v, _) = random_flight(&mut r, n);
        let start = th.start(&v);
        assert_eq!(
            bits(&start.point(&0.0, true)),
            bits(&start.point(&0.0, false)),
            "{n}"
        );
        let hi = lift(&th);
        let start = hi.start(&Vec2::new(big(v.x), big(v.y)));
        let zero = big(0.0);
        assert_eq!(
            words(&start.point(&zero, true)),
            words(&start.point(&zero, false)),
            "{n}"
        );
    }
}

/// The event's point by a Taylor step ([`Start::step_from`], `proofs-notes/thermostat-flight.md`,
/// "Taylor steps"), over 2000 random flights (a quarter near anti-alignment) and steps up
/// to the largest it takes: in `f64`, within [`Start::error`] at t + s of the exact flight; at
/// 200 bits, within the two closed forms' models plus the remainders (A_{K+1}(εs)^{K+1}/(K + 1)!
/// for the velocity, A_{K+1}(εs)^{K+1}s/(K + 2)! for the displacement, K the order taken) of the
/// closed form at t + s; refused beyond the seventh order's reach, A₈(εs)⁸/8! = u/64.
#[test]
fn a_taylor_step_to_the_event_is_within_the_model() {
    let mut r = Mix(23);
    let diff = |a: &Vec2<Float>, b: &Vec2<Float>| {
        let (x, y) = (
            Float::with_val(BITS, &a.x - &b.x),
            Float::with_val(BITS, &a.y - &b.y),
        );
        Float::with_val(BITS, x.square() + y.square())
            .sqrt()
            .to_f64()
    };
    let mut worst: f64 = 0.0;
    for n in 0..2000 {
        let (th, v, t) = random_flight(&mut r, n);
        let eps = th.strength;
        let start = th.start(&v);
        let widest = (U / 64.0 * 40320.0 / 1385.0).powf(1.0 / 8.0) / eps;
        // Steps of every order: from the widest down to 10⁻¹⁸ of it.
        let s = widest * r.unit().powi(1 + 3 * (n % 7) as i32);
        let p = start
            .step_from(&start.at(&t), &s)
            .expect("a step within the bound");
        assert!(start.step_from(&start.at(&t), &(1.01 * widest)).is_none());
        let hi = lift(&th);
        let hs = hi.start(&Vec2::new(big(v.x), big(v.y)));
        let exact = hs.at(&(big(t) + s));
        let (mx, mv) = start.error(&(t + s));
        let (dx, dv) = (dist(&exact.disp, &p.disp), dist(&exact.vel, &p.vel));
        assert!(
            dx <= mx && dv <= mv,
            "{n}: δX = {dx:e} of {mx:e}, δv = {dv:e} of {mv:e}"
        );
        worst = worst.max(dx / mx).max(dv / mv);
        // At 200 bits the remainder is what separates the step from the closed form (of a start
        // and a field of unit length at 200 bits: the forms take them so).
        let field = unit_field(eps, th.dir.y.atan2(th.dir.x));
        let hs = field.start(&unit(v.y.atan2(v.x)));
        let u = <Float as Real>::unit_roundoff(BITS);
        let s = big((u / 64.0 * 40320.0 / 1385.0).powf(1.0 / 8.0) / eps
            * r.unit().powi(1 + 3 * (n % 7) as i32));
        let p = hs
            .step_from(&hs.at(&big(t)), &s)
            .expect("a step within the bound");
        let ts = big(t) + &s;
        let exact = hs.at(&ts);
        let es = eps * s.to_f64();
        let (ma, va) = hs.error(&big(t));
        let (mb, vb) = hs.error(&ts);
        let order = taylor_order(es, u).expect("an order within the bound");
        let rv = taylor_remainder(es, order);
        let rx = rv * s.to_f64() / (order + 2) as f64;
        assert!(rv <= u / 64.0);
        let (dx, dv) = (diff(&exact.disp, &p.disp), diff(&exact.vel, &p.vel));
        let slack = 4.0 * u * (1.0 + ts.to_f64());
        assert!(dx <= ma + mb + rx + slack, "{n}: 200 bits δX = {dx:e}");
        assert!(dv <= va + vb + rv + slack, "{n}: 200 bits δv = {dv:e}");
    }
    eprintln!("largest error / model of the Taylor step in f64: {worst:.3}");
}

/// The exit bound's logarithm (`cell::ln_above`) is above ln y and within 1 − ln 2 of it, from
/// y = 1 to 10³⁰⁰ (against MPFR at 200 bits), and 0 below 1.
#[test]
fn the_exit_bounds_logarithm_is_above_by_less_than_a_third() {
    let mut r = Mix(29);
    for n in 0..20_000 {
        let y = if n < 4 {
            [1.0, 2.0, 1.999_999_999_999, f64::MAX][n]
        } else {
            10f64.powf(300.0 * r.unit().powi(3))
        };
        let ln = big(y).ln().to_f64();
        let above = super::cell::ln_above(y);
        assert!(above >= ln, "{y}: {above} < {ln}");
        assert!(
            above - ln <= 1.0 - std::f64::consts::LN_2 + 1e-12,
            "{y}: {above} vs {ln}"
        );
    }
    assert_eq!(super::cell::ln_above(0.99), 0.0);
}

/// Taylor steps of every order K = 1…7 ([`Start::step_by`]) against the closed form at 200 bits,
/// at σ = εs up to 0.4 (far beyond the steps taken, where every term counts): within the
/// remainders A_{K+1}σ^{K+1}/(K + 1)! (velocity) and A_{K+1}σ^{K+1}s/(K + 2)! (displacement) of
/// the zigzag bound, over 300 random flights — a wrong coefficient of Bₖ exceeds the bound of
/// order k at small σ, a wrong bound at large σ.
#[test]
fn taylor_steps_of_every_order_are_within_their_remainders() {
    let mut r = Mix(29);
    let (mut worst, mut tight) = (0f64, 0f64);
    for n in 0..300 {
        let (th, v, t) = random_flight(&mut r, n);
        let eps = th.strength;
        let field = unit_field(eps, th.dir.y.atan2(th.dir.x));
        let hs = field.start(&unit(v.y.atan2(v.x)));
        let sigma = 0.4 * r.unit().powi(1 + (n % 3) as i32);
        let s = big(sigma / eps);
        let a = hs.at(&big(t));
        let exact = hs.at(&(big(t) + &s));
        let (ma, va) = hs.error(&big(t));
        let (mb, vb) = hs.error(&(big(t) + &s));
        for order in 1..=7 {
            let p = hs.step_by(&a, &s, order);
            let rv = taylor_remainder(sigma, order);
            let rx = rv * s.to_f64() / (order + 2) as f64;
            let (dx, dv) = (dist_big(&exact.disp, &p.disp), dist_big(&exact.vel, &p.vel));
            let (bx, bv) = (rx + ma + mb + 1e-50, rv + va + vb + 1e-50);
            assert!(
                dv <= bv,
                "{n}, order {order}, σ = {sigma}: δv = {dv:e} > {bv:e}"
            );
            assert!(
                dx <= bx,
                "{n}, order {order}, σ = {sigma}: δX = {dx:e} > {bx:e}"
            );
            worst = worst.max(dv / bv).max(dx / bx);
            if order == 7 {
                tight = tight.max(dv / bv);
            }
        }
    }
    eprintln!("largest Taylor error over its remainder: {worst:.3} (order 7: {tight:.3})");
}

/// |a − b| at 200 bits.
fn dist_big(a: &Vec2<Float>, b: &Vec2<Float>) -> f64 {
    let x = Float::with_val(BITS, &a.x - &b.x);
    let y = Float::with_val(BITS, &a.y - &b.y);
    Float::with_val(BITS, x.square() + y.square())
        .sqrt()
        .to_f64()
}

/// The quotient on a rounding midpoint that CORE-MATH's atan2 gives up on (`exit(1)`, found by the
/// fuzz target `thermostat_kernel`): y = 3·2⁻⁵¹, x = 2 − 3·2⁻⁵¹, y/x = 1.5·2⁻⁵¹(1 + 1.5·2⁻⁵¹ + …)
/// 4.5 units of its last place above 1.5·2⁻⁵¹, atan(y/x) within |z|³/3 below that midpoint. The
/// flight takes the series there ([`atan_of_ratio`]): within 2u of the arctangent at 200 bits, the
/// same bits in MPFR-53, and the series is taken for every |y/x| ≤ 2⁻¹⁴ and no ratio above 2⁻¹³.
#[test]
fn the_atan2_worst_case_on_a_rounding_midpoint_takes_the_series() {
    let (y, x) = (3.0 * 2f64.powi(-51), 2.0 - 3.0 * 2f64.powi(-51));
    let a = atan_of_ratio(y, &x);
    let exact = Float::with_val(BITS, big(y) / big(x)).atan();
    let err = (Float::with_val(BITS, &exact - a) / &exact).to_f64().abs();
    assert!(err <= 2.0 * U, "relative error {err:e}");
    let m = atan_of_ratio(Float::with_val(53, y), &Float::with_val(53, x));
    assert_eq!(m.to_f64().to_bits(), a.to_bits());
    let mut r = Mix(37);
    for _ in 0..2000 {
        let (y, x) = (2f64.powf(-60.0 * r.unit()), 0.5 + r.unit());
        let z = y / x;
        let a = atan_of_ratio(y, &x);
        let exact = Float::with_val(BITS, big(y) / big(x)).atan();
        let err = (Float::with_val(BITS, &exact - a) / &exact).to_f64().abs();
        assert!(err <= 2.0 * U, "y = {y:e}, x = {x}: relative error {err:e}");
        if z <= 2f64.powi(-14) {
            let q = y / x;
            assert_eq!(a.to_bits(), (q - q * q * q / 3.0).to_bits());
        } else if z > 2f64.powi(-13) {
            assert_eq!(a.to_bits(), y.atan_ratio(&x).to_bits());
        }
    }
}
