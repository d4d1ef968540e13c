//! The divide/square-root unit's bound on the SIMD engine, measured on the machine it runs on.
//!
//! Each lane-event of the SIMD engine takes one square root and two divisions (the chosen disk's
//! root and the chosen disk's and edge's quotients: [`crate::kernel::choice`]). These run on
//! one shared unit, so no engine can beat (t_√ + 2·t_÷)/W per lane-event. Here t is that
//! unit's throughput per vector instruction and W the lanes per vector (8 for AVX-512, 4 for
//! AVX2). [`measure`] times the instructions at run time: [`CHAINS`] independent chains, so the
//! figure is throughput, not latency. 12 chains gave the same figures as 24. `lorentz bench`
//! prints the bound next to the engine's time per collision. `cargo bench -p lorentz-gas-benches --bench divider` runs
//! the same chains under divan.
//!
//! The bound is a floor, not a forecast. On a CPU that executes 512-bit operations as two
//! 256-bit halves, the engine's other vector instructions, about 200 per 8-lane vector and
//! step, cost more than its three divider instructions (docs/performance.md, "The divider's bound").

use std::time::Instant;

use serde::Serialize;

use super::SimdPath;

/// Independent chains per timed call.
pub const CHAINS: usize = 24;
/// Instructions per chain per timed call.
pub const ROUNDS: usize = 1000;

/// Which instruction a chain repeats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unit {
    /// `vdivpd` (a divisor just above 1 keeps the values normal).
    Div,
    /// `vsqrtpd` (the values converge to 1).
    Sqrt,
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    use std::arch::x86_64::*;

    use super::{CHAINS, ROUNDS};

    /// `CHAINS` independent chains of one vector instruction, `ROUNDS` deep; returns the sum of
    /// the lanes so that nothing is optimised away.
    macro_rules! chains {
        ($name:ident, $feature:literal, $set:ident, $store:ident, $lanes:literal, |$a:ident| $op:expr) => {
            /// # Safety
            /// The CPU must have the target feature.
            #[target_feature(enable = $feature)]
            pub unsafe fn $name() -> f64 {
                unsafe {
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

/// Runs [`CHAINS`] × [`ROUNDS`] instructions of `unit` on the vectors of `path`. `None` for the
/// portable path, or a path this CPU lacks.
pub fn run_chains(path: SimdPath, unit: Unit) -> Option<f64> {
    if !path.available() {
        return None;
    }
    #[cfg(target_arch = "x86_64")]
    // SAFETY: `path.available()` detected AVX-512F (resp. AVX2, which implies AVX) just above.
    unsafe {
        match (path, unit) {
            (SimdPath::Avx512, Unit::Div) => Some(x86::div_zmm()),
            (SimdPath::Avx512, Unit::Sqrt) => Some(x86::sqrt_zmm()),
            (SimdPath::Avx2, Unit::Div) => Some(x86::div_ymm()),
            (SimdPath::Avx2, Unit::Sqrt) => Some(x86::sqrt_ymm()),
            (SimdPath::Portable, _) => None,
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = unit;
        None
    }
}

/// The unit's figures on this machine.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct DividerBound {
    /// Nanoseconds per vector division (median of the timed calls).
    pub div_ns: f64,
    /// Nanoseconds per vector square root.
    pub sqrt_ns: f64,
    /// Lanes per vector.
    pub lanes: usize,
    /// Square roots per lane-event: 1 on straight flights, [`ARC_ROOTS`] on arcs.
    pub roots: u32,
    /// Divisions per lane-event: 2 on straight flights, [`ARC_DIVISIONS`] on arcs.
    pub divisions: u32,
    /// The bound per lane-event: (roots·t_√ + divisions·t_÷)/lanes.
    pub ns_per_event: f64,
}

/// Square roots per lane-event of the arc engine ([`crate::engine::arcs`]) on its common path:
/// |v|, one per disk (the root of Δ) and one per edge. The disk frame of nearly concentric
/// circles adds two per disk where some lane of the block needs it.
pub const ARC_ROOTS: u32 = 7;

/// Divisions per lane-event of the arc engine on its common path: two per disk (1/M and the
/// entry's quotient), one per edge, and the velocity at the contact (the reflection's division by
/// r² = 1 is exact and skipped). The disk frame adds three per disk where needed.
pub const ARC_DIVISIONS: u32 = 10;

/// Median nanoseconds per instruction over `calls` timed calls (after one warm-up).
fn instruction_ns(path: SimdPath, unit: Unit, calls: usize) -> Option<f64> {
    run_chains(path, unit)?;
    let mut t: Vec<f64> = (0..calls)
        .map(|_| {
            let start = Instant::now();
            std::hint::black_box(run_chains(path, unit));
            start.elapsed().as_secs_f64() * 1e9 / (CHAINS * ROUNDS) as f64
        })
        .collect();
    t.sort_by(f64::total_cmp);
    Some(t[calls / 2])
}

/// Measures the unit for `path` (about 20 ms: 101 calls of each instruction) and the bound of
/// `roots` square roots and `divisions` divisions per lane-event. `None` for the portable path
/// or a path this CPU lacks.
pub fn measure(path: SimdPath, roots: u32, divisions: u32) -> Option<DividerBound> {
    const CALLS: usize = 101;
    let div_ns = instruction_ns(path, Unit::Div, CALLS)?;
    let sqrt_ns = instruction_ns(path, Unit::Sqrt, CALLS)?;
    let lanes = match path {
        SimdPath::Avx512 => 8,
        _ => 4,
    };
    Some(DividerBound {
        div_ns,
        sqrt_ns,
        lanes,
        roots,
        divisions,
        ns_per_event: (f64::from(roots) * sqrt_ns + f64::from(divisions) * div_ns) / lanes as f64,
    })
}
