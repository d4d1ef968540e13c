//! Verdicts earned: a statistical verdict from too few batches (fewer than 4: a 4σ-equivalent
//! bound of 10 050σ at 1 dof, 127σ at 2) is no verdict — neither "agree" nor "consistent" in the
//! printed lines, and a SKIP (so INCOMPLETE, exit status 5) in the audit; a result whose command
//! line was emptied is not "not applicable" either.

use std::path::Path;

use crate::common::{lorentz_in as lorentz, scratch};

/// Runs `args` with `--json` into `dir/name`.
fn result(dir: &Path, name: &str, args: &str) {
    let mut a: Vec<&str> = args.split_whitespace().collect();
    a.extend(["--json", "--quiet"]);
    let (code, out, err) = lorentz(dir, &a);
    assert_eq!(code, 0, "{args}: {err}");
    std::fs::write(dir.join(name), out).unwrap();
}

/// The audit of `dir/name`: its exit status, and its checks as (verdict, name, detail).
fn audit(dir: &Path, name: &str) -> (i32, Vec<(String, String, String)>) {
    let out = format!("{name}-report");
    let (code, _, _) = lorentz(dir, &["report", name, "--quick", "--out", &out, "--quiet"]);
    let text = std::fs::read_to_string(dir.join(out).join("report.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let field = |c: &serde_json::Value, k: &str| c[k].as_str().unwrap_or_default().to_string();
    let checks = (v["checks"].as_array().unwrap().iter())
        .map(|c| (field(c, "verdict"), field(c, "name"), field(c, "detail")))
        .collect();
    (code, checks)
}

/// 2-batch backscatter and hops results: their statistical checks are skipped with the reason,
/// so the audit is INCOMPLETE (5), not a PASS; the same runs with 4 batches PASS.
#[test]
fn an_audit_of_two_batches_is_incomplete_not_a_pass() {
    let tmp = scratch();
    let dir = tmp.path();
    for (name, args) in [
        ("b2.json", "backscatter --w 0.2 --particles 2e4 --batches 2"),
        ("h2.json", "hops --w 0.2 --collisions 2e5 --batches 2"),
        ("b4.json", "backscatter --w 0.2 --particles 2e4 --batches 4"),
    ] {
        result(dir, name, args);
        let (code, checks) = audit(dir, name);
        let skipped: Vec<_> = checks.iter().filter(|c| c.0 == "SKIP").collect();
        if name.contains('4') {
            assert_eq!((code, skipped.len()), (0, 0), "{name}: {checks:?}");
            continue;
        }
        assert_eq!(code, 5, "{name}: {checks:?}");
        assert!(!skipped.is_empty(), "{name}: {checks:?}");
        for c in skipped {
            assert!(
                c.2.contains("no verdict from 1 dof") && c.2.contains("10050σ"),
                "{c:?}"
            );
        }
    }
}

/// `free-paths --batches 2` used to print "|z| = 596.6 (bound 140706): consistent".
#[test]
fn a_limit_law_from_two_batches_is_no_verdict() {
    let tmp = scratch();
    let args: Vec<&str> = "free-paths --w 0.2 --collisions 1e5 --batches 2 --quiet"
        .split(' ')
        .collect();
    let (code, out, err) = lorentz(tmp.path(), &args);
    assert_eq!(code, 0, "{err}");
    let largest = out.lines().find(|l| l.contains("largest |z|")).unwrap();
    assert!(
        largest.contains("no verdict from 1 dof") && !largest.contains("consistent"),
        "{out}"
    );
    let santalo = out.lines().find(|l| l.contains("Santalo")).unwrap();
    assert!(
        santalo.contains("no verdict") && !santalo.contains("agree"),
        "{out}"
    );
}

/// A diffusion result whose `meta.command_line` was emptied: its provenance check is a SKIP,
/// not N/A, and the audit INCOMPLETE.
#[test]
fn an_emptied_command_line_is_not_a_pass() {
    let tmp = scratch();
    let dir = tmp.path();
    result(
        dir,
        "d.json",
        "diffusion --w 0.3 --collisions 1e6 --batches 8",
    );
    let text = std::fs::read_to_string(dir.join("d.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["meta"]["command_line"] = serde_json::json!([]);
    std::fs::write(
        dir.join("e.json"),
        serde_json::to_string_pretty(&v).unwrap(),
    )
    .unwrap();
    let (code, checks) = audit(dir, "e.json");
    let c = checks
        .iter()
        .find(|c| c.1.contains("recorded command line"))
        .unwrap();
    assert_eq!(c.0, "SKIP", "{c:?}");
    assert_eq!(code, 5, "{checks:?}");
}
