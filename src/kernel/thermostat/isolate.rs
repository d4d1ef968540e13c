//! The earliest root of a contact function along a thermostatted flight, certified: a march of
//! steps each proved root-free by a lower bound, that cannot step over a grazing contact
//! (`proofs-notes/thermostat-flight.md`, "Certified events").
//!
//! A contact function F(t) is positive before the contact (|X − c|² − r² for a disk, the signed
//! distance to an edge). At a time a the [`Jet`] gives F, F′, F″ with bounds e₀, e₁, e₂ on their
//! errors, and [`Contact::third`] a bound M on |F‴| over [a, a + h]. Taylor's theorem then gives,
//! for 0 ≤ s ≤ h,
//!
//! F(a + s) ≥ L(s) = (F − e₀) + (F′ − e₁)s + ((F″ − e₂)/2 − Mh/6)s²,
//!
//! and the march advances by the smallest positive root of L (less twice a bound on its
//! rounding, [`root_error`]), or by all of h where L has none. A grazing contact has no root-free neighbourhood,
//! so the march stops before it: it can be refused only where F > e₀ is certain.
//!
//! The march stops at a time a where F − e₀ ≤ 0 (or one point earlier where the Taylor step's
//! remainder is below e₀/128, [`verdict`]'s bracket stop): there the contact is *decided within the model*
//! — taken if F′ ≤ 0 (approaching or tangent), with one Taylor step to the root; refused as a
//! near miss if F′ > 0 (leaving), the march going on from L with F itself. On the obstacle by
//! identity (the disk just left, the edge entered by) F(0) = 0 exactly: the contact is now if
//! F′(0) < 0, the creeping limit if F′(0) = 0 and F″(0) ≤ 0 ([`Found::Creeps`]), else the march
//! leaves it. Nothing is nudged.

use crate::numbers::real::Real;

/// A contact function and its first two derivatives at one time, each with a bound on its
/// error, and the distance `reach` from the obstacle's centre (for [`Contact::third`]).
#[derive(Debug, Clone)]
pub struct Jet<T> {
    /// F.
    pub f: T,
    /// F′.
    pub f1: T,
    /// F″.
    pub f2: T,
    /// Bounds on the errors of F, F′, F″.
    pub err: [T; 3],
    /// |X − c| for a disk (zero for an edge).
    pub reach: T,
    /// A bound on |sin θ| over [t, t + h] for any h, θ the velocity's angle from the field
    /// ([`Lean`]): |v̈| = ε²|sin θ|, so it scales [`Contact::third`].
    pub lean: Lean,
}

/// |sin θ| at a jet's time, rounded up by its error, and whether cos θ ≥ 0 there for certain.
/// Since d ln|sin θ|/dt = −ε cos θ, |sin θ| never grows once cos θ ≥ 0 (and θ never leaves that
/// half), and grows at most as e^{εs} before: [`Lean::over`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lean {
    /// |sin θ| at the jet's time plus its error bound.
    pub sin: f64,
    /// cos θ ≥ 0 there, beyond its error.
    pub relaxing: bool,
}

impl Lean {
    /// A bound on |sin θ| over [t, t + h] at the field ε: |sin θ(t)| where cos θ(t) ≥ 0, else
    /// |sin θ(t)|·e^{εh} bounded above by 1 + x + x² (x = εh ≤ 1; e^x ≤ 1 + x + x² there), at most 1.
    /// Arithmetic only, so the same in `f64` and every precision.
    pub fn over(&self, eps: f64, h: f64) -> f64 {
        if self.relaxing {
            return self.sin.min(1.0);
        }
        let x = eps * h;
        if x.is_nan() || x > 1.0 {
            return 1.0;
        }
        (self.sin * (1.0 + x + x * x) * (1.0 + 1e-15)).min(1.0)
    }
}

/// What a certified search finds before its horizon.
#[derive(Debug, Clone, PartialEq)]
pub enum Found<T> {
    /// The earliest contact, at this flight time.
    Root(T),
    /// No contact before the horizon.
    Clear,
    /// On the obstacle by identity, moving along it (F′ = 0) and turning into it (F″ ≤ 0).
    Creeps,
}

/// A contact function along one flight.
pub trait Contact<T: Real> {
    /// F, F′, F″ at the flight time `t` ≥ 0, with their error bounds (exact zero at t = 0 on the
    /// obstacle by identity).
    fn jet(&self, t: &T) -> Jet<T>;
    /// The jet at t = +0, where every march begins ([`Contact::jet`] of +0 unless the contact
    /// keeps the start's point).
    fn start_jet(&self, ctx: T::Ctx) -> Jet<T> {
        self.jet(&T::zero(ctx))
    }
    /// A bound on |F‴| over [t, t + h], t the time of `jet`.
    fn third(&self, jet: &Jet<T>, h: &T) -> T;
}

/// Steps after which a march stops where it is and takes the contact there (a march that has not
/// ended is at a grazing approach it can neither certify nor refuse).
pub const MAX_STEPS: usize = 1000;

/// What the jet at the current time says.
enum Decision<T> {
    Root,
    Creeps,
    /// March on with the lower bound's value and slope.
    Step(T, T),
}

fn decide<T: Real>(j: &Jet<T>, on_identity: bool) -> Decision<T> {
    if on_identity {
        if j.f1.lt0() {
            return Decision::Root;
        }
        if !j.f1.gt0() && !j.f2.gt0() {
            return Decision::Creeps;
        }
        return Decision::Step(T::zero(j.f.ctx()), j.f1.clone());
    }
    let lo = j.f.clone() - &j.err[0];
    // Marching on or taking the Taylor step to the root both end at the root.
    if T::freely(|| lo.gt0()) {
        return Decision::Step(lo, j.f1.clone() - &j.err[1]);
    }
    if !j.f1.gt0() {
        return Decision::Root;
    }
    // Leaving within the model: decided as a near miss.
    let f = if j.f.gt0() {
        j.f.clone()
    } else {
        T::zero(j.f.ctx())
    };
    Decision::Step(f, j.f1.clone())
}

/// What one jet of a march says about its contact from the march's time a on.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict<T> {
    /// The contact, at a plus this (the Taylor step from a to the root).
    Root(T),
    /// On the obstacle by identity, moving along it and turning into it ([`Found::Creeps`]).
    Creeps,
    /// Certified free up to the horizon.
    Clear,
    /// Certified free over [a, a + s] for this s > 0 (or a step below the point's resolution:
    /// a + s = a, the march standing at the root).
    Free(T),
}

/// One step of a march: the verdict of the jet `j` of `c` at the march's time (on the obstacle
/// by identity if `identity`, which only the start can be), `remaining` the time to the horizon
/// and `hint` the march's step hint, updated.
pub fn verdict<T: Real, C: Contact<T>>(
    c: &C,
    j: &Jet<T>,
    identity: bool,
    remaining: &T,
    hint: &mut T,
) -> Verdict<T> {
    let (lo, slope) = match decide(j, identity) {
        Decision::Root => return Verdict::Root(refine(j)),
        Decision::Creeps => return Verdict::Creeps,
        Decision::Step(lo, slope) => (lo, slope),
    };
    if !remaining.gt0() {
        return Verdict::Clear;
    }
    if !identity && let Some(s) = T::freely(|| bracketed(c, j, remaining)) {
        return Verdict::Root(s);
    }
    let curv = (j.f2.clone() - &j.err[2]).scale(0.5);
    match T::freely(|| advance(c, j, (&lo, &slope, &curv), remaining, hint)) {
        Some(s) => Verdict::Free(s),
        None => Verdict::Clear,
    }
}

/// The Taylor step to the root from a point a where the march may stop before F − e₀ ≤ 0: an
/// approaching contact whose Taylor step s ≤ `remaining` leaves a remainder Ms³/6, with the
/// slope's and curvature's errors e₁s + e₂s²/2, below e₀/128, and whose F stays monotone over
/// [a, a + s] (|F′| − e₁ − (|F″| + e₂)s − Ms²/2 > 0). The exact contact is then the only root
/// there and within (e_F + e₀/128)/|F′| of a + s, inside the band of the stop at F − e₀ ≤ 0
/// (`proofs-notes/thermostat-flight.md`, "The bracket stop"). In `f64` from the values, so the
/// same decision at every precision.
fn bracketed<T: Real, C: Contact<T>>(c: &C, j: &Jet<T>, remaining: &T) -> Option<T> {
    let (f, f1, e0) = (j.f.to_f64(), j.f1.to_f64(), j.err[0].to_f64());
    // Approaching, and near enough that a cubic term from the linear step may be below e₀.
    if !(f1 < 0.0 && f > e0) {
        return None;
    }
    let near = f / -f1;
    let quick = c.third(j, &T::from_f64(j.f.ctx(), 2.0 * near)).to_f64();
    // (NaN-safe: a comparison that fails, fails the stop.)
    let close = quick * near * near * near * 22.0 <= e0;
    if !close {
        return None;
    }
    let half = j.f2.clone().scale(0.5);
    let step = first_root(&j.f, &j.f1, &half)?;
    let within = step <= *remaining;
    if !within {
        return None;
    }
    let (f2, e1, e2) = (j.f2.to_f64(), j.err[1].to_f64(), j.err[2].to_f64());
    let s = step.to_f64();
    let m = c.third(j, &step).to_f64();
    let rest = m * s * s * s / 6.0 + e1 * s + e2 * s * s / 2.0;
    let slope = -f1 - e1 - (f2.abs() + e2) * s - m * s * s / 2.0;
    (rest * 128.0 <= e0 && slope > 0.0).then_some(step)
}

/// The earliest root of `c` in [0, `horizon`] (no horizon: until found), starting on the
/// obstacle by identity if `identity`: a march of [`verdict`]s at its own points.
pub fn earliest<T: Real, C: Contact<T>>(c: &C, identity: bool, horizon: &T) -> Found<T> {
    let ctx = horizon.ctx();
    let mut a = T::zero(ctx);
    let mut hint = T::one(ctx);
    for n in 0..MAX_STEPS {
        let j = if n == 0 { c.start_jet(ctx) } else { c.jet(&a) };
        let remaining = horizon.clone() - &a;
        let s = match verdict(c, &j, identity && n == 0, &remaining, &mut hint) {
            Verdict::Root(s) => return Found::Root(a + &s),
            Verdict::Creeps => return Found::Creeps,
            Verdict::Clear => return Found::Clear,
            Verdict::Free(s) => s,
        };
        let next = a.clone() + &s;
        // A step below the point's resolution: the march stands at the root (or one more
        // step, as certain, reaches it).
        if T::freely(|| next <= a) {
            return Found::Root(a);
        }
        // Any certified point serves: the event is decided by the jets at the points, and its
        // time by the last one's Taylor step, not by how the point was reached.
        a = next.anchored();
    }
    Found::Root(a)
}

/// The step from the current time: the largest the lower bound certifies, trying h = `hint`
/// (at most `remaining`; twice the linear root where that is below a quarter of it) and then
/// h = twice the root found, where the cubic term is smaller.
/// `None` where all of `remaining` is certified free.
fn advance<T: Real, C: Contact<T>>(
    c: &C,
    j: &Jet<T>,
    (lo, slope, curv): (&T, &T, &T),
    remaining: &T,
    hint: &mut T,
) -> Option<T> {
    let mut h = if *hint < *remaining {
        hint.clone()
    } else {
        remaining.clone()
    };
    // Approaching: start from twice the linear root F/|F′| where it is well inside h (the try
    // the shrinking below would reach after several).
    if slope.lt0() {
        let guess = (lo.clone() / &(-slope.clone())).scale(2.0);
        if guess.clone().scale(4.0) < h {
            h = guess;
        }
    }
    let mut best: Option<(T, T)> = None;
    for _ in 0..4 {
        // A trial step is a free choice too.
        h = h.anchored();
        // Mh/6, rounded up by the factor's excess over 1/6 (0.1666667 > 1/6).
        let quad = curv.clone() - &(c.third(j, &h) * &h).scale(0.166_666_7);
        let root = if clear_over(lo, slope, &quad, &h) {
            None
        } else {
            first_root(lo, slope, &quad)
        };
        match root {
            Some(s) if s < h => {
                let shrink = s.clone().scale(4.0) < h;
                if best.as_ref().is_none_or(|b| s > b.0) {
                    best = Some((s.clone(), quad));
                }
                if !shrink {
                    break;
                }
                // Twice the root, or an eighth of h at a root at (or near) zero: a tangent start
                // turning away needs h < 3F″/M.
                let eighth = h.scale(0.125);
                h = s.scale(2.0);
                if h < eighth {
                    h = eighth;
                }
            }
            _ => {
                if h >= *remaining {
                    return None;
                }
                *hint = h.clone().scale(2.0);
                return Some(h);
            }
        }
    }
    let (s, quad) = best?;
    let rel = root_error(lo, slope, &quad);
    *hint = s.clone().scale(2.0);
    // The root less twice its rounding error: below the exact root of L.
    Some(s.clone() - &s.scale(2.0 * rel))
}

/// Whether lo + bs + cs² (lo > 0) is certainly positive over [0, h], decided without its roots:
/// positive at h beyond the rounding of its value there, and without a minimum inside (not
/// convex, not falling at 0, or still falling at h — its vertex at or beyond h). Where this
/// cannot say, [`first_root`] decides; it says yes only where the smallest positive root is
/// beyond h, so the march's steps are those of the roots, with fewer square roots.
fn clear_over<T: Real>(lo: &T, b: &T, c: &T, h: &T) -> bool {
    let at_h = lo.clone() + &(h.clone() * &(b.clone() + &(h.clone() * c)));
    let (l, bb, cc, x) = (lo.to_f64(), b.to_f64(), c.to_f64(), h.to_f64());
    let u = T::unit_roundoff(lo.ctx());
    let above = at_h.to_f64() > 8.0 * u * (l.abs() + x * bb.abs() + x * x * cc.abs());
    if !above {
        return false;
    }
    // The vertex's test is in `f64`, so with f64's rounding at every precision.
    let w = u.max(f64::EPSILON);
    cc <= 0.0 || bb >= 0.0 || bb + 2.0 * cc * x < -8.0 * w * (bb.abs() + 2.0 * cc.abs() * x)
}

/// A bound on the relative error of [`first_root`]'s value (a + bs + cs², a ≥ 0): a few units
/// of rounding where the square root is of a discriminant D far from its rounding, and where it
/// is not, the discriminant's error δD = 4u(b² + |4ac|) carried through the root:
/// min(δD/(2√D), √δD)/(√D + |b|) (a D within δD of zero, taken as zero, by at most
/// √δD/|b| ≤ 4√u). Computed in `f64` from the values (a relative error of 2⁻⁵³ each, inside the
/// factor 2 of the step's margin).
pub fn root_error<T: Real>(a: &T, b: &T, c: &T) -> f64 {
    let u = T::unit_roundoff(a.ctx());
    let (a, b, c) = (a.to_f64(), b.to_f64(), c.to_f64());
    let (bb, ac4) = (b * b, (4.0 * a * c).abs());
    let disc = (bb - 4.0 * a * c).max(0.0);
    let dd = 4.0 * u * (bb + ac4);
    let root = disc.sqrt();
    let carried = if b < 0.0 {
        let d_root = if root > 0.0 {
            (dd / (2.0 * root)).min(dd.sqrt())
        } else {
            dd.sqrt()
        };
        d_root / (root + b.abs())
    } else {
        0.0
    };
    // Where b ≥ 0 (and c < 0) the root is (b + √D)/(−2c), D ≥ b²: no cancellation.
    let bound = 16.0 * u + carried;
    if bound.is_finite() { bound } else { 0.5 }
}

/// The smallest positive root of A + Bs + Cs² (A ≥ 0), without cancellation; `None` if it has
/// none. A discriminant within its rounding of zero counts as zero (a root, never a miss).
pub fn first_root<T: Real>(a: &T, b: &T, c: &T) -> Option<T> {
    let four_ac = (a.clone() * c).scale(4.0);
    let disc = b.square() - &four_ac;
    if b.lt0() {
        let u = T::unit_roundoff(a.ctx());
        let noise = (b.square() + &four_ac.abs()).scale(8.0 * u);
        if (disc.clone() + &noise).lt0() {
            return None;
        }
        let root = if disc.gt0() {
            disc.sqrt()
        } else {
            T::zero(a.ctx())
        };
        return Some(a.clone().scale(2.0) / &(root - b));
    }
    if !c.lt0() {
        return None;
    }
    Some((b.clone() + &disc.sqrt()) / &c.clone().scale(-2.0))
}

/// The Taylor step from a time where the contact was taken to its root: the smallest positive
/// root of F + F′s + F″s²/2 when approaching (F > 0, F′ < 0), at most the nearest approach
/// −F′/F″; zero otherwise.
fn refine<T: Real>(j: &Jet<T>) -> T {
    let zero = T::zero(j.f.ctx());
    // At the root within rounding, a step of zero or the Taylor step both stay within it.
    if !(T::freely(|| j.f.gt0()) && j.f1.lt0()) {
        return zero;
    }
    let half = j.f2.clone().scale(0.5);
    let s = first_root(&j.f, &j.f1, &half).unwrap_or_else(|| j.f.clone() / &(-j.f1.clone()));
    if j.f2.gt0() {
        let vertex = -j.f1.clone() / &j.f2;
        if vertex < s {
            return vertex;
        }
    }
    s
}
