//! A run planned for a relative error (`diffusion --rel-err`): its result is the plain run of the
//! planned size, and `lorentz report` reads its recorded command line as that run — the pilot's
//! size and target from the command line, the plan from the file.

use crate::common::lorentz_in as lorentz;

/// The verdict of the report's command-line check.
fn command_line_verdict(dir: &std::path::Path, out: &str) -> String {
    crate::report::checks(dir, out)
        .into_iter()
        .find(|(_, _, name)| name == "recorded command line gives the recorded configuration")
        .map(|(verdict, _, _)| verdict)
        .unwrap()
}

/// Breaking it on purpose: without the pilot's plan applied to the parsed command line, the check
/// fails with "collisions: 62000000 vs 10000000" (found so before `planned` existed).
#[test]
fn a_planned_result_is_the_plain_run_and_its_command_line_passes_the_report() {
    let tmp = crate::common::scratch();
    let dir = tmp.path();
    let args = ["--w", "0.2", "--collisions", "1e7", "--json", "--quiet"];
    let (code, planned, err) = lorentz(
        dir,
        &[&["diffusion", "--rel-err", "2e-3"], &args[..]].concat(),
    );
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&planned).unwrap();
    let n = v["pilot"]["planned_collisions"].as_u64().unwrap();
    assert!(n > 10_000_000 && v["collisions"] == n, "{}", v["pilot"]);
    assert!(v["config"].get("rel_err").is_none());
    let size = n.to_string();
    let (code, plain, err) = lorentz(
        dir,
        &[
            "diffusion",
            "--w",
            "0.2",
            "--collisions",
            &size,
            "--json",
            "--quiet",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let p: serde_json::Value = serde_json::from_str(&plain).unwrap();
    assert_eq!((&v["D"], &v["batch_D"]), (&p["D"], &p["batch_D"]));

    std::fs::write(dir.join("d.json"), &planned).unwrap();
    let (code, _, err) = lorentz(
        dir,
        &["report", "d.json", "--quick", "--out", "rep", "--quiet"],
    );
    assert_eq!(code, 0, "{err}");
    assert_eq!(command_line_verdict(dir, "rep"), "PASS");

    // A pilot that is not the command line's fails the check.
    let edited = planned.replacen("\"collisions\": 10000000,", "\"collisions\": 20000000,", 1);
    assert_ne!(edited, planned);
    std::fs::write(dir.join("e.json"), &edited).unwrap();
    let (code, _, _) = lorentz(
        dir,
        &["report", "e.json", "--quick", "--out", "rep2", "--quiet"],
    );
    assert_eq!(code, 1);
    assert_eq!(command_line_verdict(dir, "rep2"), "FAIL");
}
