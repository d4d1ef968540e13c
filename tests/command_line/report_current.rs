//! `lorentz report` on results of the driven gas (`diffusion --electric`): the record recomputed
//! from its batches and its exact field, the sum rule, no current across a mirror line, a shadow
//! audit of thermostatted events, a batch re-run.

use crate::report::{edited_number_report, has, passes_quick};

#[test]
fn a_driven_result_passes_its_audit_and_an_edited_batch_fails() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let args = "diffusion --w 0.2 --electric 3/10 --collisions 2e5 --batches 8 --seed 5";
    let names = [
        "recorded command line gives",
        "the record agrees",
        "between-batch F",
        "sum rule: λ₊ + λ₋ + ⟨α⟩ = 0",
        "sum rule per trajectory",
        "no current across a field along a mirror line",
        "shadow audit of thermostatted events",
        "the recorded configuration re-run",
    ];
    let json = passes_quick(&dir, "j.json", args, &names);
    // One batch's current moved by its error: J∥'s recorded error is no longer the batches'.
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let j = v["batch_J_parallel"][3].as_f64().unwrap();
    let e = v["J_parallel_err"].as_f64().unwrap();
    let c = edited_number_report(&dir, &json, j, j + e);
    assert!(has(&c, "FAIL", "the record agrees"), "{c:?}");
}

#[test]
fn a_field_off_the_mirror_lines_has_no_mirror_check() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let args = "diffusion --w 0.2 --electric 1 --electric-angle 10 --collisions 1e5 --batches 8";
    passes_quick(&dir, "j.json", args, &["the recorded configuration re-run"]);
    let c = crate::report::checks(&dir, "j-report");
    assert!(has(&c, "N/A", "no current across a field"), "{c:?}");
}
