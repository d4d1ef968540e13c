//! The batches of a run in a field on the SIMD arc engine ([`crate::engine::arcs::ArcBlock`]):
//! up to [`BLOCK`](crate::engine::simd::BLOCK) batches fly in the lanes of one block, and every event a lane records is fed
//! to that batch's [`Track`] with the very operations of the scalar driver ([`track::batch`]),
//! so each batch has the scalar kernel's bits (`tests/analyses/field.rs`).
//!
//! A lane runs on a few events past its batch's duration before it is retired; those events are
//! not observed, and a lane that loses its next event there (a measure-zero creeping slide) is
//! retired too, where the scalar driver would never have flown it.

use super::track::{self, Batch, LOOK_EVERY, Setup, Track, world_velocity};
use crate::Error;
use crate::engine::SimdPath;
use crate::engine::arcs::{ArcBlock, ArcRecord};
use crate::engine::options::StopFlag;
use crate::engine::parallel::par_lane_blocks;
use crate::scenes::Scene;
use crate::scenes::magnetic::{ArcStep, no_next_event};
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
            let counted = observe(su, ring, &mut tracks, lanes);
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
) -> u64 {
    let (lat, w) = (su.lattice, su.field.0);
    let mut counted = 0;
    for rec in ring {
        for (l, t) in tracks.iter_mut().enumerate() {
            if !t.running() {
                continue;
            }
            let Some((before, ev)) = rec.event(l) else {
                continue;
            };
            let (v, sign) = (&before.flight.vel, before.cell.sign());
            let step = ArcStep::new(ev.kind, v, &ev.chord, sign, w);
            let here = lat.unwrapped(&before, 0.0);
            counted += u64::from(t.event(&here, &world_velocity(&before), &step));
            if !t.running() {
                lanes.retire(l);
            }
        }
    }
    counted
}
