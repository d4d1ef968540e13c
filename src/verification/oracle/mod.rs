//! Fuzzing oracle: decodes arbitrary bytes into valid (often degenerate) states of any scene's
//! cell and judges the `f64` kernel on them.
//!
//! Three entry points, shared by the cargo-fuzz targets in `fuzz/` and by `tests/numerics/fuzz_oracle.rs`:
//!
//! * [`collision_primitive`]: a leading byte selects the scene ([`SceneParams`]: the triangular
//!   gas at gap w or the square gas at radius r), then one of six families of states written
//!   against the cell description ([`ConvexCell`]) only — near-grazing impact parameters
//!   r(1 ∓ 2⁻ᵏ), starts r·2⁻ᵏ off a disk surface (moving in, out, tangentially), common tangents
//!   of two disks (or, in a one-disk cell, the tangents parallel to an edge: the corridor
//!   boundaries), rays through the points where an edge meets a circle, rays through a corner
//!   of the polygon, and arbitrary free states — each nudged by a few ulps; up to four
//!   successive events are replayed in MPFR ([`ORACLE_BITS`] bits) by [`check_event`] and must
//!   be inside the one-step error model ([`replay_events`], generic over the scene).
//! * [`scene_stepper`]: a lattice state (cell index up to ±10⁹, either orientation where the
//!   lattice has two, flight from the same families) stepped up to 4096 events in `f64`; after
//!   every event the invariants of `proofs-notes/energy.md`, `proofs-notes/no-missed-collision.md`
//!   and the unwrapping continuity of `tests/numerics/physics.rs` are checked ([`step_lattice`], generic
//!   over the scene).
//!
//! * [`arc_kernel`]: the same lattice states flown on arcs in a decoded magnetic field, MPFR-53
//!   against `f64` bit for bit and the post-event invariants after every event.
//! * [`thermostat_kernel`]: the same lattice states flown under a Gaussian-thermostatted field
//!   E ∈ [10⁻³, 10] at any angle: MPFR-53 against `f64` bit for bit, no contact missed along the
//!   flight (the exact flight sampled at 128 bits), and the post-event invariants.
//! * [`decided_in_balls`]: the same decoded starts' events as the MPFR kernel decides them in
//!   `f64` balls, against its full comparison, bit for bit (`proofs-notes/certified-filter.md`).
//!
//! Decoding never fails: missing bytes read as zero, every byte pattern maps to a valid state
//! (inside the closed cell, outside the open disks and with |v| = 1, each up to the rounding
//! bounds [`VALID_DISK`], [`VALID_EDGE`], [`VALID_SPEED`]), and the decoded state is itself
//! re-validated, so a decoder bug is reported rather than blamed on the kernel. Layout of the
//! bytes and the bounds: `proofs-notes/fuzzing.md`.

use std::fmt;

use rug::Float;
use rug::float::Constant;

use crate::kernel::cell::{CellKernel, ConvexCell};
use crate::kernel::trap::Trap;
use crate::kernel::vec2::Vec2;
use crate::kernel::{flight::Event, flight::EventKind, flight::Flight};
use crate::numbers::real::Real;
use crate::scenes::Scene;
use crate::scenes::lattice::{CellIndex, LatticeState};
use crate::scenes::square::SquareScene;
use crate::scenes::triangular::TriangularScene;
use crate::scenes::triangular::geometry::Geometry;
use crate::verification::error_model::{ENERGY_BAND_U, POST_EVENT_U, UNIT_ROUNDOFF, UNWRAP_EPS};
use crate::verification::replay::check_event;

mod arcs;
mod bytes;
mod curved_walk;
mod geo;
mod long_flight;
mod long_flight_triangular;
mod starts;
mod stepper;
mod thermostat;

use bytes::*;
use geo::*;

// The decoders and the lattice stepper keep their one public path, `verification::oracle::…`
// (their modules are private).
pub use arcs::{
    ARC_ENERGY_BAND_U, MAX_ARC_STEPS, NORMAL_FLOOR, arc_energy_band_of, arc_kernel, decode_field,
    fly, in_domain,
};
pub use long_flight::{LongFlightReport, MAX_COLUMNS, long_flight};
pub use long_flight_triangular::{MAX_SPAN, TriangularFlightReport, long_flight_triangular};
pub use starts::{decode_primitive, decode_scene};
pub use stepper::step_lattice;
pub use thermostat::{
    FLIGHT_BITS, MAX_THERMO_STEPS, SAMPLES, decode_electric, fly_thermostat, thermostat_kernel,
};

/// Precision of the MPFR replay and of the decoder's geometric constructions.
pub const ORACLE_BITS: u32 = 192;

/// Unit roundoff of `f64`.
const U: f64 = UNIT_ROUNDOFF;

/// A decoded start may lie inside a disk by at most this much in (|p − c|² − r²)/r²: the same
/// ε ≤ 28u that the kernel's own rounded contact points reach (`proofs-notes/energy.md`).
pub const VALID_DISK: f64 = 28.0 * U;
/// A decoded start may lie outside an edge by at most `VALID_EDGE · extent` (signed distance;
/// extent = [`ConvexCell::extent`], the scale of the coordinates' rounding).
pub const VALID_EDGE: f64 = 16.0 * U;
/// A decoded velocity has ||v|² − 1| ≤ `VALID_SPEED` (rounding plus ≤ 4 ulps per component).
pub const VALID_SPEED: f64 = 32.0 * U;

/// Largest number of events stepped by [`scene_stepper`].
pub const MAX_STEPS: u32 = 4096;

/// Number of sample angles of the walk that finds a disk's free arcs (1° apart: far finer than
/// any arc of the two scenes, which are ≥ 60°).
const ARC_SAMPLES: usize = 360;
/// Bisection steps refining each end of a free arc in `f64` (to the last ulp of the angle).
const ARC_REFINE_STEPS: u32 = 64;
/// Tolerance of the high-precision freeness test for constructed points (points built on an
/// edge or a tangent line are free up to the 192-bit rounding of the construction).
const HP_TINY_EXP: f64 = -100.0;

/// Largest ||v|² − 1| allowed after a collision in `cell`, in units of u: 128u·(1 + extent/r).
/// The contact point's absolute rounding error is of order u·extent, relative u·extent/r to
/// |n| = r; for the square cell (extent ½) this is the 128u·(1 + 1/(2r)) of `tests/numerics/square.rs`,
/// for the triangular trap (r = 1, extent a < 2.31) at most ≈ 424u, looser than the 128u of
/// `energy.md` — the reports' `worst_energy_u` shows how much of the band is used.
pub fn energy_band<T: Real>(cell: &ConvexCell<T>) -> f64 {
    ENERGY_BAND_U * (1.0 + cell.extent() / cell.smallest_radius())
}

/// The diameter of the cell polygon (largest distance between two corners).
pub fn diameter<T: Real>(cell: &ConvexCell<T>) -> f64 {
    let c: Vec<[f64; 2]> = cell.corners.iter().map(|p| p.to_f64()).collect();
    c.iter()
        .flat_map(|p| c.iter().map(move |q| (p[0] - q[0]).hypot(p[1] - q[1])))
        .fold(0.0, f64::max)
}

/// The scene a decoded input runs in (selected by the leading byte).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SceneParams {
    /// The triangular Lorentz gas at gap w ∈ (0, 2) (scene byte even; beyond w∞ an infinite horizon).
    Triangular {
        /// The gap.
        w: f64,
    },
    /// The square Lorentz gas at radius r ∈ (0, ½) (scene byte odd).
    Square {
        /// The disk radius.
        r: f64,
    },
}

impl SceneParams {
    /// The scene's description, as [`Scene::label`].
    pub fn label(&self) -> String {
        match *self {
            SceneParams::Triangular { w } => format!("triangular w={w:e}"),
            SceneParams::Square { r } => format!("square r={r:e}"),
        }
    }
}

impl fmt::Display for SceneParams {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.label())
    }
}

/// The six families of decoded states, written against the cell description.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PrimitiveCase {
    /// Aimed at disk `disk` with impact parameter b = r(1 − 2⁻ᵏ) (or r(1 + 2⁻ᵏ) if `above`).
    Impact {
        /// Disk aimed at.
        disk: u8,
        /// Exponent k, 1..=52.
        k: u8,
        /// b = r(1 + 2⁻ᵏ) (a near miss) instead of r(1 − 2⁻ᵏ).
        above: bool,
    },
    /// Start at distance r·2⁻ᵏ from the surface of disk `disk`, at an angle on one of the
    /// disk's free arcs inside the cell.
    NearSurface {
        /// Disk.
        disk: u8,
        /// Exponent k, 1..=60 (beyond 53 the start rounds onto the surface).
        k: u8,
        /// 0 moving in, 1 moving out, 2 tangential.
        motion: u8,
        /// The disk is excluded (a post-collision state); only when not moving in.
        excluded: bool,
    },
    /// On a common tangent of two disks of the cell; in a one-disk cell, on a tangent of the
    /// disk parallel to an edge (a corridor boundary).
    DoubleTangent {
        /// With two or more disks: the pair of disks ((pair + 1) mod n, (pair + 2) mod n) (for
        /// the triangular trap, the endpoint disks of edge `pair`); with one disk: the edge the
        /// tangent is parallel to.
        pair: u8,
        /// With two or more disks: 0 the outer tangent on the cell's side (at distance r from
        /// the centre line), 1, 2 the two inner tangents through the midpoint; with one disk:
        /// 0 the tangent on the side of the edge's normal, 1 the opposite one.
        line: u8,
    },
    /// Through a point where edge `edge` meets a disk's circle inside the cell.
    GapPoint {
        /// Edge.
        edge: u8,
        /// Which of the edge's circle points, in counter-clockwise order along the edge.
        point: u8,
        /// Start at the point itself (else aimed at it from a free point).
        at_point: bool,
    },
    /// Through a corner of the cell polygon, where two edges meet.
    Corner {
        /// Corner (index into [`ConvexCell::corners`]).
        corner: u8,
        /// 0 start at the corner (if free) in any direction; 1 aimed at the corner from a free
        /// point; 2 start at the corner (if free) moving along one of its two edges.
        mode: u8,
    },
    /// A free point in the cell with a unit velocity.
    Arbitrary,
}

/// A decoded single-cell state.
#[derive(Debug, Clone, PartialEq)]
pub struct PrimitiveInput {
    /// The scene.
    pub scene: SceneParams,
    /// Which family (after fall-backs: a family whose construction fails decodes as
    /// [`PrimitiveCase::Arbitrary`]).
    pub case: PrimitiveCase,
    /// The start, in the cell's frame.
    pub flight: Flight<f64>,
    /// Number of successive events to replay (1..=4).
    pub events: u8,
}

/// A decoded lattice run.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneInput {
    /// Scene, start flight and family as for the primitive target.
    pub primitive: PrimitiveInput,
    /// The cell the start is in.
    pub cell: CellIndex,
    /// Number of events to step (1..=[`MAX_STEPS`]).
    pub steps: u32,
}

impl SceneInput {
    /// The decoded family and the lattice state the oracles fly from.
    pub fn start(&self) -> (Option<PrimitiveCase>, LatticeState<f64>) {
        let state = LatticeState {
            cell: self.cell,
            flight: self.primitive.flight.clone(),
        };
        (Some(self.primitive.case), state)
    }
}

/// What an oracle run checked.
#[derive(Debug, Clone, PartialEq)]
pub struct OracleReport {
    /// The decoded family (`None` for a hand-made state).
    pub case: Option<PrimitiveCase>,
    /// The scene.
    pub scene: String,
    /// Events checked.
    pub events: u64,
    /// Of which collisions.
    pub collisions: u64,
    /// Of which crossings.
    pub crossings: u64,
    /// Events the MPFR replay called ambiguous (primitive target only).
    pub ambiguous: u64,
    /// Largest time error / time bound over the replayed events (primitive target only).
    pub worst_time_ratio: f64,
    /// Largest ||v|² − 1| after a collision, in units of u (scene target only).
    pub worst_energy_u: f64,
}

impl OracleReport {
    fn new(case: Option<PrimitiveCase>, scene: String) -> Self {
        OracleReport {
            case,
            scene,
            events: 0,
            collisions: 0,
            crossings: 0,
            ambiguous: 0,
            worst_time_ratio: 0.0,
            worst_energy_u: 0.0,
        }
    }
}

/// Why an oracle run failed.
#[derive(Debug, Clone, PartialEq)]
pub struct OracleFailure {
    /// The decoded family.
    pub case: Option<PrimitiveCase>,
    /// The scene.
    pub scene: String,
    /// Index of the event that failed (0-based; `None` for a decoding failure).
    pub event: Option<u64>,
    /// What was violated.
    pub reason: String,
    /// The state before the failing event (Debug form).
    pub state: String,
}

impl OracleFailure {
    /// The failure of `case` on `scene` at `event` (`None`: before any event), for `reason`,
    /// from `state` (its Debug form).
    pub(crate) fn new(
        case: Option<PrimitiveCase>,
        scene: &str,
        event: Option<u64>,
        reason: String,
        state: String,
    ) -> Self {
        OracleFailure {
            case,
            scene: scene.to_string(),
            event,
            reason,
            state,
        }
    }
}

impl fmt::Display for OracleFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "oracle failure ({}, {:?}, event {:?}): {}; state {}",
            self.scene, self.case, self.event, self.reason, self.state
        )
    }
}

impl std::error::Error for OracleFailure {}

/// Replays up to `events` successive events of the `f64` flight `start` in the cell of `scene`
/// against the one-step error model by MPFR replay ([`check_event`] at [`ORACLE_BITS`]): the
/// replay must be `in_model`, the f64 event time finite and ≥ 0, no error or bound NaN, the
/// post-event state finite. `case` only labels the report.
///
/// # Errors
/// The first violation, with the state before the failing event.
pub fn replay_events<S: Scene>(
    scene: &S,
    case: Option<PrimitiveCase>,
    start: &Flight<f64>,
    events: u32,
) -> Result<OracleReport, OracleFailure> {
    let label = scene.label();
    let setup =
        |reason: String| OracleFailure::new(case, &label, None, reason, format!("{start:?}"));
    let k64 = scene.kernel::<f64>(()).map_err(|e| setup(e.to_string()))?;
    let kref = scene
        .kernel::<Float>(ORACLE_BITS)
        .map_err(|e| setup(e.to_string()))?;
    let mut f = start.clone();
    let mut rep = OracleReport::new(case, label.clone());
    for n in 0..events as u64 {
        let before = f.clone();
        let fail = |reason: String| {
            OracleFailure::new(case, &label, Some(n), reason, format!("{before:?}"))
        };
        let c = check_event(&k64, &kref, &f).map_err(|e| fail(format!("check_event: {e}")))?;
        let nums = [
            ("time_error", c.time_error),
            ("time_bound", c.time_bound),
            ("position_error", c.position_error),
            ("position_bound", c.position_bound),
            ("velocity_error", c.velocity_error),
            ("velocity_bound", c.velocity_bound),
        ];
        if let Some((name, x)) = nums.iter().find(|(_, x)| x.is_nan()) {
            return Err(fail(format!("{name} is NaN ({x}): {c:?}")));
        }
        if !c.in_model {
            return Err(fail(format!("event outside the error model: {c:?}")));
        }
        let ev: Event<f64> = k64
            .next_event(&f)
            .ok_or_else(|| fail("no next event".into()))?;
        if !(ev.time.is_finite() && ev.time >= 0.0) {
            return Err(fail(format!("bad f64 event time {:e}", ev.time)));
        }
        if c.kind_f64 == c.kind_ref && c.time_bound > 0.0 && c.time_bound.is_finite() {
            rep.worst_time_ratio = rep.worst_time_ratio.max(c.time_error / c.time_bound);
        }
        rep.ambiguous += c.ambiguous as u64;
        k64.apply(&mut f, &ev);
        if ![f.pos.x, f.pos.y, f.vel.x, f.vel.y]
            .iter()
            .all(|x| x.is_finite())
        {
            return Err(fail(format!("non-finite state after {:?}: {f:?}", ev.kind)));
        }
        rep.events += 1;
        match ev.kind {
            EventKind::Collision(_) => rep.collisions += 1,
            EventKind::Crossing(_) => rep.crossings += 1,
        }
    }
    Ok(rep)
}

/// Judges up to four successive events of a decoded single-cell state (any scene) with
/// [`replay_events`].
///
/// # Errors
/// A decoding failure or the first violation, with the state before the failing event.
pub fn collision_primitive(data: &[u8]) -> Result<OracleReport, OracleFailure> {
    let input = decode_primitive(data)?;
    let (case, events) = (Some(input.case), input.events as u32);
    match input.scene {
        SceneParams::Triangular { w } => {
            replay_events(&triangular(w)?, case, &input.flight, events)
        }
        SceneParams::Square { r } => replay_events(&square(r)?, case, &input.flight, events),
    }
}

/// The events of a decoded start ([`decode_primitive`]: grazing impacts, near-surface starts,
/// double tangents, rim crossings, corners) as the MPFR kernel decides them in `f64` balls
/// ([`crate::kernel::certified`]), against the full comparison, at 53 and at [`ORACLE_BITS`]
/// bits: wherever the balls decide, the event and its time must be the full comparison's, bit
/// for bit. Returns the number of events the balls decided (square-scene inputs: 0, the square
/// cell compares every candidate).
///
/// # Errors
/// The first event the balls decide differently, with the state before it.
pub fn decided_in_balls(data: &[u8]) -> Result<u64, OracleFailure> {
    let input = decode_primitive(data)?;
    let SceneParams::Triangular { w } = input.scene else {
        return Ok(0);
    };
    let mut decided = 0;
    for bits in [53, ORACLE_BITS] {
        let scene = format!("triangular w={w:e} at {bits} bits");
        let fail = |event: Option<u64>, reason: String, state: String| {
            OracleFailure::new(Some(input.case), &scene, event, reason, state)
        };
        let trap = Trap::new(Float::with_val(bits, w))
            .map_err(|e| fail(None, e.to_string(), String::new()))?;
        let mut f = Flight::<Float>::convert_from_f64(bits, &input.flight);
        for n in 0..u64::from(input.events) {
            let want = trap.next_event_compared(&f);
            if let Some(ev) = trap.next_event_decided(&f) {
                if Some(&ev) != want.as_ref() {
                    let why = format!("balls decided {ev:?}, the full comparison {want:?}");
                    return Err(fail(Some(n), why, format!("{f:?}")));
                }
                decided += 1;
            }
            match want {
                Some(ev) => trap.apply(&mut f, &ev),
                None => break,
            }
        }
    }
    Ok(decided)
}

fn triangular(w: f64) -> Result<TriangularScene, OracleFailure> {
    TriangularScene::new(w).map_err(|e| scene_failure(format!("triangular w={w:e}: {e}")))
}

fn square(r: f64) -> Result<SquareScene, OracleFailure> {
    SquareScene::new(r).map_err(|e| scene_failure(format!("square r={r:e}: {e}")))
}

fn scene_failure(reason: String) -> OracleFailure {
    OracleFailure {
        case: None,
        scene: "undecodable".into(),
        event: None,
        reason,
        state: String::new(),
    }
}

/// Steps a decoded lattice state (any scene) with [`step_lattice`].
///
/// # Errors
/// A decoding failure or the first violation, with the state before the failing event.
pub fn scene_stepper(data: &[u8]) -> Result<OracleReport, OracleFailure> {
    let input = decode_scene(data)?;
    let (case, start) = input.start();
    match input.primitive.scene {
        SceneParams::Triangular { w } => step_lattice(&triangular(w)?, case, &start, input.steps),
        SceneParams::Square { r } => step_lattice(&square(r)?, case, &start, input.steps),
    }
}

/// The `f64` event and the MPFR-53 one of one step: both (`Some`), neither (`None`: the flight
/// ends), or a refusal naming them where only one of the two exists.
fn both<E: std::fmt::Debug, F: std::fmt::Debug>(
    ev: Option<E>,
    ev53: Option<F>,
) -> Result<Option<(E, F)>, String> {
    match (ev, ev53) {
        (None, None) => Ok(None),
        (Some(e), Some(e53)) => Ok(Some((e, e53))),
        (e, e53) => Err(format!("f64 event {e:?}, MPFR-53 event {e53:?}")),
    }
}

/// Refuses a non-finite flight after the event `kind`.
fn finite_after(
    fl: &crate::kernel::flight::Flight<f64>,
    kind: crate::kernel::flight::EventKind,
) -> Result<(), String> {
    if [fl.pos.x, fl.pos.y, fl.vel.x, fl.vel.y]
        .iter()
        .all(|x| x.is_finite())
    {
        Ok(())
    } else {
        Err(format!("non-finite state after {kind:?}: {fl:?}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_input_decodes_and_passes() {
        assert!(collision_primitive(&[]).is_ok());
        assert!(scene_stepper(&[]).is_ok());
        assert!(collision_primitive(&[1]).is_ok());
    }

    #[test]
    fn nudge_moves_by_ulps() {
        assert_eq!(nudge(1.0, 1), 1.0 + f64::EPSILON);
        assert_eq!(nudge(1.0, -2), 1.0 - f64::EPSILON);
        assert_eq!(nudge(0.0, 1), f64::from_bits(1));
        assert_eq!(nudge(-0.5, 0), -0.5);
    }

    #[test]
    fn w_is_below_w_inf_but_in_mode_1_beyond_it() {
        let wi = Geometry::<Float>::w_inf(ORACLE_BITS);
        assert!(hp(w_max()) < wi && hp(w_min_open()) > wi);
        for mode in 0..4u8 {
            for n in [0u32, 1, 12345, u32::MAX] {
                let b = [&[mode][..], &n.to_le_bytes()[..]].concat();
                let w = decode_w(&mut Bytes::new(&b));
                if mode == 1 {
                    assert!(hp(w) > wi && w < 2.0, "mode 1 n {n}: w = {w:e}");
                } else {
                    assert!(w > 0.0 && hp(w) < wi, "mode {mode} n {n}: w = {w:e}");
                }
            }
        }
    }

    #[test]
    fn r_stays_inside_zero_half() {
        for mode in 0..4u8 {
            for n in [0u32, 1, 51, 12345, u32::MAX] {
                let b = [&[mode][..], &n.to_le_bytes()[..]].concat();
                let r = decode_r(&mut Bytes::new(&b));
                assert!(r > 0.0 && r < 0.5, "mode {mode} n {n}: r = {r:e}");
            }
        }
    }

    #[test]
    fn free_arcs_are_the_trap_sector_and_the_whole_square_circle() {
        let tri = Geo::new(&TriangularScene::new(0.1).unwrap()).unwrap();
        for m in 0..3 {
            let arcs = tri.free_arcs(m);
            assert_eq!(arcs.len(), 1, "disk {m}: {arcs:?}");
            let (lo, hi) = arcs[0];
            let base = std::f64::consts::TAU * m as f64 / 3.0;
            let third = std::f64::consts::FRAC_PI_3;
            assert!(
                (hi - lo - third).abs() < 1e-14,
                "disk {m}: width {}",
                hi - lo
            );
            let lo = lo.rem_euclid(std::f64::consts::TAU);
            let off = (lo - base)
                .abs()
                .min((lo - base - std::f64::consts::TAU).abs());
            assert!(off < 1e-14, "disk {m}: lo {lo} base {base}");
        }
        let sq = Geo::new(&SquareScene::new(0.25).unwrap()).unwrap();
        assert_eq!(sq.free_arcs(0), vec![(0.0, std::f64::consts::TAU)]);
    }
}
