//! `lorentz report` on results of the driven gas (`diffusion --electric`): the record recomputed
//! from its batches and its exact field, the sum rule, no current across a mirror line, a shadow
//! audit of thermostatted events, a batch re-run.

use crate::report::{edited_number_report, has, passes_quick};

#[test]
fn a_driven_result_passes_its_audit_and_an_edited_batch_fails() {
    let args = "diffusion --w 0.2 --electric 3/10 --collisions 2e5 --batches 8 --seed 5";
    let names = [
        "sum rule: λ₊ + λ₋ + ⟨α⟩ = 0",
        "sum rule per trajectory",
        "no current across a field along a mirror line",
        "shadow audit of thermostatted events",
    ];
    let (tmp, json) = passes_quick("j.json", args, &names);
    let dir = tmp.path();
    // One batch's current moved by its error: J∥'s recorded error is no longer the batches'.
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let j = v["batch_J_parallel"][3].as_f64().unwrap();
    let e = v["J_parallel_err"].as_f64().unwrap();
    let c = edited_number_report(dir, &json, j, j + e);
    assert!(has(&c, "FAIL", "the record agrees"), "{c:?}");
}

#[test]
fn a_field_off_the_mirror_lines_has_no_mirror_check() {
    let args = "diffusion --w 0.2 --electric 1 --electric-angle 10 --collisions 1e5 --batches 8";
    let (tmp, _) = passes_quick("j.json", args, &[]);
    let c = crate::report::checks(tmp.path(), "j-report");
    assert!(has(&c, "N/A", "no current across a field"), "{c:?}");
}

#[test]
fn a_driven_sweep_is_audited_point_by_point_and_its_odd_checks_recomputed() {
    let tmp = crate::common::scratch();
    let dir = tmp.path();
    let args = crate::common::words(
        "sweep --w 0.2 --electric=-1/2,1/2,1 --collisions-per-run 1e5 --batches-per-run 8 \
         --out ds --quiet",
    );
    let (code, out, err) = crate::common::lorentz_in(dir, &args);
    assert_eq!(code, 0, "{out}{err}");
    let (code, printed, c) = crate::report::quick_report(dir, "ds/driven-sweep.json");
    assert_eq!(code, 0, "{printed}");
    assert!(c.iter().all(|x| x.0 == "PASS"), "{c:?}");
    for name in [
        "the record agrees",
        "J(−E) = −J(E) at w = 0.2, |E| = 0.5",
        "sum rule at every point",
        "sum rule per trajectory at every point",
        "the recorded configuration re-run",
    ] {
        assert!(has(&c, "PASS", name), "{name}: {c:?}");
    }
    // J∥ of the point at E = 1 moved by its error: no longer its batches' mean.
    let json = std::fs::read_to_string(dir.join("ds/driven-sweep.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let j = v["rows"][2]["J_parallel"].as_f64().unwrap();
    let e = v["rows"][2]["J_parallel_err"].as_f64().unwrap();
    let key = |x: f64| format!("\"J_parallel\": {x}");
    assert_eq!(json.matches(&key(j)).count(), 1);
    let c = crate::report::edited_text_report(dir, &json.replacen(&key(j), &key(j + e), 1));
    assert!(has(&c, "FAIL", "the record agrees"), "{c:?}");
}
