//! `cargo bench -p lorentz-gas-benches --bench kernel`: cost per collision of the engines side by side in one run (divan reports
//! medians): the scalar engine in f64 and MPFR, and the SIMD engine (16 trajectories in vector
//! lanes) on every instruction path this CPU has, bare, with the observers of `lorentz
//! diffusion` and with those of `lorentz hops` (order 3). The CLI's `lorentz bench` gives the
//! same numbers as collisions per second.

use divan::Bencher;
use lorentz_gas::engine::observe::Nothing;
use lorentz_gas::engine::simd::BLOCK;
use lorentz_gas::engine::{SimdPath, drive, run_block};
use lorentz_gas::numbers::real::Real;
use lorentz_gas::observers::counters::CounterLanes;
use lorentz_gas::observers::msd::Msd;
use lorentz_gas::scenes::lattice::{LatticeState, TriangularLattice};
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::triangular::equilibrium_state;
use lorentz_gas::scenes::triangular::geometry::Geometry;
use rug::Float;

fn main() {
    divan::main();
}

/// Collisions per timed call of the scalar engine.
const COLLISIONS: u64 = 1000;

/// Collisions per lane per timed call of the SIMD engine (16 lanes: 16 000 collisions).
const LANE_COLLISIONS: u64 = 1000;

fn run<T: Real>(b: Bencher, lat: &TriangularLattice<T>, start: LatticeState<T>) {
    let mut s = start;
    b.counter(divan::counter::ItemsCount::new(COLLISIONS))
        .bench_local(|| drive(lat, &mut s, COLLISIONS, &mut Nothing, &|_| {}).unwrap());
}

#[divan::bench(args = [0.02, 0.1, 0.3])]
fn scalar_f64(b: Bencher, w: f64) {
    let lat = TriangularLattice::new(w).unwrap();
    let s = equilibrium_state(lat.trap(), &mut stream(1, 0));
    run(b, &lat, s);
}

#[divan::bench(args = [53, 128, 256, 1024], sample_count = 20)]
fn scalar_mpfr_w_0_1(b: Bencher, bits: u32) {
    let lat64 = TriangularLattice::new(0.1).unwrap();
    let s64 = equilibrium_state(lat64.trap(), &mut stream(1, 0));
    let lat = TriangularLattice::new(Float::with_val(bits, 0.1)).unwrap();
    let mut s = LatticeState::<Float>::convert_from_f64(bits, &s64);
    s.flight.normalise_speed();
    run(b, &lat, s);
}

fn simd<O: lorentz_gas::engine::observe::Observer<BLOCK>>(
    b: Bencher,
    path: SimdPath,
    w: f64,
    mut obs: impl FnMut() -> O,
) {
    if !path.available() {
        return;
    }
    let lat = TriangularLattice::new(w).unwrap();
    let mut states: Vec<_> = (0..BLOCK as u64)
        .map(|l| equilibrium_state(lat.trap(), &mut stream(1, l)))
        .collect();
    let quotas = vec![LANE_COLLISIONS; BLOCK];
    b.counter(divan::counter::ItemsCount::new(
        LANE_COLLISIONS * BLOCK as u64,
    ))
    .bench_local(|| {
        run_block(path, lat.trap(), &mut states, &quotas, &mut obs(), &|_| {}).unwrap()
    });
}

#[divan::bench(args = [SimdPath::Avx512, SimdPath::Avx2, SimdPath::Portable])]
fn simd_bare_w_0_1(b: Bencher, path: SimdPath) {
    simd(b, path, 0.1, || Nothing);
}

#[divan::bench(args = [0.02, 0.1, 0.3])]
fn simd_best_bare(b: Bencher, w: f64) {
    simd(b, SimdPath::best(), w, || Nothing);
}

#[divan::bench(args = [0.02, 0.1, 0.3])]
fn simd_best_with_diffusion_observers(b: Bencher, w: f64) {
    let lat = TriangularLattice::new(w).unwrap();
    let tau = Geometry::new(w).unwrap().hop_time();
    let lags = lorentz_gas::estimators::diffusion::DiffusionConfig::new(w).lags();
    let basis = lat.basis_f64();
    simd(b, SimdPath::best(), w, || {
        (CounterLanes::new(BLOCK), Msd::new(tau, &lags, basis, BLOCK))
    });
}

#[divan::bench(args = [0.02, 0.1, 0.3])]
fn simd_best_with_hop_observers(b: Bencher, w: f64) {
    simd(b, SimdPath::best(), w, || {
        lorentz_gas::observers::hops::HopLanes::new(3, BLOCK).unwrap()
    });
}
