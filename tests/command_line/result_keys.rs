//! The "Each result's keys" table of `docs/reference/results.md` is the schema of every
//! result: each command's JSON
//! has no top-level key the table does not name, and each key the table names on its own (a
//! backticked identifier) occurs in that result.

use std::collections::BTreeSet;
use std::path::Path;

use crate::common::scratch;

/// The rows of the table: the result kinds (backticked words of the first column) and the text
/// of the second.
fn documented() -> Vec<(Vec<String>, String)> {
    let readme = include_str!("../../docs/reference/results.md");
    let start = readme
        .find("**Each result's keys**")
        .expect("the table of result keys in docs/reference/results.md");
    let table = &readme[start..];
    let table = &table[..table.find("\n## ").unwrap_or(table.len())];
    table
        .lines()
        .filter(|l| l.starts_with("| `"))
        .map(|l| {
            let cols: Vec<&str> = l.split(" | ").collect();
            let kinds = spans(cols[0]);
            (kinds, cols.get(1).copied().unwrap_or("").to_string())
        })
        .collect()
}

/// The text inside each pair of backticks.
fn spans(text: &str) -> Vec<String> {
    text.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// Every identifier inside the spans (the keys a row names, nested ones included).
fn words(spans: &[String]) -> BTreeSet<String> {
    spans
        .iter()
        .flat_map(|s| {
            s.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .filter(|w| !w.is_empty())
                .map(str::to_string)
                .collect::<Vec<_>>()
        })
        .collect()
}

/// Every key at any depth of `v`.
fn all_keys(v: &serde_json::Value, into: &mut BTreeSet<String>) {
    match v {
        serde_json::Value::Object(o) => {
            for (k, x) in o {
                into.insert(k.clone());
                all_keys(x, into);
            }
        }
        serde_json::Value::Array(a) => a.iter().for_each(|x| all_keys(x, into)),
        _ => {}
    }
}

fn json_of(dir: &Path, line: &str) -> serde_json::Value {
    crate::common::lorentz_json(dir, &line.split_whitespace().collect::<Vec<_>>())
}

fn file_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// One small result of every kind in the table, by the kind's name there.
fn results(dir: &Path) -> Vec<(&'static str, serde_json::Value)> {
    let q = "--json --quiet";
    let diffusion = json_of(
        dir,
        &format!(
            "diffusion --w 0.2 --collisions 2e6 --batches 8 --window 2:8 --check-window 4:16 --msd-grid log {q}"
        ),
    );
    std::fs::write(dir.join("d.json"), diffusion.to_string()).unwrap();
    let run = |line: &str| json_of(dir, &format!("{line} {q}"));
    let table = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/tables/two-radius-square.toml"
    );
    let mut out = vec![
        (
            "diffusion --table",
            run(&format!(
                "diffusion --table {table} --collisions 1e6 --batches 4"
            )),
        ),
        (
            "diffusion --field",
            run(
                "diffusion --w 0.2 --field 1 --collisions 1e6 --batches 4 --localization-samples 1000",
            ),
        ),
        (
            "diffusion --field",
            run(
                "diffusion --scene square --radius 1/4 --field 1 --collisions 1e6 --batches 4 --localization-samples 1000",
            ),
        ),
        (
            "hops",
            run("hops --w 0.1 --collisions 1e6 --batches 4 --order 2"),
        ),
        (
            "theory",
            run("theory --w 0.1 --collisions 1e6 --batches 4 --order 2"),
        ),
        (
            "lattice-walk",
            run("lattice-walk --w 0.1 --collisions 1e6 --batches 4 --order 2"),
        ),
        (
            "backscatter",
            run("backscatter --w 0.1 --particles 2e4 --batches 4"),
        ),
        (
            "escape",
            run("escape --w 0.3 --widths 10,12,14 --particles-per-width 3.2e3"),
        ),
        (
            "escape --repeller",
            run("escape --repeller --side 6 --radius 1 --particles 1e6"),
        ),
        (
            "escape --repeller",
            run("escape --repeller --side 3 --radius 1 --particles 1e5 --window 2"),
        ),
        (
            "sweep",
            run(
                "sweep --w-from 0.1 --w-to 0.2 --steps 3 --runs 2 --collisions-per-run 1e6 --batches-per-run 4 --out sw",
            ),
        ),
        (
            "sweep --shard",
            run(
                "sweep --w-from 0.1 --w-to 0.2 --steps 3 --runs 2 --collisions-per-run 1e6 --batches-per-run 4 --shard 0/2 --out part",
            ),
        ),
        (
            "sweep --fields",
            run(
                "sweep --w 0.1 --fields=-1,1 --collisions-per-run 4e5 --batches-per-run 4 --localization-samples 1000 --out fsw",
            ),
        ),
        (
            "lyapunov --field",
            run("lyapunov --w 0.1 --field 1 --collisions-per-batch 2e4 --batches 2"),
        ),
        (
            "lyapunov --electric",
            run("lyapunov --w 0.1 --electric 1/2 --collisions-per-batch 2e4 --batches 2"),
        ),
        ("audit", run("audit --w 0.1 --collisions 2e3 --batches 2")),
        (
            "audit --field",
            run("audit --w 0.1 --field 1 --collisions 2e3 --batches 2"),
        ),
        (
            "lyapunov",
            run("lyapunov --w 0.1 --collisions-per-batch 2e4 --batches 2 --starts 2"),
        ),
        (
            "shadow",
            run("shadow --w 0.1 --collisions-per-segment 20 --segments 2"),
        ),
        (
            "certify",
            run("certify --w 0.1 --collisions 50 --digits 20"),
        ),
        ("cycles", run("cycles --max-length 3")),
        (
            "trajectory",
            run(
                "trajectory --scene square --radius 1/3 --start 1/2,1/10 --direction 1,1/7 --time 3",
            ),
        ),
        // Beyond w_inf, so that the superdiffusion block and its corridors are there.
        ("constants", json_of(dir, "constants --w 1/2 --json")),
        (
            "superdiffusion",
            run(
                "superdiffusion --scene square --radius 1/4 --collisions 3.2e6 --batches 16 --octaves 6 --vacf-fit 8:32 --msd-fit 16:64",
            ),
        ),
        (
            "free-paths",
            run("free-paths --scene square --radius 1/1000 --collisions 4e4 --batches 4"),
        ),
        (
            "bench",
            run("bench --w 0.1 --collisions-per-thread 1e5 --repetitions 1"),
        ),
        (
            "bench --observer-costs",
            run("bench --w 0.1 --observer-costs --collisions-per-thread 1e5 --repetitions 1"),
        ),
        (
            "bench --long-flights",
            run(
                "bench --long-flights 1/4,1/100 --collisions-per-radius 1e4 --repetitions 1 --walk-collisions 100",
            ),
        ),
        (
            "bench --long-flights --scene triangular",
            run(
                "bench --scene triangular --long-flights 10,100 --collisions-per-radius 1e4 --repetitions 1 --walk-collisions 100",
            ),
        ),
    ];
    run("figure backscatter-map --particles 1e3 --out fig");
    out.push((
        "figure",
        file_json(&dir.join("fig/fig5-backscatter-map.json")),
    ));
    run("report d.json --quick --out rep");
    out.push(("report", file_json(&dir.join("rep/report.json"))));
    out.insert(0, ("diffusion", diffusion));
    out
}

/// Breaking it on purpose: dropping `D_minus_D_check` from the schema's diffusion row fails
/// with "diffusion: top-level key D_minus_D_check is not in the schema's row"; naming a key
/// that no result has fails with "the schema names `…`, the result has no such key".
#[test]
fn every_result_has_exactly_the_keys_the_schema_documents() {
    let tmp = scratch();
    let rows = documented();
    let kinds: BTreeSet<String> = rows.iter().flat_map(|(k, _)| k.clone()).collect();
    let mut failures = Vec::new();
    for (kind, v) in results(tmp.path()) {
        let row = rows
            .iter()
            .find(|(k, _)| k.iter().any(|k| k == kind))
            .or_else(|| {
                let prefix = format!("{kind} ");
                rows.iter().find(|(k, _)| k[0].starts_with(&prefix))
            })
            .unwrap_or_else(|| panic!("no schema row for {kind}"));
        let text = own_part(&row.1, kind, &row.0);
        let named = words(&spans(text));
        let top: Vec<&String> = v.as_object().expect("a JSON object").keys().collect();
        for k in top {
            if !documented_key(k, &named) {
                failures.push(format!(
                    "{kind}: top-level key {k} is not in the schema's row"
                ));
            }
        }
        if row.0[0].starts_with("figure") {
            // The row lists the data of every figure; this run made one of them.
            continue;
        }
        let mut present = BTreeSet::new();
        all_keys(&v, &mut present);
        // A variant's keys (`bench`'s "with `--report`: …") are not in the plain run's result.
        let plain = text.split("with `--").next().unwrap_or("");
        for s in spans(plain) {
            let is_key = s.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
                && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
            if is_key
                && !kinds.contains(&s)
                && !VALUES.contains(&s.as_str())
                && !present.contains(&s)
            {
                failures.push(format!(
                    "{kind}: the schema names `{s}`, the result has no such key"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The part of a row shared by several kinds (`certify`, `trajectory`) that describes `kind`:
/// from "`kind`:" to the next kind's "`other`:"; the whole row otherwise.
fn own_part<'a>(text: &'a str, kind: &str, kinds: &[String]) -> &'a str {
    let Some(from) = text.find(&format!("`{kind}`:")) else {
        return text;
    };
    let rest = &text[from..];
    let to = kinds
        .iter()
        .filter(|k| *k != kind)
        .filter_map(|k| rest.find(&format!("`{k}`:")))
        .min()
        .unwrap_or(rest.len());
    &rest[..to]
}

/// A key the row names, or `X_err` / `X_exact` of a named X where the table's heading ("all
/// estimates with `_err`") or the row (`_exact`) says so.
fn documented_key(k: &str, named: &BTreeSet<String>) -> bool {
    named.contains(k)
        || k.strip_suffix("_err").is_some_and(|x| named.contains(x))
        || k.strip_suffix("_exact")
            .is_some_and(|x| named.contains(x) && named.contains("_exact"))
}

/// Backticked words in the table that are values, not keys.
const VALUES: &[&str] = &["PASS", "FAIL", "SKIP", "N/A", "INCOMPLETE"];
