//! Degenerate triangular-cell states (grazing, near-surface, tangents, rim crossings, corners)
//! through the MPFR kernel's `f64` balls: every event they decide must be the full comparison's,
//! bit for bit. See `lorentz_gas::verification::oracle::decided_in_balls` and
//! `proofs-notes/certified-filter.md`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lorentz_gas::verification::oracle::decided_in_balls;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = decided_in_balls(data) {
        panic!("{e}");
    }
});
