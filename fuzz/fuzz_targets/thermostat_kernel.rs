//! Degenerate lattice states of any scene flown under a Gaussian-thermostatted field decoded from
//! the last three bytes (E from 10⁻³ to 10 at any angle): MPFR at 53 bits against `f64` bit for
//! bit, no contact missed along the flight, and the post-event invariants after every event. See
//! `lorentz_gas::verification::oracle::thermostat_kernel` and `proofs-notes/thermostat-audit.md`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lorentz_gas::verification::oracle::thermostat_kernel;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = thermostat_kernel(data) {
        panic!("{e}");
    }
});
