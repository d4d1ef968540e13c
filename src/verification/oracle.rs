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
//! * [`decided_in_balls`]: the same decoded starts' events as the MPFR kernel decides them in
//!   `f64` balls, against its full comparison, bit for bit (`proofs-notes/certified-filter.md`).
//!
//! Decoding never fails: missing bytes read as zero, every byte pattern maps to a valid state
//! (inside the closed cell, outside the open disks and with |v| = 1, each up to the rounding
//! bounds [`VALID_DISK`], [`VALID_EDGE`], [`VALID_SPEED`]), and the decoded state is itself
//! re-validated, so a decoder bug is reported rather than blamed on the kernel. Layout of the
//! bytes and the bounds: `proofs-notes/fuzzing.md`.

use std::fmt;

use rug::float::Constant;
use rug::Float;

use crate::kernel::cell::{CellKernel, ConvexCell};
use crate::kernel::certified;
use crate::kernel::trap::Trap;
use crate::kernel::vec2::Vec2;
use crate::kernel::{flight::Event, flight::EventKind, flight::Flight};
use crate::numbers::real::Real;
use crate::scenes::lattice::{CellIndex, LatticeState};
use crate::scenes::square::SquareScene;
use crate::scenes::triangular::geometry::Geometry;
use crate::scenes::triangular::TriangularScene;
use crate::scenes::Scene;
use crate::verification::error_model::{ENERGY_BAND_U, POST_EVENT_U, UNIT_ROUNDOFF, UNWRAP_EPS};
use crate::verification::replay::check_event;

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
    ENERGY_BAND_U * (1.0 + cell.extent() / cell.radius.to_f64())
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

/// Reads bytes front to back; past the end every read is zero, so every input decodes.
struct Bytes<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> Bytes<'a> {
    fn new(data: &'a [u8]) -> Self {
        Bytes { data, pos: 0 }
    }
    fn u8(&mut self) -> u8 {
        let b = self.data.get(self.pos).copied().unwrap_or(0);
        self.pos += 1;
        b
    }
    fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }
    fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
    /// A fraction in [0, 1], both ends included.
    fn frac16(&mut self) -> f64 {
        self.u16() as f64 / 65535.0
    }
    /// A fraction in [0, 1), fine-grained.
    fn frac32(&mut self) -> f64 {
        self.u32() as f64 / 4_294_967_296.0
    }
    /// A fraction in (0, 1), both ends excluded.
    fn open16(&mut self) -> f64 {
        (self.u16() as f64 + 1.0) / 65537.0
    }
}

/// Small signed offsets, 0 first so that missing bytes mean "no nudge".
const NUDGE: [i32; 9] = [0, 1, -1, 2, -2, 3, -3, 4, -4];

fn next_up(x: f64) -> f64 {
    if x.is_nan() || x == f64::INFINITY {
        return x;
    }
    if x == 0.0 {
        return f64::from_bits(1);
    }
    let b = x.to_bits();
    f64::from_bits(if x > 0.0 { b + 1 } else { b - 1 })
}

fn next_down(x: f64) -> f64 {
    -next_up(-x)
}

/// `x` moved by `n` ulps.
fn nudge(mut x: f64, n: i32) -> f64 {
    for _ in 0..n.unsigned_abs() {
        x = if n > 0 { next_up(x) } else { next_down(x) };
    }
    x
}

fn hp(x: f64) -> Float {
    Float::with_val(ORACLE_BITS, x)
}

fn pi() -> Float {
    Float::with_val(ORACLE_BITS, Constant::Pi)
}

/// The unit vector at angle `theta` (computed at [`ORACLE_BITS`], then rounded).
fn unit(theta: &Float) -> Vec2<Float> {
    let (s, c) = theta.clone().sin_cos(Float::new(ORACLE_BITS));
    Vec2::new(c, s)
}

fn angle_of(v: &Vec2<Float>) -> Float {
    v.y.clone().atan2(&v.x)
}

fn round(p: &Vec2<Float>) -> Vec2<f64> {
    Vec2::new(p.x.to_f64(), p.y.to_f64())
}

fn lift(p: &Vec2<f64>) -> Vec2<Float> {
    Vec2::<Float>::from_f64(ORACLE_BITS, p.x, p.y)
}

/// The largest f64 gap strictly below w∞.
fn w_max() -> f64 {
    let wi = Geometry::<Float>::w_inf(ORACLE_BITS);
    let mut w = wi.to_f64();
    while hp(w) >= wi {
        w = next_down(w);
    }
    w
}

/// The smallest f64 gap strictly above w∞.
fn w_min_open() -> f64 {
    let wi = Geometry::<Float>::w_inf(ORACLE_BITS);
    let mut w = wi.to_f64();
    while hp(w) <= wi {
        w = next_up(w);
    }
    w
}

/// w from a mode byte and 32 bits: uniform in (0, w∞), uniform in (w∞, 2) (an infinite
/// horizon: flights along the corridors cross many traps), a power 2⁻ᵉ (e = 2..=40), or within
/// ~2⁻¹⁴ (relative) of w∞ below it.
fn decode_w(r: &mut Bytes) -> f64 {
    let mode = r.u8() % 4;
    let n = r.u32();
    let wm = w_max();
    match mode {
        0 => wm * ((n as f64 + 1.0) / 4_294_967_297.0),
        1 => {
            let lo = w_min_open();
            lo + (2.0 - lo) * (n as f64 / 4_294_967_296.0)
        }
        2 => (-((2 + n % 39) as f64)).exp2(),
        _ => wm * (1.0 - (n >> 18) as f64 * (-32f64).exp2()),
    }
}

/// r from a mode byte and 32 bits: uniform in (0, ½), a power 2⁻ᵉ (e = 2..=40), or ½ − 2⁻ᵏ
/// (k = 2..=53, exact; ½ − 2⁻⁵³ is the largest double below ½).
fn decode_r(r: &mut Bytes) -> f64 {
    let mode = r.u8() % 4;
    let n = r.u32();
    match mode {
        0 | 1 => 0.5 * ((n as f64 + 1.0) / 4_294_967_297.0),
        2 => (-((2 + n % 39) as f64)).exp2(),
        _ => 0.5 - (-((2 + n % 52) as f64)).exp2(),
    }
}

/// Geometric context of a decoding: the scene's cell at f64 and at [`ORACLE_BITS`].
struct Geo {
    c64: ConvexCell<f64>,
    chp: ConvexCell<Float>,
}

impl Geo {
    fn new<S: Scene>(scene: &S) -> Result<Self, String> {
        let k64 = scene.kernel::<f64>(()).map_err(|e| e.to_string())?;
        let khp = scene
            .kernel::<Float>(ORACLE_BITS)
            .map_err(|e| e.to_string())?;
        Ok(Geo {
            c64: k64.cell().clone(),
            chp: khp.cell().clone(),
        })
    }

    fn n_disks(&self) -> usize {
        self.chp.disks.len()
    }

    /// Free at high precision, up to 2⁻¹⁰⁰: σₖ(p) ≥ −2⁻¹⁰⁰ for every edge and
    /// |p − c|² ≥ r²(1 − 2⁻¹⁰⁰) for every disk (points constructed on an edge or a tangent line).
    fn free_hp(&self, p: &Vec2<Float>) -> bool {
        let tiny = HP_TINY_EXP.exp2();
        let r2 = self.chp.radius2.to_f64();
        (0..self.chp.edges.len()).all(|k| self.chp.edge_distance(k, p).to_f64() >= -tiny)
            && self
                .chp
                .disks
                .iter()
                .all(|c| p.sub(c).norm2().to_f64() >= r2 * (1.0 - tiny))
    }

    /// A free point from two fractions: c₀ + u₁(c₁ − c₀) + u₂(c_last − c₀) over the corners
    /// (folded back onto the triangle c₀c₁c₂ when the cell is one; the whole cell when it is a
    /// parallelogram), then an additive-recurrence walk until free; the centroid or a free
    /// corner as the last resort.
    fn free_point(&self, u1: f64, u2: f64) -> Vec2<f64> {
        let c = &self.c64.corners;
        let (o, p1, p2) = (&c[0], &c[1], &c[c.len() - 1]);
        let (e1, e2) = (p1.sub(o), p2.sub(o));
        for i in 0..256 {
            let (mut a, mut b) = (
                (u1 + i as f64 * 0.618_033_988_749_895).fract(),
                (u2 + i as f64 * 0.414_213_562_373_095).fract(),
            );
            if c.len() == 3 && a + b > 1.0 {
                a = 1.0 - a;
                b = 1.0 - b;
            }
            let p = Vec2::new(o.x + a * e1.x + b * e2.x, o.y + a * e1.y + b * e2.y);
            if self.c64.is_free(&p) {
                return p;
            }
        }
        let n = c.len() as f64;
        let centroid = Vec2::new(
            c.iter().map(|p| p.x).sum::<f64>() / n,
            c.iter().map(|p| p.y).sum::<f64>() / n,
        );
        std::iter::once(centroid.clone())
            .chain(c.iter().cloned())
            .find(|p| self.c64.is_free(p))
            .unwrap_or(centroid)
    }

    /// The range of s with A + s·u in the closed cell (at high precision), if not empty.
    fn clip(&self, a: &Vec2<Float>, u: &Vec2<Float>) -> Option<(Float, Float)> {
        let (mut lo, mut hi): (Option<Float>, Option<Float>) = (None, None);
        for (k, e) in self.chp.edges.iter().enumerate() {
            let sigma = self.chp.edge_distance(k, a);
            let nu = e.normal.dot(u);
            // A direction within rounding of an edge's is parallel to it.
            if nu.to_f64().abs() < 1e-40 {
                if sigma.to_f64() < -1e-40 {
                    return None;
                }
                continue;
            }
            let s = -(sigma.clone()) / &nu;
            if nu.gt0() {
                lo = Some(match lo {
                    Some(l) if l >= s => l,
                    _ => s,
                });
            } else {
                hi = Some(match hi {
                    Some(h) if h <= s => h,
                    _ => s,
                });
            }
        }
        let (lo, hi) = (lo?, hi?);
        (lo <= hi).then_some((lo, hi))
    }

    /// A free point A + s·u of the line, s chosen from `frac` (then a walk, then the ends and
    /// the middle of the clipped range).
    fn point_on_line(&self, a: &Vec2<Float>, u: &Vec2<Float>, frac: f64) -> Option<Vec2<Float>> {
        let (lo, hi) = self.clip(a, u)?;
        let len = hi - &lo;
        let tries = (0..64)
            .map(|i| (frac + i as f64 * 0.618_033_988_749_895).fract())
            .chain([0.0, 1.0, 0.5]);
        for f in tries {
            let s = lo.clone() + &(len.clone() * &hp(f));
            let p = a.along(&s, u);
            if self.free_hp(&p) {
                return Some(p);
            }
        }
        None
    }

    /// `true` if the point of disk `m`'s surface at angle `theta` is in the closed cell and
    /// outside the other disks (decided in `f64`, for the arc walk).
    fn surface_free64(&self, m: usize, theta: f64) -> bool {
        let c = &self.c64;
        let (s, co) = theta.sin_cos();
        let p = Vec2::new(c.disks[m].x + c.radius * co, c.disks[m].y + c.radius * s);
        (0..c.edges.len()).all(|k| c.edge_distance(k, &p) >= 0.0)
            && c.disks
                .iter()
                .enumerate()
                .all(|(j, d)| j == m || p.sub(d).norm2() >= c.radius2)
    }

    /// The free arcs of disk `m`'s surface inside the cell, as angle intervals [lo, hi] (hi may
    /// exceed 2π): a walk over [`ARC_SAMPLES`] angles finds the runs of free samples, each end
    /// is then bisected to the last ulp. The whole circle is one arc [0, 2π].
    fn free_arcs(&self, m: usize) -> Vec<(f64, f64)> {
        let step = std::f64::consts::TAU / ARC_SAMPLES as f64;
        let free: Vec<bool> = (0..ARC_SAMPLES)
            .map(|i| self.surface_free64(m, i as f64 * step))
            .collect();
        if free.iter().all(|&f| f) {
            return vec![(0.0, std::f64::consts::TAU)];
        }
        let Some(start) = free.iter().position(|&f| !f) else {
            return Vec::new();
        };
        // Bisects between a free angle and a non-free one, returning the free end.
        let refine = |mut inside: f64, mut outside: f64| {
            for _ in 0..ARC_REFINE_STEPS {
                let mid = 0.5 * (inside + outside);
                if mid == inside || mid == outside {
                    break;
                }
                if self.surface_free64(m, mid) {
                    inside = mid;
                } else {
                    outside = mid;
                }
            }
            inside
        };
        let mut arcs = Vec::new();
        let mut run: Option<usize> = None;
        for n in start + 1..=start + ARC_SAMPLES {
            let i = n % ARC_SAMPLES;
            match (free[i], run) {
                (true, None) => run = Some(n),
                (false, Some(first)) => {
                    let lo = refine(first as f64 * step, (first - 1) as f64 * step);
                    let hi = refine((n - 1) as f64 * step, n as f64 * step);
                    arcs.push((lo, hi));
                    run = None;
                }
                _ => {}
            }
        }
        arcs
    }

    /// The points where edge `k`'s line meets a disk's circle inside the closed cell, in
    /// counter-clockwise order along the edge.
    fn edge_circle_points(&self, k: usize) -> Vec<Vec2<Float>> {
        let c = &self.chp;
        let e = &c.edges[k];
        let n = &e.normal;
        // Counter-clockwise direction along the edge: the interior (n) is on its left.
        let t = Vec2::new(n.y.clone(), -n.x.clone());
        let mut pts: Vec<(Float, Vec2<Float>)> = Vec::new();
        for d in &c.disks {
            // Foot of the perpendicular from the centre, q = c + (o − n·c)n; half-chord √(r² − δ²).
            let delta = e.offset.clone() - &n.dot(d);
            let h2 = c.radius2.clone() - &Real::square(&delta);
            if h2.is_sign_negative() {
                continue;
            }
            let q = d.along(&delta, n);
            let h = h2.sqrt();
            for s in [-h.clone(), h] {
                let p = q.along(&s, &t);
                let on_cell = (0..c.edges.len())
                    .all(|j| j == k || c.edge_distance(j, &p).to_f64() >= -HP_TINY_EXP.exp2());
                if on_cell {
                    pts.push((t.dot(&p), p));
                }
            }
        }
        pts.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal));
        pts.into_iter().map(|(_, p)| p).collect()
    }
}

/// Checks that a decoded state is valid in `cell` (see the module documentation).
fn validate(cell: &ConvexCell<Float>, f: &Flight<f64>) -> Result<(), String> {
    let p = lift(&f.pos);
    let v = lift(&f.vel);
    let extent = cell.extent();
    for k in 0..cell.edges.len() {
        let s = cell.edge_distance(k, &p).to_f64();
        if s.is_nan() || s < -VALID_EDGE * extent {
            return Err(format!("decoded start outside edge {k}: sigma = {s:e}"));
        }
    }
    let r2 = cell.radius2.to_f64();
    for (m, c) in cell.disks.iter().enumerate() {
        let e = ((p.sub(c).norm2() - &cell.radius2) / &cell.radius2).to_f64();
        if e.is_nan() || e < -VALID_DISK {
            return Err(format!(
                "decoded start inside disk {m}: (|p-c|^2 - r^2)/r^2 = {e:e} (r^2 = {r2:e})"
            ));
        }
    }
    let e = (v.norm2() - 1u32).to_f64();
    if e.abs().is_nan() || e.abs() > VALID_SPEED {
        return Err(format!("decoded speed off: |v|^2 - 1 = {e:e}"));
    }
    if f.excluded_edge.is_some() {
        return Err("decoded start with an excluded edge".into());
    }
    if let Some(m) = f.excluded_disk {
        let d = p.sub(&cell.disks[m as usize]);
        let beta = d.dot(&v).to_f64();
        // Excluding a disk is valid only if the flight leaves it, up to the rounding of v·n:
        // each component of v is within 4.5 ulps (≤ 4.5u) of the exact tangent direction.
        let tol = 16.0 * U * d.norm2().sqrt().to_f64();
        if beta < -tol {
            return Err(format!("excluded disk approached: v.n = {beta:e}"));
        }
    }
    Ok(())
}

/// A decoded start: family, position, high-precision velocity, excluded disk.
type Built = (PrimitiveCase, Vec2<f64>, Vec2<Float>, Option<u8>);

/// Number of families selected by the case byte (its value modulo this).
const FAMILIES: u8 = 6;

/// Decodes a start in the cell of `scene` from the case byte `sel` and the case's own bytes
/// (see `proofs-notes/fuzzing.md` for the layout); the bytes of each family are always read in
/// full (a fixed layout per family).
fn build_flight(geo: &Geo, sel: u8, r: &mut Bytes) -> (PrimitiveCase, Flight<f64>) {
    let built: Option<Built> = match sel % FAMILIES {
        0 => impact_start(geo, r),
        1 => near_surface_start(geo, r),
        2 => double_tangent_start(geo, r),
        3 => gap_point_start(geo, r),
        4 => None,
        _ => corner_start(geo, r),
    };
    let (case, pos, vel_hp, excluded_disk) = built.unwrap_or_else(|| arbitrary_start(geo, r));
    let (pn, vn) = (r.u8(), r.u8());
    let pos = Vec2::new(
        nudge(pos.x, NUDGE[(pn % 3) as usize]),
        nudge(pos.y, NUDGE[((pn / 3) % 3) as usize]),
    );
    let vel = Vec2::new(
        nudge(vel_hp.x.to_f64(), NUDGE[(vn % 9) as usize]),
        nudge(vel_hp.y.to_f64(), NUDGE[((vn / 9) % 9) as usize]),
    );
    let mut flight = Flight::new(pos, vel);
    flight.excluded_disk = excluded_disk;
    (case, flight)
}

/// 2π at [`ORACLE_BITS`].
fn two_pi() -> Float {
    pi() * 2u32
}

/// Family 0 ([`PrimitiveCase::Impact`]): aimed at a disk with impact parameter r(1 ∓ 2⁻ᵏ), from a
/// free start.
fn impact_start(geo: &Geo, r: &mut Bytes) -> Option<Built> {
    let chp = &geo.chp;
    let nd = geo.n_disks();
    let disk = r.u8() % nd as u8;
    let kb = r.u8();
    let side = r.u8() & 1 == 1;
    let (u1, u2) = (r.frac16(), r.frac16());
    let above = kb & 0x80 != 0;
    let k = 1 + (kb & 0x7f) % 52;
    let factor = if above {
        1.0 + (-(k as f64)).exp2()
    } else {
        1.0 - (-(k as f64)).exp2()
    };
    let b = chp.radius.clone() * &hp(factor);
    let c = &chp.disks[disk as usize];
    // A free start far enough from the disk (|p − c| > b), by the same walk.
    (0..16)
        .map(|i| {
            geo.free_point(
                (u1 + i as f64 * std::f64::consts::FRAC_1_PI).fract(),
                (u2 + i as f64 * 0.577_215_664_901_532).fract(),
            )
        })
        .find_map(|p64| {
            let to_c = c.sub(&lift(&p64));
            let dist = to_c.norm2().sqrt();
            let ratio = b.clone() / &dist;
            if ratio.to_f64() >= 1.0 {
                return None;
            }
            let alpha = ratio.asin();
            let phi = if side {
                angle_of(&to_c) + &alpha
            } else {
                angle_of(&to_c) - &alpha
            };
            Some((
                PrimitiveCase::Impact { disk, k, above },
                p64,
                unit(&phi),
                None,
            ))
        })
}

/// Family 1 ([`PrimitiveCase::NearSurface`]): a start r·2⁻ᵏ from a disk's surface on one of its
/// free arcs, moving in, out or tangentially.
fn near_surface_start(geo: &Geo, r: &mut Bytes) -> Option<Built> {
    let chp = &geo.chp;
    let nd = geo.n_disks();
    let half_pi = pi() / 2u32;
    let disk = r.u8() % nd as u8;
    let k = 1 + r.u8() % 60;
    let motion = r.u8() % 3;
    let flags = r.u8();
    let (psi_f, chi_f) = (r.frac16(), r.open16());
    let excluded = motion != 0 && flags & 1 == 1;
    let c = &chp.disks[disk as usize];
    let arcs = geo.free_arcs(disk as usize);
    let dist = chp.radius.clone() * &(hp(1.0) + &hp((-(k as f64)).exp2()));
    (!arcs.is_empty())
        .then(|| arcs[(flags >> 2) as usize % arcs.len()])
        .and_then(|(lo, hi)| {
            let (lo, hi) = (hp(lo), hp(hi));
            let width = hi.clone() - &lo;
            let mid = lo.clone() + &(width.clone() / 2u32);
            let psi0 = lo + &(width * &hp(psi_f));
            // Near the arc ends the point can fall outside the cell or in a
            // neighbouring disk: pull it towards the middle of the arc, by tiny
            // fractions first (an end on an edge stays on it), then by halves.
            let pulls = std::iter::once(0.0)
                .chain([-50.0, -40.0, -30.0, -20.0, -10.0].map(f64::exp2))
                .chain((1..=64).map(|n| 1.0 - (-(n as f64)).exp2()));
            pulls
                .map(|fr| psi0.clone() + &((mid.clone() - &psi0) * &hp(fr)))
                .find_map(|psi| {
                    let p = c.along(&dist, &unit(&psi));
                    geo.free_hp(&p).then_some((psi, p))
                })
        })
        .map(|(psi, p)| {
            let dir = match motion {
                0 => psi.clone() + &half_pi + &(pi() * &hp(chi_f)),
                1 => psi.clone() - &half_pi + &(pi() * &hp(chi_f)),
                _ => {
                    if flags & 2 == 2 {
                        psi.clone() + &half_pi
                    } else {
                        psi.clone() - &half_pi
                    }
                }
            };
            (
                PrimitiveCase::NearSurface {
                    disk,
                    k,
                    motion,
                    excluded,
                },
                round(&p),
                unit(&dir),
                if excluded { Some(disk) } else { None },
            )
        })
}

/// Family 2 ([`PrimitiveCase::DoubleTangent`]): on a common tangent of two disks (in a one-disk
/// cell, a tangent parallel to an edge), either way along it.
fn double_tangent_start(geo: &Geo, r: &mut Bytes) -> Option<Built> {
    let chp = &geo.chp;
    let nd = geo.n_disks();
    let ne = chp.edges.len();
    let pair_b = r.u8();
    let line_b = r.u8();
    let back = r.u8() & 1 == 1;
    let s_f = r.frac16();
    let found = |pair: u8, line: u8, anchor: Vec2<Float>, dir: Vec2<Float>| {
        geo.point_on_line(&anchor, &dir, s_f).map(|p| {
            let v = if back { -dir.clone() } else { dir };
            (
                PrimitiveCase::DoubleTangent { pair, line },
                round(&p),
                v,
                None,
            )
        })
    };
    if nd >= 2 {
        let pair = pair_b % nd as u8;
        let tangents = PairTangents::new(geo, pair);
        // The outer tangent can run inside a third disk for all its length inside the
        // cell (the triangular trap at small w); then the first inner tangent is used.
        let line = line_b % 3;
        [line, 1].into_iter().find_map(|line| {
            let (anchor, dir) = tangents.line(line);
            found(pair, line, anchor, dir)
        })
    } else {
        // One disk: the tangents parallel to edge `pair` (corridor boundaries).
        let pair = pair_b % ne as u8;
        let line = line_b % 2;
        let n = &chp.edges[pair as usize].normal;
        let side = if line == 0 { hp(1.0) } else { hp(-1.0) };
        let anchor = chp.disks[0].along(&(chp.radius.clone() * &side), n);
        let dir = Vec2::new(n.y.clone(), -n.x.clone());
        found(pair, line, anchor, dir)
    }
}

/// The common tangents of two disks of the cell: the midpoint of their centres, the direction
/// of the centre line and its normal towards the cell, the centres' distance, the radius.
struct PairTangents {
    mid: Vec2<Float>,
    e_dir: Vec2<Float>,
    n: Vec2<Float>,
    len: Float,
    radius: Float,
}

impl PairTangents {
    /// The disks chosen by `pair`: the two disks, or the two after disk `pair` (cyclically).
    fn new(geo: &Geo, pair: u8) -> Self {
        let chp = &geo.chp;
        let nd = geo.n_disks();
        let (i, j) = if nd == 2 {
            (0, 1)
        } else {
            ((pair as usize + 1) % nd, (pair as usize + 2) % nd)
        };
        let (ci, cj) = (&chp.disks[i], &chp.disks[j]);
        let d = cj.sub(ci);
        let len = d.norm2().sqrt();
        let e_dir = Vec2::new(d.x.clone() / &len, d.y.clone() / &len);
        let mid = Vec2::new((ci.x.clone() + &cj.x) / 2u32, (ci.y.clone() + &cj.y) / 2u32);
        // The normal of the centre line pointing to the cell's side (its centroid).
        let nc = chp.corners.len() as u32;
        let centroid = Vec2::new(
            chp.corners.iter().fold(hp(0.0), |s, p| s + &p.x) / nc,
            chp.corners.iter().fold(hp(0.0), |s, p| s + &p.y) / nc,
        );
        let mut n = Vec2::new(-e_dir.y.clone(), e_dir.x.clone());
        if centroid.sub(&mid).dot(&n).is_sign_negative() {
            n = -n;
        }
        PairTangents {
            mid,
            e_dir,
            n,
            len,
            radius: chp.radius.clone(),
        }
    }

    /// Tangent `line` as (anchor, direction): 0 the outer one on the cell's side, 1 and 2 the
    /// inner ones.
    fn line(&self, line: u8) -> (Vec2<Float>, Vec2<Float>) {
        match line {
            0 => (self.mid.along(&self.radius, &self.n), self.e_dir.clone()),
            _ => {
                // Inner tangents: through the midpoint at angle ±α, sin α = 2r/|cⱼ − cᵢ|.
                let alpha = (self.radius.clone() * 2u32 / &self.len).asin();
                let th = angle_of(&self.e_dir);
                let th = if line == 1 { th + &alpha } else { th - &alpha };
                (self.mid.clone(), unit(&th))
            }
        }
    }
}

/// Family 3 ([`PrimitiveCase::GapPoint`]): at a point where an edge meets a disk's circle, or aimed
/// at one from a free point.
fn gap_point_start(geo: &Geo, r: &mut Bytes) -> Option<Built> {
    let ne = geo.chp.edges.len();
    let edge = r.u8() % ne as u8;
    let point_b = r.u8();
    let at_point = r.u8() & 1 == 1;
    let ang = r.frac32();
    let (u1, u2) = (r.frac16(), r.frac16());
    let pts = geo.edge_circle_points(edge as usize);
    if pts.is_empty() {
        None
    } else {
        let point = point_b % pts.len() as u8;
        let g = &pts[point as usize];
        let case = PrimitiveCase::GapPoint {
            edge,
            point,
            at_point,
        };
        if at_point {
            Some((case, round(g), unit(&(two_pi() * &hp(ang))), None))
        } else {
            let p64 = geo.free_point(u1, u2);
            let to_g = g.sub(&lift(&p64));
            (to_g.norm2().to_f64() > 1e-6).then(|| (case, p64, unit(&angle_of(&to_g)), None))
        }
    }
}

/// Family 5 ([`PrimitiveCase::Corner`]): at a corner of the cell, aimed at one, or along an edge
/// through it.
fn corner_start(geo: &Geo, r: &mut Bytes) -> Option<Built> {
    let chp = &geo.chp;
    let ne = chp.edges.len();
    let corner = r.u8() % chp.corners.len() as u8;
    let mode = r.u8() % 3;
    let which = r.u8();
    let ang = r.frac32();
    let (u1, u2) = (r.frac16(), r.frac16());
    let q = &chp.corners[corner as usize];
    let case = PrimitiveCase::Corner { corner, mode };
    match mode {
        0 => geo
            .free_hp(q)
            .then(|| (case, round(q), unit(&(two_pi() * &hp(ang))), None)),
        1 => {
            let p64 = geo.free_point(u1, u2);
            let to_q = q.sub(&lift(&p64));
            (to_q.norm2().to_f64() > 1e-6).then(|| (case, p64, unit(&angle_of(&to_q)), None))
        }
        _ => {
            // Along one of the (two) edges through the corner, either way.
            let tiny = HP_TINY_EXP.exp2();
            let through: Vec<usize> = (0..ne)
                .filter(|&k| chp.edge_distance(k, q).to_f64().abs() <= tiny)
                .collect();
            (geo.free_hp(q) && !through.is_empty()).then(|| {
                let n = &chp.edges[through[(which >> 1) as usize % through.len()]].normal;
                let t = Vec2::new(n.y.clone(), -n.x.clone());
                let t = if which & 1 == 1 { -t } else { t };
                (case, round(q), t, None)
            })
        }
    }
}

/// [`PrimitiveCase::Arbitrary`] (family 4, and the fall-back of a failed construction: reads its
/// own bytes).
fn arbitrary_start(geo: &Geo, r: &mut Bytes) -> Built {
    let (u1, u2) = (r.frac16(), r.frac16());
    let ang = r.frac32();
    (
        PrimitiveCase::Arbitrary,
        geo.free_point(u1, u2),
        unit(&(two_pi() * &hp(ang))),
        None,
    )
}

/// Decodes the whole single-cell input: `[scene][case][parameter mode][parameter: u32][events]`,
/// then the family's bytes and the nudges.
fn decode_flight(r: &mut Bytes) -> Result<(PrimitiveInput, Geo), String> {
    let scene_b = r.u8();
    let sel = r.u8();
    let (scene, geo) = if scene_b.is_multiple_of(2) {
        let w = decode_w(r);
        let s = TriangularScene::new(w).map_err(|e| e.to_string())?;
        (SceneParams::Triangular { w }, Geo::new(&s)?)
    } else {
        let radius = decode_r(r);
        let s = SquareScene::new(radius).map_err(|e| e.to_string())?;
        (SceneParams::Square { r: radius }, Geo::new(&s)?)
    };
    let events = 1 + r.u8() % 4;
    let (case, flight) = build_flight(&geo, sel, r);
    Ok((
        PrimitiveInput {
            scene,
            case,
            flight,
            events,
        },
        geo,
    ))
}

/// Decodes and validates a single-cell input, keeping the cell it was decoded in.
fn decode_validated(data: &[u8]) -> Result<(PrimitiveInput, Geo), OracleFailure> {
    let (input, geo) = decode_flight(&mut Bytes::new(data)).map_err(|reason| OracleFailure {
        case: None,
        scene: "undecodable".into(),
        event: None,
        reason,
        state: format!("{data:?}"),
    })?;
    validate(&geo.chp, &input.flight).map_err(|reason| OracleFailure {
        case: Some(input.case),
        scene: input.scene.label(),
        event: None,
        reason,
        state: format!("{:?}", input.flight),
    })?;
    Ok((input, geo))
}

/// Decodes the input of [`collision_primitive`].
///
/// # Errors
/// If the decoded state is not valid (a decoder bug, never expected).
pub fn decode_primitive(data: &[u8]) -> Result<PrimitiveInput, OracleFailure> {
    decode_validated(data).map(|(input, _)| input)
}

/// Decodes the input of [`scene_stepper`]: cell index (i, j) ∈ [−10⁹, 10⁹]², orientation
/// (honoured only if the lattice has point-reflected cells), step count, then the flight as for
/// [`decode_primitive`].
///
/// # Errors
/// If the decoded state is not valid (a decoder bug, never expected).
pub fn decode_scene(data: &[u8]) -> Result<SceneInput, OracleFailure> {
    let mut r = Bytes::new(data);
    let idx = |n: u32| (n % 2_000_000_001) as i64 - 1_000_000_000;
    let (i, j) = (idx(r.u32()), idx(r.u32()));
    let down = r.u8() & 1 == 1;
    let steps = 1 + r.u16() as u32 % MAX_STEPS;
    let rest = &data[r.pos.min(data.len())..];
    let (primitive, geo) = decode_validated(rest)?;
    let flips = geo.chp.edges.iter().any(|e| e.flips());
    Ok(SceneInput {
        primitive,
        cell: CellIndex {
            i,
            j,
            down: down && flips,
        },
        steps,
    })
}

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
    let setup = |reason: String| OracleFailure {
        case,
        scene: label.clone(),
        event: None,
        reason,
        state: format!("{start:?}"),
    };
    let k64 = scene.kernel::<f64>(()).map_err(|e| setup(e.to_string()))?;
    let kref = scene
        .kernel::<Float>(ORACLE_BITS)
        .map_err(|e| setup(e.to_string()))?;
    let mut f = start.clone();
    let mut rep = OracleReport::new(case, label.clone());
    for n in 0..events as u64 {
        let before = f.clone();
        let fail = |reason: String| OracleFailure {
            case,
            scene: label.clone(),
            event: Some(n),
            reason,
            state: format!("{before:?}"),
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
        let fail = |event: Option<u64>, reason: String, state: String| OracleFailure {
            case: Some(input.case),
            scene: format!("triangular w={w:e} at {bits} bits"),
            event,
            reason,
            state,
        };
        let trap = Trap::new(Float::with_val(bits, w))
            .map_err(|e| fail(None, e.to_string(), String::new()))?;
        let mut f = Flight::<Float>::convert_from_f64(bits, &input.flight);
        for n in 0..u64::from(input.events) {
            let want = trap.next_event_compared(&f);
            if let Some(ev) = certified::next_event(&trap, &f) {
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

/// Steps the lattice state `start` of `scene` up to `steps` events in `f64` and checks after
/// every event (bounds of `tests/numerics/kernel_properties.rs`, `tests/numerics/square.rs`,
/// `proofs-notes/energy.md`, `tests/numerics/physics.rs`), for any cell:
///
/// * event time finite, ≥ 0 and ≤ 2·diameter of the cell polygon; state finite;
/// * after a collision ||v|² − 1| ≤ [`energy_band`]·u; after a crossing |v|² unchanged bit for
///   bit (translations and point reflections are exact);
/// * |x − c|² ≥ r² − 256u for every disk, σₖ(x) ≥ −256u·extent for every edge;
/// * unwrapped world displacement = t·(s·v) within 64ε(diameter + t);
/// * the cell index moves by [`CellIndex::across`] exactly on a crossing and not at all on a
///   collision; the disk hit (`Some(m)`) / edge entered (`Some(edge.entered)`) is the one
///   excluded.
///
/// # Errors
/// The first violation, with the state before the failing event.
pub fn step_lattice<S: Scene>(
    scene: &S,
    case: Option<PrimitiveCase>,
    start: &LatticeState<f64>,
    steps: u32,
) -> Result<OracleReport, OracleFailure> {
    let label = scene.label();
    let lat = scene.lattice::<f64>(()).map_err(|e| OracleFailure {
        case,
        scene: label.clone(),
        event: None,
        reason: e.to_string(),
        state: format!("{start:?}"),
    })?;
    let basis = lat.basis_f64();
    let bounds = EventBounds::new(lat.cell().clone());
    let diam = bounds.diam;
    let mut s = start.clone();
    let mut rep = OracleReport::new(case, label.clone());
    for n in 0..steps as u64 {
        let before = s.clone();
        let fail = |reason: String| OracleFailure {
            case,
            scene: label.clone(),
            event: Some(n),
            reason,
            state: format!("{before:?}"),
        };
        let u_before = lat.unwrapped(&s, 0.0);
        let sg = s.cell.sign();
        let (vx, vy) = (sg * s.flight.vel.x, sg * s.flight.vel.y);
        let ev = lat
            .step(&mut s)
            .map_err(|e| fail(format!("step failed: {e}")))?;
        bounds
            .check_after(&before, &ev, &s, &mut rep)
            .map_err(fail)?;
        let d = lat.unwrapped(&s, 0.0).displacement_from(&u_before, &basis);
        let err = ((d[0] - ev.time * vx).powi(2) + (d[1] - ev.time * vy).powi(2)).sqrt();
        if err.is_nan() || err > UNWRAP_EPS * f64::EPSILON * (diam + ev.time) {
            return Err(fail(format!("unwrapped jump {err:e} over {:?}", ev.kind)));
        }
        rep.events += 1;
    }
    Ok(rep)
}

/// The cell of [`step_lattice`] with the bounds its per-event checks use: extent, diameter and
/// energy band.
struct EventBounds {
    cell: ConvexCell<f64>,
    extent: f64,
    diam: f64,
    band: f64,
}

impl EventBounds {
    /// The bounds of `cell`.
    fn new(cell: ConvexCell<f64>) -> Self {
        EventBounds {
            extent: cell.extent(),
            diam: diameter(&cell),
            band: energy_band(&cell),
            cell,
        }
    }

    /// The checks of one event `ev` from `before` to `after` but the unwrapped displacement,
    /// counting it in `rep`; the reason of the first violation.
    fn check_after(
        &self,
        before: &LatticeState<f64>,
        ev: &Event<f64>,
        after: &LatticeState<f64>,
        rep: &mut OracleReport,
    ) -> Result<(), String> {
        let fl = &after.flight;
        if !(ev.time.is_finite() && ev.time >= 0.0 && ev.time <= 2.0 * self.diam) {
            return Err(format!("bad event time {:e} ({:?})", ev.time, ev.kind));
        }
        if ![fl.pos.x, fl.pos.y, fl.vel.x, fl.vel.y]
            .iter()
            .all(|x| x.is_finite())
        {
            return Err(format!("non-finite state after {:?}: {fl:?}", ev.kind));
        }
        match ev.kind {
            EventKind::Collision(m) => self.check_collision(m, before, after, rep)?,
            EventKind::Crossing(k) => self.check_crossing(k, before, after, rep)?,
        }
        self.check_position(fl, ev.kind)
    }

    /// After collision `m`: |v|² within the energy band, the same cell, disk `m` excluded.
    fn check_collision(
        &self,
        m: u8,
        before: &LatticeState<f64>,
        after: &LatticeState<f64>,
        rep: &mut OracleReport,
    ) -> Result<(), String> {
        let (fl, band) = (&after.flight, self.band);
        let e2 = fl.vel.norm2();
        rep.collisions += 1;
        let dev = (e2 - 1.0).abs() / U;
        rep.worst_energy_u = rep.worst_energy_u.max(dev);
        if dev.is_nan() || dev > band {
            return Err(format!(
                "|v|^2 - 1 = {:e} = {dev} u after a collision (band {band} u)",
                e2 - 1.0
            ));
        }
        if after.cell != before.cell {
            return Err(format!("cell changed on a collision: {:?}", after.cell));
        }
        if fl.excluded_disk != Some(m) || fl.excluded_edge.is_some() {
            return Err(format!("exclusions after collision {m}: {fl:?}"));
        }
        Ok(())
    }

    /// After crossing edge `k`: |v|² unchanged bit for bit, the cell moved across the edge, the
    /// edge entered excluded.
    fn check_crossing(
        &self,
        k: u8,
        before: &LatticeState<f64>,
        after: &LatticeState<f64>,
        rep: &mut OracleReport,
    ) -> Result<(), String> {
        let fl = &after.flight;
        let (e2_before, e2) = (before.flight.vel.norm2(), fl.vel.norm2());
        rep.crossings += 1;
        if e2.to_bits() != e2_before.to_bits() {
            return Err(format!(
                "|v|^2 changed on a crossing: {e2_before:e} -> {e2:e}"
            ));
        }
        let edge = &self.cell.edges[k as usize];
        let expected = before.cell.across(edge);
        if after.cell != expected {
            return Err(format!(
                "cell {:?} after crossing {k}, expected {expected:?}",
                after.cell
            ));
        }
        if fl.excluded_edge != Some(edge.entered) {
            return Err(format!("exclusions after crossing {k}: {fl:?}"));
        }
        Ok(())
    }

    /// After event `kind`: outside every disk and inside every edge, up to rounding.
    fn check_position(&self, fl: &Flight<f64>, kind: EventKind) -> Result<(), String> {
        let cell = &self.cell;
        for (m, c) in cell.disks.iter().enumerate() {
            let d = fl.pos.sub(c).norm2() - cell.radius2;
            if d.is_nan() || d < -POST_EVENT_U * U {
                return Err(format!(
                    "inside disk {m} after {kind:?}: |x-c|^2 - r^2 = {d:e}"
                ));
            }
        }
        for k in 0..cell.edges.len() {
            let sig = cell.edge_distance(k, &fl.pos);
            if sig.is_nan() || sig < -POST_EVENT_U * U * self.extent {
                return Err(format!("outside edge {k} after {kind:?}: sigma = {sig:e}"));
            }
        }
        Ok(())
    }
}

/// Steps a decoded lattice state (any scene) with [`step_lattice`].
///
/// # Errors
/// A decoding failure or the first violation, with the state before the failing event.
pub fn scene_stepper(data: &[u8]) -> Result<OracleReport, OracleFailure> {
    let input = decode_scene(data)?;
    let case = Some(input.primitive.case);
    let start = LatticeState {
        cell: input.cell,
        flight: input.primitive.flight.clone(),
    };
    match input.primitive.scene {
        SceneParams::Triangular { w } => step_lattice(&triangular(w)?, case, &start, input.steps),
        SceneParams::Square { r } => step_lattice(&square(r)?, case, &start, input.steps),
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
