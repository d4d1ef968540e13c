//! Per-event audit of long flights: each sampled jump of a run on the square lattice
//! ([`crate::scenes::long_flight::jump`]) is replayed from its exact `f64` pre-jump state against
//! an exact reference, and judged against the jump's own error model
//! (`proofs-notes/long-flights.md`, "The audit").
//!
//! The reference walks the flight column by column in exact integers: for every column the flight
//! crosses before the candidate's it computes D(k, l) of the row nearest the line and checks that
//! no disk is inside the window (a disk the search skipped), then checks that the candidate is the
//! row nearest the line in its column and inside the window up to the machine search's documented
//! widening. The entered edge follows from the exact sign of 2D − v_y + v_x, and the entry point
//! and the flight time are computed at the reference precision from the exact D. The walk costs a
//! few nanoseconds a column; the MPFR cell walk it stands for (about 7 µs a crossing) is checked
//! against it in `tests/numerics/long_flight_audit.rs`.

use std::ops::{AddAssign, SubAssign};

use rug::{Float, Integer};
use serde::{Deserialize, Serialize};

use super::error_model::UNIT_ROUNDOFF as U;
use super::log_histogram::LogHistogram;
use crate::kernel::flight::Flight;
use crate::kernel::vec2::Vec2;
use crate::scenes::long_flight::{Frame, Jump, Scale, jump, widening, window};

/// The verdict on one replayed jump.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct JumpCheck {
    /// Columns from the flight's to the candidate's (the flight's length in cells along its
    /// major axis).
    pub columns: u64,
    /// The first column before the candidate's with a disk inside the window W or met by the
    /// exact line (|D| < r|v|, at the reference precision): a skipped disk, outside the model.
    pub skipped_column: Option<u64>,
    /// The candidate's |D| over the window W (at most 1 up to the machine search's widening).
    pub candidate_over_window: f64,
    /// The candidate is the row nearest the line in its column.
    pub row_agrees: bool,
    /// The entered edge of the jump and of the exact line (0 right, 1 top, 2 left, 3 bottom).
    pub entered: [u8; 2],
    /// |t_f64 − t_ref| of the flight time to the entry point, and its bound.
    pub time_error: f64,
    /// Error-model bound on the time error.
    pub time_bound: f64,
    /// |x_f64 − x_ref| of the entry point along the entered edge, and its bound.
    pub position_error: f64,
    /// Error-model bound on the position error.
    pub position_bound: f64,
    /// The exact line passes the entered cell's corner within the rounding of the edge's
    /// choice: either edge is inside the model.
    pub ambiguous: bool,
    /// Everything within the model.
    pub in_model: bool,
}

/// Replays the jump the engine takes from the `f64` pre-jump state `f` (its cell's disk at the
/// origin, leaving through the edge it faces along its major axis) among disks of radius `r`,
/// with the reference at `bits` of precision, and judges it. Returns `None` where the flight
/// meets no disk (the engine stops there with an error of its own).
pub fn check_jump(f: &Flight<f64>, r: f64, bits: u32) -> Option<JumpCheck> {
    let j = jump(&f.pos, &f.vel, r)?;
    Some(judge(f, r, bits, &j))
}

/// The exact quantities of one jump in the turned frame, scaled by 2^s.
struct Exact {
    frame: Frame,
    x: f64,
    y: f64,
    vx: f64,
    vy: f64,
    w: f64,
    scale: Scale,
    a: Integer,
    m: Integer,
    /// ⌈max(W, r|v|(1 + 2u))·2^s⌉: a disk closer than that to the line must not be skipped.
    skip: Integer,
    p0: Integer,
}

impl Exact {
    fn of(f: &Flight<f64>, r: f64, bits: u32) -> Exact {
        let frame = Frame::of(&f.vel);
        let (x, y) = frame.to(f.pos.x, f.pos.y);
        let (vx, vy) = frame.to(f.vel.x, f.vel.y);
        let w = window(vx, vy, r);
        let scale = Scale::of(&[vx, vy, w], &[(x, vy), (y, vx)]);
        let p0 = scale.prod(y, vx) - scale.prod(x, vy);
        let wi = scale.int(w);
        // The exact line meets a disk iff |D| < r|v|: that threshold is the engine's window's
        // independent of how the window was computed.
        let nv = (Float::with_val(bits, vx).square() + Float::with_val(bits, vy).square()).sqrt();
        let met = (nv * r * (1.0 + f64::EPSILON)) << scale.bits;
        let met = met.ceil().to_integer().unwrap_or_default();
        let skip = if met > wi { met } else { wi.clone() };
        Exact {
            frame,
            x,
            y,
            vx,
            vy,
            w,
            a: scale.int(vy),
            m: scale.int(vx),
            skip,
            p0,
            scale,
        }
    }
}

fn judge(f: &Flight<f64>, r: f64, bits: u32, j: &Jump) -> JumpCheck {
    let e = Exact::of(f, r, bits);
    let (k, l) = e.frame.uncells(j.cells[0], j.cells[1]);
    let k = u64::try_from(k).unwrap_or(0);
    let walk = walk_columns(&e, k);
    let d = Float::with_val(bits, &walk.n) >> e.scale.bits;
    let d64 = d.to_f64();
    let pq = (e.y * e.vx).abs() + (e.x * e.vy).abs();
    // The machine search's widening, or the exact search's rounding of D to a double.
    let widened = e.w + widening(e.x, e.y, e.vx, e.vy, e.w).max(4.0 * U * e.w) + 4.0 * U * pq;
    let left_ref = {
        let c = Integer::from(&walk.n * 2u32) - &e.a + &e.m;
        c >= 0
    };
    let left = j.entered == e.frame.edge(true);
    // |d − D| of the search's D (`proofs-notes/long-flights.md`, "The audit").
    let e_d = U * (2.1 * d64.abs() + 3.1 * pq);
    let corner = (2.0 * d64 - e.vy + e.vx).abs();
    let corner_bound = 1.01 * (2.0 * e_d + U * (4.0 * d64.abs() + 2.0 * e.vy + e.vx));
    let entry = entry_errors(&e, j, left, &d, k, l, e_d);
    let mut c = JumpCheck {
        columns: k,
        skipped_column: walk.skipped,
        candidate_over_window: d64.abs() / e.w,
        row_agrees: walk.row == l,
        entered: [j.entered, e.frame.edge(left_ref)],
        time_error: entry.0,
        time_bound: entry.1,
        position_error: entry.2,
        position_bound: entry.3,
        ambiguous: left != left_ref && corner <= corner_bound,
        in_model: false,
    };
    c.in_model = k >= 1
        && c.skipped_column.is_none()
        && c.row_agrees
        && d64.abs() < widened
        && (left == left_ref || c.ambiguous)
        && c.time_error <= c.time_bound
        && c.position_error <= c.position_bound;
    c
}

/// (time error, time bound, position error, position bound) of the entry on the edge the jump
/// chose (`left` in the turned frame), the reference at the precision of `d`, the exact D.
fn entry_errors(
    e: &Exact,
    j: &Jump,
    left: bool,
    d: &Float,
    k: u64,
    l: i64,
    e_d: f64,
) -> (f64, f64, f64, f64) {
    let bits = d.prec();
    let fl = |x: f64| Float::with_val(bits, x);
    let (px, py) = e.frame.to(j.pos.x, j.pos.y);
    let d64 = d.to_f64();
    let (along, denominator, offset, t_ref) = if left {
        let ey = Float::with_val(bits, d - fl(0.5 * e.vy)) / fl(e.vx);
        let t = (fl(k as f64) - fl(0.5) - fl(e.x)) / fl(e.vx);
        (fl(py) - ey, e.vx, (d64 - 0.5 * e.vy).abs(), t)
    } else {
        let ex = -(Float::with_val(bits, d + fl(0.5 * e.vx)) / fl(e.vy));
        let t = (fl(l as f64) - fl(0.5) - fl(e.y)) / fl(e.vy);
        (fl(px) - ex, e.vy, (d64 + 0.5 * e.vx).abs(), t)
    };
    let position_error = along.to_f64().abs();
    let coordinate = if left { py } else { px };
    let position_bound =
        1.01 * ((e_d + U * offset) / denominator + U * coordinate.abs()) + f64::MIN_POSITIVE;
    let time_error = (t_ref - j.time).to_f64().abs();
    let time_bound = 2.02 * U * j.time.abs() + f64::MIN_POSITIVE;
    (time_error, time_bound, position_error, position_bound)
}

/// What the column walk found: the first column before the candidate's with a disk inside the
/// window, and the nearest row and its D·2^s at the candidate's column.
struct Walked {
    skipped: Option<u64>,
    row: i64,
    n: Integer,
}

/// Walks columns 1 to `last` of the line: at each, the row l nearest the line and
/// N = D(k, l)·2^s ∈ (−M/2, M/2] (N grows by A a column and drops by M a row, 0 ≤ A ≤ M).
/// Machine integers where every N, A and M fit with room (M < 2¹²⁵), else GMP's.
fn walk_columns(e: &Exact, last: u64) -> Walked {
    // Column 1: N = A + P₀ − l·M with l the nearest row.
    let n1 = Integer::from(&e.a + &e.p0);
    let (mut row, mut n) = n1.div_rem_floor(e.m.clone());
    let half = Integer::from(&e.m >> 1u32);
    if n > half {
        n -= &e.m;
        row += 1;
    }
    let row = row.to_i64().unwrap_or(i64::MAX);
    let fits = e.m.significant_bits() < 125 && e.skip < e.m;
    let (skipped, rows, n) = if fits {
        let i = |z: &Integer| z.to_i128().expect("below 2^125");
        let z = Columns {
            a: i(&e.a),
            m: i(&e.m),
            half: i(&half),
            w: i(&e.skip),
            neg_w: -i(&e.skip),
        };
        let (s, r, n) = z.walk(i(&n), last);
        (s, r, Integer::from(n))
    } else {
        let z = Columns {
            a: e.a.clone(),
            m: e.m.clone(),
            half,
            w: e.skip.clone(),
            neg_w: Integer::from(-&e.skip),
        };
        z.walk(n, last)
    };
    Walked {
        skipped,
        row: row.saturating_add(rows),
        n,
    }
}

/// The increments and thresholds of the column walk, in machine or GMP integers.
struct Columns<Z> {
    a: Z,
    m: Z,
    half: Z,
    w: Z,
    neg_w: Z,
}

impl<Z> Columns<Z>
where
    Z: PartialOrd + for<'a> AddAssign<&'a Z> + for<'a> SubAssign<&'a Z>,
{
    /// From N at column 1 to column `last`: (the first column before `last` inside the window,
    /// rows moved, N at `last`).
    fn walk(&self, mut n: Z, last: u64) -> (Option<u64>, i64, Z) {
        let (mut rows, mut skipped) = (0i64, None);
        for k in 1..=last {
            if k > 1 {
                n += &self.a;
                if n > self.half {
                    n -= &self.m;
                    rows += 1;
                }
            }
            if skipped.is_none() && k < last && n < self.w && n > self.neg_w {
                skipped = Some(k);
            }
        }
        (skipped, rows, n)
    }
}

/// Every jump audited: counts, the error ratios, and the worst and outside jumps with their
/// exact pre-jump states (mergeable across batches).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct JumpSummary {
    /// Jumps replayed.
    pub audited: u64,
    /// Jumps outside the model.
    pub outside: u64,
    /// Jumps whose entered edge was a tie within its rounding (inside the model).
    pub ambiguous: u64,
    /// Columns walked by the reference, in all.
    pub columns: u64,
    /// The longest jump, in columns.
    pub longest: u64,
    /// The candidate's |D| over the window.
    pub candidate_over_window: LogHistogram,
    /// Time error over its bound.
    pub time_error_over_bound: LogHistogram,
    /// Entry-point error over its bound.
    pub position_error_over_bound: LogHistogram,
    /// The worst jumps by the larger error ratio (at most 10).
    pub worst: Vec<AuditedJump>,
    /// Every jump outside the model (at most 1000 kept).
    pub outside_jumps: Vec<AuditedJump>,
}

/// A replayed jump with its exact `f64` pre-jump state.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct AuditedJump {
    /// Position and velocity (x, y, vx, vy) as IEEE bit patterns.
    pub state_bits: [u64; 4],
    /// The same as decimals.
    pub state: [f64; 4],
    /// The verdict.
    pub check: JumpCheck,
}

impl AuditedJump {
    /// The pre-jump state of `f` with its verdict.
    pub fn new(f: &Flight<f64>, check: &JumpCheck) -> AuditedJump {
        let s = [f.pos.x, f.pos.y, f.vel.x, f.vel.y];
        AuditedJump {
            state_bits: s.map(f64::to_bits),
            state: s,
            check: check.clone(),
        }
    }

    /// The pre-jump flight, exactly.
    pub fn flight(&self) -> Flight<f64> {
        let [x, y, vx, vy] = self.state_bits.map(f64::from_bits);
        Flight::new(Vec2::new(x, y), Vec2::new(vx, vy))
    }

    fn ratio(&self) -> f64 {
        worst_ratio(&self.check)
    }
}

fn worst_ratio(c: &JumpCheck) -> f64 {
    (c.time_error / c.time_bound).max(c.position_error / c.position_bound)
}

impl JumpSummary {
    /// Counts one replayed jump of the pre-jump flight `f`.
    pub fn add(&mut self, f: &Flight<f64>, c: &JumpCheck) {
        self.audited += 1;
        self.columns += c.columns;
        self.longest = self.longest.max(c.columns);
        self.candidate_over_window.add(c.candidate_over_window);
        self.time_error_over_bound.add(c.time_error / c.time_bound);
        self.position_error_over_bound
            .add(c.position_error / c.position_bound);
        self.ambiguous += u64::from(c.ambiguous);
        if !c.in_model {
            self.outside += 1;
            if self.outside_jumps.len() < 1000 {
                self.outside_jumps.push(AuditedJump::new(f, c));
            }
        }
        let r = worst_ratio(c);
        if self.worst.len() < 10 || r > self.worst.last().map_or(0.0, AuditedJump::ratio) {
            self.worst.push(AuditedJump::new(f, c));
            self.sort_worst();
        }
    }

    fn sort_worst(&mut self) {
        self.worst.sort_by(|a, b| b.ratio().total_cmp(&a.ratio()));
        self.worst.truncate(10);
    }

    /// Adds another summary.
    pub fn merge(&mut self, o: &JumpSummary) {
        self.audited += o.audited;
        self.outside += o.outside;
        self.ambiguous += o.ambiguous;
        self.columns += o.columns;
        self.longest = self.longest.max(o.longest);
        self.candidate_over_window.merge(&o.candidate_over_window);
        self.time_error_over_bound.merge(&o.time_error_over_bound);
        self.position_error_over_bound
            .merge(&o.position_error_over_bound);
        self.worst.extend(o.worst.iter().cloned());
        self.sort_worst();
        self.outside_jumps.extend(o.outside_jumps.iter().cloned());
        self.outside_jumps.truncate(1000);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::Scene;
    use crate::scenes::sampling::stream;
    use crate::scenes::square::SquareScene;

    /// Pre-jump states: from invariant-measure starts at radius `r`, the flight up to its first
    /// crossing of the edge it faces along its major axis.
    fn pre_jump_states(r: f64, n: u64) -> Vec<Flight<f64>> {
        let scene = SquareScene::new(r).unwrap();
        let lat = scene.lattice::<f64>(()).unwrap();
        (0..n)
            .filter_map(|b| {
                let mut s = scene.sample(&mut stream(35, b));
                for _ in 0..8 {
                    let ev = lat.next_event(&s)?;
                    if ev.kind
                        == crate::kernel::flight::EventKind::Crossing(major_edge(&s.flight.vel))
                    {
                        return Some(s.flight);
                    }
                    lat.apply(&mut s, &ev);
                }
                None
            })
            .collect()
    }

    use crate::scenes::long_flight::major_edge;

    /// Every jump of the engine is inside the model; each way of breaking it is caught: a
    /// candidate one column too far (a skipped disk), a flight time 8u too long, an entry point
    /// 64u along its edge, and a search run at 0.9r (disks at 0.9r ≤ |D| < r skipped).
    #[test]
    fn jumps_are_inside_the_model_and_broken_jumps_are_not() {
        let r = 0.01;
        let states = pre_jump_states(r, 400);
        assert!(states.len() > 350, "{}", states.len());
        let (mut shrunk_caught, u) = (0, f64::EPSILON / 2.0);
        for f in &states {
            let j = jump(&f.pos, &f.vel, r).unwrap();
            assert!(judge(f, r, 128, &j).in_model, "{f:?}");
            let frame = Frame::of(&f.vel);
            let (k, l) = frame.uncells(j.cells[0], j.cells[1]);
            let (ci, cj) = frame.cells(k + 1, l);
            let far = Jump {
                cells: [ci, cj],
                ..j.clone()
            };
            let c = judge(f, r, 128, &far);
            assert_eq!(c.skipped_column, Some(k as u64), "{f:?}");
            assert!(!c.in_model);
            let late = Jump {
                time: j.time * (1.0 + 8.0 * u),
                ..j.clone()
            };
            assert!(!judge(f, r, 128, &late).in_model, "{f:?}");
            let (a, b) = frame.to(j.pos.x, j.pos.y);
            let shift = if j.entered == frame.edge(true) {
                (a, b + 64.0 * u)
            } else {
                (a + 64.0 * u, b)
            };
            let (px, py) = frame.from(shift.0, shift.1);
            let moved = Jump {
                pos: Vec2::new(px, py),
                ..j.clone()
            };
            assert!(!judge(f, r, 128, &moved).in_model, "{f:?}");
            let shrunk = jump(&f.pos, &f.vel, 0.9 * r).unwrap();
            let c = judge(f, r, 128, &shrunk);
            if shrunk.cells != j.cells {
                assert!(c.skipped_column.is_some() && !c.in_model, "{f:?}");
                shrunk_caught += 1;
            }
        }
        // About a tenth of the first disks met lie at 0.9r ≤ |D| < r.
        assert!(shrunk_caught > 20, "{shrunk_caught}");
    }

    /// The long-flight fuzz target's first finding: a candidate 2·10⁻¹⁶ beyond the window W
    /// (|D|/W = 1 + 8.6·10⁻¹²), which the machine search may take (its window is up to 2g·2^−s
    /// wider, 6.7·10⁻¹⁶ here) but the audit's first bound (16ε(|y v_x| + |x v_y| + W) = 5·10⁻¹⁷)
    /// called outside the model.
    #[test]
    fn regression_a_candidate_within_the_searchs_widening_is_inside_the_model() {
        let f = Flight::new(
            Vec2::new(7.629510948348184e-6, -0.023430228122377328),
            Vec2::new(0.6183688865891823, 0.7858879819022906),
        );
        let c = check_jump(&f, 0.000023140675651833966, 128).expect("a disk ahead");
        assert!(c.candidate_over_window > 1.0, "{c:?}");
        assert!(c.in_model, "{c:?}");
    }
}
