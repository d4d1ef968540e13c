//! The arc engine's winner-only floor: the engine fed, step by step, the event each lane makes
//! (its code, read from a tape the engine itself recorded) computes only that disk's contact and
//! that edge's exit — by the full step's own operations, on constants selected lane by lane —
//! instead of every candidate's and their order. It makes the full engine's events bit for bit
//! (checked on every run), so its time is what no way of choosing the next event in advance can
//! beat with this kernel's arithmetic. `lorentz bench --field B --oracle-floor` measures it beside
//! the full engine on the CPU at hand (`docs/guide/field.md`, "Speed").

use std::time::Instant;

use super::contacts::{disk, edge};
use super::order::{Cand, blend};
use super::{
    ArcBlock, ArcL, ArcLanes, ArcRecord, Consts, Line, Loaded, Mode, dispatch, no_next_event, step,
};
use crate::Error;
use crate::engine::SimdPath;
use crate::engine::observe::CROSSING_CODE;
use crate::engine::simd::BLOCK;
use crate::kernel::cell::ConvexCell;
use crate::numbers::lanes::Lanes;

/// Steps recorded per call of the engine while a tape is made.
const RING: usize = 64;

/// The candidate each lane's code names (disk m, or [`CROSSING_CODE`] + edge k), computed as
/// [`super::choose`] computes it; no lane is lost (the tape was recorded without a loss).
#[inline(always)]
pub(super) fn choose<V: Lanes>(
    c: &Consts<V>,
    a: &ArcL<V>,
    s: &Loaded<V>,
    code: V,
) -> (Cand<V>, V, V::Mask) {
    let (dc, _) = disk(c, a, &c.cell.disk(code), s.p, s.ed.eq(code));
    let k = code.sub(V::splat(CROSSING_CODE));
    let l0 = &c.cell.edges[0].line;
    let mut l = Line {
        nx: l0.nx,
        ny: l0.ny,
        off: l0.off,
    };
    for (j, e) in c.cell.edges.iter().enumerate().skip(1) {
        let here = k.eq(V::splat(j as f64));
        l.nx = V::select(here, e.line.nx, l.nx);
        l.ny = V::select(here, e.line.ny, l.ny);
        l.off = V::select(here, e.line.off, l.off);
    }
    let ec = edge(c, a, &l, s.p, s.ee.eq(k));
    let hit = code.lt(V::splat(CROSSING_CODE));
    let best = Cand {
        x: V::select(hit, dc.x, ec.x),
        y: V::select(hit, dc.y, ec.y),
        frame: blend::<V>(hit, dc.frame, ec.frame),
        has: blend::<V>(hit, dc.has, ec.has),
        turning: blend::<V>(hit, dc.turning, ec.turning),
        half: blend::<V>(hit, dc.half, ec.half),
        near: blend::<V>(hit, dc.near, ec.near),
        len: V::select(hit, dc.len, ec.len),
    };
    (best, code, V::from_bits(0))
}

/// One step per entry of `tape`, each lane's winner read from it.
#[inline(always)]
pub(super) fn steps<V: Lanes>(
    c: &Consts<V>,
    st: &mut ArcLanes,
    tape: &[[f64; BLOCK]],
) -> Option<usize> {
    for codes in tape {
        let (mut live, mut o) = (0u64, 0);
        while o < BLOCK {
            live |= step::<V>(c, st, o, None, Some(codes)).1;
            o += V::WIDTH;
        }
        if live == 0 {
            break;
        }
    }
    None
}

/// The events of a block of trajectories as the full arc engine chose them, step by step, with
/// the lanes they started from.
#[derive(Debug, Clone)]
pub struct WinnerTape {
    path: SimdPath,
    cell: ConvexCell<f64>,
    w: f64,
    start: ArcLanes,
    codes: Vec<[f64; BLOCK]>,
    collisions: f64,
    events: f64,
}

/// The full engine and the engine fed its own winners, each timed over one tape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OracleTiming {
    /// Seconds of the full engine.
    pub full: f64,
    /// Seconds of the engine fed the tape's winners.
    pub oracle: f64,
}

impl WinnerTape {
    /// Records the next `steps` events of every trajectory of `block` (left where it is).
    ///
    /// # Errors
    /// A trajectory with no next event.
    pub fn record(block: &ArcBlock, steps: usize) -> Result<Self, Error> {
        let (path, cell, w) = (block.path, &block.cell, block.w);
        let start = block.st.clone();
        let mut b = block.clone();
        let mut ring = vec![ArcRecord::default(); RING];
        let mut codes = Vec::with_capacity(steps);
        while codes.len() < steps {
            let n = (steps - codes.len()).min(RING);
            if let Some(l) = b.advance(&mut ring[..n]) {
                return Err(no_next_event(l, &b.state(l)));
            }
            codes.extend(ring[..n].iter().map(|r| r.before.code));
        }
        let end = &b.st;
        // Counts since the start (a block that has run before has counted its earlier events).
        let count = |x: &ArcLanes| -> (f64, f64) {
            let c: f64 = x.collisions.iter().sum();
            (c, c + x.crossings.iter().sum::<f64>())
        };
        let ((c1, e1), (c0, e0)) = (count(end), count(&start));
        Ok(WinnerTape {
            path,
            cell: cell.clone(),
            w,
            codes,
            collisions: c1 - c0,
            events: e1 - e0,
            start,
        })
    }

    /// Steps on the tape.
    pub fn steps(&self) -> usize {
        self.codes.len()
    }

    /// Collisions over the tape (all lanes).
    pub fn collisions(&self) -> f64 {
        self.collisions
    }

    /// Events (collisions and crossings) over the tape (all lanes).
    pub fn events(&self) -> f64 {
        self.events
    }

    /// Runs the tape's steps from its start on the full engine, then on the engine fed the
    /// tape's winners, timing each.
    ///
    /// # Errors
    /// The fed engine ending anywhere but where the full engine ends, bit for bit (a tape that
    /// is not the engine's own), or a lane losing its next event.
    pub fn time(&self) -> Result<OracleTiming, Error> {
        let (path, cell, w) = (self.path, &self.cell, self.w);
        let mut full = self.start.clone();
        let t = Instant::now();
        let lost = dispatch(path, cell, w, &mut full, self.steps() as u64, Mode::Free);
        let full_s = t.elapsed().as_secs_f64();
        if let Some(l) = lost {
            return Err(no_next_event(l, &full.lanes.state(l)));
        }
        let mut fed = self.start.clone();
        let t = Instant::now();
        dispatch(path, cell, w, &mut fed, 0, Mode::Oracle(&self.codes));
        let oracle_s = t.elapsed().as_secs_f64();
        if !same_bits(&full, &fed) {
            return Err(Error::Failed(
                "the arc engine fed its winners left the full engine's trajectory: the tape is not this engine's own".into(),
            ));
        }
        Ok(OracleTiming {
            full: full_s,
            oracle: oracle_s,
        })
    }
}

/// `true` where two blocks of lanes hold the same bits: states, exclusions, cells and counts.
fn same_bits(a: &ArcLanes, b: &ArcLanes) -> bool {
    let bits = |x: &ArcLanes| -> Vec<u64> {
        let l = &x.lanes;
        [
            l.pos[0],
            l.pos[1],
            l.vel[0],
            l.vel[1],
            l.excluded[0],
            l.excluded[1],
        ]
        .iter()
        .chain(&l.cell)
        .chain([&x.collisions, &x.crossings])
        .flatten()
        .map(|v| v.to_bits())
        .collect()
    };
    bits(a) == bits(b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::trap::Trap;
    use crate::scenes::sampling::stream;
    use crate::scenes::triangular::equilibrium_state;

    /// A block of `lanes` equilibrium starts (seed `seed`) at gap `w` in the field `b`.
    fn block(w: f64, b: f64, lanes: usize, seed: u64) -> ArcBlock {
        let trap = Trap::<f64>::new(w).unwrap();
        let mut rng = stream(seed, 0);
        let states: Vec<_> = (0..lanes)
            .map(|_| {
                let mut s = equilibrium_state(&trap, &mut rng);
                s.flight.normalise_speed();
                s
            })
            .collect();
        ArcBlock::new(SimdPath::best(), trap.cell(), b, &states).unwrap()
    }

    fn tape(w: f64, b: f64, lanes: usize) -> WinnerTape {
        WinnerTape::record(&block(w, b, lanes, 5), 3000).unwrap()
    }

    #[test]
    fn the_engine_fed_its_own_winners_makes_the_full_engines_events() {
        for (w, b, lanes) in [(0.1, 1.0, 16), (0.3, -0.37, 11), (0.05, 7.5, 16)] {
            let t = tape(w, b, lanes);
            assert_eq!(t.steps(), 3000);
            // Every lane makes an event per step.
            assert_eq!(t.events(), (3000 * lanes) as f64, "w = {w}, B = {b}");
            assert!(t.collisions() > 0.5 * t.events(), "w = {w}, B = {b}");
            t.time().unwrap();
        }
    }

    #[test]
    fn a_tape_counts_only_its_own_events() {
        let mut block = block(0.1, 1.0, 16, 6);
        assert!(
            block
                .advance(&mut vec![ArcRecord::default(); 100])
                .is_none()
        );
        let t = WinnerTape::record(&block, 500).unwrap();
        assert_eq!(t.events(), 16.0 * 500.0);
        t.time().unwrap();
    }

    #[test]
    fn a_tape_that_is_not_the_engines_own_is_refused() {
        let mut t = tape(0.1, 1.0, 16);
        // One lane told, at one step, that it crosses an edge where it hits a disk (or the
        // other way round): the fed engine leaves the full engine's trajectory.
        let k = t.codes[1000][3];
        t.codes[1000][3] = if k < CROSSING_CODE {
            CROSSING_CODE
        } else {
            0.0
        };
        let e = t.time().unwrap_err();
        assert!(e.to_string().contains("not this engine's own"), "{e}");
    }
}
