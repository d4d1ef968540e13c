//! `cargo bench`: kernel cost per collision, f64 and MPFR side by side in one run (divan reports
//! medians). The CLI's `lorentz bench` gives the same number as collisions per second.

use divan::Bencher;
use lorentz_gas::real::Real;
use lorentz_gas::sampling::stream;
use lorentz_gas::scenes::lattice::{LatticeState, TriangularLattice};
use lorentz_gas::scenes::triangular::equilibrium_state;
use rug::Float;

fn main() {
    divan::main();
}

const COLLISIONS: u64 = 1000;

fn run<T: Real>(b: Bencher, lat: &TriangularLattice<T>, start: LatticeState<T>) {
    let mut s = start;
    b.counter(divan::counter::ItemsCount::new(COLLISIONS))
        .bench_local(|| lat.run_collisions(&mut s, COLLISIONS).unwrap());
}

#[divan::bench(args = [0.02, 0.1, 0.3])]
fn f64_collisions(b: Bencher, w: f64) {
    let lat = TriangularLattice::new(w).unwrap();
    let s = equilibrium_state(lat.trap(), &mut stream(1, 0));
    run(b, &lat, s);
}

#[divan::bench(args = [53, 128, 256, 1024], sample_count = 20)]
fn mpfr_collisions_w_0_1(b: Bencher, bits: u32) {
    let lat64 = TriangularLattice::new(0.1).unwrap();
    let s64 = equilibrium_state(lat64.trap(), &mut stream(1, 0));
    let lat = TriangularLattice::new(Float::with_val(bits, 0.1)).unwrap();
    let mut s = LatticeState::<Float>::convert_from_f64(bits, &s64);
    s.flight.normalise_speed();
    run(b, &lat, s);
}
