//! `lorentz report` on survival results of open tables: the three-disk repeller's γ, λ and h_KS
//! checked against its certified cycle expansion, the record recomputed from its batches, the
//! batches re-run; an open table given as data has no cycle check (N/A).

use crate::common::lorentz_in as lorentz;
use crate::common::words;
use crate::report::{checks, quick_report, result_text_in};

/// Whether `c` holds a check of `verdict` whose name starts with `name`.
fn has(c: &[(String, String, String)], verdict: &str, name: &str) -> bool {
    c.iter().any(|x| x.0 == verdict && x.2.starts_with(name))
}

#[test]
fn a_repeller_survival_result_agrees_with_its_cycles_and_an_edited_batch_fails() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let args = words("escape --repeller --side 6 --radius 1 --particles 2e6 --seed 3");
    let json = result_text_in(&dir, "s.json", &args);
    let (code, printed, c) = quick_report(&dir, "s.json");
    assert_eq!(code, 0, "{printed}");
    assert!(c.iter().all(|x| x.0 == "PASS"), "{c:?}");
    for name in [
        "recorded command line gives",
        "the record agrees",
        "between-batch F",
        "the window is late enough",
        "γ by survival = γ by cycles",
        "λ by survival = λ by cycles",
        "h_KS by survival = h_KS by cycles",
        "the recorded configuration re-run",
    ] {
        assert!(has(&c, "PASS", name), "{name}: {c:?}");
    }
    // The full audit re-runs the whole run: every field to the bit.
    let (code, out, err) = lorentz(&dir, &["report", "s.json", "--quiet"]);
    assert_eq!(code, 0, "{out}{err}");
    let c = checks(&dir, "s-report");
    assert!(c.iter().all(|x| x.0 == "PASS"), "{c:?}");

    // One batch's γ moved by its error: the recorded error is no longer the batches' spread,
    // so the record fails.
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let g = v["batch_gamma"][5].as_f64().unwrap();
    let e = v["gamma_err"].as_f64().unwrap();
    assert_eq!(json.matches(&format!("{g}")).count(), 1);
    let edited = json.replacen(&format!("{g}"), &format!("{}", g + e), 1);
    std::fs::write(dir.join("edited.json"), &edited).unwrap();
    let (code, printed, c) = quick_report(&dir, "edited.json");
    assert_eq!(code, 1, "{printed}");
    assert!(has(&c, "FAIL", "the record agrees"), "{c:?}");

    // γ itself moved by 10 of its errors (and h_KS with it, so that h_KS = λ − γ still holds):
    // the cycles disagree.
    let (gamma, h) = (v["gamma"].as_f64().unwrap(), v["entropy"].as_f64().unwrap());
    let lyapunov = v["lyapunov"].as_f64().unwrap();
    let moved = gamma + 10.0 * e;
    let json2 = json.replacen(
        &format!("\"gamma\": {gamma}"),
        &format!("\"gamma\": {moved}"),
        1,
    );
    let json2 = json2.replacen(
        &format!("\"entropy\": {h}"),
        &format!("\"entropy\": {}", lyapunov - moved),
        1,
    );
    assert_ne!(json2, json);
    std::fs::write(dir.join("edited.json"), &json2).unwrap();
    let (code, printed, c) = quick_report(&dir, "edited.json");
    assert_eq!(code, 1, "{printed}");
    assert!(has(&c, "FAIL", "γ by survival = γ by cycles"), "{c:?}");
}

#[test]
fn an_open_table_given_as_data_has_no_cycle_check() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let table = r#"{"name": "an open triangle", "disks": [{"centre": [0, 0], "radius": 1},
        {"centre": [4, 0], "radius": 1}, {"centre": [2, "7/2"], "radius": 1}]}"#;
    std::fs::write(dir.join("t.json"), table).unwrap();
    let args = words("escape --open t.json --particles 1e5 --seed 4");
    result_text_in(&dir, "o.json", &args);
    let (code, printed, c) = quick_report(&dir, "o.json");
    assert_eq!(code, 0, "{printed}");
    assert!(has(&c, "N/A", "γ, λ and h_KS agree"), "{c:?}");
    assert!(
        has(&c, "PASS", "the recorded configuration re-run"),
        "{c:?}"
    );
}
