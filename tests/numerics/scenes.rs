//! The scene interface: the generic cell kernel and the triangular trap's fused fast path agree
//! bit for bit (every event kind, flight time, position, velocity, exclusion and cell index), in
//! `f64` and in MPFR at 53 bits; grazing starts, starts on an edge and starts aimed at the
//! corners where a gap meets a disk included. This is what lets the
//! shadow audit, the fuzz oracle and the tangent map work from the generic cell description
//! while production runs use the fused path.

use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::kernel::{cell::ConvexCell, flight::Flight};
use lorentz_gas::numbers::real::Real;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::lattice::{Lattice, LatticeState, TriangularLattice};
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::triangular::TriangularScene;
use lorentz_gas::verification::error_model::UNIT_ROUNDOFF;
use rand::Rng;
use rug::Float;

/// The gaps of `tests/numerics/bit_for_bit.rs`: tiny, small, the paper's, w₀, large, near w∞.
const GAPS: [f64; 7] = [0.005, 0.02, 0.1, 0.1547, 0.2, 0.3, 0.3094];

/// Equal values with equal signs (the sign of a zero shows in the `f64` bits).
fn same_bits<T: Real>(a: &T, b: &T) -> bool {
    a.to_f64().to_bits() == b.to_f64().to_bits() && a == b
}

fn compare_runs<T: Real>(
    fused: &TriangularLattice<T>,
    generic: &Lattice<T, ConvexCell<T>>,
    start: LatticeState<T>,
    events: usize,
    what: &str,
) {
    let (mut a, mut b) = (start.clone(), start);
    for i in 0..events {
        let ea = fused.step(&mut a).unwrap();
        let eb = generic.step(&mut b).unwrap();
        assert_eq!(ea.kind, eb.kind, "{what}: event {i}");
        assert!(same_bits(&ea.time, &eb.time), "{what}: event {i} time");
        assert_eq!(a.cell, b.cell, "{what}: event {i} cell");
        let (fa, fb) = (&a.flight, &b.flight);
        assert_eq!(fa.excluded_disk, fb.excluded_disk, "{what}: event {i}");
        assert_eq!(fa.excluded_edge, fb.excluded_edge, "{what}: event {i}");
        for (x, y) in [
            (&fa.pos.x, &fb.pos.x),
            (&fa.pos.y, &fb.pos.y),
            (&fa.vel.x, &fb.vel.x),
            (&fa.vel.y, &fb.vel.y),
        ] {
            assert!(same_bits(x, y), "{what}: event {i} state {x:?} vs {y:?}");
        }
    }
}

#[test]
fn generic_cell_kernel_reproduces_the_fused_trap_bit_for_bit_in_f64() {
    for (k, &w) in GAPS.iter().enumerate() {
        let scene = TriangularScene::new(w).unwrap();
        let fused = scene.lattice::<f64>(()).unwrap();
        let generic = Lattice::from_kernel(fused.trap().cell().clone());
        for run in 0..2u64 {
            let start = scene.sample(&mut stream(61, 2 * k as u64 + run));
            compare_runs(
                &fused,
                &generic,
                start,
                100_000,
                &format!("f64 w={w} run {run}"),
            );
        }
    }
}

#[test]
fn generic_cell_kernel_reproduces_the_fused_trap_bit_for_bit_in_mpfr() {
    for (k, &w) in GAPS.iter().enumerate() {
        let scene = TriangularScene::new(w).unwrap();
        for bits in [53u32, 113] {
            let fused = scene.lattice::<Float>(bits).unwrap();
            let generic = Lattice::from_kernel(fused.trap().cell().clone());
            let s64 = scene.sample(&mut stream(62, k as u64));
            let start = LatticeState::<Float>::convert_from_f64(bits, &s64);
            compare_runs(
                &fused,
                &generic,
                start,
                3_000,
                &format!("{bits} bits w={w}"),
            );
        }
    }
}

/// The six points where a gap meets a disk, each with its disk's outward normal n there: on
/// each edge PᵢPⱼ (length a, unit disks), at distance 1 from either end, n = ±(Pⱼ − Pᵢ)/a along
/// the edge. A ray with direction d reaches the corner before its disk only if n·d < 0; it meets
/// the disk at the angle whose cosine is |n·d| and the edge at |n × d|.
fn gap_disk_corners(t: &lorentz_gas::kernel::trap::Trap<f64>) -> Vec<(Vec2<f64>, Vec2<f64>)> {
    let mut out = Vec::new();
    for (i, j) in [(0, 1), (1, 2), (2, 0)] {
        let (p, q) = (&t.vertices()[i], &t.vertices()[j]);
        let e = Vec2::new((q.x - p.x) / t.a(), (q.y - p.y) / t.a());
        out.push((Vec2::new(p.x + e.x, p.y + e.y), e.clone()));
        out.push((Vec2::new(q.x - e.x, q.y - e.y), Vec2::new(-e.x, -e.y)));
    }
    out
}

/// Starts aimed at the corners where a gap meets a disk — where a collision and a crossing
/// happen at the same time and the two paths could plausibly choose differently: from those of
/// eight points on a circle around the trap centre (a fifth of the free radius a/√3 − 1) that see
/// the corner in front of its disk, each ray turned by k·10⁻¹⁶ rad
/// (k = −2 … 2) about the direction to the corner, so the rays pass the corner within a few ulps
/// on both sides. Each ray's first event must be at the corner (within its lateral offset and
/// rounding over the cosine of its angle of incidence: the aim is checked, not assumed), and both
/// kinds of first event must occur among the rays at each gap.
#[test]
fn generic_and_fused_agree_on_starts_aimed_at_the_gap_disk_corners() {
    use lorentz_gas::kernel::flight::EventKind;
    for &w in &GAPS {
        let lat = TriangularLattice::new(w).unwrap();
        let generic = Lattice::from_kernel(lat.trap().cell().clone());
        let t = lat.trap().clone();
        let centre = Vec2::new(t.a() / 2.0, t.h() / 3.0);
        // A fifth of the free radius a/√3 − 1 around the centre: every corner is in sight.
        let rho = 0.2 * (t.a() / 3f64.sqrt() - 1.0);
        let (mut collisions, mut crossings, mut aimed) = (0, 0, 0);
        for (n, (corner, normal)) in gap_disk_corners(&t).into_iter().enumerate() {
            for o in 0..8 {
                let ang = o as f64 * std::f64::consts::FRAC_PI_4;
                let p = Vec2::new(centre.x + rho * ang.cos(), centre.y + rho * ang.sin());
                let aim = (corner.y - p.y).atan2(corner.x - p.x);
                if normal.x * aim.cos() + normal.y * aim.sin() >= 0.0 {
                    continue; // the corner is behind its own disk from here
                }
                aimed += 1;
                for k in -2i32..=2 {
                    let th = aim + k as f64 * 1e-16;
                    let start = LatticeState {
                        cell: Default::default(),
                        flight: Flight::new(p.clone(), Vec2::new(th.cos(), th.sin())),
                    };
                    let what = format!("corner w={w} corner {n} from {o} turned {k}");
                    let mut first = start.clone();
                    let ev = lat.step(&mut first).unwrap();
                    let (dx, dy) = (th.cos(), th.sin());
                    let hit = Vec2::new(p.x + ev.time * dx, p.y + ev.time * dy);
                    let miss = (hit.x - corner.x).hypot(hit.y - corner.y);
                    // The ray passes the corner at the lateral distance of its turn plus the
                    // rounding of corner, origin, direction and hit point (each term doubled);
                    // on the disk or the edge that is stretched by 1/cos of the angle of
                    // incidence (rays to a corner next to a narrow gap come in nearly tangent).
                    let dist = (corner.x - p.x).hypot(corner.y - p.y);
                    let lateral = 2.0
                        * (k.abs() as f64 * 1e-16 * dist + 16.0 * UNIT_ROUNDOFF * (t.a() + dist));
                    let cos = (normal.x * dx + normal.y * dy)
                        .abs()
                        .min((normal.x * dy - normal.y * dx).abs());
                    assert!(
                        miss <= lateral / cos,
                        "{what}: first event {:?} at {miss:e} from the corner {corner:?}, more than {:e}",
                        ev.kind,
                        lateral / cos
                    );
                    match ev.kind {
                        EventKind::Collision(_) => collisions += 1,
                        EventKind::Crossing(_) => crossings += 1,
                    }
                    compare_runs(&lat, &generic, start, 2_000, &what);
                }
            }
        }
        // Every corner is in sight from about half the circle: at least 3 of the 8 origins.
        assert!(
            aimed >= 6 * 3,
            "w={w}: only {aimed} origins see their corner"
        );
        assert!(
            collisions > 0 && crossings > 0,
            "w={w}: the rays at the corners gave {collisions} collisions and {crossings} crossings"
        );
    }
}

/// Degenerate starts where the two paths could plausibly round differently: grazing the vertex
/// disks (impact parameter 1 ∓ 2⁻ᵏ), starting on an edge, flying along an edge (the starts aimed
/// at the gap–disk corners are [`generic_and_fused_agree_on_starts_aimed_at_the_gap_disk_corners`]).
#[test]
fn generic_and_fused_agree_on_grazing_and_edge_starts() {
    let mut rng = stream(63, 0);
    for &w in &GAPS {
        let lat = TriangularLattice::new(w).unwrap();
        let generic = Lattice::from_kernel(lat.trap().cell().clone());
        let t = lat.trap().clone();
        for k in 1..53 {
            let b = 1.0 - (-(k as f64)).exp2() * if rng.random::<bool>() { 1.0 } else { -1.0 };
            // From the base-gap midpoint towards P₂ with impact parameter b.
            let p = Vec2::new(t.a() / 2.0, 0.0);
            let to = Vec2::new(t.vertices()[2].x - p.x, t.vertices()[2].y - p.y);
            let d = (to.x * to.x + to.y * to.y).sqrt();
            let alpha = (b / d).asin();
            let th = to.y.atan2(to.x) + alpha;
            let start = LatticeState {
                cell: Default::default(),
                flight: Flight::new(p, Vec2::new(th.cos(), th.sin())),
            };
            compare_runs(&lat, &generic, start, 2_000, &format!("graze w={w} k={k}"));
        }
        for e in 0..3 {
            // On the gap of each edge, moving along the edge and across it.
            let c = &t.centres()[e];
            let mid = Vec2::new(c.x / 2.0, c.y / 2.0);
            let n = &t.normals()[e];
            for v in [
                Vec2::new(-n.y, n.x),
                Vec2::new(n.y, -n.x),
                Vec2::new(-n.x, -n.y),
            ] {
                let start = LatticeState {
                    cell: Default::default(),
                    flight: Flight::new(mid.clone(), v),
                };
                compare_runs(&lat, &generic, start, 2_000, &format!("edge w={w} e={e}"));
            }
        }
    }
}
