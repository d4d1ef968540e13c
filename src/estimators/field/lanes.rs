//! The batches of a run in a field on the SIMD arc engine ([`crate::engine::arcs::ArcBlock`]):
//! up to [`BLOCK`](crate::engine::simd::BLOCK) batches fly in the lanes of one block, and every event a lane records is fed
//! to that batch's [`Track`] with the very operations of the scalar driver ([`track::batch`]),
//! so each batch has the scalar kernel's bits (`tests/analyses/field.rs`).
//!
//! A lane runs on a few events past its batch's duration before it is retired; those events are
//! not observed, and a lane that loses its next event there (a measure-zero creeping slide) is
//! retired too, where the scalar driver would never have flown it.

use super::track::{self, Batch, LOOK_EVERY, Setup, Track};
use crate::Error;
use crate::engine::arcs::{ArcBlock, ArcRecord};
use crate::engine::observe::CROSSING_CODE;
use crate::engine::options::StopFlag;
use crate::engine::parallel::par_lane_blocks;
use crate::engine::simd::BLOCK;
use crate::engine::{LaneWork, SimdPath, on_path};
use crate::kernel::vec2::Vec2;
use crate::numbers::lanes::Lanes;
use crate::scenes::Scene;
use crate::scenes::lattice::Basis64;
use crate::scenes::magnetic::{arc_observables, no_next_event};
use crate::scenes::sampling::StreamKey;

/// Events per lane between two looks at the recorded events.
pub(super) const RING: usize = 64;

/// Every batch (`keys[i]` the stream of batch i) on the SIMD path `path`, in blocks of at most
/// [`BLOCK`](crate::engine::simd::BLOCK) batches spread over `threads` threads; the batches in their order.
///
/// # Errors
/// A start that cannot be drawn, an orbit of a batch without a next event within its duration,
/// or an interruption.
pub(super) fn batches<S: Scene>(
    su: &Setup<'_, f64, S>,
    path: SimdPath,
    keys: &[StreamKey],
    duration: f64,
    threads: usize,
) -> Result<Vec<Batch>, Error> {
    par_lane_blocks(threads, keys, su.stop, |keys| {
        block(su, path, keys, duration)
    })
}

/// The batches of `keys` in the lanes of one block.
fn block<S: Scene>(
    su: &Setup<'_, f64, S>,
    path: SimdPath,
    keys: &[StreamKey],
    duration: f64,
) -> Result<Vec<Batch>, Error> {
    let (mut states, mut rejected) = (Vec::new(), Vec::new());
    for &key in keys {
        let (mut s, r) = track::start(su.scene, su.geometry, key)?;
        s.flight.normalise_speed();
        states.push(s);
        rejected.push(r);
    }
    let lat = su.lattice;
    let mut tracks: Vec<Track> = states
        .iter()
        .map(|s| Track::new(su, lat.unwrapped(s, 0.0), duration))
        .collect();
    let mut lanes = ArcBlock::new(path, lat.cell(), *su.field.0, &states)?;
    fly(
        &mut lanes,
        (su.progress, su.stop),
        running(&tracks),
        |ring, lanes| {
            let counted = observe(su, ring, &mut tracks, lanes)?;
            Ok(Looked {
                counted,
                running: running(&tracks),
            })
        },
    )?;
    Ok(tracks
        .into_iter()
        .zip(rejected)
        .map(|(t, r)| t.finish(r))
        .collect())
}

/// The lanes whose track is still running, as bits.
fn running(tracks: &[Track]) -> u64 {
    (tracks.iter().enumerate()).fold(0, |b, (l, t)| b | u64::from(t.running()) << l)
}

/// What a look at a ring of recorded events found: the collisions counted, and the lanes still
/// running (bits).
pub(super) struct Looked {
    pub(super) counted: u64,
    pub(super) running: u64,
}

/// Flies the lanes of `block` while any of `running` (bits) runs: [`RING`] events at a time, each
/// ring shown to `look` (which takes its events and retires the lanes it has finished), with
/// progress reported and the stop flag looked at every [`LOOK_EVERY`] collisions. A lane that
/// loses its next event while it runs is an error; one that is done is retired.
///
/// # Errors
/// What `look` returns, an orbit without a next event, or an interruption.
pub(super) fn fly(
    block: &mut ArcBlock,
    (progress, stop): (&dyn Fn(u64), Option<&StopFlag>),
    mut running: u64,
    mut look: impl FnMut(&[ArcRecord], &mut ArcBlock) -> Result<Looked, Error>,
) -> Result<(), Error> {
    let mut ring = vec![ArcRecord::default(); RING];
    let mut unreported = 0;
    while running != 0 {
        let lost = block.advance(&mut ring);
        let seen = look(&ring, block)?;
        (unreported, running) = (unreported + seen.counted, seen.running);
        if let Some(l) = lost {
            if running >> l & 1 == 1 {
                return Err(no_next_event(block.state(l).flight.vel.to_f64()));
            }
            block.retire(l);
        }
        if unreported >= LOOK_EVERY {
            progress(unreported);
            unreported = 0;
            if let Some(stop) = stop {
                stop.check()?;
            }
        }
    }
    progress(unreported);
    Ok(())
}

/// Feeds the recorded events of every lane still running to its track, in order, and retires
/// the lanes whose batch has flown its duration; returns the collisions counted.
fn observe<S: Scene>(
    su: &Setup<'_, f64, S>,
    ring: &[ArcRecord],
    tracks: &mut [Track],
    lanes: &mut ArcBlock,
) -> Result<u64, Error> {
    let mut feed = Feed::new(ring, *su.field.0, su.lattice.basis_f64(), tracks);
    on_path(lanes.path(), &mut feed)?;
    let counted = feed.counted;
    for (l, t) in feed.tracks.iter_mut().enumerate() {
        t.set_hot((feed.t[l], feed.area[l], feed.done[l] as u64));
        if !t.running() {
            lanes.retire(l);
        }
    }
    Ok(counted)
}

/// A ring of recorded events fed to the tracks of a block lane by lane: every event's flight
/// time and arc area ([`arc_observables`]), displacement, Lévy area and collision count in the
/// block's lanes, with the very operations of [`Track::event`] on each lane (the scalar
/// driver's bits); the few flights that hold a sample of the time grid go to
/// [`Track::sample_flight`] one by one.
struct Feed<'a> {
    ring: &'a [ArcRecord],
    w: f64,
    basis: Basis64,
    tracks: &'a mut [Track],
    /// Each lane's flight time, cumulative area, next sample time and collisions (the tracks'
    /// hot state, carried in the lanes through the ring).
    t: [f64; BLOCK],
    area: [f64; BLOCK],
    next: [f64; BLOCK],
    done: [f64; BLOCK],
    /// Each lane's start: lattice indices i, j and offset (x, y).
    origin: [[f64; BLOCK]; 4],
    duration: f64,
    counted: u64,
}

impl<'a> Feed<'a> {
    fn new(ring: &'a [ArcRecord], w: f64, basis: Basis64, tracks: &'a mut [Track]) -> Self {
        let mut f = Feed {
            ring,
            w,
            basis,
            t: [0.0; BLOCK],
            area: [0.0; BLOCK],
            // Lanes without a track never run: their time is their duration (0).
            next: [f64::INFINITY; BLOCK],
            done: [0.0; BLOCK],
            origin: [[0.0; BLOCK]; 4],
            duration: tracks.first().map_or(0.0, Track::duration),
            counted: 0,
            tracks,
        };
        for (l, tr) in f.tracks.iter().enumerate() {
            let (t, area, done) = tr.hot();
            (f.t[l], f.area[l], f.done[l]) = (t, area, done as f64);
            f.next[l] = tr.next_sample();
            let o = tr.origin();
            f.origin[0][l] = o.i as f64;
            f.origin[1][l] = o.j as f64;
            f.origin[2][l] = o.off[0];
            f.origin[3][l] = o.off[1];
        }
        f.t[f.tracks.len()..].fill(f.duration);
        f
    }

    /// The samples within the flights of the lanes `bits` at offset `o`: (x, y) the
    /// displacement and world velocity, `end` the flights' ends.
    #[inline(always)]
    fn sample<V: Lanes>(&mut self, o: usize, bits: u64, r: (V, V), v: (V, V), end: V) {
        let mut a = [[0.0; BLOCK]; 5];
        for (k, x) in [r.0, r.1, v.0, v.1, end].into_iter().enumerate() {
            x.store(&mut a[k][..]);
        }
        for l in (0..V::WIDTH).filter(|l| bits >> l & 1 == 1) {
            let tr = &mut self.tracks[o + l];
            let hot = (self.t[o + l], self.area[o + l]);
            let vw = Vec2::new(a[2][l], a[3][l]);
            tr.sample_flight(hot, [a[0][l], a[1][l]], &vw, a[4][l]);
            self.next[o + l] = tr.next_sample();
        }
    }

    /// The events of `rec` on lanes `o ..` (one vector).
    #[inline(always)]
    fn step<V: Lanes>(&mut self, rec: &ArcRecord, o: usize) {
        let b = &rec.before;
        let (t, duration) = (V::load(&self.t[o..]), V::splat(self.duration));
        let go = V::and(V::from_bits(b.live_bits >> o), t.lt(duration));
        if V::bits(go) == 0 {
            return;
        }
        let v = (V::load(&b.vel[0][o..]), V::load(&b.vel[1][o..]));
        let x = (V::load(&rec.chord[0][o..]), V::load(&rec.chord[1][o..]));
        let (time, arc) = arc_observables(v, x, V::splat(self.w));
        let end = t.add(time);
        // As `Lattice::unwrapped(s, 0.0)`, `world_velocity` and `Unwrapped::displacement_from`.
        let sign = V::load(&b.cell[2][o..]);
        let z = V::splat(0.0);
        let off = (
            sign.mul(V::load(&b.pos[0][o..]).add(z.mul(v.0))),
            sign.mul(V::load(&b.pos[1][o..]).add(z.mul(v.1))),
        );
        let di = V::load(&b.cell[0][o..]).sub(V::load(&self.origin[0][o..]));
        let dj = V::load(&b.cell[1][o..]).sub(V::load(&self.origin[1][o..]));
        let (ba, bb, bh) = (self.basis.a, self.basis.beta, self.basis.h);
        let r = (
            V::splat(ba)
                .mul(di.add(V::splat(bb).mul(dj)))
                .add(off.0.sub(V::load(&self.origin[2][o..]))),
            V::splat(bh)
                .mul(dj)
                .add(off.1.sub(V::load(&self.origin[3][o..]))),
        );
        let lim = V::select(end.lt(duration), end, duration);
        let sampled = V::and(go, lim.ge(V::load(&self.next[o..])));
        if V::bits(sampled) != 0 {
            let vw = (sign.mul(v.0), sign.mul(v.1));
            self.sample(o, V::bits(sampled), r, vw, end);
        }
        let c = (sign.mul(x.0), sign.mul(x.1));
        let area = V::load(&self.area[o..]);
        let moved = area.add(r.0.mul(c.1).sub(r.1.mul(c.0)).add(arc));
        V::select(go, moved, area).store(&mut self.area[o..]);
        V::select(go, end, t).store(&mut self.t[o..]);
        let hit = V::load(&b.code[o..]).lt(V::splat(CROSSING_CODE));
        let counted = V::and(V::and(go, hit), duration.ge(end));
        let done = V::load(&self.done[o..]);
        V::select(counted, done.add(V::splat(1.0)), done).store(&mut self.done[o..]);
        self.counted += u64::from(V::bits(counted).count_ones());
    }
}

impl LaneWork for Feed<'_> {
    #[inline(always)]
    fn run<V: Lanes>(&mut self) {
        for rec in self.ring {
            for o in (0..BLOCK).step_by(V::WIDTH) {
                self.step::<V>(rec, o);
            }
        }
    }
}
