//! Degenerate lattice states of any scene flown on arcs in a decoded magnetic field (cyclotron
//! radii about 10⁻⁶ to 10⁶, either sense): MPFR at 53 bits against `f64` bit for bit, and the
//! post-event invariants after every event. See `lorentz_gas::verification::oracle::arc_kernel`
//! and `proofs-notes/magnetic-arcs.md`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lorentz_gas::verification::oracle::arc_kernel;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = arc_kernel(data) {
        panic!("{e}");
    }
});
