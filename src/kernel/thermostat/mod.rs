//! Flights under a Gaussian-thermostatted electric field: ṙ = v, v̇ = E − (E·v)v, |v| = 1.
//!
//! In the frame of the field (ê = E/|E|, ê⊥ = Jê, ε = |E|) the velocity angle θ from ê obeys
//! θ̇ = −ε sin θ, so tan(θ/2) = tan(θ₀/2)e^{−εt}: the velocity relaxes towards ê, and the flight
//! has a closed form (`proofs-notes/thermostat-flight.md`). With c = ê·v, s = ê×v at the start,
//! p = 1 + c, m = 1 − c (each formed without cancellation, p·m = s²) and x = e^{−εt}:
//!
//! * along the field, ξ(t) = t + ln A/ε, A = (p + m x²)/2 = 1 − m(1 − x²)/2, taken as
//!   `ln_1p(−m·(−expm1(−2εt))/2)` where A ≥ 1/2 and as `ln(A)` (two positive terms) below;
//! * across it, η(t) = (2/ε)·atan(s·(−expm1(−εt))/(p + m x)), the arctangent of the exact
//!   quotient ([`Real::atan_ratio`]; below |quotient| = 2⁻¹⁴ the series q − q³/3, since
//!   CORE-MATH's atan2 exits on a quotient on a rounding midpoint, `atan_of_ratio`);
//! * the velocity, cos θ = (p − m x²)/(p + m x²), sin θ = 2sx/(p + m x²);
//! * the acceleration v̇ = ε sin θ·(sin θ ê − cos θ ê⊥), of size ε|sin θ| ≤ ε, and
//!   |v̈| = ε²|sin θ| ≤ ε² (the certificates' curvature bounds, [`isolate`]);
//! * the phase-space contraction α = E·v integrates to ∫₀ᵗ α = εξ(t) (the work of the field).
//!
//! Every form is free of cancellation as εt → 0 (it tends to the straight flight t·v) and as
//! εt → ∞ (the anti-aligned start p → 0 included). `exp`, `expm1`, `ln`, `ln_1p` and `atan` are
//! correctly rounded in `f64` too (CORE-MATH), so the `f64` flight is the MPFR-53 flight to the
//! bit, and both are within the error model of the exact one. The next event in a cell is [`ConvexCell::next_event_thermostat`]
//! (`cell.rs`), its contacts certified by [`isolate`].
//!
//! [`ConvexCell::next_event_thermostat`]: super::cell::ConvexCell::next_event_thermostat

pub mod cell;
mod contacts;
pub mod isolate;
mod screen;
mod search;

use super::arc::perp;
use super::vec2::Vec2;
use crate::numbers::real::Real;
use rug::Rational;
use std::cell::OnceCell;

/// The thermostatted field: its strength ε = |E| > 0 and direction ê (unit to rounding).
#[derive(Debug, Clone, PartialEq)]
pub struct Thermostat<T> {
    /// ε = |E| > 0.
    pub strength: T,
    /// ê = E/|E|.
    pub dir: Vec2<T>,
}

/// Where a flight is at a time t: displacement from the start, velocity, acceleration, and the
/// displacement ξ along the field (ε·ξ is the integrated contraction ∫α dt).
#[derive(Debug, Clone, PartialEq)]
pub struct FlightPoint<T> {
    /// X(t) = ξê + ηê⊥.
    pub disp: Vec2<T>,
    /// v(t).
    pub vel: Vec2<T>,
    /// v̇(t).
    pub acc: Vec2<T>,
    /// ξ(t).
    pub along: T,
}

/// A flight about to start: the start velocity in the field's frame (c, s) and p = 1 + c,
/// m = 1 − c without cancellation.
#[derive(Debug, Clone)]
pub struct Start<'a, T: Real> {
    th: &'a Thermostat<T>,
    s: T,
    p: T,
    m: T,
    /// The error model's constants of this flight, in `f64` ([`Start::error`]): ε, 1/|s| and
    /// π/(ε|s|), formed once for the flight instead of at every point of every march.
    model: [f64; 3],
    /// cos θ₀ ≥ 0: |sin θ| never grows along the flight, sin θ/sin θ₀ ≤ 1 ([`Start::error`]).
    relaxing: bool,
    /// The point at t = +0, formed once for every march of the flight ([`Start::origin`]).
    origin: OnceCell<FlightPoint<T>>,
}

impl<T: Real> Thermostat<T> {
    /// The field of signed strength `field` (exact) along the angle `degrees` (exact) from the
    /// x axis, at the working precision `ctx`; `None` for a zero field (straight flights). A
    /// multiple of 90° gives the exact axis; other angles round cos and sin at `ctx`.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::kernel::thermostat::Thermostat;
    /// use rug::Rational;
    /// let th = Thermostat::<f64>::exact(&Rational::from((-3, 10)), &Rational::from(90), ()).unwrap();
    /// assert_eq!((th.strength, th.dir.x, th.dir.y), (0.3, 0.0, -1.0));
    /// assert!(Thermostat::<f64>::exact(&Rational::new(), &Rational::from(30), ()).is_none());
    /// ```
    pub fn exact(field: &Rational, degrees: &Rational, ctx: T::Ctx) -> Option<Self> {
        if *field == 0 {
            return None;
        }
        let turn = Rational::from(degrees / 90u32);
        let (cos, sin) = if *turn.denom() == 1 {
            let q = turn.numer().mod_u(4) as usize;
            let (c, s) = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][q];
            (T::from_f64(ctx, c), T::from_f64(ctx, s))
        } else {
            let angle = T::pi(ctx) * &T::from_rational(ctx, &Rational::from(degrees / 180u32));
            (angle.clone().cos(), angle.sin())
        };
        let sign = if *field < 0 { -1.0 } else { 1.0 };
        let strength = T::from_rational(ctx, &Rational::from(field.abs_ref()));
        Some(Thermostat::new(
            strength,
            Vec2::new(cos.scale(sign), sin.scale(sign)),
        ))
    }

    /// The field of strength `strength` > 0 along `dir` (≠ 0), normalised at the working
    /// precision: the closed form takes |ê| = 1, and a direction a rounding off unit length would
    /// break the flight's reversibility at that rounding (an exact axis stays exact).
    pub fn new(strength: T, dir: Vec2<T>) -> Self {
        let norm = dir.norm2().sqrt();
        let dir = Vec2::new(dir.x / &norm, dir.y / &norm);
        Thermostat { strength, dir }
    }

    /// The flight that starts with the velocity `v`, of unit speed up to the rounding of the
    /// engine's states (|v|² − 1 = O(u): every start is a rounded unit vector, and the Newton
    /// factor after every event keeps it so). The forms take c² + s² = 1; a start of speed 1 + δ
    /// is flown with cos θ₀ = c along the field but c/|v| in its velocity, a slope error ≈ δ —
    /// inside the error model for δ of a few u, outside it beyond
    /// (`proofs-notes/thermostat-flight.md`, "The start's speed").
    pub fn start(&self, v: &Vec2<T>) -> Start<'_, T> {
        let c = self.dir.dot(v);
        let s = self.dir.cross(v);
        let relaxing = !c.lt0();
        let (p, m) = if c.lt0() {
            let m = (-c).add_f64(1.0);
            ((s.square()) / &m, m)
        } else {
            let p = c.add_f64(1.0);
            (p.clone(), s.square() / &p)
        };
        let (eps, sin) = (self.strength.to_f64(), s.to_f64().abs());
        let model = [eps, 1.0 / sin, std::f64::consts::PI / (eps * sin)];
        Start {
            th: self,
            s,
            p,
            m,
            model,
            relaxing,
            origin: OnceCell::new(),
        }
    }

    /// The acceleration ε sin θ (sin θ ê − cos θ ê⊥) at the velocity (cos θ, sin θ) in the
    /// field's frame.
    fn acceleration(&self, cos: &T, sin: &T) -> Vec2<T> {
        let k = self.strength.clone() * sin;
        let (a, b) = (k.clone() * sin, -(k * cos));
        self.world(&a, &b)
    }

    /// aê + bê⊥.
    fn world(&self, a: &T, b: &T) -> Vec2<T> {
        let e = &self.dir;
        let j = perp(e);
        Vec2::new(
            a.clone() * &e.x + &(b.clone() * &j.x),
            a.clone() * &e.y + &(b.clone() * &j.y),
        )
    }
}

impl<T: Real> Start<'_, T> {
    /// The flight at the time `t` ≥ 0 (see the module documentation for the forms).
    ///
    /// Three transcendental calls: g = −expm1(−εt), atan (of a ratio) and a logarithm; x = e^{−εt} is 1 − g
    /// while g ≤ ½ (no cancellation there) and exp(−εt) beyond, and 1 − x² = g(1 + x). At
    /// t = 0 no call is made: exp, expm1, atan and log1p are exact at ±0 (1, ±0, ±0, ±0), so the
    /// start's point is the same value, bit for bit, as the calls would give.
    pub fn at(&self, t: &T) -> FlightPoint<T> {
        self.point(t, true)
    }

    /// The flight at t = +0, [`Start::at`] of +0, formed once for the flight: every march of
    /// every candidate begins there (the same value, bit for bit, as forming it again).
    pub fn origin(&self) -> &FlightPoint<T> {
        self.origin
            .get_or_init(|| self.point(&T::zero(self.th.strength.ctx()), true))
    }

    /// [`Start::at`], with the calls at t = 0 skipped if `shortcut` (the test of the shortcut
    /// calls them).
    fn point(&self, t: &T, shortcut: bool) -> FlightPoint<T> {
        let eps = &self.th.strength;
        let et = eps.clone() * t;
        let now = shortcut && !(et.gt0() || et.lt0());
        // g = −expm1(−εt); expm1(±0) = ±0 makes it εt itself at the start.
        let g = if now {
            et.clone()
        } else {
            -((-et.clone()).exp_m1())
        };
        let x = if now || !g.clone().add_f64(-0.5).gt0() {
            (-g.clone()).add_f64(1.0)
        } else {
            (-et.clone()).exp()
        };
        let mx = self.m.clone() * &x;
        let across = if self.s.gt0() || self.s.lt0() {
            let (y, x) = (self.s.clone() * &g, self.p.clone() + &mx);
            // atan2(±0, x > 0) = ±0 (x > 0 unless p = 0 and x = 0: then y = 0 too, and s = 0).
            let a = if now { y / &x } else { atan_of_ratio(y, &x) };
            a.scale(2.0) / eps
        } else {
            T::zero(t.ctx())
        };
        let mx2 = mx * &x;
        let log_a = if self.p.gt0() || self.p.lt0() {
            // m·(1 − x²)/2, 1 − x² = g(1 + x) = −expm1(−2εt).
            let z = (self.m.clone() * &(g * &x.clone().add_f64(1.0))).scale(0.5);
            if z.clone().add_f64(-0.5).gt0() {
                (self.p.clone() + &mx2).scale(0.5).ln()
            } else if now {
                -z
            } else {
                (-z).ln_1p()
            }
        } else {
            // Anti-aligned (s = 0, c < 0): A(t)/A(0) = x², its logarithm −2εt without underflow
            // of x². A(0) = m/2 is taken as 1, as the forms above take p + m = 2: the flight of
            // the start's direction at speed 1, whose displacement at t = 0 is exactly 0 (with
            // ln(m/2) kept, a speed 1 − δ displaced the start by ≈ −δ/(2ε): 10⁻¹³ at ε = 10⁻³,
            // outside the error model, found by the fuzz target `thermostat_kernel`).
            -(et.scale(2.0))
        };
        let along = t.clone() + &(log_a / eps);
        let den = self.p.clone() + &mx2;
        let cos = (self.p.clone() - &mx2) / &den;
        let sin = (self.s.clone() * &x).scale(2.0) / &den;
        FlightPoint {
            disp: self.th.world(&along, &across),
            vel: self.th.world(&cos, &sin),
            acc: self.th.acceleration(&cos, &sin),
            along,
        }
    }

    /// The flight at a + `s` from its point `at` at a, by a Taylor step of the lowest order K ≤ 7
    /// whose remainder is below the working precision (`None` where even the seventh order's is
    /// not: εs beyond about 8.5·10⁻³ in `f64`).
    /// The velocity's derivatives are bounded by the zigzag numbers, |v⁽ⁿ⁾| ≤ Aₙεⁿ, so the
    /// remainders are A_{K+1}(εs)^{K+1}/(K + 1)! ≤ u/64 for the velocity and
    /// A_{K+1}(εs)^{K+1}s/(K + 2)! for the displacement (`proofs-notes/thermostat-flight.md`,
    /// "Taylor steps"). In the field's frame v⁽ᵏ⁾ = εᵏBₖ·v (complex, v = cos θ + i sin θ,
    /// `taylor_terms`); the sums are taken in σ = εs by Horner's rule, with exact divisions by
    /// the factorials' factors. Four operations only, so the same in `f64` and MPFR-53.
    pub fn step_from(&self, at: &FlightPoint<T>, s: &T) -> Option<FlightPoint<T>> {
        let es = (self.th.strength.clone() * s).to_f64();
        let order = taylor_order(es, T::unit_roundoff(s.ctx()))?;
        Some(self.step_by(at, s, order))
    }

    /// [`Start::step_from`] at the order `order` (1 to 7), its remainders added to the running
    /// error analysis's bound.
    fn step_by(&self, at: &FlightPoint<T>, s: &T, order: usize) -> FlightPoint<T> {
        let th = self.th;
        let ctx = s.ctx();
        let sigma = th.strength.clone() * s;
        let es = sigma.to_f64();
        let (c, n) = (th.dir.dot(&at.vel), th.dir.cross(&at.vel));
        let b = taylor_terms(&c, &n, order);
        // h[k] = σ/(k + 2), up to σ/(order + 1).
        let h: [T; 7] = std::array::from_fn(|i| match i + 2 {
            k if k > order + 1 => T::zero(ctx),
            k if k.is_power_of_two() => sigma.clone().scale(1.0 / k as f64),
            k => sigma.clone() / &T::from_f64(ctx, k as f64),
        });
        // Σ Bₖσᵏ/k! over v (the velocity's increment) and 1 + Σ Bₖσᵏ/(k + 1)! (the
        // displacement's over s·v), as (real, imaginary) pairs.
        let horner = |shift: usize| {
            let mut z = b[order - 1].clone();
            for j in (1..order).rev() {
                let hj = &h[j + shift - 2];
                z = (
                    b[j - 1].0.clone() + &(hj.clone() * &z.0),
                    b[j - 1].1.clone() + &(hj.clone() * &z.1),
                );
            }
            z
        };
        let q = horner(1);
        let q = (sigma.clone() * &q.0, sigma * &q.1);
        let p = horner(2);
        let p = (
            (h[0].clone() * &p.0).add_f64(1.0) * s,
            h[0].clone() * &p.1 * s,
        );
        // Multiplied by v = c + in in the field's frame.
        let turn = |z: &(T, T)| {
            let re = c.clone() * &z.0 - &(n.clone() * &z.1);
            let im = c.clone() * &z.1 + &(n.clone() * &z.0);
            (re, im)
        };
        let (dx, dv) = (turn(&p), turn(&q));
        let (dx_w, dv_w) = (th.world(&dx.0, &dx.1), th.world(&dv.0, &dv.1));
        // The remainders, in the running error analysis's bound (no arithmetic elsewhere).
        let rv = taylor_remainder(es, order);
        let rx = rv * s.to_f64() / (order + 2) as f64;
        let vel = Vec2::new(
            (at.vel.x.clone() + &dv_w.x).truncated(rv),
            (at.vel.y.clone() + &dv_w.y).truncated(rv),
        );
        let (cv, nv) = (th.dir.dot(&vel), th.dir.cross(&vel));
        FlightPoint {
            disp: Vec2::new(
                (at.disp.x.clone() + &dx_w.x).truncated(rx),
                (at.disp.y.clone() + &dx_w.y).truncated(rx),
            ),
            acc: th.acceleration(&cv, &nv),
            vel,
            along: (at.along.clone() + &dx.0).truncated(rx),
        }
    }

    /// The error model of [`Start::at`] at `t` in units of the working precision
    /// (`proofs-notes/thermostat-flight.md`): bounds (δX, δv) on the errors of the displacement
    /// and the velocity against the exact flight of the same start. The forms' own rounding gives
    /// 64u·t and 16u(1 + εt); the start's angle from ê, formed with an absolute error ≤ 2u,
    /// perturbs θ(t) by 2u·sin θ/sin θ₀ ≤ 2u·min(e^{εt}, 1/|s|) and X by 2u(|X| + I),
    /// I = ∫₀ᵗ sin θ/sin θ₀ ≤ min(t·e^{εt}, π/(ε|s|)) (the anti-aligned start is unstable); where
    /// cos θ₀ ≥ 0, sin θ/sin θ₀ = 1/(cosh εt + c sinh εt) ≤ 1, so both factors are 1 and I ≤ t.
    pub fn error(&self, t: &T) -> (f64, f64) {
        let u = T::unit_roundoff(t.ctx());
        let t = t.to_f64().abs();
        let [eps, inv_s, turn] = self.model;
        // e⁰ = 1 exactly: no call at the start of a march, nor along a relaxing flight.
        let et = eps * t;
        let grow = if et == 0.0 || self.relaxing {
            1.0
        } else {
            et.exp()
        };
        let lean = grow.min(inv_s);
        let integral = (t * grow).min(turn);
        (
            u * (64.0 * t + 4.0 * (t + integral)),
            u * (16.0 * (1.0 + eps * t) + 4.0 * lean),
        )
    }

    /// The thermostat this flight runs in.
    pub fn thermostat(&self) -> &Thermostat<T> {
        self.th
    }

    /// The flight's variation with its start angle at the time `t`: (∂X(t)/∂θ₀, ∂θ(t)/∂θ₀),
    /// the tangent map of a flight (`proofs-notes/thermostat-lyapunov.md`). With x = e^{−εt} and
    /// D = p + m x², ∂θ/∂θ₀ = sin θ/sin θ₀ = 2x/D and, in the field's frame,
    /// ∂X/∂θ₀ = (v(t) − v(0))/θ̇(0) = (−s(1 − x²), (1 − x)(p − m x))/(εD), each factor formed
    /// without cancellation (1 − x and 1 − x² by `expm1`); it tends to t·Jv(0) as εt → 0.
    pub fn variation(&self, t: &T) -> (Vec2<T>, T) {
        let eps = &self.th.strength;
        let et = eps.clone() * t;
        let x = (-et.clone()).exp();
        let g1 = -((-et.clone()).exp_m1());
        let g2 = -(et.scale(-2.0).exp_m1());
        let mx = self.m.clone() * &x;
        let den = self.p.clone() + &(mx.clone() * &x);
        let eden = eps.clone() * &den;
        let along = -(self.s.clone() * &g2) / &eden;
        let across = (g1 * &(self.p.clone() - &mx)) / &eden;
        (self.th.world(&along, &across), x.scale(2.0) / &den)
    }
}

/// atan(y/x) for x > 0: the series q − q³/3 of the rounded quotient q = y/x where z⁴ ≤ u/8
/// (z = y/x read in `f64`: |z| ≤ 2⁻¹⁴ in `f64`; the remainder |z|⁵/5 is below u|z|/40), else the
/// correctly rounded arctangent of the exact quotient ([`Real::atan_ratio`]). Below that ratio
/// CORE-MATH's atan2 can meet a quotient y/x on a rounding midpoint, where atan(y/x) lies within
/// |z|³/3 of it and its accurate path gives up: it prints "Unexpected worst-case found" and calls
/// `exit(1)` (found by the fuzz target `thermostat_kernel` at y = 3·2⁻⁵¹, x = 2 − 3·2⁻⁵¹; reported
/// in `proofs-notes/thermostat-flight.md`, "Error model"). The series is four operations, so the
/// same in `f64` and MPFR-53, within 2u of the arctangent (the error model's count allows it).
fn atan_of_ratio<T: Real>(y: T, x: &T) -> T {
    let z = y.to_f64() / x.to_f64();
    let z2 = z * z;
    if z2 * z2 <= T::unit_roundoff(x.ctx()) / 8.0 {
        let q = y / x;
        // ±0 stays ±0, as atan2(±0, x > 0) (q − q³/3 would be +0).
        if !(q.gt0() || q.lt0()) {
            return q;
        }
        let cube = q.clone() * &q.square();
        return q - &(cube / &T::from_f64(x.ctx(), 3.0));
    }
    y.atan_ratio(x)
}

/// The zigzag numbers A₀…A₈: |v⁽ⁿ⁾| ≤ Aₙεⁿ along every thermostatted flight
/// (`proofs-notes/thermostat-flight.md`, "Taylor steps").
const ZIGZAG: [f64; 9] = [1.0, 1.0, 1.0, 2.0, 5.0, 16.0, 61.0, 272.0, 1385.0];

/// A_{K+1}/(K + 1)! for the orders K = 1…7.
const TAYLOR: [f64; 7] = [
    ZIGZAG[2] / 2.0,
    ZIGZAG[3] / 6.0,
    ZIGZAG[4] / 24.0,
    ZIGZAG[5] / 120.0,
    ZIGZAG[6] / 720.0,
    ZIGZAG[7] / 5040.0,
    ZIGZAG[8] / 40320.0,
];

/// Bounds on the velocity's remainder of Taylor steps of the orders K = 1…7 at σ = εs:
/// A_{K+1}σ^{K+1}/(K + 1)! (rounded up by 2⁻⁵⁰, in `f64`).
fn taylor_remainders(es: f64) -> [f64; 7] {
    let mut p = es;
    std::array::from_fn(|k| {
        p *= es;
        p * TAYLOR[k] * (1.0 + 1.0 / (1u64 << 50) as f64)
    })
}

/// The bound on the velocity's remainder of a Taylor step of order `order` at σ = εs.
fn taylor_remainder(es: f64, order: usize) -> f64 {
    taylor_remainders(es)[order - 1]
}

/// The lowest order K ≤ 7 of a Taylor step at σ = εs ≥ 0 whose velocity remainder is at most
/// u/64 (`None` if none is). Multiplications in `f64`, so the same decision at every precision of
/// the same u.
fn taylor_order(es: f64, u: f64) -> Option<usize> {
    if es.is_nan() || es < 0.0 {
        return None;
    }
    let r = taylor_remainders(es);
    r.iter().position(|&x| x <= u / 64.0).map(|k| k + 1)
}

/// B₁…B_K (K = `order`, zero beyond) of a Taylor step at the velocity (cos θ, sin θ) = (C, S) in
/// the field's frame, ε = 1: v⁽ᵏ⁾ = εᵏBₖ·v as complex numbers, from θ̇ = −ε sin θ
/// (B_{k+1} = DBₖ − iS·Bₖ, D the derivative along the flight: Ṡ = −CS, Ċ = S²):
/// B₁ = −iS, B₂ = −S² + iCS, B₃ = 3CS² − iS(C² − 2S²), B₄ = −S²(7C² − 5S²) + iCS(C² − 11S²),
/// B₅ = 15CS²(C² − 3S²) − iS(C⁴ − 43C²S² + 16S⁴),
/// B₆ = −S²(31C⁴ − 268C²S² + 61S⁴) + iCS(C⁴ − 148C²S² + 211S⁴),
/// B₇ = 21CS²(3C⁴ − 64C²S² + 53S⁴) − iS(C⁶ − 480C⁴S² + 1767C²S⁴ − 272S⁶).
fn taylor_terms<T: Real>(c: &T, n: &T, order: usize) -> [(T, T); 7] {
    let ctx = c.ctx();
    let k = |x: f64| T::from_f64(ctx, x);
    let (cc, ss, cs) = (c.square(), n.square(), c.clone() * n);
    let s2c = ss.clone() * c;
    // A polynomial Σ aᵢ C^{2(m−i)} S^{2i} by Horner's rule in the pair (C², S²).
    let even = |a: &[f64]| {
        let mut p = k(a[0]);
        let mut sp = T::one(ctx);
        for &ai in &a[1..] {
            sp *= &ss;
            p = p * &cc + &(k(ai) * &sp);
        }
        p
    };
    let mut b: [(T, T); 7] = std::array::from_fn(|_| (T::zero(ctx), T::zero(ctx)));
    b[0] = (T::zero(ctx), -n.clone());
    b[1] = (-ss.clone(), cs.clone());
    if order >= 3 {
        b[2] = (s2c.clone().scale(3.0), -(n.clone() * &even(&[1.0, -2.0])));
    }
    if order >= 4 {
        b[3] = (
            -(ss.clone() * &even(&[7.0, -5.0])),
            cs.clone() * &even(&[1.0, -11.0]),
        );
    }
    if order >= 5 {
        b[4] = (
            (s2c.clone() * &even(&[1.0, -3.0])).scale(15.0),
            -(n.clone() * &even(&[1.0, -43.0, 16.0])),
        );
    }
    if order >= 6 {
        b[5] = (
            -(ss.clone() * &even(&[31.0, -268.0, 61.0])),
            cs.clone() * &even(&[1.0, -148.0, 211.0]),
        );
    }
    if order >= 7 {
        b[6] = (
            (s2c * &even(&[3.0, -64.0, 53.0])) * &k(21.0),
            -(n.clone() * &even(&[1.0, -480.0, 1767.0, -272.0])),
        );
    }
    b
}

/// The integrated phase-space contraction ∫₀ᵗ α dt = ε·ξ(t) of a flight that has reached `at`.
pub fn contraction<T: Real>(th: &Thermostat<T>, at: &FlightPoint<T>) -> T {
    th.strength.clone() * &at.along
}

#[cfg(test)]
mod event_tests;
#[cfg(test)]
mod tests;
