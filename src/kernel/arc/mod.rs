//! Flights in a uniform magnetic field: first contact of an arc with a circle and with a line,
//! by algebra alone (no `acos`, no `atan2`, no nudging), and the order of contacts along the arc.
//!
//! A particle of speed 1 in the field B turns at the angular velocity ω = B: v̇ = ωJv, J the
//! rotation by +90°, so B > 0 turns it counter-clockwise, on a cyclotron circle of radius
//! 1/|B|. Since v − ωJp is conserved, the particle that has moved by the **chord** x from p has
//! the velocity
//!
//! v(x) = v + ωJx,  and x is on the arc iff ω|x|² = 2 Jv·x.
//!
//! Everything below is written in the chord, relative to the current position, so that no large
//! quantity (the cyclotron centre p + Jv/ω, up to 10⁶ away) is ever formed, and ω → 0 tends to
//! the straight-line formulas (`proofs-notes/magnetic-arcs.md`):
//!
//! * [`Arc::circle`]: the chord to the entry into a circle |y − c| = r, with d = p − c,
//!   β = d·v, q = d×v, γ = |d|² − r². The chord lies on the radical line x·m = −ωγ/2,
//!   m = Jv + ωd; along it, x = x₀ + s·e with e = v − ωJd ⟂ m, |e|² = |m|² = M =
//!   (1 − ωq)² + (ωβ)², and M s² + 2βs + γK/M = 0, K = 1 − ωq + ω²γ/4. Its discriminant
//!   β² − γK is computed as the product Δ = (r + q − ωγ/2)(r − q + ωγ/2) (at |v| = 1;
//!   [`Arc::circle`] has the general speed), whose small factor at a hit is a signed distance
//!   (at ω = 0 the straight kernel's r ± q: no cancellation of β² − γ near the surface). The
//!   entry is s = (−β − √Δ)/M, taken as γK/(M(√Δ − β)) where β < 0 (Vieta: no subtraction of
//!   nearly equal numbers either way). Where the cyclotron centre is within half a cyclotron
//!   radius of the disk's centre the two circles can cut at a small angle, and the contact is
//!   found in the disk's frame instead ([`Arc::contact`]: on the circle to a few u);
//! * [`arc_line`]: the chord to the exit through a line n·y = o (n the inward unit normal,
//!   σ = n·p − o ≥ 0 inside): x = −σn + sJn with ωs = a + √D, a = n·v, b = n·Jv,
//!   D = a² − ωσ(ωσ + 2b), taken as −σ(ωσ + 2b)/(√D − a) where a ≤ 0;
//! * a start **on** the circle just left, or on the line just entered by, is on it by identity
//!   (γ = 0, σ = 0): the contact is then the *other* intersection, s = −2β/M or ωs = 2a, which a
//!   straight flight never has — an arc can come back to the disk it left;
//! * [`earlier`]: contacts are ordered by the angle of their chord from v, which lies in the
//!   half-plane on the turning side, compared by the sign of a cross product (the order of the
//!   flight times, with no transcendental function);
//! * [`velocity_after`]: the velocity at the end of the chord, the reflection of v in the chord,
//!   2(v·x)x/|x|² − v (a reflection keeps |v| whatever the rounding of x), or
//!   [`velocity_along`], v + ωJx, at a contact found in the disk's frame;
//! * [`arc_time`]: the flight time 2·atan2(ω|x|²/2, v·x)/ω, for observables only.
//!
//! Only correctly rounded operations (+ − × ÷ √) decide and carry out an event, so the `f64`
//! kernel and MPFR at 53 bits agree event for event, bit for bit.

mod disk_frame;
use disk_frame::Frame;

use super::vec2::Vec2;
use crate::numbers::lanes::Lanes;
use crate::numbers::real::Real;

/// Jv: `v` turned by +90°.
#[inline(always)]
pub fn perp<T: Real>(v: &Vec2<T>) -> Vec2<T> {
    Vec2::new(-v.y.clone(), v.x.clone())
}

/// `true` if both components of `x` are zero (a contact where the particle is).
#[inline(always)]
pub fn is_zero<T: Real>(x: &Vec2<T>) -> bool {
    !x.x.gt0() && !x.x.lt0() && !x.y.gt0() && !x.y.lt0()
}

/// A contact of an arc with a circle: the chord to it, and whether it was found in the disk's
/// frame (near-concentric circles, `proofs-notes/magnetic-arcs.md`), where the velocity at the
/// contact is v + ωJx (no division by a chord whose direction carries the disk frame's absolute
/// rounding).
#[derive(Debug, Clone, PartialEq)]
pub struct Contact<T> {
    /// The chord from the particle to the contact.
    pub chord: Vec2<T>,
    /// Found in the disk's frame (near-concentric circles).
    pub disk_frame: bool,
}

impl<T> Contact<T> {
    fn radical(chord: Vec2<T>) -> Option<Self> {
        Some(Contact {
            chord,
            disk_frame: false,
        })
    }
}

/// An arc about to be flown: the velocity `v`, its |v|² and |v| (the cyclotron radius is |v|/|ω|:
/// every formula holds for the speed the rounded state has, so that a speed a few units of
/// roundoff off 1 is a slightly larger circle, never an inconsistent one), and the field `w` ≠ 0.
/// Built once per event and shared by every candidate.
#[derive(Debug, Clone)]
pub struct Arc<'a, T: Real> {
    /// The velocity at the start.
    pub v: &'a Vec2<T>,
    /// The field ω.
    pub w: &'a T,
    vv: T,
    speed: T,
}

impl<'a, T: Real> Arc<'a, T> {
    /// The arc of velocity `v` in the field `w` (≠ 0).
    pub fn new(v: &'a Vec2<T>, w: &'a T) -> Self {
        let vv = v.norm2();
        let speed = vv.clone().sqrt();
        Arc { v, w, vv, speed }
    }

    /// The chord from the particle to its entry into the circle of radius `r` (`r2` = r²
    /// rounded) whose centre is at −d from it (d = p − c = (`dx`, `dy`)); `None` if the arc
    /// misses the circle. `on_surface`: the particle is on this circle by identity (it has just
    /// left the disk): γ = 0. On the circle (by identity, or numerically inside, γ ≤ 0) the
    /// contact is the return (−2β/M) if moving out, now if moving in or along it turning in
    /// (on the disk just left, that is the creeping limit: [`Arc::creeps`]), none if moving along
    /// it turning away.
    ///
    /// With |v|² = V² not assumed 1, M = |m|² = M̃/V² with M̃ = (V² − ωq)² + (ωβ)²,
    /// K = V² − ωq + ω²γ/4, and Δ = β² − γK = (Vr + q − ωγ/2)(Vr − q + ωγ/2).
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::kernel::{arc::Arc, vec2::Vec2};
    /// // Leaving the unit disk at (1, 0) radially in a field 1: the cyclotron circle of radius 1
    /// // about (1, 1) returns to the disk at (0, 1) after a three-quarter turn: chord (−1, 1).
    /// let v = Vec2::new(1.0f64, 0.0);
    /// let x = Arc::new(&v, &1.0).circle(1.0, 0.0, &1.0, &1.0, true).unwrap();
    /// assert!((x.x + 1.0).abs() < 1e-15 && (x.y - 1.0).abs() < 1e-15);
    /// ```
    pub fn circle(&self, dx: T, dy: T, r: &T, r2: &T, on_surface: bool) -> Option<Vec2<T>> {
        self.contact(dx, dy, r, r2, on_surface).map(|c| c.chord)
    }

    /// [`Arc::circle`] with how the chord was found: near-concentric circles (the cyclotron
    /// centre within ρ/2 of the disk's, `proofs-notes/magnetic-arcs.md`) give the contact in the
    /// disk's frame, and the velocity there is then v + ωJx rather than the reflection of v in
    /// the chord.
    pub fn contact(&self, dx: T, dy: T, r: &T, r2: &T, on_surface: bool) -> Option<Contact<T>> {
        let (v, w) = (self.v, self.w);
        let ctx = w.ctx();
        let d = Vec2::new(dx, dy);
        let beta = d.dot(v);
        let q = d.cross(v);
        let vv_wq = self.vv.clone() - &(w.clone() * &q);
        let wb = w.clone() * &beta;
        // V²/M̃ = 1/M.
        let inv = self.vv.clone() / &(vv_wq.square() + &wb.square());
        // e = v − ωJd = (vₓ + ωd_y, v_y − ωdₓ).
        let e = Vec2::new(
            v.x.clone() + &(w.clone() * &d.y),
            v.y.clone() - &(w.clone() * &d.x),
        );
        let gamma = if on_surface {
            T::zero(ctx)
        } else {
            d.norm2() - r2
        };
        let mut on = !gamma.gt0();
        if !on {
            match self.disk_frame(&d, r, true) {
                Frame::Decided(c) => return c.map(|c| self.entry_now(c, &d, (r, &gamma), &beta)),
                Frame::OnCircle => on = true,
                Frame::Radical => {}
            }
        }
        if on {
            // On the circle: the roots are s = 0 (here) and s = −2β/M (the return).
            if beta.gt0() {
                if let Frame::Decided(c) = self.disk_frame(&d, r, false) {
                    return c;
                }
                let s = (beta * &T::from_f64(ctx, -2.0)) * &inv;
                return Contact::radical(Vec2::new(e.x * &s, e.y * &s));
            }
            // Moving in (β < 0, also on the disk just left, by rounding after a grazing
            // reflection): meets it now. Moving along it (β = 0): now if the arc turns in
            // (ω Jv·d < 0), which on the disk just left is the creeping limit ([`Arc::creeps`]);
            // else it touches it from outside, a measure-zero tangency that is no collision.
            let inward = beta.lt0() || (w.clone() * &perp(v).dot(&d)).lt0();
            return inward.then(|| Contact {
                chord: Vec2::new(T::zero(ctx), T::zero(ctx)),
                disk_frame: false,
            });
        }
        let k = vv_wq + &(w.clone().square() * &gamma).scale(0.25);
        let disc = self.discriminant(&q, &gamma, r, &beta, &k)?;
        let root = disc.sqrt();
        let s = if beta.lt0() {
            (gamma.clone() * &k) / &(root - &beta) * &inv
        } else {
            -(beta + &root) * &inv
        };
        // x = x₀ + s·e, x₀ = −(ωγ/2)·m/M, m = Jv + ωd = (ωdₓ − v_y, ωd_y + vₓ).
        let f = -(w.clone() * &gamma).scale(0.5) * &inv;
        let mx = w.clone() * &d.x - &v.y;
        let my = w.clone() * &d.y + &v.x;
        Contact::radical(Vec2::new(
            f.clone() * &mx + &(s.clone() * &e.x),
            f * &my + &(s * &e.y),
        ))
    }

    /// `true` if the particle, on the circle of radius² `r2` at −d (d = p − c) by identity, moves
    /// along it (β = 0 exactly) with the arc turning into it: the limit of ever shorter skips, a
    /// slide along the surface that no sequence of collisions represents (a reflection leaves a
    /// tangent velocity unchanged). Measure zero; the kernel reports no next event rather than
    /// collide for ever in place.
    ///
    /// Also `true` if its cyclotron circle *is* the disk's circle to rounding: the centres closer
    /// than the rounding of m = Jv + ωd, |m| ≤ 8u(|ω||d| + |v|) (a particle on the disk then has
    /// ρ = r too). The contact of two coincident circles is undefined; the eighth libFuzzer
    /// campaign found one at w = 0.07, B = 1 (ρ = r) whose rounding-level m gave a random point of
    /// the disk and a speed 2 % off. Also measure zero, and the same slide.
    pub fn creeps(&self, dx: &T, dy: &T) -> bool {
        let (v, w) = (self.v, self.w);
        let d = Vec2::new(dx.clone(), dy.clone());
        let beta = d.dot(v);
        if !beta.gt0() && !beta.lt0() && (w.clone() * &perp(v).dot(&d)).lt0() {
            return true;
        }
        let m = Vec2::new(w.clone() * &d.x - &v.y, w.clone() * &d.y + &v.x);
        let u = T::unit_roundoff(w.ctx());
        let noise = (w.clone().abs() * &d.norm2().sqrt() + &self.speed).scale(8.0 * u);
        !(m.norm2() - &noise.square()).gt0()
    }

    /// The discriminant Δ = β² − γK of the arc–circle contact, if positive (the cyclotron circle
    /// cuts the circle in two points), computed as the product
    /// Δ = (Vr + q − ωγ/2)(Vr − q + ωγ/2): q − ωγ/2 = q − ω(|d|² − r²)/2 is, up to the factor
    /// V/ω, the distance of the disk's centre from the cyclotron circle, so at a hit one factor is
    /// a signed distance of size ≲ 2Vr formed with the absolute rounding u|d|(1 + |ω||d|) of its
    /// terms — the error of Δ is linear in |d|/r, as a straight flight's V²r² − q² is. (Two other
    /// forms of the same number are worse: (Vr + q)(2V² + ω(Vr − q)) − ωβ² times its partner
    /// loses a factor entirely at a tangent start a rounding off a disk — the fuzz target found
    /// it — and (V²r² − q²) + ωγ(q − ωγ/4) cancels terms of size q² ≫ r² at a small disk.) At ω = 0
    /// the factors are the    /// straight kernel's Vr ± q.
    ///
    /// Off the circle (γ > 0) with K < 0 (ωq > V² + ω²γ/4: an arc bending towards the disk faster
    /// than the disk's own boundary near a tangency) the sum β² − γK of two non-negative terms is
    /// positive exactly, so the circles cut. There a product that rounds to ≤ 0 is a cancellation, not a
    /// miss (the tenth libFuzzer campaign: a particle an ulp off a disk, tangent to it, on a
    /// cyclotron circle internally tangent to the disk — Vr + q − ωγ/2 ≈ 10⁻¹⁶ rounded to 0 —
    /// flew 3·10⁻⁵ into it), and the sum, which cannot cancel, is taken instead. Where the
    /// product is positive it stands, so no other event changes.
    #[inline(always)]
    fn discriminant(&self, q: &T, gamma: &T, r: &T, beta: &T, k: &T) -> Option<T> {
        let vr = self.speed.clone() * r;
        let shift = q.clone() - &(self.w.clone() * gamma).scale(0.5);
        let plus = vr.clone() + &shift;
        let minus = vr - &shift;
        let disc = plus * &minus;
        if disc.gt0() {
            return Some(disc);
        }
        if gamma.gt0() && k.lt0() {
            let sum = beta.square() - &(gamma.clone() * k);
            return sum.gt0().then_some(sum);
        }
        None
    }

    /// [`arc_line`] on this arc.
    pub fn line(&self, n: &Vec2<T>, sigma: T, entered: bool) -> Option<Vec2<T>> {
        arc_line(n, sigma, self.v, self.w, entered)
    }

    /// [`earlier`] on this arc.
    pub fn earlier(&self, x1: &Vec2<T>, x2: &Vec2<T>) -> bool {
        earlier(x1, x2, self.v, self.w)
    }
}

/// The chord to the entry into a circle along the arc of velocity `v` in the field `w` (see
/// [`Arc::circle`], which shares |v| between candidates).
pub fn arc_circle<T: Real>(
    d: (T, T),
    v: &Vec2<T>,
    w: &T,
    r: &T,
    r2: &T,
    on_surface: bool,
) -> Option<Vec2<T>> {
    Arc::new(v, w).circle(d.0, d.1, r, r2, on_surface)
}

/// The chord from the particle to its exit through the line at signed distance `sigma` (> 0
/// inside) with inward unit normal `n`, along the arc of velocity `v` in the field `w` ≠ 0;
/// `None` if the arc never reaches the line. `entered`: the particle is on this line by identity
/// (it has just crossed it): σ = 0. On the line (by identity, or numerically beyond it, σ ≤ 0)
/// the exit is the return (ωs = 2a) if moving in, now if moving out or along it turning out,
/// none if moving along it turning in. The two sides of an edge see exactly opposite a and
/// n·Jv, so an exit now is never followed by an exit back.
///
/// # Examples
///
/// ```
/// use lorentz_gas::kernel::{arc::arc_line, vec2::Vec2};
/// // Entering the half-plane y ≥ 0 straight up in a field 1 (radius 1, turning left): back on
/// // the line at (−2, 0) after half a turn.
/// let n = Vec2::new(0.0f64, 1.0);
/// let x = arc_line(&n, 0.0, &Vec2::new(0.0, 1.0), &1.0, true).unwrap();
/// assert_eq!((x.x, x.y), (-2.0, 0.0));
/// ```
pub fn arc_line<T: Real>(
    n: &Vec2<T>,
    sigma: T,
    v: &Vec2<T>,
    w: &T,
    entered: bool,
) -> Option<Vec2<T>> {
    let ctx = w.ctx();
    let a = n.dot(v);
    let jn = perp(n);
    if entered || !sigma.gt0() {
        // On the line: s = 0 (here, an exit if moving out) or ωs = 2a (the return, moving in).
        if a.gt0() {
            let s = a.scale(2.0) / w;
            return Some(Vec2::new(jn.x * &s, jn.y * &s));
        }
        // Moving out (a < 0; on the line just entered only by rounding of a tangent crossing,
        // whose other side then sees a > 0 exactly: no return) or along it (a = 0) with the arc
        // turning out of the cell (ω n·Jv < 0): out now.
        let out = a.lt0() || (w.clone() * &n.dot(&perp(v))).lt0();
        return out.then(|| Vec2::new(T::zero(ctx), T::zero(ctx)));
    }
    let b = n.dot(&perp(v));
    let ws = w.clone() * &sigma;
    let c = ws.clone() + &b.scale(2.0);
    let disc = a.square() - &(ws * &c);
    if !disc.gt0() {
        return None;
    }
    let root = disc.sqrt();
    let s = if a.gt0() {
        (a + &root) / w
    } else {
        -(sigma.clone() * &c) / &(root - &a)
    };
    Some(Vec2::new(
        s.clone() * &jn.x - &(sigma.clone() * &n.x),
        s * &jn.y - &(sigma * &n.y),
    ))
}

/// Where a chord lies on the way round, for [`earlier`]: at the start (zero, or numerically just
/// behind it), on the open half-turn (the turning side of v), or numerically at the half-turn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Stage {
    Start,
    Turning,
    HalfTurn,
}

#[inline(always)]
fn stage<T: Real>(x: &Vec2<T>, v: &Vec2<T>, left: bool) -> Stage {
    let side = v.cross(x);
    let turning = if left { side.gt0() } else { side.lt0() };
    if turning {
        Stage::Turning
    } else if is_zero(x) || v.dot(x).gt0() {
        Stage::Start
    } else {
        Stage::HalfTurn
    }
}

/// `true` if the chord `x` is within π/4 of the velocity `v` (v·x ≥ |v × x|).
#[inline(always)]
fn ahead<T: Real>(x: &Vec2<T>, v: &Vec2<T>) -> bool {
    v.dot(x) >= v.cross(x).abs()
}

/// `true` if the contact at chord `x1` comes strictly before the one at chord `x2` on the arc of
/// velocity `v` in the field `w` (≠ 0). Chords of an arc lie on the side it turns to, at the angle
/// α ∈ [0, π) from v, and the flight time is 2α/|ω|. Chords within π/4 of v — on the turning side,
/// or numerically just behind v (α ≈ 0) — are ordered by their lengths, which grow with α there
/// and resolve a near-tie in a weak field that their directions cannot (the fuzz target's third
/// finding, two edges 8·10⁻¹² apart in time at B = −1.1·10⁻⁶; its sixth, a crossing 10⁻¹⁶ ahead
/// whose chord rounded onto the turning side and a collision 6·10⁻¹¹ ahead whose chord rounded
/// just behind v, which a side-first order took in the wrong order). They come before every other
/// chord. Beyond π/4 two chords on the turning side are ordered by the sign of x₁ × x₂; a chord
/// numerically behind v and not ahead of it is at α ≈ π, ordered there by its length.
pub fn earlier<T: Real>(x1: &Vec2<T>, x2: &Vec2<T>, v: &Vec2<T>, w: &T) -> bool {
    let left = w.gt0();
    let (s1, s2) = (stage(x1, v, left), stage(x2, v, left));
    let near = |s: Stage, x: &Vec2<T>| s == Stage::Start || (s == Stage::Turning && ahead(x, v));
    match (near(s1, x1), near(s2, x2)) {
        (true, true) => return x1.norm2() < x2.norm2(),
        (true, false) => return true,
        (false, true) => return false,
        (false, false) => {}
    }
    if s1 != s2 {
        return s1 < s2;
    }
    match s1 {
        Stage::HalfTurn => x1.norm2() > x2.norm2(),
        _ => {
            let c = x1.cross(x2);
            if left { c.gt0() } else { c.lt0() }
        }
    }
}

/// The velocity at the end of the chord `x` of an arc that starts with velocity `v`: the
/// reflection of v in the chord, 2(v·x)x/|x|² − v (v itself for a zero chord).
pub fn velocity_after<T: Real>(v: &Vec2<T>, x: &Vec2<T>) -> Vec2<T> {
    let xx = x.norm2();
    if !xx.gt0() {
        return v.clone();
    }
    let k = v.dot(x).scale(2.0) / &xx;
    Vec2::new(k.clone() * &x.x - &v.x, k * &x.y - &v.y)
}

/// The velocity at the end of the chord `x` of the arc of velocity `v` in the field `w`,
/// v + ωJx: exact on the arc, and free of any division by |x|.
pub fn velocity_along<T: Real>(v: &Vec2<T>, x: &Vec2<T>, w: &T) -> Vec2<T> {
    Vec2::new(
        v.x.clone() - &(w.clone() * &x.y),
        v.y.clone() + &(w.clone() * &x.x),
    )
}

/// The flight time along the arc to the end of the chord `x` (velocity `v`, field `w` ≠ 0):
/// 2α/ω with α = atan2(ω|x|²/2, v·x) the chord's angle from v; 0 for a chord of no length (where
/// atan2(±0, −0) would say a whole turn). For observables only (not correctly rounded in `f64`;
/// no event depends on it); a field run's observers use
/// [`crate::scenes::magnetic::arc_observables`], the same bits on every engine.
pub fn arc_time<T: Real>(v: &Vec2<T>, x: &Vec2<T>, w: &T) -> T {
    if is_zero(x) {
        return x.norm2();
    }
    let y = (w.clone() * &x.norm2()).scale(0.5);
    let alpha = y.atan2(&v.dot(x));
    alpha.scale(2.0) / w
}

/// The chord of the arc of duration `t` (velocity `v`, field `w` ≠ 0): L·R(φ/2)v with φ = ωt and
/// L = 2 sin(φ/2)/ω (where a sample falls inside a flight; observables only).
pub fn chord_at<T: Real>(v: &Vec2<T>, t: &T, w: &T) -> Vec2<T> {
    let half = (w.clone() * t).scale(0.5);
    let (s, c) = (half.clone().sin(), half.cos());
    let len = s.clone().scale(2.0) / w;
    // R(φ/2)v = cos·v + sin·Jv.
    let ux = c.clone() * &v.x - &(s.clone() * &v.y);
    let uy = c * &v.y + &(s * &v.x);
    Vec2::new(len.clone() * &ux, len * &uy)
}

/// The signed area ∫ x × dx swept by the chord of an arc of duration `t` in the field `w` ≠ 0:
/// (φ − sin φ)/ω², φ = ωt (twice the area between the arc and its chord; the arc's part of the
/// Lévy area of a trajectory). A series where φ is small, so that nothing cancels
/// ([`excess_series`]).
pub fn arc_area(t: f64, w: f64) -> f64 {
    let phi = w * t;
    let excess = if phi.abs() < 0.25 {
        excess_series(phi)
    } else {
        phi - phi.sin()
    };
    excess / (w * w)
}

/// φ − sin φ = φ³/3! − φ⁵/5! + … − φ¹³/13! in every lane, for |φ| < 1/4: the first term left out,
/// φ¹⁵/15!, is below 10⁻¹⁸ of the sum there.
#[inline(always)]
pub fn excess_series<V: Lanes>(phi: V) -> V {
    const INVERSE_FACTORIALS: [f64; 6] = [
        1.0 / 6.0,
        1.0 / 120.0,
        1.0 / 5040.0,
        1.0 / 362_880.0,
        1.0 / 39_916_800.0,
        1.0 / 6_227_020_800.0,
    ];
    let p2 = phi.mul(phi);
    let tail = INVERSE_FACTORIALS[..5]
        .iter()
        .rev()
        .fold(V::splat(INVERSE_FACTORIALS[5]), |acc, &c| {
            V::splat(c).sub(p2.mul(acc))
        });
    phi.mul(p2).mul(tail)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_contact_lies_on_both_circles() {
        // Aimed at the disk: the straight line hits it (|q| = 0.4), weak and moderate fields too.
        let v = Vec2::new(1.0f64, 0.0);
        let mut found = 0;
        for w in [-3.0, -0.2, 0.01, 0.7, 5.0] {
            let (dx, dy) = (-2.3, 0.4);
            if let Some(x) = arc_circle((dx, dy), &v, &w, &1.0, &1.0, false) {
                found += 1;
                let cyc = w * x.norm2() - 2.0 * perp(&v).dot(&x);
                let disk = (x.x + dx).powi(2) + (x.y + dy).powi(2) - 1.0;
                assert!(
                    cyc.abs() < 1e-14 && disk.abs() < 1e-14,
                    "w={w}: {cyc} {disk}"
                );
                // Entering: the velocity there points into the disk.
                let vx = velocity_after(&v, &x);
                assert!(vx.dot(&Vec2::new(x.x + dx, x.y + dy)) < 0.0);
            }
        }
        // Only B = −0.2 and 0.01 reach it (the others turn away within a radius of 1.4 or less;
        // checked by brute force along the arc).
        assert_eq!(found, 2);
    }

    #[test]
    fn a_weak_field_bends_the_straight_contact_by_its_sagitta() {
        // Straight: entry after t = 3 − √(1 − 0.25). In a field ω the contact moves by O(ωt²).
        let v = Vec2::new(1.0f64, 0.0);
        let t0 = 3.0 - 0.75f64.sqrt();
        let x = arc_circle((-3.0, 0.5), &v, &1e-9, &1.0, &1.0, false).unwrap();
        assert!((arc_time(&v, &x, &1e-9) - t0).abs() < 1e-8);
        assert!((x.x - t0).abs() < 1e-8 && x.y.abs() < 1e-8);
    }

    #[test]
    fn chords_are_ordered_by_their_flight_time() {
        let v = Vec2::new(0.0f64, 1.0);
        for w in [2.0f64, -2.0] {
            let times = [0.1, 0.5, 1.2, 1.5];
            let chords: Vec<_> = times.iter().map(|t| chord_at(&v, t, &w)).collect();
            for i in 0..chords.len() {
                assert!((arc_time(&v, &chords[i], &w) - times[i]).abs() < 1e-14);
                for j in 0..chords.len() {
                    assert_eq!(
                        earlier(&chords[i], &chords[j], &v, &w),
                        i < j,
                        "{w} {i} {j}"
                    );
                }
            }
            let zero = Vec2::new(0.0, 0.0);
            assert!(earlier(&zero, &chords[0], &v, &w));
        }
    }

    #[test]
    fn the_arc_area_series_joins_the_closed_form() {
        let (t, w) = (0.25f64 - 1e-12, 1.0);
        let closed = (t - t.sin()) / (w * w);
        assert!(((arc_area(t, w) - closed) / closed).abs() < 1e-9);
        assert!((arc_area(0.3, -1.0) + arc_area(0.3, 1.0)).abs() < 1e-18);
    }
}
