//! Fuzzing oracle: decodes arbitrary bytes into valid (often degenerate) states and judges the
//! `f64` kernel on them.
//!
//! Two entry points, shared by the cargo-fuzz targets in `fuzz/` and by `tests/fuzz_oracle.rs`:
//!
//! * [`collision_primitive`]: one of five families of canonical-trap states — near-grazing impact
//!   parameters b = 1 ∓ 2⁻ᵏ, starts 2⁻ᵏ off a disk surface (moving in, out, tangentially),
//!   common tangents of two vertex disks, rays through the points where a gap meets a disk, and
//!   arbitrary free states — each nudged by a few ulps; up to four successive events are replayed
//!   in MPFR ([`ORACLE_BITS`] bits) by [`check_event`] and must be inside the one-step error model.
//! * [`scene_stepper`]: a lattice state (trap index up to ±10⁹, either orientation, flight from
//!   the same five families) stepped up to 4096 events in `f64`; after every event the
//!   invariants of `proofs-notes/energy.md`, `proofs-notes/no-missed-collision.md` and the
//!   unwrapping continuity of `tests/physics.rs` are checked.
//!
//! Decoding never fails: missing bytes read as zero, every byte pattern maps to a valid state
//! (inside the closed triangle, outside the open disks and with |v| = 1, each up to the
//! rounding bounds [`VALID_DISK`], [`VALID_EDGE`], [`VALID_SPEED`]), and the decoded state is
//! itself re-validated, so a decoder bug is reported rather than blamed on the kernel. Layout of
//! the bytes and the bounds: `proofs-notes/fuzzing.md`.

use std::fmt;

use rug::float::Constant;
use rug::Float;

use crate::geometry::Geometry;
use crate::kernel::trap::{Event, EventKind, Flight, Trap};
use crate::kernel::vec2::Vec2;
use crate::real::Real;
use crate::scenes::lattice::{CellIndex, LatticeState, TriangularLattice};
use crate::verification::shadow::check_event;

/// Precision of the MPFR replay and of the decoder's geometric constructions.
pub const ORACLE_BITS: u32 = 192;

/// Unit roundoff of `f64`.
const U: f64 = f64::EPSILON / 2.0;

/// A decoded start may lie inside a disk by at most this much in |p − c|² − 1: the same ε ≤ 28u
/// that the kernel's own rounded contact points reach (`proofs-notes/energy.md`).
pub const VALID_DISK: f64 = 28.0 * U;
/// A decoded start may lie outside an edge by at most `VALID_EDGE · a` (signed distance).
pub const VALID_EDGE: f64 = 16.0 * U;
/// A decoded velocity has ||v|² − 1| ≤ `VALID_SPEED` (rounding plus ≤ 4 ulps per component).
pub const VALID_SPEED: f64 = 32.0 * U;

/// Largest number of events stepped by [`scene_stepper`].
pub const MAX_STEPS: u32 = 4096;

/// The five families of decoded states.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PrimitiveCase {
    /// Aimed at vertex disk `disk` with impact parameter b = 1 − 2⁻ᵏ (or 1 + 2⁻ᵏ if `above`).
    Impact {
        /// Vertex disk aimed at.
        disk: u8,
        /// Exponent k, 1..=52.
        k: u8,
        /// b = 1 + 2⁻ᵏ (a near miss) instead of 1 − 2⁻ᵏ.
        above: bool,
    },
    /// Start at distance 2⁻ᵏ from the surface of vertex disk `disk`.
    NearSurface {
        /// Vertex disk.
        disk: u8,
        /// Exponent k, 1..=60 (beyond 53 the start rounds onto the surface).
        k: u8,
        /// 0 moving in, 1 moving out, 2 tangential.
        motion: u8,
        /// The disk is excluded (a post-collision state); only when not moving in.
        excluded: bool,
    },
    /// On a common tangent of the two endpoint disks of edge `edge`.
    DoubleTangent {
        /// Edge whose endpoint disks the line touches.
        edge: u8,
        /// 0: the outer tangent parallel to the edge (at distance 1 inside); 1, 2: the two
        /// inner tangents through the edge midpoint.
        line: u8,
    },
    /// Through a point where the gap of edge `edge` meets a disk (distance 1 from an endpoint).
    GapPoint {
        /// Edge.
        edge: u8,
        /// Which endpoint's disk.
        end: u8,
        /// Start at the point itself (else aimed at it from a free point).
        at_point: bool,
    },
    /// A free point in the triangle with a unit velocity.
    Arbitrary,
}

/// A decoded canonical-trap state.
#[derive(Debug, Clone, PartialEq)]
pub struct PrimitiveInput {
    /// Which family (after fall-backs: a family whose construction fails decodes as
    /// [`PrimitiveCase::Arbitrary`]).
    pub case: PrimitiveCase,
    /// Gap w ∈ (0, w∞).
    pub w: f64,
    /// The start.
    pub flight: Flight<f64>,
    /// Number of successive events to replay (1..=4).
    pub events: u8,
}

/// A decoded lattice run.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneInput {
    /// Gap, start flight and family as for the primitive target.
    pub primitive: PrimitiveInput,
    /// The trap the start is in.
    pub cell: CellIndex,
    /// Number of events to step (1..=[`MAX_STEPS`]).
    pub steps: u32,
}

/// What an oracle run checked.
#[derive(Debug, Clone, PartialEq)]
pub struct OracleReport {
    /// The decoded family.
    pub case: PrimitiveCase,
    /// The gap.
    pub w: f64,
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

/// Why an oracle run failed.
#[derive(Debug, Clone, PartialEq)]
pub struct OracleFailure {
    /// The decoded family.
    pub case: Option<PrimitiveCase>,
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
            "oracle failure ({:?}, event {:?}): {}; state {}",
            self.case, self.event, self.reason, self.state
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

/// The largest f64 gap strictly below w∞.
fn w_max() -> f64 {
    let wi = Geometry::<Float>::w_inf(ORACLE_BITS);
    let mut w = wi.to_f64();
    while hp(w) >= wi {
        w = next_down(w);
    }
    w
}

/// w from a mode byte and 32 bits: uniform in (0, w∞), a power 2⁻ᵉ (e = 2..=40), or within
/// ~2⁻¹⁴ (relative) of w∞.
fn decode_w(r: &mut Bytes) -> f64 {
    let mode = r.u8() % 4;
    let n = r.u32();
    let wm = w_max();
    match mode {
        0 | 1 => wm * ((n as f64 + 1.0) / 4_294_967_297.0),
        2 => (-((2 + n % 39) as f64)).exp2(),
        _ => wm * (1.0 - (n >> 18) as f64 * (-32f64).exp2()),
    }
}

/// Geometric context of a decoding: the trap at f64 and at [`ORACLE_BITS`].
struct Geo {
    t64: Trap<f64>,
    thp: Trap<Float>,
}

impl Geo {
    fn new(w: f64) -> Self {
        Geo {
            t64: Trap::new(w).expect("w > 0"),
            thp: Trap::new(hp(w)).expect("w > 0"),
        }
    }
    /// Free at high precision, up to 2⁻¹⁰⁰: σₖ(p) ≥ −2⁻¹⁰⁰ for every edge and
    /// |p − c|² ≥ 1 − 2⁻¹⁰⁰ for every disk (points constructed on an edge or a tangent line).
    fn free_hp(&self, p: &Vec2<Float>) -> bool {
        let tiny = (-100f64).exp2();
        (0..3).all(|k| self.thp.edge_distance(k, p).to_f64() >= -tiny)
            && self
                .thp
                .vertices
                .iter()
                .all(|c| p.sub(c).norm2().to_f64() >= 1.0 - tiny)
    }
    /// A free point from two fractions (folded onto the triangle, then an additive-recurrence
    /// walk until free; the centroid, always free, as the last resort).
    fn free_point(&self, u1: f64, u2: f64) -> Vec2<f64> {
        let t = &self.t64;
        for i in 0..256 {
            let (mut a, mut b) = (
                (u1 + i as f64 * 0.618_033_988_749_895).fract(),
                (u2 + i as f64 * 0.414_213_562_373_095).fract(),
            );
            if a + b > 1.0 {
                a = 1.0 - a;
                b = 1.0 - b;
            }
            let p = Vec2::new(a * t.a + b * t.a * 0.5, b * t.h);
            if t.is_free(&p) {
                return p;
            }
        }
        Vec2::new(t.a * 0.5, t.h / 3.0)
    }
    /// The range of s with A + s·u in the closed triangle (at high precision), if not empty.
    fn clip(&self, a: &Vec2<Float>, u: &Vec2<Float>) -> Option<(Float, Float)> {
        let (mut lo, mut hi): (Option<Float>, Option<Float>) = (None, None);
        for k in 0..3 {
            let sigma = self.thp.edge_distance(k, a);
            let nu = self.thp.normals[k].dot(u);
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
}

fn round(p: &Vec2<Float>) -> Vec2<f64> {
    Vec2::new(p.x.to_f64(), p.y.to_f64())
}

/// Checks that a decoded state is valid (see the module documentation).
fn validate(thp: &Trap<Float>, f: &Flight<f64>) -> Result<(), String> {
    let p = Vec2::<Float>::from_f64(ORACLE_BITS, f.pos.x, f.pos.y);
    let v = Vec2::<Float>::from_f64(ORACLE_BITS, f.vel.x, f.vel.y);
    let a = thp.a.to_f64();
    for k in 0..3 {
        let s = thp.edge_distance(k, &p).to_f64();
        if s.is_nan() || s < -VALID_EDGE * a {
            return Err(format!("decoded start outside edge {k}: sigma = {s:e}"));
        }
    }
    for (m, c) in thp.vertices.iter().enumerate() {
        let e = (p.sub(c).norm2() - 1u32).to_f64();
        if e.is_nan() || e < -VALID_DISK {
            return Err(format!(
                "decoded start inside disk {m}: |p-c|^2 - 1 = {e:e}"
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
        let d = p.sub(&thp.vertices[m as usize]);
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

/// Decodes the canonical-trap part of an input (see `proofs-notes/fuzzing.md` for the layout).
fn decode_flight(r: &mut Bytes) -> PrimitiveInput {
    let sel = r.u8();
    let w = decode_w(r);
    let events = 1 + r.u8() % 4;
    let geo = Geo::new(w);
    let thp = &geo.thp;
    let two_pi = pi() * 2u32;
    // Case-specific bytes are always read in full (fixed layout per case).
    let built: Option<Built> = match sel % 5 {
        0 => {
            let disk = r.u8() % 3;
            let kb = r.u8();
            let side = r.u8() & 1 == 1;
            let (u1, u2) = (r.frac16(), r.frac16());
            let above = kb & 0x80 != 0;
            let k = 1 + (kb & 0x7f) % 52;
            let b = if above {
                1.0 + (-(k as f64)).exp2()
            } else {
                1.0 - (-(k as f64)).exp2()
            };
            let c = &thp.vertices[disk as usize];
            // A free start far enough from the disk (|p − c| > b), by the same walk.
            (0..16)
                .map(|i| {
                    geo.free_point(
                        (u1 + i as f64 * std::f64::consts::FRAC_1_PI).fract(),
                        (u2 + i as f64 * 0.577_215_664_901_532).fract(),
                    )
                })
                .find_map(|p64| {
                    let p = Vec2::<Float>::from_f64(ORACLE_BITS, p64.x, p64.y);
                    let to_c = c.sub(&p);
                    let dist = to_c.norm2().sqrt();
                    let ratio = hp(b) / &dist;
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
        1 => {
            let disk = r.u8() % 3;
            let k = 1 + r.u8() % 60;
            let motion = r.u8() % 3;
            let flags = r.u8();
            let (psi_f, chi_f) = (r.frac16(), r.open16());
            let excluded = motion != 0 && flags & 1 == 1;
            let c = &thp.vertices[disk as usize];
            // The 60° sector of the disk inside the triangle starts at 0, 2π/3, 4π/3.
            let base = pi() * 2u32 * (disk as u32) / 3u32;
            let width = pi() / 3u32;
            let mid = base.clone() + &(width.clone() / 2u32);
            let r_dist = hp(1.0) + &hp((-(k as f64)).exp2());
            let mut psi = base.clone() + &(width * &hp(psi_f));
            // Near the sector ends the point can fall in a neighbouring disk (small w): move
            // it towards the bisector until free.
            let mut found = None;
            for _ in 0..64 {
                let p = c.along(&r_dist, &unit(&psi));
                if geo.free_hp(&p) {
                    found = Some(p);
                    break;
                }
                psi = mid.clone() + &((psi - &mid) / 2u32);
            }
            found.map(|p| {
                let half_pi = pi() / 2u32;
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
        2 => {
            let edge = r.u8() % 3;
            let line = r.u8() % 3;
            let back = r.u8() & 1 == 1;
            let s_f = r.frac16();
            let (i, j) = match edge {
                0 => (1, 2),
                1 => (2, 0),
                _ => (0, 1),
            };
            let (pi_, pj) = (&thp.vertices[i], &thp.vertices[j]);
            let along = pj.sub(pi_);
            let e_dir = Vec2::new(along.x.clone() / &thp.a, along.y.clone() / &thp.a);
            let mid = Vec2::new(
                thp.centres[edge as usize].x.clone() / 2u32,
                thp.centres[edge as usize].y.clone() / 2u32,
            );
            let line_through = |line: u8| match line {
                0 => {
                    let n = &thp.normals[edge as usize];
                    (
                        Vec2::new(mid.x.clone() + &n.x, mid.y.clone() + &n.y),
                        e_dir.clone(),
                    )
                }
                _ => {
                    // Inner tangents: through the midpoint at angle ±α, sin α = 2/a.
                    let alpha = (hp(2.0) / &thp.a).asin();
                    let th = angle_of(&e_dir);
                    let th = if line == 1 { th + &alpha } else { th - &alpha };
                    (mid.clone(), unit(&th))
                }
            };
            // The outer tangent runs through the opposite disk for all its length inside the
            // triangle when w is small; then the first inner tangent is used instead.
            [line, 1].into_iter().find_map(|line| {
                let (anchor, dir) = line_through(line);
                geo.point_on_line(&anchor, &dir, s_f).map(|p| {
                    let v = if back { -dir.clone() } else { dir };
                    (
                        PrimitiveCase::DoubleTangent { edge, line },
                        round(&p),
                        v,
                        None,
                    )
                })
            })
        }
        3 => {
            let edge = r.u8() % 3;
            let end = r.u8() % 2;
            let at_point = r.u8() & 1 == 1;
            let ang = r.frac32();
            let (u1, u2) = (r.frac16(), r.frac16());
            let (i, j) = match edge {
                0 => (1usize, 2usize),
                1 => (2, 0),
                _ => (0, 1),
            };
            let (from, to) = if end == 0 { (i, j) } else { (j, i) };
            let d = thp.vertices[to].sub(&thp.vertices[from]);
            let g = Vec2::new(
                thp.vertices[from].x.clone() + &(d.x.clone() / &thp.a),
                thp.vertices[from].y.clone() + &(d.y.clone() / &thp.a),
            );
            let case = PrimitiveCase::GapPoint {
                edge,
                end,
                at_point,
            };
            if at_point {
                Some((case, round(&g), unit(&(two_pi.clone() * &hp(ang))), None))
            } else {
                let p64 = geo.free_point(u1, u2);
                let p = Vec2::<Float>::from_f64(ORACLE_BITS, p64.x, p64.y);
                let to_g = g.sub(&p);
                (to_g.norm2().to_f64() > 1e-6).then(|| (case, p64, unit(&angle_of(&to_g)), None))
            }
        }
        _ => None,
    };
    let (case, pos, vel_hp, excluded_disk) = built.unwrap_or_else(|| {
        // Arbitrary (also the fall-back of a failed construction: reads its own bytes).
        let (u1, u2) = (r.frac16(), r.frac16());
        let ang = r.frac32();
        (
            PrimitiveCase::Arbitrary,
            geo.free_point(u1, u2),
            unit(&(two_pi.clone() * &hp(ang))),
            None,
        )
    });
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
    PrimitiveInput {
        case,
        w,
        flight,
        events,
    }
}

/// Decodes the input of [`collision_primitive`].
///
/// # Errors
/// If the decoded state is not valid (a decoder bug, never expected).
pub fn decode_primitive(data: &[u8]) -> Result<PrimitiveInput, OracleFailure> {
    let input = decode_flight(&mut Bytes::new(data));
    let thp = Trap::new(hp(input.w)).expect("w > 0");
    validate(&thp, &input.flight).map_err(|reason| OracleFailure {
        case: Some(input.case),
        event: None,
        reason,
        state: format!("w = {:e}, {:?}", input.w, input.flight),
    })?;
    Ok(input)
}

/// Decodes the input of [`scene_stepper`]: trap index (i, j) ∈ [−10⁹, 10⁹]², orientation,
/// step count, then the flight as for [`decode_primitive`].
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
    let primitive = decode_primitive(rest)?;
    Ok(SceneInput {
        primitive,
        cell: CellIndex { i, j, down },
        steps,
    })
}

/// Judges up to four successive events of a decoded canonical-trap state against the one-step
/// error model by MPFR replay ([`check_event`] at [`ORACLE_BITS`]): the replay must be
/// `in_model`, the f64 event time finite and ≥ 0, no error or bound NaN, the post-event state
/// finite.
///
/// # Errors
/// The first violation, with the state before the failing event.
pub fn collision_primitive(data: &[u8]) -> Result<OracleReport, OracleFailure> {
    let input = decode_primitive(data)?;
    let t64 = Trap::new(input.w).expect("w > 0");
    let tref = Trap::new(hp(input.w)).expect("w > 0");
    let mut f = input.flight.clone();
    let mut rep = OracleReport {
        case: input.case,
        w: input.w,
        events: 0,
        collisions: 0,
        crossings: 0,
        ambiguous: 0,
        worst_time_ratio: 0.0,
        worst_energy_u: 0.0,
    };
    for n in 0..input.events as u64 {
        let before = f.clone();
        let fail = |reason: String| OracleFailure {
            case: Some(input.case),
            event: Some(n),
            reason,
            state: format!("w = {:e}, {:?}", input.w, before),
        };
        let c = check_event(&t64, &tref, &f).map_err(|e| fail(format!("check_event: {e}")))?;
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
        let ev: Event<f64> = t64
            .next_event(&f)
            .ok_or_else(|| fail("no next event".into()))?;
        if !(ev.time.is_finite() && ev.time >= 0.0) {
            return Err(fail(format!("bad f64 event time {:e}", ev.time)));
        }
        if c.kind_f64 == c.kind_ref && c.time_bound > 0.0 && c.time_bound.is_finite() {
            rep.worst_time_ratio = rep.worst_time_ratio.max(c.time_error / c.time_bound);
        }
        rep.ambiguous += c.ambiguous as u64;
        t64.apply(&mut f, &ev);
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

/// Steps a decoded lattice state in `f64` and checks after every event (bounds of
/// `tests/kernel_properties.rs`, `proofs-notes/energy.md`, `tests/physics.rs`):
///
/// * event time finite, ≥ 0 and ≤ 2a (a chord of the triangle is ≤ a); state finite;
/// * after a collision ||v|² − 1| ≤ 128u; after a crossing |v|² unchanged bit for bit;
/// * |x − c|² ≥ 1 − 256u for every vertex disk, σₖ(x) ≥ −256u·a for every edge;
/// * unwrapped world displacement = t·(s·v) within 64ε(a + t);
/// * the cell moves by `Cell::across(k)` exactly on `Crossing(k)` and not at all on a collision;
///   the disk hit / edge crossed is the one excluded.
///
/// # Errors
/// The first violation, with the state before the failing event.
pub fn scene_stepper(data: &[u8]) -> Result<OracleReport, OracleFailure> {
    let input = decode_scene(data)?;
    let w = input.primitive.w;
    let lat = TriangularLattice::new(w).expect("w > 0");
    let basis = lat.basis_f64();
    let a = basis.a;
    let mut s = LatticeState {
        cell: input.cell,
        flight: input.primitive.flight.clone(),
    };
    let mut rep = OracleReport {
        case: input.primitive.case,
        w,
        events: 0,
        collisions: 0,
        crossings: 0,
        ambiguous: 0,
        worst_energy_u: 0.0,
        worst_time_ratio: 0.0,
    };
    for n in 0..input.steps as u64 {
        let before = s.clone();
        let fail = |reason: String| OracleFailure {
            case: Some(input.primitive.case),
            event: Some(n),
            reason,
            state: format!("w = {w:e}, {before:?}"),
        };
        let u_before = lat.unwrapped(&s, 0.0);
        let sg = s.cell.sign();
        let (vx, vy) = (sg * s.flight.vel.x, sg * s.flight.vel.y);
        let e2_before = s.flight.vel.norm2();
        let ev = lat
            .step(&mut s)
            .map_err(|e| fail(format!("step failed: {e}")))?;
        let fl = &s.flight;
        if !(ev.time.is_finite() && ev.time >= 0.0 && ev.time <= 2.0 * a) {
            return Err(fail(format!(
                "bad event time {:e} ({:?})",
                ev.time, ev.kind
            )));
        }
        if ![fl.pos.x, fl.pos.y, fl.vel.x, fl.vel.y]
            .iter()
            .all(|x| x.is_finite())
        {
            return Err(fail(format!(
                "non-finite state after {:?}: {fl:?}",
                ev.kind
            )));
        }
        let e2 = fl.vel.norm2();
        match ev.kind {
            EventKind::Collision(m) => {
                rep.collisions += 1;
                let dev = (e2 - 1.0).abs() / U;
                rep.worst_energy_u = rep.worst_energy_u.max(dev);
                if dev.is_nan() || dev > 128.0 {
                    return Err(fail(format!(
                        "|v|^2 - 1 = {:e} = {dev} u after a collision",
                        e2 - 1.0
                    )));
                }
                if s.cell != before.cell {
                    return Err(fail(format!("cell changed on a collision: {:?}", s.cell)));
                }
                if fl.excluded_disk != Some(m) || fl.excluded_edge.is_some() {
                    return Err(fail(format!("exclusions after collision {m}: {fl:?}")));
                }
            }
            EventKind::Crossing(k) => {
                rep.crossings += 1;
                if e2.to_bits() != e2_before.to_bits() {
                    return Err(fail(format!(
                        "|v|^2 changed on a crossing: {e2_before:e} -> {e2:e}"
                    )));
                }
                let edge = &lat.cell().edges[k as usize];
                if s.cell != before.cell.across(edge) {
                    return Err(fail(format!(
                        "cell {:?} after crossing {k}, expected {:?}",
                        s.cell,
                        before.cell.across(edge)
                    )));
                }
                if fl.excluded_edge != Some(edge.entered) {
                    return Err(fail(format!("exclusions after crossing {k}: {fl:?}")));
                }
            }
        }
        for (m, c) in lat.trap().vertices.iter().enumerate() {
            let r2 = fl.pos.sub(c).norm2();
            if r2.is_nan() || r2 < 1.0 - 256.0 * U {
                return Err(fail(format!(
                    "inside disk {m} after {:?}: |x-c|^2 = {r2:e}",
                    ev.kind
                )));
            }
        }
        for k in 0..3 {
            let sig = lat.trap().edge_distance(k, &fl.pos);
            if sig.is_nan() || sig < -256.0 * U * a {
                return Err(fail(format!(
                    "outside edge {k} after {:?}: sigma = {sig:e}",
                    ev.kind
                )));
            }
        }
        let d = lat.unwrapped(&s, 0.0).displacement_from(&u_before, &basis);
        let err = ((d[0] - ev.time * vx).powi(2) + (d[1] - ev.time * vy).powi(2)).sqrt();
        if err.is_nan() || err > 64.0 * f64::EPSILON * (a + ev.time) {
            return Err(fail(format!("unwrapped jump {err:e} over {:?}", ev.kind)));
        }
        rep.events += 1;
    }
    Ok(rep)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_input_decodes_and_passes() {
        assert!(collision_primitive(&[]).is_ok());
        assert!(scene_stepper(&[]).is_ok());
    }

    #[test]
    fn nudge_moves_by_ulps() {
        assert_eq!(nudge(1.0, 1), 1.0 + f64::EPSILON);
        assert_eq!(nudge(1.0, -2), 1.0 - f64::EPSILON);
        assert_eq!(nudge(0.0, 1), f64::from_bits(1));
        assert_eq!(nudge(-0.5, 0), -0.5);
    }

    #[test]
    fn w_stays_below_w_inf() {
        let wi = Geometry::<Float>::w_inf(ORACLE_BITS);
        assert!(hp(w_max()) < wi);
        for mode in 0..4u8 {
            for n in [0u32, 1, 12345, u32::MAX] {
                let b = [&[mode][..], &n.to_le_bytes()[..]].concat();
                let w = decode_w(&mut Bytes::new(&b));
                assert!(w > 0.0 && hp(w) < wi, "mode {mode} n {n}: w = {w:e}");
            }
        }
    }
}
