//! `lorentz report`: a fresh result passes every check; a result with an edited number fails.

use std::path::Path;

use crate::common::lorentz_in as lorentz;

fn checks(dir: &Path, report: &str) -> Vec<(String, String, String)> {
    let text = std::fs::read_to_string(dir.join(report).join("report.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["checks"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            (
                c["verdict"].as_str().unwrap().to_string(),
                c["group"].as_str().unwrap().to_string(),
                c["name"].as_str().unwrap().to_string(),
            )
        })
        .collect()
}

#[test]
fn a_fresh_diffusion_result_passes_and_an_edited_one_fails() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let (code, json, err) = lorentz(
        &dir,
        &[
            "diffusion",
            "--w",
            "0.3",
            "--collisions",
            "4e6",
            "--batches",
            "16",
            "--json",
            "--quiet",
        ],
    );
    assert_eq!(code, 0, "{err}");
    std::fs::write(dir.join("d.json"), &json).unwrap();

    let (code, out, err) = lorentz(&dir, &["report", "d.json", "--quick", "--quiet"]);
    assert_eq!(code, 0, "{out}{err}");
    let c = checks(&dir, "d-report");
    let groups: Vec<&str> = c.iter().map(|x| x.1.as_str()).collect();
    for g in [
        "provenance",
        "reproducibility",
        "statistics",
        "identities",
        "verification",
    ] {
        assert!(groups.contains(&g), "no {g} check in {c:?}");
    }
    assert!(c.iter().all(|x| x.0 == "PASS"), "{c:?}");
    assert!(c.iter().any(|x| x.2.contains("shadowing")), "{c:?}");
    let html = std::fs::read_to_string(dir.join("d-report/report.html")).unwrap();
    assert_eq!(html.matches("<svg").count(), 2, "the two figures inlined");
    for f in ["report.md", "local-slope.png", "batch-histogram.svg"] {
        assert!(dir.join("d-report").join(f).exists(), "{f}");
    }

    // One digit of D changed: the report fails, in its reproducibility group, with status 1.
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let d = v["D"].as_f64().unwrap();
    let edited = json.replacen(
        &format!("\"D\": {d}"),
        &format!("\"D\": {}", d * (1.0 + 1e-4)),
        1,
    );
    assert_ne!(edited, json);
    std::fs::write(dir.join("edited.json"), &edited).unwrap();
    let (code, _, err) = lorentz(&dir, &["report", "edited.json", "--quick", "--quiet"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("FAILED"), "{err}");
    let c = checks(&dir, "edited-report");
    assert!(
        c.iter().any(|x| x.0 == "FAIL" && x.1 == "reproducibility"),
        "{c:?}"
    );

    // One batch value changed (D left alone): also a failure.
    let b0 = v["batch_D"][0].as_f64().unwrap();
    let edited = json.replacen(&format!("{b0}"), &format!("{}", b0 * 1.001), 1);
    std::fs::write(dir.join("batch.json"), &edited).unwrap();
    let (code, _, _) = lorentz(&dir, &["report", "batch.json", "--quick", "--quiet"]);
    assert_eq!(code, 1);

    // Not a result: exit 2, one line.
    std::fs::write(dir.join("junk.json"), "{}").unwrap();
    let (code, _, err) = lorentz(&dir, &["report", "junk.json", "--quick"]);
    assert_eq!(code, 2);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The whole quick reproduction (about 1.5 minutes on 2 cores): every step, the index, and a
/// rerun that resumes everything. `cargo test --release -- --ignored`.
#[test]
#[ignore]
fn quick_reproduction_writes_every_figure_and_resumes() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.to_str().unwrap();
    let (code, _, err) = lorentz(
        Path::new("."),
        &["reproduce", "--budget", "quick", "--out", out, "--quiet"],
    );
    assert_eq!(code, 0, "{err}");
    let index = std::fs::read_to_string(dir.join("index.html")).unwrap();
    for f in [
        "sweep/fig2-D-vs-w.png",
        "sweep/fig7-boltzmann.png",
        "sweep/fig8-residuals.png",
        "fig8-fine/fig8-residuals.png",
        "backscatter/fig5-backscatter-map.png",
        "backscatter/fig4a-p-bs.png",
        "backscatter/fig4a-inset-p-bs.png",
        "hierarchy/fig3a-p-cf.png",
        "hierarchy/fig6b-lattice-walks.png",
        "speed/speed-vs-error.png",
    ] {
        assert!(dir.join(f).exists(), "{f} missing");
        assert!(index.contains(f), "{f} not in index.html");
    }
    assert!(index.contains("D = D_MZ"));
    let (code, json, _) = lorentz(
        Path::new("."),
        &[
            "reproduce",
            "--budget",
            "quick",
            "--out",
            out,
            "--quiet",
            "--json",
        ],
    );
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert!(v["steps"]
        .as_array()
        .unwrap()
        .iter()
        .all(|s| s["resumed"] == true));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn other_results_are_re_run_from_their_command_line() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let (code, json, err) = lorentz(
        &dir,
        &[
            "backscatter",
            "--w",
            "0.1",
            "--particles",
            "20000",
            "--json",
            "--quiet",
        ],
    );
    assert_eq!(code, 0, "{err}");
    std::fs::write(dir.join("b.json"), &json).unwrap();
    let (code, out, err) = lorentz(&dir, &["report", "b.json", "--quick", "--quiet"]);
    assert_eq!(code, 0, "{out}{err}");
    let c = checks(&dir, "b-report");
    assert!(c.iter().all(|x| x.0 == "PASS"), "{c:?}");
    assert!(c.iter().any(|x| x.1 == "identities"), "{c:?}");
    assert!(c.iter().any(|x| x.1 == "reproducibility"), "{c:?}");

    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let p = v["p_bs"].as_f64().unwrap();
    let edited = json.replacen(
        &format!("\"p_bs\": {p}"),
        &format!("\"p_bs\": {}", p + 1e-5),
        1,
    );
    assert_ne!(edited, json);
    std::fs::write(dir.join("edited.json"), &edited).unwrap();
    let (code, _, _) = lorentz(&dir, &["report", "edited.json", "--quick", "--quiet"]);
    assert_eq!(code, 1);
    let c = checks(&dir, "edited-report");
    assert!(
        c.iter().any(|x| x.0 == "FAIL" && x.1 == "reproducibility"),
        "{c:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
