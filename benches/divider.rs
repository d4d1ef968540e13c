//! `cargo bench -p lorentz-gas-benches --bench divider`: the throughput of the vector divide and square-root unit on this
//! CPU, the resource that bounds the SIMD engine (issue "the engine at the hardware's bound").
//!
//! One 16-lane step of the AVX-512 engine (two 8-lane vectors) issues 4 `vdivpd zmm` and 2
//! `vsqrtpd zmm` — per vector the chosen disk's root and quotient and the chosen edge's quotient
//! (before the choice moved ahead of the divisions: 12 and 6). The AVX2 path issues twice as
//! many `ymm` ones for the same 16 lanes. Divan reports the time per instruction (item = one
//! vector instruction) of the chains of `lorentz_gas::engine::bound`, 24 independent ones in
//! flight, so the figure is the unit's throughput, not its latency. `lorentz bench` measures the
//! same at start-up and prints the bound, (t_sqrt + 2·t_div)/lanes per lane-event times the
//! events per collision, next to the engine's ns per collision.

use divan::Bencher;
use lorentz_gas::engine::SimdPath;
use lorentz_gas::engine::bound::{CHAINS, ROUNDS, Unit, run_chains};

fn main() {
    divan::main();
}

/// Times one call of the chains (item = one vector instruction); nothing on a CPU without the
/// path.
fn instructions(b: Bencher, path: SimdPath, unit: Unit) {
    if path.available() {
        b.counter(divan::counter::ItemsCount::new(ROUNDS * CHAINS))
            .bench_local(|| divan::black_box(run_chains(path, unit)));
    }
}

#[divan::bench]
fn vdivpd_zmm(b: Bencher) {
    instructions(b, SimdPath::Avx512, Unit::Div);
}

#[divan::bench]
fn vsqrtpd_zmm(b: Bencher) {
    instructions(b, SimdPath::Avx512, Unit::Sqrt);
}

#[divan::bench]
fn vdivpd_ymm(b: Bencher) {
    instructions(b, SimdPath::Avx2, Unit::Div);
}

#[divan::bench]
fn vsqrtpd_ymm(b: Bencher) {
    instructions(b, SimdPath::Avx2, Unit::Sqrt);
}
