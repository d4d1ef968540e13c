//! The scene interface: the generic cell kernel and the triangular trap's fused fast path agree
//! bit for bit (every event kind, flight time, position, velocity, exclusion and cell index), in
//! `f64` and in MPFR at 53 bits; grazing and near-corner starts included. This is what lets the
//! shadow audit, the fuzz oracle and the tangent map work from the generic cell description
//! while production runs use the fused path.

use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::kernel::{cell::ConvexCell, flight::Flight};
use lorentz_gas::numbers::real::Real;
use lorentz_gas::scenes::lattice::{Lattice, LatticeState, TriangularLattice};
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::triangular::TriangularScene;
use lorentz_gas::scenes::Scene;
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
        let generic = Lattice::from_kernel(fused.trap().cell.clone());
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
            let generic = Lattice::from_kernel(fused.trap().cell.clone());
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

/// Degenerate starts where the two paths could plausibly round differently: grazing the vertex
/// disks (impact parameter 1 ∓ 2⁻ᵏ), starting on an edge, aiming at the points where a gap
/// meets a disk, flying along an edge.
#[test]
fn generic_and_fused_agree_on_grazing_and_edge_starts() {
    let mut rng = stream(63, 0);
    for &w in &GAPS {
        let lat = TriangularLattice::new(w).unwrap();
        let generic = Lattice::from_kernel(lat.trap().cell.clone());
        let t = lat.trap().clone();
        for k in 1..53 {
            let b = 1.0 - (-(k as f64)).exp2() * if rng.random::<bool>() { 1.0 } else { -1.0 };
            // From the base-gap midpoint towards P₂ with impact parameter b.
            let p = Vec2::new(t.a / 2.0, 0.0);
            let to = Vec2::new(t.vertices[2].x - p.x, t.vertices[2].y - p.y);
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
            let c = &t.centres[e];
            let mid = Vec2::new(c.x / 2.0, c.y / 2.0);
            let n = &t.normals[e];
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
