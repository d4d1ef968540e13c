//! The candidate events of an arc in lanes: each disk's contact
//! ([`crate::kernel::arc::Arc::contact`]) and each edge's exit ([`crate::kernel::arc::arc_line`]),
//! every branch of the scalar code computed and blended by masks.

use super::order::Cand;
use super::{ArcL, Consts, DiskC, Line, not};
use crate::numbers::lanes::Lanes;

/// `!(mm − noise² > 0)` with noise = (|ω|·√|d|² + V)·8u ([`crate::kernel::arc::Arc::creeps`]),
/// its square root taken only where a bound without it cannot rule the test out.
#[inline(always)]
pub(super) fn coincident<V: Lanes>(
    c: &Consts<V>,
    a: &ArcL<V>,
    dd: V,
    mm: V,
    lanes: V::Mask,
) -> V::Mask {
    let eight_u = V::splat(8.0 * f64::EPSILON / 2.0);
    let hi = c.aw.mul(dd.add(V::splat(1.0))).add(a.speed).mul(eight_u);
    let maybe = V::and(lanes, V::ge(hi.mul(hi), mm));
    if V::bits(maybe) == 0 {
        return maybe;
    }
    let noise = c.aw.mul(dd.sqrt()).add(a.speed).mul(eight_u);
    V::and(
        lanes,
        not::<V>(mm.sub(noise.mul(noise)).gt(V::splat(0.0)), a.all),
    )
}

/// The disk-frame contact ([`crate::kernel::arc::Arc`]'s `disk_frame`) where it decides, in
/// the lanes `ok` (`off`: the particle is off the circle): (no contact, a contact, contact as on
/// the circle, chord x, chord y).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn disk_frame<V: Lanes>(
    c: &Consts<V>,
    a: &ArcL<V>,
    d: &DiskC<V>,
    (dx, dy, dd): (V, V, V),
    (mx, my, mm): (V, V, V),
    (ok, off): (V::Mask, V::Mask),
) -> (V::Mask, V::Mask, V::Mask, V, V) {
    let z = V::splat(0.0);
    let conc = coincident(c, a, dd, mm, ok);
    let sm = mm.sqrt();
    let awr = c.aw.mul(d.r);
    let small = awr.sub(a.speed);
    let wider = small.lt(z);
    let g = small.mul(awr.add(a.speed)).add(mm);
    let aa = g.div(c.w.mul(V::splat(2.0)).mul(sm));
    let rs2 = d.r.sub(aa).mul(d.r.add(aa));
    let cut = rs2.gt(z);
    let some = V::and(V::and_not(ok, conc), cut);
    // Off the circle without a cut: a disk inside the cyclotron circle is missed, a particle
    // whose circle is inside the disk is on it ([`crate::kernel::arc::Arc`]).
    let rest = V::and(off, V::and_not(V::and_not(ok, conc), cut));
    let miss = V::and(rest, wider);
    let as_on = V::and_not(rest, wider);
    let rs = rs2.sqrt();
    let yx = aa.mul(mx).sub(rs.mul(my)).div(sm);
    let yy = aa.mul(my).add(rs.mul(mx)).div(sm);
    (V::or(conc, miss), some, as_on, yx.sub(dx), yy.sub(dy))
}

/// Disk `m`'s contact in every lane ([`crate::kernel::arc::Arc::contact`]), and where the
/// particle, on it, slides ([`crate::kernel::arc::Arc::creeps`]: the scalar kernel then has no
/// event at all).
#[inline(always)]
pub(super) fn disk<V: Lanes>(
    c: &Consts<V>,
    a: &ArcL<V>,
    d: &DiskC<V>,
    (px, py): (V, V),
    on: V::Mask,
) -> (Cand<V>, V::Mask) {
    let (z, w, all) = (V::splat(0.0), c.w, a.all);
    let (dx, dy) = (px.sub(d.cx), py.sub(d.cy));
    let beta = dx.mul(a.vx).add(dy.mul(a.vy));
    let q = dx.mul(a.vy).sub(dy.mul(a.vx));
    let vv_wq = a.vv.sub(w.mul(q));
    let wb = w.mul(beta);
    let inv = a.vv.div(vv_wq.mul(vv_wq).add(wb.mul(wb)));
    let (ex, ey) = (a.vx.add(w.mul(dy)), a.vy.sub(w.mul(dx)));
    let dd = dx.mul(dx).add(dy.mul(dy));
    let gamma = V::select(on, z, dd.sub(d.r2));
    let onc = not::<V>(gamma.gt(z), all);
    let (bpos, bneg) = (beta.gt(z), beta.lt(z));
    let (mx, my) = (w.mul(dx).sub(a.vy), w.mul(dy).add(a.vx));
    let mm = mx.mul(mx).add(my.mul(my));
    let turn_in = w.mul(a.vy.neg().mul(dx).add(a.vx.mul(dy))).lt(z);
    // Creeping: on the disk, moving along it (β = 0) turning in, or on its own circle.
    let along = V::and(not::<V>(V::or(bpos, bneg), all), turn_in);
    let stuck = V::or(V::and(on, along), coincident(c, a, dd, mm, on));
    // The disk frame, where 4M < V² in a lane that consults it.
    let ok = V::and(
        a.vv.sub(mm.mul(V::splat(4.0))).gt(z),
        V::or(not::<V>(onc, all), V::and(onc, bpos)),
    );
    let (none, some, as_on, fx, fy) = if V::bits(ok) == 0 {
        (ok, ok, ok, z, z)
    } else {
        let off = not::<V>(onc, all);
        disk_frame(c, a, d, (dx, dy, dd), (mx, my, mm), (ok, off))
    };
    // Off the circle moving in, a disk-frame entry within its rounding of the particle is now.
    let near = entry_now(
        c,
        a,
        d,
        (dd, mm, beta, gamma),
        (fx, fy),
        V::and(V::and_not(some, onc), bneg),
    );
    let (fx, fy) = (V::select(near, z, fx), V::select(near, z, fy));
    let frame = V::and_not(some, near);
    // On the circle, moving out: the return s = −2β/M.
    let s_ret = beta.mul(V::splat(-2.0)).mul(inv);
    // Off it: the entry.
    let (disc, s_in) = entry(c, a, d, (q, vv_wq, beta, gamma), inv);
    let f = w.mul(gamma).mul(V::splat(0.5)).neg().mul(inv);
    let (nx, ny) = (f.mul(mx).add(s_in.mul(ex)), f.mul(my).add(s_in.mul(ey)));
    // A particle off the circle that the disk frame puts on it has the contact of one on it.
    let onc = V::or(onc, as_on);
    let ret = V::and(onc, bpos);
    let now = V::and(V::and_not(onc, bpos), V::or(bneg, turn_in));
    let decided = V::or(none, some);
    let off = V::and(
        not::<V>(onc, all),
        V::or(some, V::and_not(disc.gt(z), decided)),
    );
    let has = V::or(V::or(V::and_not(ret, none), now), off);
    let x = V::select(
        some,
        fx,
        V::select(ret, ex.mul(s_ret), V::select(now, z, nx)),
    );
    let y = V::select(
        some,
        fy,
        V::select(ret, ey.mul(s_ret), V::select(now, z, ny)),
    );
    (Cand::new(a, c.left, (x, y), frame, has), stuck)
}

/// The entry of a particle off the circle ([`disk`]): the discriminant (β² − γK where the
/// product (vr + shift)(vr − shift) rounded to ≤ 0 with γ > 0 and K < 0) and the arc parameter
/// of the entry, by the cancellation-free root on each side of β = 0.
#[inline(always)]
fn entry<V: Lanes>(
    c: &Consts<V>,
    a: &ArcL<V>,
    d: &DiskC<V>,
    (q, vv_wq, beta, gamma): (V, V, V, V),
    inv: V,
) -> (V, V) {
    let (z, w) = (V::splat(0.0), c.w);
    let vr = a.speed.mul(d.r);
    let shift = q.sub(w.mul(gamma).mul(V::splat(0.5)));
    let k = vv_wq.add(w.mul(w).mul(gamma).mul(V::splat(0.25)));
    let product = vr.add(shift).mul(vr.sub(shift));
    // Off the circle with K < 0, β² − γK where the product rounded to ≤ 0.
    let sum = beta.mul(beta).sub(gamma.mul(k));
    let cancelled = V::and_not(V::and(gamma.gt(z), k.lt(z)), product.gt(z));
    let disc = V::select(cancelled, sum, product);
    let root = disc.sqrt();
    let s_in = V::select(
        beta.lt(z),
        gamma.mul(k).div(root.sub(beta)).mul(inv),
        beta.add(root).neg().mul(inv),
    );
    (disc, s_in)
}

/// Where a disk-frame entry (chord `f`) of a particle off the circle moving in (`lanes`) lies
/// within its own rounding of the particle ([`crate::kernel::arc::Arc`]'s `entry_now`): there
/// the contact is now.
#[inline(always)]
pub(super) fn entry_now<V: Lanes>(
    c: &Consts<V>,
    a: &ArcL<V>,
    d: &DiskC<V>,
    (dd, mm, beta, gamma): (V, V, V, V),
    (fx, fy): (V, V),
    lanes: V::Mask,
) -> V::Mask {
    if V::bits(lanes) == 0 {
        return lanes;
    }
    let dn = dd.sqrt();
    let turn = d.r.mul(c.aw.mul(dn).add(a.speed)).div(mm.sqrt());
    let four_u = V::splat(4.0 * f64::EPSILON / 2.0);
    // β < 0 in `lanes`; elsewhere the quotient may be infinite or NaN, and is masked out.
    let across = dn.mul(a.speed).div(beta.abs()).add(V::splat(1.0));
    let bound = turn
        .add(d.r.add(dn).mul(V::splat(2.0)).mul(across))
        .mul(four_u);
    let chord2 = fx.mul(fx).add(fy.mul(fy));
    let within = not::<V>(chord2.sub(bound.mul(bound)).gt(V::splat(0.0)), a.all);
    // The premise: the particle within reach × sin α of the surface, or within γ's rounding.
    let sin = beta.abs().div(dn.mul(a.speed));
    let depth = bound
        .mul(sin)
        .mul(dn.add(d.r))
        .add(dd.add(d.r.mul(d.r)).mul(V::splat(4.0 * f64::EPSILON / 2.0)));
    let close = not::<V>(gamma.sub(depth).gt(V::splat(0.0)), a.all);
    V::and(lanes, V::and(within, close))
}

/// Edge `e`'s exit in every lane ([`crate::kernel::arc::arc_line`]).
#[inline(always)]
pub(super) fn edge<V: Lanes>(
    c: &Consts<V>,
    a: &ArcL<V>,
    e: &Line<V>,
    (px, py): (V, V),
    entered: V::Mask,
) -> Cand<V> {
    let (z, w, all) = (V::splat(0.0), c.w, a.all);
    let aa = e.nx.mul(a.vx).add(e.ny.mul(a.vy));
    let (jx, jy) = (e.ny.neg(), e.nx);
    let sigma = e.nx.mul(px).add(e.ny.mul(py)).sub(e.off);
    let online = V::or(entered, not::<V>(sigma.gt(z), all));
    let apos = aa.gt(z);
    let b = e.nx.mul(a.vy.neg()).add(e.ny.mul(a.vx));
    let out = V::or(aa.lt(z), w.mul(b).lt(z));
    let ws = w.mul(sigma);
    let cc = ws.add(b.mul(V::splat(2.0)));
    let disc = aa.mul(aa).sub(ws.mul(cc));
    let root = disc.sqrt();
    // One quotient: 2a/ω (the return), (a + √Δ)/ω or −σc/(√Δ − a) (the exit).
    let num = V::select(
        online,
        aa.mul(V::splat(2.0)),
        V::select(apos, aa.add(root), sigma.mul(cc).neg()),
    );
    let den = V::select(V::or(online, apos), w, root.sub(aa));
    let s = num.div(den);
    let (ox, oy) = (
        s.mul(jx).sub(sigma.mul(e.nx)),
        s.mul(jy).sub(sigma.mul(e.ny)),
    );
    let back = V::and(online, apos);
    let now = V::and(V::and_not(online, apos), out);
    let exit = V::and(not::<V>(online, all), disc.gt(z));
    let x = V::select(back, jx.mul(s), V::select(now, z, ox));
    let y = V::select(back, jy.mul(s), V::select(now, z, oy));
    Cand::new(
        a,
        c.left,
        (x, y),
        V::from_bits(0),
        V::or(V::or(back, now), exit),
    )
}
