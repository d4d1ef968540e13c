//! The contact of an arc with a disk found in the disk's frame, for a cyclotron centre within half
//! a cyclotron radius of the disk's centre (`proofs-notes/magnetic-arcs.md`): the entry, the
//! rounding that tells a miss from a tangency, and the entry that is now.

use super::{Arc, Contact};
use crate::kernel::vec2::Vec2;
use crate::numbers::real::Real;

/// What the disk frame decided about a disk ([`Arc`]'s `disk_frame`).
pub(super) enum Frame<T> {
    /// The contact, or that there is none.
    Decided(Option<Contact<T>>),
    /// The particle, off the circle, is on it within the rounding: its contact is the one of a
    /// particle on the circle (γ = 0).
    OnCircle,
    /// The radical line decides.
    Radical,
}

impl<T: Real> Arc<'_, T> {
    /// The entry into the circle of radius `r` at −d when the cyclotron centre is within half a
    /// cyclotron radius of its centre (M < V²/4) and the circles cut; a decision without one
    /// where they do not. Nearly concentric circles of nearly equal radii cut at a small angle,
    /// and the radical-line form x₀ + s·e then carries its rounding along e, across both
    /// circles, by a factor 1/M (the fourth libFuzzer campaign: 10⁸u off the disk at
    /// M = 2·10⁻⁹, and the particle, hugging the disk, still inside it after the next crossing).
    /// In the disk's frame the entry is y = (a·m + r sin φ·Jm)/√M with a = sgn ω·r cos φ =
    /// ((|ω|r − V)(|ω|r + V) + M)/(2ω√M), the law of cosines with the centres √M/|ω| apart (ρ ≈ r
    /// is the exact factor |ω|r − V, and M < V²/4 keeps M − V² from cancelling), and
    /// r sin φ = √((r − a)(r + a)) ≥ 0 (Jm·y > 0 is the entry: there the velocity ωJ(y − m/ω)
    /// points into the disk). |y| = r to a few u whatever M, and the chord is y − d
    /// (`proofs-notes/magnetic-arcs.md`).
    ///
    /// Where they do not cut (rs² ≤ 0), one circle is inside the other to within the rounding
    /// (D < ρ/2 rules out circles apart). For a particle off the circle (`off`: γ > 0): a disk
    /// inside the cyclotron circle (ρ > r) is missed, and the orbit enters it by no more than the
    /// rounding of a tangency, r + D − ρ ≲ 32u(r + ρ); a cyclotron circle inside the disk
    /// (ρ ≤ r) puts the particle on the surface within that rounding, and its contact is the
    /// one on the circle ([`Frame::OnCircle`]: now, or the return, which lands exactly as far
    /// from the disk as the particle is). The radical line, with its 1/M, is not consulted there
    /// (the seventeenth and twenty-first libFuzzer campaigns: contacts 0.16 and 10⁻⁹ off the
    /// disk). For a particle on the circle the radical line decides its return: on both
    /// circles, a position drifted inside the disk by its returns can put its whole cyclotron
    /// circle inside the disk, and "no contact" then flies it through the disk (the eighteenth
    /// campaign); near tangency the radical line runs along both circles, so its rounding moves
    /// the return along them, not off them.
    pub(super) fn disk_frame(&self, d: &Vec2<T>, r: &T, off: bool) -> Frame<T> {
        let (v, w) = (self.v, self.w);
        let m = Vec2::new(w.clone() * &d.x - &v.y, w.clone() * &d.y + &v.x);
        let mm = m.norm2();
        if !(self.vv.clone() - &mm.clone().scale(4.0)).gt0() {
            return Frame::Radical;
        }
        let u = T::unit_roundoff(w.ctx());
        let noise = (w.clone().abs() * &d.norm2().sqrt() + &self.speed).scale(8.0 * u);
        if !(mm.clone() - &noise.square()).gt0() {
            // Concentric to rounding: off the surface a circle about the disk's centre that
            // meets it nowhere; on it the disk's own circle, the slide of [`Arc::creeps`]
            // (the ninth libFuzzer campaign: not on it by identity, β a rounding, a random
            // contact and the speed off by 150 %).
            return Frame::Decided(None);
        }
        let sm = mm.clone().sqrt();
        let awr = w.clone().abs() * r;
        let small = awr.clone() - &self.speed;
        let g = small.clone() * &(awr + &self.speed) + &mm;
        let a = g / &(w.clone().scale(2.0) * &sm);
        let rs2 = (r.clone() - &a) * &(r.clone() + &a);
        if !rs2.gt0() {
            if !off {
                return Frame::Radical;
            }
            // |ω|r − V < 0: the cyclotron radius exceeds the disk's (ρ > r). A sign taken only
            // here, where it decides (the audit counts every sign within its rounding).
            return if small.lt0() {
                Frame::Decided(None)
            } else {
                Frame::OnCircle
            };
        }
        let rs = rs2.sqrt();
        let yx = (a.clone() * &m.x - &(rs.clone() * &m.y)) / &sm;
        let yy = (a * &m.y + &(rs * &m.x)) / &sm;
        Frame::Decided(Some(Contact {
            chord: Vec2::new(yx - &d.x, yy - &d.y),
            disk_frame: true,
        }))
    }

    /// A disk-frame entry `c` for a particle off the circle (γ > 0) moving into it (β < 0), taken
    /// as *now* (chord 0, the velocity v) where it lies within its own rounding of the particle.
    /// The disk frame finds the entry on the disk to a few u, but along the disk only to the
    /// direction of m = Jv + ωd, whose components carry an absolute rounding of 2u(|ω||d| + V)
    /// each: the entry turns about the disk's centre by up to 3u(|ω||d| + V)/√M, so it moves
    /// along the disk by r times that, besides the few u(r + |d|) of its other operations. An
    /// entry closer to the particle than E = 4u(r(|ω||d| + V)/√M + 2(r + |d|)) has no
    /// determined side of v, and one rounded behind it was ordered as a chord at the half-turn,
    /// after every other event (the eleventh libFuzzer campaign: a particle an ulp off a disk,
    /// moving in at 5·10⁻⁵ rad, with its cyclotron circle 5·10⁻⁵ from the disk's, ρ = r: the
    /// entry 2·10⁻¹² ahead came out 4·10⁻¹⁴ behind, and the particle flew 4·10⁻⁵ deep into the
    /// disk). Moving in, the entry is ahead and as near as the particle is to the surface, so
    /// within rounding it is now — as on the circle (γ ≤ 0, β < 0). Elsewhere `c` stands.
    ///
    /// Across the disk the entry is exact to the few u(r + |d|) of those operations, but the
    /// arc crosses the disk's circle at the angle α of v to the surface, sin α = |β|/(|d|V) near
    /// the particle, so that error moves the entry *along* the arc by 1/sin α times as much: the
    /// second term of E is 8u(r + |d|)(1 + |d|V/|β|) (the fifteenth libFuzzer campaign: a particle
    /// an ulp off a disk, moving in at 4.8·10⁻⁵ rad, its cyclotron circle nearly internally
    /// tangent to the disk, ρ = 0.70; the entry 1.2·10⁻¹² ahead came out 1.3·10⁻¹² behind, ordered
    /// after a crossing, and the particle flew into the disk). An entry within that reach of the
    /// particle is within the rounding of the surface across it (reach × sin α), so taking it
    /// now moves no contact off the disk by more than the rounding any contact has.
    ///
    /// That premise is checked, not assumed: the particle must be within reach × sin α of the
    /// surface, γ = |d|² − r² ≤ reach·|β|(|d| + r)/(|d|V), or within the rounding of γ,
    /// 4u(|d|² + r²). Along an arc the angle to the surface changes, and a far entry of a
    /// particle moving in at a rounding-level angle has a reach of the whole circle (the
    /// twenty-first libFuzzer campaign: a particle 1.3·10⁻¹³ off a disk of radius 1/2 at the far
    /// side of a cyclotron circle 6·10⁻¹⁴ from concentric, taken now and reflected there, the
    /// speed then off by 10³u).
    pub(super) fn entry_now(
        &self,
        c: Contact<T>,
        d: &Vec2<T>,
        (r, gamma): (&T, &T),
        beta: &T,
    ) -> Contact<T> {
        if !beta.lt0() {
            return c;
        }
        let (v, w) = (self.v, self.w);
        let u = T::unit_roundoff(w.ctx());
        let m = Vec2::new(w.clone() * &d.x - &v.y, w.clone() * &d.y + &v.x);
        let dn = d.norm2().sqrt();
        let turn = r.clone() * &(w.clone().abs() * &dn + &self.speed) / &m.norm2().sqrt();
        let across = (dn.clone() * &self.speed / &beta.clone().abs()).add_f64(1.0);
        let bound = (turn + &((r.clone() + &dn).scale(2.0) * &across)).scale(4.0 * u);
        if (c.chord.norm2() - &bound.square()).gt0() {
            return c;
        }
        let dd = d.norm2();
        let sin = beta.clone().abs() / &(dn.clone() * &self.speed);
        let depth = bound * &sin * &(dn + r) + &(dd + &r.clone().square()).scale(4.0 * u);
        if (gamma.clone() - &depth).gt0() {
            return c;
        }
        let ctx = w.ctx();
        Contact {
            chord: Vec2::new(T::zero(ctx), T::zero(ctx)),
            disk_frame: false,
        }
    }
}
