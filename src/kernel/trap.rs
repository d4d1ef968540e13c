//! The canonical trap: one triangle of the lattice, its three vertex disks and three edges.
//!
//! Every trap of the triangular lattice is congruent to the canonical triangle
//! P₀ = (0, 0), P₁ = (a, 0), P₂ = (a/2, h), h = √3a/2, either directly ("up" traps) or by a
//! point reflection ("down" traps). Inside it only the three vertex disks can be hit (every other
//! disk centre is at distance ≥ h > 1 from the triangle: `proofs-notes/no-missed-collision.md`),
//! so the next event of a free flight is one of at most five candidates: a collision with a
//! vertex disk, or a crossing of an edge Eₖ (the edge opposite Pₖ) through its gap into the
//! neighbouring trap. The disk just hit and the edge just crossed are excluded **by identity**,
//! never by a tolerance.
//!
//! Crossing Eₖ maps the neighbouring trap onto the canonical one by the point reflection about
//! the midpoint of Eₖ, p ↦ cₖ − p with cₖ = sum of the endpoints of Eₖ, and v ↦ −v (exact).
//! The two endpoint disks of Eₖ swap labels; the opposite disk leaves the candidate set.

use super::cell::{CellKernel, ConvexCell, Disk, Edge, EdgeMap, LatticeBasis};
use super::certified::{self, TrapBalls};
use super::choice::{Choice, EarliestDisk, EarliestEdge, edge_time, first};
use super::flight::{Event, EventKind, Flight};
use super::ray_disk::{approach, ray_disk_centred};
use super::vec2::Vec2;
use crate::Error;
use crate::numbers::real::Real;

/// The canonical trap at gap `w`, all constants at the working precision. Every constant is
/// derived from w by [`Trap::new`] and read through a method (`trap.a()`): no safe code outside
/// the crate can make a trap inconsistent with its gap.
///
/// ```compile_fail
/// let mut t = lorentz_gas::kernel::trap::Trap::new(0.1f64).unwrap();
/// t.a = 3.0; // the spacing of another gap: refused, the field is the crate's
/// ```
#[derive(Debug, Clone)]
pub struct Trap<T: Real> {
    /// Gap w.
    pub(crate) w: T,
    /// Spacing a = 2 + w.
    pub(crate) a: T,
    /// Height h = √3a/2.
    pub(crate) h: T,
    /// Disk centres P₀, P₁, P₂.
    pub(crate) vertices: [Vec2<T>; 3],
    /// Inward unit normals nₖ of the edges Eₖ (opposite Pₖ).
    pub(crate) normals: [Vec2<T>; 3],
    /// Offsets oₖ: the signed distance to Eₖ is σₖ(p) = nₖ·p − oₖ (≥ 0 inside).
    pub(crate) offsets: [T; 3],
    /// Reflection centres cₖ = sum of the endpoints of Eₖ.
    pub(crate) centres: [Vec2<T>; 3],
    /// How [`Trap::next_event_chosen`] (and the SIMD engine) choose before dividing: derived
    /// from w, read through [`Trap::choice`].
    choice: Choice<T>,
    /// The same trap as a generic [`ConvexCell`] of the triangular lattice (e₁ = (a, 0),
    /// e₂ = (a/2, h)); its generic kernel and the fused one here agree bit for bit. Derived
    /// from w, read through [`Trap::cell`].
    cell: ConvexCell<T>,
    /// The constants as `f64` balls, for deciding events before computing them
    /// ([`super::certified`]).
    balls: TrapBalls,
}

/// The lattice spacing a = 2 + w of a positive finite gap `w` at its working precision (the
/// closed forms of `scenes::triangular::geometry` start from the same a).
///
/// # Errors
/// An unusable precision, a gap that is not finite, or w ≤ 0 (the disks overlap).
pub fn spacing<T: Real>(w: &T) -> Result<T, Error> {
    let ctx = w.ctx();
    T::check_ctx(ctx)?;
    if !w.is_finite() {
        return Err(Error::NotFinite { what: "w" });
    }
    if *w <= T::zero(ctx) {
        return Err(Error::Trapped { w: w.to_f64() });
    }
    Ok(w.clone() + &T::from_f64(ctx, 2.0))
}

impl<T: Real> Trap<T> {
    /// Gap w.
    pub fn w(&self) -> &T {
        &self.w
    }

    /// Spacing a = 2 + w.
    pub fn a(&self) -> &T {
        &self.a
    }

    /// Height h = √3a/2.
    pub fn h(&self) -> &T {
        &self.h
    }

    /// Disk centres P₀, P₁, P₂.
    pub fn vertices(&self) -> &[Vec2<T>; 3] {
        &self.vertices
    }

    /// Inward unit normals nₖ of the edges Eₖ (opposite Pₖ).
    pub fn normals(&self) -> &[Vec2<T>; 3] {
        &self.normals
    }

    /// Offsets oₖ: the signed distance to Eₖ is σₖ(p) = nₖ·p − oₖ (≥ 0 inside).
    pub fn offsets(&self) -> &[T; 3] {
        &self.offsets
    }

    /// Reflection centres cₖ = sum of the endpoints of Eₖ.
    pub fn centres(&self) -> &[Vec2<T>; 3] {
        &self.centres
    }

    /// How [`Trap::next_event_chosen`] and the SIMD engine choose before dividing.
    pub fn choice(&self) -> &Choice<T> {
        &self.choice
    }

    /// The same trap as a generic [`ConvexCell`] (its kernel agrees with the fused one bit for
    /// bit).
    pub fn cell(&self) -> &ConvexCell<T> {
        &self.cell
    }

    /// The canonical trap at gap `w > 0` (any precision ≥ 53 bits).
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::kernel::trap::Trap;
    /// let t = Trap::new(0.1f64).unwrap();
    /// assert_eq!(t.vertices()[1].x, 2.1);
    /// assert_eq!(*t.a(), 2.1);
    /// ```
    pub fn new(w: T) -> Result<Self, Error> {
        let ctx = w.ctx();
        let a = spacing(&w)?;
        let sqrt3 = T::sqrt3(ctx);
        let h = (sqrt3.clone() * &a).scale(0.5);
        let half_sqrt3 = sqrt3.scale(0.5);
        let half = T::from_f64(ctx, 0.5);
        let z = T::zero(ctx);
        let vertices = [
            Vec2::new(z.clone(), z.clone()),
            Vec2::new(a.clone(), z.clone()),
            Vec2::new(a.clone().scale(0.5), h.clone()),
        ];
        let normals = [
            Vec2::new(-half_sqrt3.clone(), -half.clone()),
            Vec2::new(half_sqrt3, -half.clone()),
            Vec2::new(z.clone(), T::one(ctx)),
        ];
        let offsets = [-h.clone(), z.clone(), z.clone()];
        let centres = [
            Vec2::new(a.clone().scale(1.5), h.clone()),
            Vec2::new(a.clone().scale(0.5), h.clone()),
            Vec2::new(a.clone(), z),
        ];
        // Crossing Eₖ: the point reflection about cₖ/2; the edge keeps its label, the endpoints
        // of Eₖ swap and Pₖ leaves; the anchor steps by the lattice vector dₖ of cₖ.
        let steps = [[1, 1], [0, 1], [1, 0]];
        let edges = (0..3u8)
            .map(|k| Edge {
                normal: normals[k as usize].clone(),
                offset: offsets[k as usize].clone(),
                map: EdgeMap::PointReflection(centres[k as usize].clone()),
                entered: k,
                disks_after: (0..3u8)
                    .map(|m| relabel_after_crossing(k, Some(m)))
                    .collect(),
                step: steps[k as usize],
            })
            .collect();
        let cell = ConvexCell {
            corners: vertices.to_vec(),
            disks: vertices
                .iter()
                .map(|c| Disk::new(c.clone(), T::one(ctx)))
                .collect(),
            edges,
            lattice: LatticeBasis {
                a: a.clone(),
                beta: half.clone(),
                h: h.clone(),
            },
        };
        // The three disks are pairwise a = 2 + w apart: gap w.
        let choice = Choice::new(ctx, Some(&w), &T::one(ctx));
        let mut trap = Trap {
            w,
            a,
            h,
            vertices,
            normals,
            offsets,
            centres,
            choice,
            cell,
            balls: TrapBalls::default(),
        };
        trap.balls = TrapBalls::new(
            &trap.normals[1].x,
            &trap.h,
            &trap.vertices[1],
            &trap.vertices[2],
        );
        Ok(trap)
    }

    /// Signed distance from `p` to edge `k` (positive inside the triangle).
    #[inline(always)]
    pub fn edge_distance(&self, k: usize, p: &Vec2<T>) -> T {
        self.normals[k].dot(p) - &self.offsets[k]
    }

    /// (nₖ·v, σₖ) of the slanted edges E₀ and E₁ (E₂'s are v_y and p_y). The normals are
    /// n₀ = (−k, −½), n₁ = (k, −½), k = √3/2; in-place forms with the same rounded operations:
    /// −(kvₓ + v_y/2), h − (kpₓ + p_y/2) = −(kpₓ + p_y/2) + h, kvₓ − v_y/2 and kpₓ − p_y/2.
    #[inline(always)]
    fn slanted_edges(&self, p: &Vec2<T>, v: &Vec2<T>) -> [(T, T); 2] {
        let parts = self.slanted_parts(p, v);
        [self.slanted_from(0, &parts), self.slanted_from(1, &parts)]
    }

    /// (nₑ·v, σₑ) of one slanted edge e ∈ {0, 1}, by the operations of the pair's.
    #[inline(always)]
    pub fn slanted_edge(&self, e: u8, p: &Vec2<T>, v: &Vec2<T>) -> (T, T) {
        self.slanted_from(e, &self.slanted_parts(p, v))
    }

    /// The products both slanted edges share: kvₓ, v_y/2, kpₓ, p_y/2.
    #[inline(always)]
    fn slanted_parts(&self, p: &Vec2<T>, v: &Vec2<T>) -> [T; 4] {
        let k = &self.normals[1].x;
        [
            k.clone() * &v.x,
            v.y.clone().scale(0.5),
            k.clone() * &p.x,
            p.y.clone().scale(0.5),
        ]
    }

    /// Edge e's (n·v, σ) from the shared products.
    #[inline(always)]
    fn slanted_from(&self, e: u8, [kvx, hvy, kpx, hpy]: &[T; 4]) -> (T, T) {
        if e == 0 {
            let mut nv = kvx.clone() + hvy;
            nv.neg_mut();
            let mut sigma = kpx.clone() + hpy;
            sigma.neg_mut();
            sigma += &self.h;
            (nv, sigma)
        } else {
            (kvx.clone() - hvy, kpx.clone() - hpy)
        }
    }

    /// The next event of the straight flight `f`, or `None` if there is none (only for a zero
    /// or non-finite velocity: a finite nonzero velocity always leaves the triangle): the event
    /// of the full comparison [`Trap::next_event_compared`], bit for bit. Where arithmetic is
    /// dear ([`Real::DECIDE_IN_BALLS`]: MPFR) the event is first decided in `f64` balls and only
    /// its own time computed at the working precision ([`super::certified`]); where the balls
    /// cannot decide, and always for `f64`, every candidate is compared.
    #[inline(always)]
    pub fn next_event(&self, f: &Flight<T>) -> Option<Event<T>> {
        if T::DECIDE_IN_BALLS
            && let Some(ev) = self.next_event_decided(f)
        {
            return Some(ev);
        }
        self.next_event_compared(f)
    }

    /// The next event of `f`, exactly as [`Trap::next_event_compared`] finds it, when the balls
    /// decide it ([`certified::decide`]): only the chosen candidate's time is computed, by the
    /// full comparison's own operations. `None` when the balls cannot decide.
    #[inline(always)]
    pub fn next_event_decided(&self, f: &Flight<T>) -> Option<Event<T>> {
        let chosen = certified::decide(&self.balls, f)?;
        let (p, v) = (&f.pos, &f.vel);
        if chosen < 3 {
            let m = chosen as u8;
            // As the full comparison forms d: p itself for P₀ = (0, 0).
            let d = if m == 0 {
                p.clone()
            } else {
                p.sub(&self.vertices[m as usize])
            };
            let a = approach(d.x, d.y, v, v.norm2())?;
            return Some(Event {
                kind: EventKind::Collision(m),
                time: a.entry(None),
            });
        }
        let e = (chosen - 3) as u8;
        let (mut nv, sigma) = match e {
            2 => (v.y.clone(), p.y.clone()),
            _ => self.slanted_edge(e, p, v),
        };
        nv.neg_mut();
        Some(Event {
            kind: EventKind::Crossing(e),
            time: edge_time(sigma, &nv),
        })
    }

    /// The full comparison: the next event of `f` among every candidate's rounded time, the
    /// kernel's definition of the next event.
    ///
    /// Candidates are the vertex disks other than `f.excluded_disk` (cancellation-free root,
    /// [`super::ray_disk::ray_disk_with_speed`]) and the edges other than `f.excluded_edge` that the velocity
    /// points out of (time σₖ/(−nₖ·v), or 0 if the start is numerically beyond the edge).
    /// Ties go to the lower disk label, then collisions before crossings.
    ///
    /// The canonical coordinates make several operations exact, and they are skipped without
    /// changing a bit of the result (see `proofs-notes/bit-for-bit.md`): d = p − P₀ = p,
    /// n₂·v = v_y, σ₂ = p_y, σ₁ = n₁·p (o₁ = 0), and n₀, n₁ share the products (√3/2)·x and x/2.
    #[inline(always)]
    pub fn next_event_compared(&self, f: &Flight<T>) -> Option<Event<T>> {
        let (p, v) = (&f.pos, &f.vel);
        let vv = v.norm2();
        let mut best: Option<Event<T>> = None;
        let mut offer = |t: T, kind: EventKind| {
            if best.as_ref().is_none_or(|b| t < b.time) {
                best = Some(Event { kind, time: t });
            }
        };
        if f.excluded_disk != Some(0)
            && let Some(t) = ray_disk_centred(p.x.clone(), p.y.clone(), v, &vv)
        {
            offer(t, EventKind::Collision(0));
        }
        for m in 1..3u8 {
            if f.excluded_disk != Some(m) {
                let c = &self.vertices[m as usize];
                if let Some(t) = ray_disk_centred(p.x.clone() - &c.x, p.y.clone() - &c.y, v, &vv) {
                    offer(t, EventKind::Collision(m));
                }
            }
        }
        let mut edge = |e: u8, nv: T, sigma: T| {
            if f.excluded_edge != Some(e) && nv.lt0() {
                let t = if sigma.gt0() {
                    sigma / &(-nv)
                } else {
                    T::zero(nv.ctx())
                };
                offer(t, EventKind::Crossing(e));
            }
        };
        let [(nv0, sigma0), (nv1, sigma1)] = self.slanted_edges(p, v);
        edge(0, nv0, sigma0);
        edge(1, nv1, sigma1);
        if f.excluded_edge != Some(2) && v.y.lt0() {
            edge(2, v.y.clone(), p.y.clone());
        }
        best
    }

    /// The same event as [`Trap::next_event_compared`], with the same bits, found by choosing before
    /// dividing ([`super::choice`]): the earliest disk by β (when w ≥ 2⁻²⁰), the earliest edge
    /// by certified cross products, then one root and two quotients. This is the rule the SIMD
    /// engine applies lane by lane (`proofs-notes/choose-before-dividing.md`). On one scalar
    /// trajectory it is no faster than the full comparison — whose branches already skip the
    /// candidates that move away — so the scalar engine keeps that in `f64` and decides in balls
    /// at MPFR precision ([`Trap::next_event`]).
    #[inline(always)]
    pub fn next_event_chosen(&self, f: &Flight<T>) -> Option<Event<T>> {
        let (p, v) = (&f.pos, &f.vel);
        let vv = v.norm2();
        let mut disks = EarliestDisk::new(self.choice.disks_by_beta, None);
        if f.excluded_disk != Some(0) {
            disks.offer(0, approach(p.x.clone(), p.y.clone(), v, vv.clone()));
        }
        for m in 1..3u8 {
            if f.excluded_disk != Some(m) {
                let c = &self.vertices[m as usize];
                let (dx, dy) = (p.x.clone() - &c.x, p.y.clone() - &c.y);
                disks.offer(m, approach(dx, dy, v, vv.clone()));
            }
        }
        let mut edges = EarliestEdge::new(&self.choice.certain);
        for (e, (nv, sigma)) in (0..2u8).zip(self.slanted_edges(p, v)) {
            if f.excluded_edge != Some(e) {
                edges.offer(e, nv, sigma);
            }
        }
        if f.excluded_edge != Some(2) {
            edges.offer(2, v.y.clone(), p.y.clone());
        }
        first(disks.event(), edges.event())
    }

    /// Moves along the flight to the event and carries it out: a specular reflection
    /// v' = v − 2(v·n)n with n = x − Pₘ at the contact point x (|n| = 1 up to rounding),
    /// times the Newton factor (3 − |v|²)/2 that keeps |v| = 1 without drift; the
    /// particle stays at x. A crossing is the point reflection into the neighbour's frame.
    ///
    /// Written in place (the same correctly rounded operations as x = p + t·v, n = x − Pₘ,
    /// v − (n·s) with s = 2(v·n), and cₖ − x as −x + cₖ), so that MPFR allocates five
    /// temporaries per collision rather than a dozen.
    #[inline(always)]
    pub fn apply(&self, f: &mut Flight<T>, ev: &Event<T>) {
        // x = p + t·v, into the position.
        let mut nx = f.vel.x.clone();
        nx *= &ev.time;
        f.pos.x += &nx;
        let mut ny = f.vel.y.clone();
        ny *= &ev.time;
        f.pos.y += &ny;
        match ev.kind {
            EventKind::Collision(m) => {
                // n = x − Pₘ; for P₀ = (0, 0) the subtraction is exact and skipped.
                nx.clone_from(&f.pos.x);
                ny.clone_from(&f.pos.y);
                if m != 0 {
                    nx -= &self.vertices[m as usize].x;
                    ny -= &self.vertices[m as usize].y;
                }
                // The speed is 1 by the model. Rounding in the reflection changes |v|² by O(u)
                // per collision with a small systematic bias (ties at the binade boundary 1), so
                // |v| would drift. One division-free Newton step for 1/|v|, with the factor
                // k = (3 − |v_in|²)/2 taken from the *incoming* speed (independent of the
                // reflection, so off the critical path), maps |v_in|² = 1 + η to
                // |v_out|² = 1 + δ + O(η²), δ the reflection's own rounding: nothing
                // accumulates (proofs-notes/energy.md).
                let mut k = f.vel.x.clone();
                k.square_mut();
                let mut tmp = f.vel.y.clone();
                tmp.square_mut();
                k += &tmp;
                k.neg_mut();
                let k = k.add_f64(3.0).scale(0.5);
                // s = 2(v·n).
                let mut s = f.vel.x.clone();
                s *= &nx;
                tmp.set_mul(&f.vel.y, &ny);
                s += &tmp;
                let s = s.scale(2.0);
                tmp.set_mul(&nx, &s);
                f.vel.x -= &tmp;
                tmp.set_mul(&ny, &s);
                f.vel.y -= &tmp;
                f.vel.x *= &k;
                f.vel.y *= &k;
                f.excluded_disk = Some(m);
                f.excluded_edge = None;
            }
            EventKind::Crossing(k) => {
                let c = &self.centres[k as usize];
                f.pos.x.neg_mut();
                f.pos.x += &c.x;
                f.pos.y.neg_mut();
                f.pos.y += &c.y;
                f.vel.x.neg_mut();
                f.vel.y.neg_mut();
                f.excluded_disk = relabel_after_crossing(k, f.excluded_disk);
                f.excluded_edge = Some(k);
            }
        }
    }

    /// `true` if `p` is in the closed triangle and outside the open disks (the free trap),
    /// decided at the working precision.
    pub fn is_free(&self, p: &Vec2<T>) -> bool {
        (0..3).all(|k| !self.edge_distance(k, p).lt0())
            && self
                .vertices
                .iter()
                .all(|c| !p.sub(c).norm2().add_f64(-1.0).lt0())
    }
}

/// Label of a disk after crossing edge `k`: the endpoints of Eₖ swap (m ↦ 3 − k − m), the
/// opposite disk Pₖ is not a vertex of the new trap (`None`).
#[inline(always)]
pub fn relabel_after_crossing(k: u8, m: Option<u8>) -> Option<u8> {
    match m {
        Some(m) if m != k => Some(3 - k - m),
        _ => None,
    }
}

impl<T: Real> CellKernel<T> for Trap<T> {
    fn cell(&self) -> &ConvexCell<T> {
        &self.cell
    }
    #[inline(always)]
    fn next_event(&self, f: &Flight<T>) -> Option<Event<T>> {
        Trap::next_event(self, f)
    }
    #[inline(always)]
    fn apply(&self, f: &mut Flight<T>, ev: &Event<T>) {
        Trap::apply(self, f, ev)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflection_centres_map_edges_onto_themselves() {
        let t = Trap::new(0.1f64).unwrap();
        for k in 0..3u8 {
            let (i, j) = match k {
                0 => (1, 2),
                1 => (2, 0),
                _ => (0, 1),
            };
            // cₖ − Pᵢ = Pⱼ: the endpoints swap, and relabel agrees.
            let img = t.centres[k as usize].sub(&t.vertices[i]);
            assert!(
                (img.x - t.vertices[j].x).abs() < 1e-15 && (img.y - t.vertices[j].y).abs() < 1e-15
            );
            assert_eq!(relabel_after_crossing(k, Some(i as u8)), Some(j as u8));
            assert_eq!(relabel_after_crossing(k, Some(k)), None);
        }
    }

    #[test]
    fn normals_point_inward_and_vertices_lie_on_their_edges() {
        let t = Trap::new(0.2f64).unwrap();
        let centroid = Vec2::new(t.a / 2.0, t.h / 3.0);
        for k in 0..3 {
            assert!(t.edge_distance(k, &centroid) > 0.0);
            for (i, p) in t.vertices.iter().enumerate() {
                let d = t.edge_distance(k, p);
                if i == k {
                    assert!((d - t.h).abs() < 1e-14, "opposite vertex at height h");
                } else {
                    assert!(d.abs() < 1e-15);
                }
            }
        }
    }

    #[test]
    fn crossing_then_crossing_back_is_the_identity_up_to_rounding() {
        let t = Trap::new(0.1f64).unwrap();
        // A point in the gap of E2 (y = 0, x = a/2) moving down.
        let mut f = Flight::new(Vec2::new(t.a / 2.0, 0.3), Vec2::new(0.0, -1.0));
        let ev = t.next_event(&f).unwrap();
        assert_eq!(ev.kind, EventKind::Crossing(2));
        t.apply(&mut f, &ev);
        assert_eq!(f.excluded_edge, Some(2));
        // Now moving up in the neighbour's frame (the frame is point-reflected).
        assert_eq!(f.vel.y, 1.0);
        assert!((f.pos.x - t.a / 2.0).abs() < 1e-15 && f.pos.y.abs() < 1e-15);
    }
}
