//! `lorentz report`: a fresh result passes every check; a result with an edited number fails;
//! doctored files (an edited command line, a foreign kind, understated work, extra keys, an
//! oversized file) never make it run what the file says or write outside `--out`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use crate::common::lorentz_in as lorentz;
use crate::common::words;

pub(crate) fn checks(dir: &Path, report: &str) -> Vec<(String, String, String)> {
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
        &words("diffusion --w 0.3 --collisions 4e6 --batches 16 --json --quiet"),
    );
    assert_eq!(code, 0, "{err}");
    std::fs::write(dir.join("d.json"), &json).unwrap();
    let v0: serde_json::Value = serde_json::from_str(&json).unwrap();

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
    // The headline first: the run and D ± its error to the place of the error, and the verdict.
    let (d, e) = (v0["D"].as_f64().unwrap(), v0["D_err"].as_f64().unwrap());
    let shown = lorentz_gas::report::publication::headline::with_error(d, e);
    let head = &html[..html.find("<h2>Provenance").unwrap()];
    for cell in [
        "<td>0.3</td>",
        "<td>4000000</td>",
        "<td>16</td>",
        &format!("<td>{shown}</td>"),
    ] {
        assert!(head.contains(cell), "{cell} not in the headline: {head}");
    }
    assert!(
        head.contains("<th>verdict</th><td class=\"PASS\">PASS (quick audit: 1 of 16 batches"),
        "{head}"
    );
    for f in ["report.md", "local-slope.png", "batch-histogram.svg"] {
        assert!(dir.join("d-report").join(f).exists(), "{f}");
    }

    // One digit of D changed: the report fails, in its reproducibility group, with status 1.
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let d = v["D"].as_f64().unwrap();
    let (err, c) = edited_report(&dir, &json, "D", d, d * (1.0 + 1e-4));
    assert!(err.contains("FAILED"), "{err}");
    assert!(
        c.iter().any(|x| x.0 == "FAIL" && x.1 == "reproducibility"),
        "{c:?}"
    );

    // One batch value changed (D left alone): also a failure.
    let b0 = v["batch_D"][0].as_f64().unwrap();
    let at = json.find("\"batch_D\"").expect("batch_D in the result");
    let (head, tail) = json.split_at(at);
    let edited = format!(
        "{head}{}",
        tail.replacen(&format!("{b0}"), &format!("{}", b0 * 1.001), 1)
    );
    let e: serde_json::Value = serde_json::from_str(&edited).unwrap();
    assert_eq!(
        e["batch_D"][0].as_f64(),
        Some(b0 * 1.001),
        "batch_D[0] edited"
    );
    assert_eq!(e["D"], v["D"], "D left alone");
    let mut rest = e.clone();
    rest["batch_D"][0] = v["batch_D"][0].clone();
    assert_eq!(rest, v, "nothing but batch_D[0] changed");
    std::fs::write(dir.join("batch.json"), &edited).unwrap();
    assert_eq!(
        std::fs::read_to_string(dir.join("batch.json")).unwrap(),
        edited
    );
    let (code, _, _) = lorentz(&dir, &["report", "batch.json", "--quick", "--quiet"]);
    assert_eq!(code, 1);

    // Not a result: exit 2, one line.
    std::fs::write(dir.join("junk.json"), "{}").unwrap();
    let (code, _, err) = lorentz(&dir, &["report", "junk.json", "--quick"]);
    assert_eq!(code, 2);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A run on the logarithmic grid is also checked by Green–Kubo: D by the integral of the
/// velocity autocorrelation against D, paired over the batches. Broken on purpose (the recorded
/// difference made 10 errors wide): that check fails and the report exits 1.
#[test]
fn a_log_grid_result_is_checked_by_green_kubo() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let args = "diffusion --w 0.3 --collisions 4e6 --batches 16 --msd-grid log";
    let json = result_text_in(&dir, "g.json", &args.split(' ').collect::<Vec<_>>());
    let (code, printed, c) = quick_report(&dir, "g.json");
    assert_eq!(code, 0, "{printed}");
    let gk: Vec<_> = c.iter().filter(|x| x.2.contains("Green–Kubo")).collect();
    assert_eq!(gk.len(), 1, "{c:?}");
    assert_eq!(gk[0].0, "PASS", "{gk:?}");

    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let (d, e) = (
        v["D_minus_D_green_kubo"].as_f64().unwrap(),
        v["D_minus_D_green_kubo_err"].as_f64().unwrap(),
    );
    let edited = json.replacen(
        &format!("\"D_minus_D_green_kubo\": {d}"),
        &format!("\"D_minus_D_green_kubo\": {}", 10.0 * e),
        1,
    );
    assert_ne!(edited, json);
    std::fs::write(dir.join("e.json"), &edited).unwrap();
    let (code, printed, c) = quick_report(&dir, "e.json");
    assert_eq!(code, 1, "{printed}");
    let gk = c.iter().find(|x| x.2.contains("Green–Kubo")).unwrap();
    assert_eq!(gk.0, "FAIL", "{c:?}");
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
    assert!(
        v["steps"]
            .as_array()
            .unwrap()
            .iter()
            .all(|s| s["resumed"] == true)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn other_results_are_re_run_from_their_configuration() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let (code, json, err) = lorentz(
        &dir,
        &words("backscatter --w 0.1 --particles 20000 --json --quiet"),
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
    let (_, c) = edited_report(&dir, &json, "p_bs", p, p + 1e-5);
    assert!(
        c.iter().any(|x| x.0 == "FAIL" && x.1 == "reproducibility"),
        "{c:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every file and directory below `dir` (recursively), relative to it.
fn listing(dir: &Path) -> BTreeSet<PathBuf> {
    fn walk(root: &Path, d: &Path, out: &mut BTreeSet<PathBuf>) {
        for e in std::fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            out.insert(p.strip_prefix(root).unwrap().to_path_buf());
            if p.is_dir() {
                walk(root, &p, out);
            }
        }
    }
    let mut out = BTreeSet::new();
    walk(dir, dir, &mut out);
    out
}

/// What appeared below `dir` since `before`, outside `out` (relative to `dir`).
fn written_outside(dir: &Path, before: &BTreeSet<PathBuf>, out: &str) -> Vec<PathBuf> {
    listing(dir)
        .difference(before)
        .filter(|p| !p.starts_with(out))
        .cloned()
        .collect()
}

/// A small `lorentz NAME … --json` result in `dir/file` (checked to exit 0), as JSON.
fn result_in(dir: &Path, file: &str, args: &[&str]) -> serde_json::Value {
    serde_json::from_str(&result_text_in(dir, file, args)).unwrap()
}

/// As [`result_in`], the text of the result.
pub(crate) fn result_text_in(dir: &Path, file: &str, args: &[&str]) -> String {
    let mut all = args.to_vec();
    all.extend(["--json", "--quiet"]);
    let (code, json, err) = lorentz(dir, &all);
    assert_eq!(code, 0, "{err}");
    std::fs::write(dir.join(file), &json).unwrap();
    json
}

/// `lorentz report FILE --quick --quiet` in `dir`: its exit status, what it printed, and the
/// checks of the report it wrote (next to FILE, named after its stem).
pub(crate) fn quick_report(dir: &Path, file: &str) -> (i32, String, Vec<(String, String, String)>) {
    let (code, out, err) = lorentz(dir, &["report", file, "--quick", "--quiet"]);
    let stem = file.strip_suffix(".json").unwrap_or(file);
    (
        code,
        format!("{out}{err}"),
        checks(dir, &format!("{stem}-report")),
    )
}

/// `json` with the first `"key": old` replaced by `"key": new`, written to `dir/edited.json` and
/// reported on with `--quick`: the report must fail (status 1). What it printed and its checks.
pub(crate) fn edited_report(
    dir: &Path,
    json: &str,
    key: &str,
    old: f64,
    new: f64,
) -> (String, Vec<(String, String, String)>) {
    let edited = json.replacen(
        &format!("\"{key}\": {old}"),
        &format!("\"{key}\": {new}"),
        1,
    );
    assert_ne!(edited, json);
    std::fs::write(dir.join("edited.json"), &edited).unwrap();
    let (code, printed, c) = quick_report(dir, "edited.json");
    assert_eq!(code, 1, "{printed}");
    (printed, c)
}

/// A quick hops run (its command line).
const HOPS: &str = "hops --w 0.1 --collisions 2e5 --batches 4 --order 3";

#[test]
fn an_edited_command_line_is_never_run() {
    let tmp = crate::common::scratch();
    let dir = tmp.path();
    let mut v = result_in(dir, "h.json", &words(HOPS));
    // The file's author asks for figures in `evil/`: a subcommand, an output and work of their
    // choosing.
    v["meta"]["command_line"] = serde_json::json!(words(
        "lorentz figure backscatter-map --particles 1000 --out evil"
    ));
    std::fs::write(
        dir.join("evil.json"),
        serde_json::to_string_pretty(&v).unwrap(),
    )
    .unwrap();
    let before = listing(dir);
    let (code, out, err) = lorentz(dir, &["report", "evil.json", "--quick", "--out", "rep"]);
    assert!(!dir.join("evil").exists(), "the recorded command line ran");
    assert_eq!(written_outside(dir, &before, "rep"), Vec::<PathBuf>::new());
    // It is parsed with the command line's own parser (never run): it runs `figure`, which
    // writes no hops result, so provenance FAILs (exit 1); every other check is the unedited
    // file's.
    assert_eq!(code, 1, "{out}{err}");
    let (code, _, err) = lorentz(dir, &["report", "h.json", "--quick", "--out", "rep-h"]);
    assert_eq!(code, 0, "{err}");
    let line = "recorded command line gives the recorded configuration";
    let (evil, fresh) = (checks(dir, "rep"), checks(dir, "rep-h"));
    assert!(
        evil.iter().any(|c| c.0 == "FAIL" && c.2 == line),
        "{evil:?}"
    );
    assert!(
        fresh.iter().any(|c| c.0 == "PASS" && c.2 == line),
        "{fresh:?}"
    );
    let others = |c: &[(String, String, String)]| -> Vec<_> {
        c.iter().filter(|x| x.2 != line).cloned().collect()
    };
    assert_eq!(others(&evil), others(&fresh));
    assert!(
        evil.iter().any(
            |c| c.0 == "PASS" && c.2 == "the recorded configuration re-run gives the same bits"
        )
    );

    // The right command with another configuration (one option changed) FAILs naming the field.
    let mut v = serde_json::from_str::<serde_json::Value>(
        &std::fs::read_to_string(dir.join("h.json")).unwrap(),
    )
    .unwrap();
    let cl = v["meta"]["command_line"].as_array().unwrap().clone();
    let at = cl.iter().position(|a| a == "--order").unwrap() + 1;
    v["meta"]["command_line"][at] = serde_json::json!("4");
    std::fs::write(dir.join("other.json"), v.to_string()).unwrap();
    let (code, _, err) = lorentz(dir, &["report", "other.json", "--quick", "--out", "rep-o"]);
    assert_eq!(code, 1, "{err}");
    let text = std::fs::read_to_string(dir.join("rep-o/report.json")).unwrap();
    assert!(text.contains("order: 3 vs 4"), "{text}");
}

#[test]
fn a_foreign_or_unknown_kind_is_refused() {
    let tmp = crate::common::scratch();
    let dir = tmp.path();
    let (code, json, err) = lorentz(dir, &["constants", "--w", "0.1", "--json"]);
    assert_eq!(code, 0, "{err}");
    std::fs::write(dir.join("c.json"), json).unwrap();
    std::fs::write(dir.join("k.json"), r#"{"kind": "launch", "meta": {}}"#).unwrap();
    // `bench --report` has `rows` too, but is no sweep.
    std::fs::write(dir.join("b.json"), r#"{"w": 0.1, "rows": [], "meta": {}}"#).unwrap();
    let before = listing(dir);
    for f in ["c.json", "k.json", "b.json"] {
        let (code, _, err) = lorentz(dir, &["report", f, "--quick", "--out", "rep"]);
        assert_eq!(code, 2, "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(
            err.contains(f) && err.contains("not a result that report audits"),
            "{err}"
        );
        assert!(err.contains("diffusion (batch_D)"), "{err}");
    }
    assert_eq!(listing(dir), before, "nothing written, not even --out");
}

#[test]
fn understated_work_is_computed_from_the_configuration_and_bounded() {
    let tmp = crate::common::scratch();
    let dir = tmp.path();
    let mut v = result_in(dir, "h.json", &words(HOPS));
    // The configuration asks for 10^14 collisions (about a day on 2 cores); the summary field
    // understates it.
    v["config"]["collisions"] = serde_json::json!(100_000_000_000_000u64);
    std::fs::write(
        dir.join("big.json"),
        serde_json::to_string_pretty(&v).unwrap(),
    )
    .unwrap();
    let before = listing(dir);
    let t = std::time::Instant::now();
    let (code, out, err) = lorentz(dir, &["report", "big.json", "--quick", "--out", "rep"]);
    assert!(t.elapsed().as_secs() < 60, "the configured work ran");
    assert_eq!(code, 1, "{out}{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("rep/report.json")).unwrap())
            .unwrap();
    let c = v["checks"].as_array().unwrap();
    let rerun = c
        .iter()
        .find(|c| c["name"] == "the recorded configuration re-run gives the same bits")
        .unwrap();
    assert_eq!(rerun["verdict"], "SKIP", "{rerun}");
    let why = rerun["detail"].as_str().unwrap();
    assert!(
        why.contains("needs 1.000e14 collisions") && why.contains("2.000e9"),
        "{why}"
    );
    assert!(
        c.iter()
            .any(|c| c["verdict"] == "FAIL"
                && c["name"] == "the record agrees with its configuration")
    );
    assert_eq!(v["rerun_collisions"], 0);
    assert_eq!(written_outside(dir, &before, "rep"), Vec::<PathBuf>::new());

    // Without --quick, a bound of one's own: the same skip (so not a PASS: INCOMPLETE, exit
    // status 5, naming the skipped check), and a fitting re-run still runs.
    let (code, _, err) = lorentz(
        dir,
        &words("report h.json --max-rerun-collisions 1e5 --out rep-bounded"),
    );
    assert_eq!(code, 5, "{err}");
    assert!(
        err.contains("INCOMPLETE") && err.contains("re-run"),
        "{err}"
    );
    assert!(checks(dir, "rep-bounded").iter().any(|c| c.0 == "SKIP"));
    let (code, _, err) = lorentz(
        dir,
        &words("report h.json --max-rerun-collisions 2e5 --out rep-fits"),
    );
    assert_eq!(code, 0, "{err}");
    assert!(checks(dir, "rep-fits").iter().all(|c| c.0 == "PASS"));
}

#[test]
fn extra_keys_are_refused_naming_the_key() {
    let tmp = crate::common::scratch();
    let dir = tmp.path();
    let v = result_in(dir, "h.json", &words(HOPS));
    for (file, key) in [
        ("top.json", "unaudited"),
        ("nested.json", "config.unaudited"),
    ] {
        let mut e = v.clone();
        match key.split_once('.') {
            Some((outer, inner)) => e[outer][inner] = serde_json::json!([1.0, 2.0]),
            None => e[key] = serde_json::json!([1.0, 2.0]),
        }
        std::fs::write(dir.join(file), serde_json::to_string(&e).unwrap()).unwrap();
    }
    let before = listing(dir);
    for (file, key) in [
        ("top.json", "unaudited"),
        ("nested.json", "config.unaudited"),
    ] {
        let (code, _, err) = lorentz(dir, &["report", file, "--quick", "--out", "rep"]);
        assert_eq!(code, 2, "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        // Named with its path by the reader, or by the configuration's own refusal of unknown
        // fields (`unknown field `unaudited``).
        let leaf = key.rsplit('.').next().unwrap();
        assert!(
            (err.contains(&format!("unknown key `{key}`"))
                || err.contains(&format!("unknown field `{leaf}`")))
                && err.contains(file),
            "{err}"
        );
    }
    assert_eq!(listing(dir), before, "nothing written");
}

#[test]
fn an_oversized_file_is_refused_naming_the_limit() {
    let tmp = crate::common::scratch();
    let dir = tmp.path();
    // A sparse file one byte over the limit: refused from its size, before it is read.
    let f = std::fs::File::create(dir.join("big.json")).unwrap();
    f.set_len((64 << 20) + 1).unwrap();
    let before = listing(dir);
    let t = std::time::Instant::now();
    let (code, _, err) = lorentz(dir, &["report", "big.json", "--quick", "--out", "rep"]);
    assert_eq!(code, 2, "{err}");
    assert!(t.elapsed().as_secs() < 10);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("64 MiB") && err.contains("67108865 bytes"),
        "{err}"
    );
    assert_eq!(listing(dir), before, "nothing written");
}

/// The `report_audit` fuzz target's property on its seed corpus and fixed mutations of it
/// (truncations, flipped bytes, numbers made huge, negative or fractional): the quick audit with
/// a re-run bound of 25 000 collisions never panics and writes nothing outside its `out`.
#[test]
fn the_fuzz_seeds_and_their_mutations_stay_inside_out() {
    use lorentz_gas::report::publication::{self, AuditConfig};
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus/report_audit");
    let tmp = crate::common::scratch();
    let dir = tmp.path();
    let mut inputs = Vec::new();
    let mut seeds = 0;
    for e in std::fs::read_dir(&corpus).unwrap() {
        let bytes = std::fs::read(e.unwrap().path()).unwrap();
        let text = String::from_utf8(bytes.clone()).unwrap();
        let n = bytes.len();
        // The seeds first: real results, none fails (the corpus reaches every kind's checks; with
        // a re-run bound of 25 000 collisions some re-runs are skipped: INCOMPLETE, not PASS).
        inputs.insert(0, bytes.clone());
        seeds += 1;
        inputs.push(bytes[..n / 2].to_vec());
        for k in 1..8 {
            let mut b = bytes.clone();
            b[k * n / 8] ^= 0x5a;
            inputs.push(b);
        }
        for (from, to) in [("2,", "1e300,"), ("0.", "-0."), ("1,", "1.5,"), ("[", "[[")] {
            inputs.push(text.replacen(from, to, 3).into_bytes());
        }
    }
    let options = lorentz_gas::engine::options::RunOptions {
        threads: 1,
        ..lorentz_gas::engine::options::RunOptions::default()
    };
    for (i, input) in inputs.iter().enumerate() {
        let _ = std::fs::remove_dir_all(dir.join("out"));
        std::fs::write(dir.join("input.json"), input).unwrap();
        let cfg = AuditConfig {
            quick: true,
            max_rerun_collisions: Some(25_000),
            ..AuditConfig::new(dir.join("input.json"), dir.join("out"))
        };
        let r = publication::run(&cfg, &options);
        if i < seeds {
            let r = r.unwrap_or_else(|e| panic!("seed {i}: {e}"));
            assert_ne!(
                r.verdict,
                publication::Verdict::Fail,
                "seed {i}: {:?}",
                r.checks
            );
            // PASS exactly when nothing was skipped.
            let skipped = r
                .checks
                .iter()
                .any(|c| c.verdict == publication::Verdict::Skip);
            assert_eq!(r.verdict == publication::Verdict::Incomplete, skipped);
        }
        let outside: Vec<PathBuf> = listing(dir)
            .into_iter()
            .filter(|p| p != Path::new("input.json") && !p.starts_with("out"))
            .collect();
        assert!(outside.is_empty(), "input {i}: {outside:?}");
    }
}

/// Whether `c` holds a check of `verdict` whose name starts with `name`.
pub(crate) fn has(c: &[(String, String, String)], verdict: &str, name: &str) -> bool {
    c.iter().any(|x| x.0 == verdict && x.2.starts_with(name))
}

/// The checks every audit of a result with batches passes (their names' beginnings).
const EVERY_AUDIT: [&str; 4] = [
    "recorded command line gives",
    "the record agrees",
    "between-batch F",
    "the recorded configuration re-run",
];

/// A fresh `lorentz ARGS --json` result in a new scratch directory's `file`, reported on with
/// `--quick`: every check passes or does not apply, and each of `names` passes besides those of
/// every audit. The directory and the result's JSON.
pub(crate) fn passes_quick(file: &str, args: &str, names: &[&str]) -> (tempfile::TempDir, String) {
    let tmp = crate::common::scratch();
    let dir = tmp.path();
    let json = result_text_in(dir, file, &words(args));
    let (code, printed, c) = quick_report(dir, file);
    assert_eq!(code, 0, "{printed}");
    assert!(c.iter().all(|x| x.0 == "PASS" || x.0 == "N/A"), "{c:?}");
    for name in EVERY_AUDIT.iter().chain(names) {
        assert!(has(&c, "PASS", name), "{name}: {c:?}");
    }
    (tmp, json)
}

/// `json` with its one occurrence of the number `old` replaced by `new`, written to
/// `dir/edited.json` and reported on with `--quick`: the report must fail (status 1). Its checks.
pub(crate) fn edited_number_report(
    dir: &Path,
    json: &str,
    old: f64,
    new: f64,
) -> Vec<(String, String, String)> {
    assert_eq!(json.matches(&format!("{old}")).count(), 1, "{old}");
    edited_text_report(dir, &json.replacen(&format!("{old}"), &format!("{new}"), 1))
}

/// The result text `edited` written to `dir/edited.json` and reported on with `--quick`: the
/// report must fail (status 1). Its checks.
pub(crate) fn edited_text_report(dir: &Path, edited: &str) -> Vec<(String, String, String)> {
    std::fs::write(dir.join("edited.json"), edited).unwrap();
    let (code, printed, c) = quick_report(dir, "edited.json");
    assert_eq!(code, 1, "{printed}");
    c
}
