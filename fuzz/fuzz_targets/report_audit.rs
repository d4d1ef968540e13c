//! The publication audit (`lorentz report`) on arbitrary bytes and on mutations of real result
//! files (the seed corpus `fuzz/corpus/report_audit/`, written by `fuzz/report_seeds.sh`): it
//! never panics, and it writes nothing outside its output directory — checked by listing the
//! scratch directory (the input file and `out/` only) and the current directory (no name added or removed)
//! after every input. The quick audit with a re-run bound of [`MAX_RERUN`] collisions: re-runs
//! above it are reported as SKIP, so an input costs milliseconds (a re-run that fits, such as
//! a small backscatter result's, runs for real).
#![no_main]

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::report::publication::{self, AuditConfig};

/// Most collisions one input may re-run.
const MAX_RERUN: u64 = 25_000;

/// Every path below `dir`, relative to it.
fn listing(dir: &Path) -> BTreeSet<PathBuf> {
    fn walk(root: &Path, d: &Path, out: &mut BTreeSet<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(d) else {
            return;
        };
        for e in entries.flatten() {
            let p = e.path();
            out.insert(p.strip_prefix(root).unwrap_or(&p).to_path_buf());
            if p.is_dir() {
                walk(root, &p, out);
            }
        }
    }
    let mut out = BTreeSet::new();
    walk(dir, dir, &mut out);
    out
}

/// The names in `dir` (not below it: the current directory may hold a large build tree).
fn names(dir: &Path) -> BTreeSet<PathBuf> {
    std::fs::read_dir(dir)
        .map(|e| e.flatten().map(|e| e.path()).collect())
        .unwrap_or_default()
}

/// This process's scratch directory (made once).
fn scratch() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = std::env::temp_dir().join(format!("lorentz-fuzz-report-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).expect("a scratch directory");
        d
    })
}

fuzz_target!(|data: &[u8]| {
    let root = scratch();
    let input = root.join("input.json");
    let out = root.join("out");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::write(&input, data).expect("write the input");
    let cwd = std::env::current_dir().expect("the current directory");
    let here = names(&cwd);
    let cfg = AuditConfig {
        quick: true,
        max_rerun_collisions: Some(MAX_RERUN),
        ..AuditConfig::new(&input, &out)
    };
    let options = RunOptions {
        threads: 1,
        ..RunOptions::default()
    };
    // Bad input is an `Err`, a FAIL a report: both fine; a panic is the bug.
    let _ = publication::run(&cfg, &options);
    let outside: Vec<PathBuf> = listing(root)
        .into_iter()
        .filter(|p| p != Path::new("input.json") && !p.starts_with("out"))
        .collect();
    assert!(outside.is_empty(), "written outside --out: {outside:?}");
    assert_eq!(names(&cwd), here, "the current directory changed");
});
