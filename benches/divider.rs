//! `cargo bench --bench divider`: the throughput of the vector divide and square-root unit on this
//! CPU, the resource that bounds the SIMD engine (issue "the engine at the hardware's bound").
//!
//! One 16-lane step of the AVX-512 engine (two 8-lane vectors) issues 12 `vdivpd zmm` and 6
//! `vsqrtpd zmm` — per vector 3 disk roots, 3 disk times and 3 edge times; `objdump -d` of every
//! `run_avx512` in the release binary shows exactly these (2026-11-25). The AVX2 path issues
//! twice as many `ymm` ones for the same 16 lanes. Divan reports the time per instruction
//! (item = one vector instruction) with 24 independent chains in flight, so the figure is the
//! unit's throughput, not its latency; the bound per lane-event is then
//! (12·t_div + 6·t_sqrt)/16, and per collision that times the events per collision
//! (`lorentz bench` prints `crossings_per_collision`). Compare it with `lorentz bench`'s ns per
//! collision on the same machine.

use divan::Bencher;

fn main() {
    divan::main();
}

/// Vector instructions per timed call: 24 chains × 1000 rounds (12 gave the same throughput).
const ROUNDS: usize = 1000;
const CHAINS: usize = 24;

#[cfg(target_arch = "x86_64")]
mod x86 {
    use std::arch::x86_64::*;

    use super::{CHAINS, ROUNDS};

    /// `CHAINS` independent chains of one vector instruction, `ROUNDS` deep (a divisor just above
    /// 1, and square roots converging to 1, keep every value normal). Returns the sum of the
    /// lanes so that nothing is optimised away.
    macro_rules! chains {
        ($name:ident, $feature:literal, $set:ident, $store:ident, $lanes:literal, |$a:ident| $op:expr) => {
            /// # Safety
            /// The CPU must have the target feature.
            #[target_feature(enable = $feature)]
            pub unsafe fn $name() -> f64 {
                let mut acc = [$set(1.5); CHAINS];
                for _ in 0..ROUNDS {
                    for $a in acc.iter_mut() {
                        *$a = $op;
                    }
                }
                let mut out = [0.0; $lanes];
                let mut sum = 0.0;
                for a in acc {
                    $store(out.as_mut_ptr(), a);
                    sum += out.iter().sum::<f64>();
                }
                sum
            }
        };
    }

    chains!(
        div_zmm,
        "avx512f",
        _mm512_set1_pd,
        _mm512_storeu_pd,
        8,
        |a| _mm512_div_pd(*a, _mm512_set1_pd(1.000_000_1))
    );
    chains!(
        sqrt_zmm,
        "avx512f",
        _mm512_set1_pd,
        _mm512_storeu_pd,
        8,
        |a| _mm512_sqrt_pd(*a)
    );
    chains!(div_ymm, "avx", _mm256_set1_pd, _mm256_storeu_pd, 4, |a| {
        _mm256_div_pd(*a, _mm256_set1_pd(1.000_000_1))
    });
    chains!(sqrt_ymm, "avx", _mm256_set1_pd, _mm256_storeu_pd, 4, |a| {
        _mm256_sqrt_pd(*a)
    });
}

fn instructions(b: Bencher, f: fn() -> f64) {
    b.counter(divan::counter::ItemsCount::new(ROUNDS * CHAINS))
        .bench_local(|| divan::black_box(f()));
}

#[cfg(target_arch = "x86_64")]
#[divan::bench]
fn vdivpd_zmm(b: Bencher) {
    if std::arch::is_x86_feature_detected!("avx512f") {
        // SAFETY: AVX-512F was detected just above.
        instructions(b, || unsafe { x86::div_zmm() });
    }
}

#[cfg(target_arch = "x86_64")]
#[divan::bench]
fn vsqrtpd_zmm(b: Bencher) {
    if std::arch::is_x86_feature_detected!("avx512f") {
        // SAFETY: AVX-512F was detected just above.
        instructions(b, || unsafe { x86::sqrt_zmm() });
    }
}

#[cfg(target_arch = "x86_64")]
#[divan::bench]
fn vdivpd_ymm(b: Bencher) {
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: AVX was detected just above.
        instructions(b, || unsafe { x86::div_ymm() });
    }
}

#[cfg(target_arch = "x86_64")]
#[divan::bench]
fn vsqrtpd_ymm(b: Bencher) {
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: AVX was detected just above.
        instructions(b, || unsafe { x86::sqrt_ymm() });
    }
}
