//! The order of an arc's candidate events in lanes ([`crate::kernel::arc::earlier`]): each
//! candidate's stage on the way round, computed once, and the offer that keeps the earlier.

use super::{ArcL, is_zero, not};
use crate::numbers::lanes::Lanes;

/// A candidate per lane: chord, found in the disk's frame, present, and the chord's place on the
/// way round for [`earlier`] (computed once per candidate).
#[derive(Clone, Copy)]
pub(super) struct Cand<V: Lanes> {
    pub(super) x: V,
    pub(super) y: V,
    pub(super) frame: V::Mask,
    pub(super) has: V::Mask,
    pub(super) turning: V::Mask,
    pub(super) half: V::Mask,
    pub(super) near: V::Mask,
    pub(super) len: V,
}

impl<V: Lanes> Cand<V> {
    #[inline(always)]
    pub(super) fn new(
        a: &ArcL<V>,
        left: bool,
        (x, y): (V, V),
        frame: V::Mask,
        has: V::Mask,
    ) -> Self {
        let (turning, half, near) = stage(a, left, x, y);
        Cand {
            x,
            y,
            frame,
            has,
            turning,
            half,
            near,
            len: x.mul(x).add(y.mul(y)),
        }
    }
}

/// A chord's stage on the way round and its class ([`crate::kernel::arc::earlier`]):
/// (turning, at the half-turn, near: at the start or turning within π/4 of v).
#[inline(always)]
pub(super) fn stage<V: Lanes>(a: &ArcL<V>, left: bool, x: V, y: V) -> (V::Mask, V::Mask, V::Mask) {
    let (z, all) = (V::splat(0.0), a.all);
    let side = a.vx.mul(y).sub(a.vy.mul(x));
    let dot = a.vx.mul(x).add(a.vy.mul(y));
    let turning = if left { side.gt(z) } else { side.lt(z) };
    let start = V::and_not(V::or(is_zero::<V>(x, y, all), dot.gt(z)), turning);
    let half = V::and_not(V::and_not(all, turning), start);
    let near = V::or(start, V::and(turning, V::ge(dot, side.abs())));
    (turning, half, near)
}

/// Where candidate `c1` comes strictly before `c2` ([`crate::kernel::arc::earlier`]), lane by
/// lane.
#[inline(always)]
pub(super) fn earlier<V: Lanes>(a: &ArcL<V>, left: bool, c1: &Cand<V>, c2: &Cand<V>) -> V::Mask {
    let z = V::splat(0.0);
    let both_near = V::and(c1.near, c2.near);
    let far = not::<V>(V::or(c1.near, c2.near), a.all);
    let cross = c1.x.mul(c2.y).sub(c1.y.mul(c2.x));
    let turned = if left { cross.gt(z) } else { cross.lt(z) };
    // Both far: a turning chord before a half-turn one; two half-turn chords by length
    // (longer first), two turning ones by the cross product.
    let far_rule = V::or(
        V::and(c1.turning, c2.half),
        V::or(
            V::and(V::and(c1.half, c2.half), c1.len.gt(c2.len)),
            V::and(V::and(c1.turning, c2.turning), turned),
        ),
    );
    V::or(
        V::or(
            V::and(both_near, c1.len.lt(c2.len)),
            V::and_not(c1.near, c2.near),
        ),
        V::and(far, far_rule),
    )
}

/// `m ? a : b` on masks.
#[inline(always)]
pub(super) fn blend<V: Lanes>(m: V::Mask, a: V::Mask, b: V::Mask) -> V::Mask {
    V::or(V::and(m, a), V::and_not(b, m))
}

/// `later` replaces `best` where it has a chord and `best` has none or it is strictly earlier.
#[inline(always)]
pub(super) fn offer<V: Lanes>(
    a: &ArcL<V>,
    left: bool,
    best: Cand<V>,
    later: Cand<V>,
) -> (Cand<V>, V::Mask) {
    let better = earlier(a, left, &later, &best);
    let take = V::and(later.has, V::or(better, V::and_not(a.all, best.has)));
    let c = Cand {
        x: V::select(take, later.x, best.x),
        y: V::select(take, later.y, best.y),
        frame: blend::<V>(take, later.frame, best.frame),
        has: V::or(best.has, later.has),
        turning: blend::<V>(take, later.turning, best.turning),
        half: blend::<V>(take, later.half, best.half),
        near: blend::<V>(take, later.near, best.near),
        len: V::select(take, later.len, best.len),
    };
    (c, take)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::arc::earlier as scalar_earlier;
    use crate::kernel::vec2::Vec2;
    use rand::{Rng, SeedableRng};

    /// A chord of the arc of velocity v in one of the places `earlier` tells apart: zero, just
    /// behind or ahead of v, turning within or beyond π/4, or near the half-turn (short and
    /// behind), at lengths from 10⁻¹⁸ to 2.
    fn chord(rng: &mut impl Rng, v: (f64, f64), left: bool) -> (f64, f64) {
        let side = if left { 1.0 } else { -1.0 };
        let (jx, jy) = (-v.1 * side, v.0 * side);
        let len = 10f64.powf(rng.random_range(-18.0..0.3));
        let (a, b) = match rng.random_range(0..6) {
            0 => return (0.0, 0.0),
            1 => (1.0, -1e-3 * rng.random::<f64>()),
            2 => (1.0, rng.random::<f64>()),
            3 => (rng.random::<f64>(), 1.0),
            4 => (-1.0, rng.random::<f64>() * 1e-3),
            _ => (-1.0, -1e-3 * rng.random::<f64>()),
        };
        let n = (a * a + b * b).sqrt();
        (len * (a * v.0 + b * jx) / n, len * (a * v.1 + b * jy) / n)
    }

    #[test]
    fn the_lanes_order_of_chords_is_the_scalar_order() {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(7);
        let mut taken = [0u32; 2];
        for k in 0..200_000 {
            let phi = rng.random_range(0.0..std::f64::consts::TAU);
            let v = (phi.cos(), phi.sin());
            let w: f64 = if k % 2 == 0 { 1.5 } else { -0.7 };
            let left = w > 0.0;
            let (x1, x2) = (chord(&mut rng, v, left), chord(&mut rng, v, left));
            let vv = v.0 * v.0 + v.1 * v.1;
            let a = ArcL::<f64> {
                vx: v.0,
                vy: v.1,
                vv,
                speed: vv.sqrt(),
                all: true,
            };
            let c1 = Cand::new(&a, left, x1, false, true);
            let c2 = Cand::new(&a, left, x2, false, true);
            let lanes = earlier(&a, left, &c1, &c2);
            let scalar = scalar_earlier(
                &Vec2::new(x1.0, x1.1),
                &Vec2::new(x2.0, x2.1),
                &Vec2::new(v.0, v.1),
                &w,
            );
            assert_eq!(
                lanes, scalar,
                "v = {v:?}, w = {w}, x1 = {x1:?}, x2 = {x2:?}"
            );
            taken[usize::from(lanes)] += 1;
        }
        // Both answers are common: the comparison is not vacuous.
        assert!(taken.iter().all(|&n| n > 50_000), "{taken:?}");
    }
}
