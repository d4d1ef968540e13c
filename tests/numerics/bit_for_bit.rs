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

/// A gap given exactly (`w_exact`, as `--w 1/10` records it) reaches MPFR unrounded: at 53 bits
/// it is the double and the run keeps the bits of the `f64` run; at 128 bits it is 1/10 to 128
/// bits, 5.6·10⁻¹⁸ from the double, and a chaotic trajectory (Lyapunov exponent ≈ 2 per unit
/// time) turns that into a different run within a few dozen collisions, so D differs. A
/// `w_exact` that does not round to `w` is refused before any work.
#[test]
fn an_exact_gap_reaches_mpfr_without_the_doubles_rounding() {
    use lorentz_gas::estimators::diffusion::{DiffusionConfig, run};
    use lorentz_gas::numbers::precision::Precision;
    use lorentz_gas::scenes::spec::Table;
    let base = DiffusionConfig {
        collisions: 20_000,
        batches: 2,
        window: "2:8".parse().unwrap(),
        check_window: "3:9".parse().unwrap(),
        ..DiffusionConfig::new(0.1)
    };
    let d = |precision: Precision, exact: Option<&str>| {
        let table = exact.map_or(Table::triangular_at(0.1), |t| Table::triangular(t).unwrap());
        let cfg = DiffusionConfig {
            precision,
            table,
            ..base.clone()
        };
        let r = run(&cfg, &crate::common::threads(2)).unwrap();
        (r.D.to_bits(), r.mean_free_path.to_bits())
    };
    let f64_run = d(Precision::F64, None);
    assert_eq!(d(Precision::Bits(53), Some("1/10")), f64_run);
    assert_eq!(d(Precision::F64, Some("1/10")), f64_run);
    let of_double = d(Precision::Bits(128), None);
    let of_tenth = d(Precision::Bits(128), Some("1/10"));
    assert_eq!(d(Precision::Bits(128), Some("0.1")), of_tenth);
    assert_ne!(
        of_tenth, of_double,
        "1/10 at 128 bits ran as the double 0.1"
    );
    // A record whose exact gap is not its double is refused as it is read.
    let mut wrong = serde_json::to_value(&base).unwrap();
    wrong["w_exact"] = "1/5".into();
    let e = serde_json::from_value::<DiffusionConfig>(wrong)
        .unwrap_err()
        .to_string();
    assert!(e.contains("w_exact = '1/5': not w = 0.1"), "{e}");
}
