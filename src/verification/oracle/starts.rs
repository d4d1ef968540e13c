//! The six families of decoded starts (impacts, near-surface starts, double tangents, rim points, corners, arbitrary states) and the decoders of primitive and lattice inputs.

use super::*;

/// A decoded start: family, position, high-precision velocity, excluded disk.
pub(super) type Built = (PrimitiveCase, Vec2<f64>, Vec2<Float>, Option<u8>);

/// Number of families selected by the case byte (its value modulo this).
pub(super) const FAMILIES: u8 = 6;

/// Decodes a start in the cell of `scene` from the case byte `sel` and the case's own bytes
/// (see `proofs-notes/fuzzing.md` for the layout); the bytes of each family are always read in
/// full (a fixed layout per family).
pub(super) fn build_flight(geo: &Geo, sel: u8, r: &mut Bytes) -> (PrimitiveCase, Flight<f64>) {
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
pub(super) fn two_pi() -> Float {
    pi() * 2u32
}

/// Family 0 ([`PrimitiveCase::Impact`]): aimed at a disk with impact parameter r(1 ∓ 2⁻ᵏ), from a
/// free start.
pub(super) fn impact_start(geo: &Geo, r: &mut Bytes) -> Option<Built> {
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
    let b = chp.disks[disk as usize].radius().clone() * &hp(factor);
    let c = &chp.disks[disk as usize].centre;
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
pub(super) fn near_surface_start(geo: &Geo, r: &mut Bytes) -> Option<Built> {
    let chp = &geo.chp;
    let nd = geo.n_disks();
    let half_pi = pi() / 2u32;
    let disk = r.u8() % nd as u8;
    let k = 1 + r.u8() % 60;
    let motion = r.u8() % 3;
    let flags = r.u8();
    let (psi_f, chi_f) = (r.frac16(), r.open16());
    let excluded = motion != 0 && flags & 1 == 1;
    let c = &chp.disks[disk as usize].centre;
    let arcs = geo.free_arcs(disk as usize);
    let dist = chp.disks[disk as usize].radius().clone() * &(hp(1.0) + &hp((-(k as f64)).exp2()));
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
pub(super) fn double_tangent_start(geo: &Geo, r: &mut Bytes) -> Option<Built> {
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
        let d0 = &chp.disks[0];
        let anchor = d0.centre.along(&(d0.radius().clone() * &side), n);
        let dir = Vec2::new(n.y.clone(), -n.x.clone());
        found(pair, line, anchor, dir)
    }
}

/// The common tangents of two disks of the cell: the midpoint of their centres, the direction
/// of the centre line and its normal towards the cell, the centres' distance, the radius.
pub(super) struct PairTangents {
    pub(super) mid: Vec2<Float>,
    pub(super) e_dir: Vec2<Float>,
    pub(super) n: Vec2<Float>,
    pub(super) len: Float,
    pub(super) radius: Float,
}

impl PairTangents {
    /// The disks chosen by `pair`: the two disks, or the two after disk `pair` (cyclically).
    pub(super) fn new(geo: &Geo, pair: u8) -> Self {
        let chp = &geo.chp;
        let nd = geo.n_disks();
        let (i, j) = if nd == 2 {
            (0, 1)
        } else {
            ((pair as usize + 1) % nd, (pair as usize + 2) % nd)
        };
        // The oracle's scenes (triangular, square) have disks of one radius: disk i's.
        let (ci, cj) = (&chp.disks[i].centre, &chp.disks[j].centre);
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
            radius: chp.disks[i].radius().clone(),
        }
    }

    /// Tangent `line` as (anchor, direction): 0 the outer one on the cell's side, 1 and 2 the
    /// inner ones.
    pub(super) fn line(&self, line: u8) -> (Vec2<Float>, Vec2<Float>) {
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
pub(super) fn gap_point_start(geo: &Geo, r: &mut Bytes) -> Option<Built> {
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
pub(super) fn corner_start(geo: &Geo, r: &mut Bytes) -> Option<Built> {
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
pub(super) fn arbitrary_start(geo: &Geo, r: &mut Bytes) -> Built {
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
pub(super) fn decode_flight(r: &mut Bytes) -> Result<(PrimitiveInput, Geo), String> {
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
pub(super) fn decode_validated(data: &[u8]) -> Result<(PrimitiveInput, Geo), OracleFailure> {
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
