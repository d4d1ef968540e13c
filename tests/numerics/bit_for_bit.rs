//! Differential test: the generic kernel instantiated with `rug::Float` at 53 bits reproduces
//! the `f64` instantiation bit for bit — every event kind, flight time, position, velocity and
//! trap index — which proves the generic code contains no stray `f64` operation, constant or
//! non-correctly-rounded function (proofs-notes/bit-for-bit.md).

use lorentz_gas::kernel::flight::Event;
use lorentz_gas::numbers::real::Real;
use lorentz_gas::scenes::lattice::{LatticeState, TriangularLattice};
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::triangular::equilibrium_state;
use rug::Float;

fn same(a: f64, b: &Float) -> bool {
    a.to_bits() == b.to_f64().to_bits() && Float::with_val(53, a) == *b
}

#[test]
fn rug53_reproduces_f64_bit_for_bit() {
    for (k, &w) in [0.005, 0.02, 0.1, 0.1547, 0.2, 0.3, 0.3094]
        .iter()
        .enumerate()
    {
        let l64 = TriangularLattice::new(w).unwrap();
        let l53 = TriangularLattice::new(Float::with_val(53, w)).unwrap();
        let mut s64 = equilibrium_state(l64.trap(), &mut stream(11, k as u64));
        let mut s53 = LatticeState::<Float>::convert_from_f64(53, &s64);
        for i in 0..30_000 {
            let e64: Event<f64> = l64.step(&mut s64).unwrap();
            let e53: Event<Float> = l53.step(&mut s53).unwrap();
            assert_eq!(e64.kind, e53.kind, "w={w} event {i}");
            assert!(
                same(e64.time, &e53.time),
                "w={w} event {i}: time {} vs {}",
                e64.time,
                e53.time
            );
            assert_eq!(s64.cell, s53.cell, "w={w} event {i}");
            let f = &s53.flight;
            assert!(
                same(s64.flight.pos.x, &f.pos.x) && same(s64.flight.pos.y, &f.pos.y),
                "w={w} event {i} pos"
            );
            assert!(
                same(s64.flight.vel.x, &f.vel.x) && same(s64.flight.vel.y, &f.vel.y),
                "w={w} event {i} vel"
            );
        }
    }
}

#[test]
fn constants_at_53_bits_are_the_f64_constants() {
    use lorentz_gas::scenes::triangular::geometry::Geometry;
    let g64 = Geometry::new(0.1f64).unwrap();
    let g53 = Geometry::new(Float::with_val(53, 0.1)).unwrap();
    assert!(same(g64.mean_free_path(), &g53.mean_free_path()));
    assert!(same(g64.hop_time(), &g53.hop_time()));
    assert!(same(g64.d_mz(), &g53.d_mz()));
    assert!(same(
        Geometry::<f64>::w_inf(()),
        &Geometry::<Float>::w_inf(53)
    ));
    assert!(same(<f64 as Real>::pi(()), &<Float as Real>::pi(53)));
}
