//! `lorentz report` on results in a magnetic field: a field run audited against its exact
//! geometry, a field sweep row by row with its Onsager checks recomputed, and results where every
//! orbit is localized.

use crate::common::lorentz_in as lorentz;
use crate::common::words;
use crate::report::{checks, edited_report, quick_report, result_text_in};

#[test]
fn a_field_result_is_audited_against_its_exact_geometry() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let args = "diffusion --w 0.1 --field 1 --collisions 4e5 --batches 8";
    let json = result_text_in(&dir, "f.json", &args.split(' ').collect::<Vec<_>>());
    let (code, printed, c) = quick_report(&dir, "f.json");
    assert_eq!(code, 0, "{printed}");
    assert!(c.iter().all(|x| x.0 == "PASS"), "{c:?}");
    assert!(
        c.iter().any(|x| x.2.starts_with("sampled localized share")),
        "{c:?}"
    );
    assert!(
        c.iter()
            .any(|x| x.2.starts_with("the recorded configuration re-run")),
        "{c:?}"
    );

    // A sampled share moved by 10 of its binomial errors fails the identity (and the re-run).
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let (p, e) = (
        v["localized_fraction"].as_f64().unwrap(),
        v["localized_fraction_err"].as_f64().unwrap(),
    );
    let (_, c) = edited_report(&dir, &json, "localized_fraction", p, p + 10.0 * e);
    assert!(
        c.iter()
            .any(|x| x.0 == "FAIL" && x.2.starts_with("sampled localized share")),
        "{c:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_field_sweep_is_audited_row_by_row_and_its_onsager_checks_recomputed() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let args = words(
        "sweep --w 0.1 --fields=-1,1,5/2 --collisions-per-run 4e5 --batches-per-run 8 \
         --localization-samples 1e4 --out fs --quiet",
    );
    let (code, out, err) = lorentz(&dir, &args);
    assert_eq!(code, 0, "{out}{err}");
    let (code, out, err) = lorentz(&dir, &["report", "fs/field-sweep.json", "--quiet"]);
    assert_eq!(code, 0, "{out}{err}");
    let c = checks(&dir, "fs/field-sweep-report");
    assert!(c.iter().all(|x| x.0 == "PASS"), "{c:?}");
    for name in [
        "recorded command line gives",
        "the record agrees",
        "Onsager-Casimir at w = 0.1, |B| = 1: D_xy(B) + D_xy(-B) = 0",
        "every sampled localized share",
        "every mean free time",
        "the recorded configuration re-run",
    ] {
        assert!(c.iter().any(|x| x.2.starts_with(name)), "{name}: {c:?}");
    }
    // A Hall part made even in B (the sign of D_xy at B = -1 flipped) fails the recomputed
    // Onsager-Casimir check and the record (the file's own checks no longer match its rows).
    let json = std::fs::read_to_string(dir.join("fs/field-sweep.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let d = v["rows"][0]["D_xy"].as_f64().unwrap();
    assert!(d < 0.0);
    let (_, c) = edited_report(&dir, &json, "D_xy", d, -d);
    assert!(
        c.iter()
            .any(|x| x.0 == "FAIL" && x.2.starts_with("Onsager-Casimir at w = 0.1, |B| = 1: D_xy")),
        "{c:?}"
    );
    assert!(
        c.iter()
            .any(|x| x.0 == "FAIL" && x.2.starts_with("the record agrees")),
        "{c:?}"
    );
}

/// Regression: where every orbit is localized the mean free time is infinite (`null` in JSON)
/// and the exact localized share rounds to 1 + 2⁻⁵². A sweep holding such a point could not be
/// resumed (its point file did not read back) and the audit failed every such result (a NaN
/// binomial error, a NaN mean free time against Kac's infinity). Also the square lattice's sweep
/// over B: audited row by row, Onsager–Casimir at its radius.
#[test]
fn where_every_orbit_is_localized_a_result_and_a_resumed_square_sweep_pass_the_audit() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let args = "diffusion --w 0.1 --field 25 --collisions 4e5 --batches 4";
    let json = result_text_in(&dir, "loc.json", &args.split(' ').collect::<Vec<_>>());
    assert!(json.contains("\"mean_free_time\": null"), "{json}");
    let (code, printed, c) = quick_report(&dir, "loc.json");
    assert_eq!(code, 0, "{printed}");
    assert!(c.iter().all(|x| x.0 == "PASS"));
    let sweep = "sweep --scene square --radius 1/4 --fields=-1,1,4 --collisions-per-run 4e5 \
                 --batches-per-run 8 --localization-samples 1e4 --out sq --json --quiet";
    let sweep = words(sweep);
    let (code, first, err) = lorentz(&dir, &sweep);
    assert_eq!(code, 0, "{err}");
    let (code, again, err) = lorentz(&dir, &sweep);
    assert_eq!(code, 0, "{err}");
    let rows = |text: &str| {
        let v: serde_json::Value = serde_json::from_str(text).unwrap();
        (v["rows"].clone(), v["resumed_points"].as_u64())
    };
    assert_eq!(rows(&again), (rows(&first).0, Some(3)));
    assert_eq!(rows(&first).0[2]["all_localized"], true);
    assert_eq!(rows(&first).0[2]["radius"], 0.25);
    let (code, printed, c) = quick_report(&dir, "sq/field-sweep.json");
    assert_eq!(code, 0, "{printed}");
    assert!(c.iter().all(|x| x.0 == "PASS"), "{c:?}");
    assert!(
        c.iter()
            .any(|x| x.2.starts_with("Onsager-Casimir at r = 0.25, |B| = 1")),
        "{c:?}"
    );
}
