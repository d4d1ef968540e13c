//! The thermostat kernel's fuzz oracle (`verification::oracle::thermostat_kernel`, the cargo-fuzz
//! target `thermostat_kernel`): the committed grazing seeds and random bytes (seeded ChaCha,
//! shrinking) — MPFR-53 against `f64` bit for bit, no contact missed along the sampled exact
//! flight, the post-event invariants (`proofs-notes/thermostat-audit.md`).

use std::path::PathBuf;

use lorentz_gas::verification::oracle::{decode_electric, thermostat_kernel};
use proptest::prelude::*;

/// Every committed seed passes, weak and strong fields both among them.
#[test]
fn committed_thermostat_seeds_pass() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus/thermostat_kernel");
    let (mut n, mut events, mut fields) = (0, 0, Vec::new());
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        let data = std::fs::read(&p).unwrap();
        let rep = thermostat_kernel(&data).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        events += rep.events;
        fields.push(decode_electric(&data).0);
        n += 1;
    }
    assert!(n >= 30, "{n} seeds");
    assert!(events >= 60, "{events} events");
    let (lo, hi) = fields
        .iter()
        .fold((f64::MAX, 0.0f64), |(a, b), &e| (a.min(e), b.max(e)));
    assert!(lo <= 1e-3 && hi >= 10.0, "{lo} {hi}");
}

/// Random bytes: every decoded state of either scene in a field from 10⁻³ to 10.
#[test]
fn random_bytes_through_the_thermostat_oracle() {
    let events = std::cell::Cell::new(0u64);
    crate::common::runner(400, 60)
        .run(&proptest::collection::vec(any::<u8>(), 0..64), |data| {
            match thermostat_kernel(&data) {
                Ok(rep) => events.set(events.get() + rep.events),
                Err(e) => prop_assert!(false, "{e}"),
            }
            Ok(())
        })
        .unwrap();
    assert!(events.get() > 400, "{} events", events.get());
}
