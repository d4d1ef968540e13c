//! `lorentz report` on survival results of open tables: the three-disk repeller's γ, λ and h_KS
//! checked against its certified cycle expansion, the record recomputed from its batches, the
//! batches re-run; an open table given as data has no cycle check (N/A).

use crate::common::lorentz_in as lorentz;
use crate::report::{checks, edited_number_report, edited_text_report, has, passes_quick};

#[test]
fn a_repeller_survival_result_agrees_with_its_cycles_and_an_edited_batch_fails() {
    let args = "escape --repeller --side 6 --radius 1 --particles 2e6 --seed 3";
    let names = [
        "the window is late",
        "γ by survival",
        "λ by survival",
        "h_KS by survival",
    ];
    let (tmp, json) = passes_quick("s.json", args, &names);
    let dir = tmp.path();
    // The full audit re-runs the whole run: every field to the bit.
    let (code, out, err) = lorentz(dir, &["report", "s.json", "--quiet"]);
    assert_eq!(code, 0, "{out}{err}");
    let c = checks(dir, "s-report");
    assert!(c.iter().all(|x| x.0 == "PASS"), "{c:?}");

    // One batch's γ moved by the error: the recorded error is no longer the batches' spread.
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let g = v["batch_gamma"][5].as_f64().unwrap();
    let e = v["gamma_err"].as_f64().unwrap();
    let c = edited_number_report(dir, &json, g, g + e);
    assert!(has(&c, "FAIL", "the record agrees"), "{c:?}");

    // γ itself moved by 10 of its errors (and h_KS with it, so that h_KS = λ − γ still holds):
    // the cycles disagree.
    let (gamma, h) = (v["gamma"].as_f64().unwrap(), v["entropy"].as_f64().unwrap());
    let shift = 10.0 * e;
    let edited = json
        .replacen(
            &format!("\"gamma\": {gamma}"),
            &format!("\"gamma\": {}", gamma + shift),
            1,
        )
        .replacen(
            &format!("\"entropy\": {h}"),
            &format!("\"entropy\": {}", h - shift),
            1,
        );
    let c = edited_text_report(dir, &edited);
    assert!(has(&c, "FAIL", "γ by survival = γ by cycles"), "{c:?}");
}

#[test]
fn an_open_table_given_as_data_has_no_cycle_check() {
    let data = crate::common::scratch();
    let table = r#"{"name": "an open triangle", "disks": [{"centre": [0, 0], "radius": 1},
        {"centre": [4, 0], "radius": 1}, {"centre": [2, "7/2"], "radius": 1}]}"#;
    let path = data.path().join("t.json");
    std::fs::write(&path, table).unwrap();
    let args = format!("escape --open {} --particles 1e5 --seed 4", path.display());
    let (tmp, _) = passes_quick("o.json", &args, &[]);
    let c = checks(tmp.path(), "o-report");
    assert!(has(&c, "N/A", "γ, λ and h_KS agree"), "{c:?}");
}
