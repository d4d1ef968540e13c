//! Degenerate single-cell states of any scene (leading byte: triangular or square) replayed
//! in MPFR: see `lorentz_gas::verification::oracle::collision_primitive` and
//! `proofs-notes/fuzzing.md`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lorentz_gas::verification::oracle::collision_primitive;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = collision_primitive(data) {
        panic!("{e}");
    }
});
