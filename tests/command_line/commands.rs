//! The command line: every subcommand refuses bad input with exit status 2 and one line naming the
//! valid range — never a panic, an abort or a file written — and every result carries the same
//! metadata block; counts are typed as physicists type them; results do not depend on --threads.

use std::process::Command;

use crate::common::{lorentz_in, words};

use crate::bad_inputs::{BAD, BAD_WITH_SPACES};

#[test]
fn bad_input_is_refused_with_status_2_one_line_and_no_files() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let mut failures = Vec::new();
    let split = BAD.iter().map(|(line, needle)| (words(line), needle));
    let spaced = BAD_WITH_SPACES
        .iter()
        .map(|(a, needle)| (a.to_vec(), needle));
    for (args, needle) in split.chain(spaced) {
        let (code, out, err) = lorentz_in(&dir, &args);
        let lines = err.lines().filter(|l| !l.trim().is_empty()).count();
        let written: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().collect();
        if code != 2
            || !out.is_empty()
            || lines != 1
            || !err.to_lowercase().contains(&needle.to_lowercase())
            || err.contains("panicked")
            || !written.is_empty()
        {
            failures.push(format!(
                "{args:?}: status {code}, {lines} stderr lines '{}' (wanted '{needle}'), stdout {} bytes, {} files written",
                err.trim(),
                out.len(),
                written.len()
            ));
        }
        for f in written {
            let _ = std::fs::remove_dir_all(f.path());
            let _ = std::fs::remove_file(f.path());
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A file or directory that cannot be read or written exits with status 3 and one line naming
/// the operation and the path — whatever the command: an output directory under a regular file
/// (a test may run as root, where permission bits do not stop a write, but a path through a file
/// stops everyone), an input file that does not exist.
#[test]
fn unreadable_or_unwritable_paths_exit_3_naming_the_path() {
    let tmp = crate::common::scratch();
    let dir = tmp.path();
    std::fs::write(dir.join("file"), "a regular file").unwrap();
    // (command line, the operation and the path its one line must name)
    let cases = [
        (
            "report no-such-result.json --quick",
            "cannot read",
            "no-such-result.json",
        ),
        (
            "slurm sweep --w-from 0.1 --w-to 0.2 --array 2 --out file/sub",
            "cannot create directory",
            "file/sub",
        ),
        (
            "sweep --w-from 0.1 --w-to 0.2 --steps 2 --runs 2 --collisions-per-run 1e5 \
             --batches-per-run 2 --out file/sweep",
            "cannot create directory",
            "file/sweep",
        ),
        (
            "figure backscatter-map --particles 100 --out file/fig",
            "cannot create directory",
            "file/fig",
        ),
        (
            "trajectory --scene square --radius 1/3 --start 1/2,1/10 --direction 1,1/7 \
             --time 5 --events file/events.csv",
            "cannot create",
            "file/events.csv",
        ),
    ];
    let mut failures = Vec::new();
    for (line, op, path) in cases {
        let args = words(line);
        let (code, out, err) = lorentz_in(dir, &args);
        let lines = err.lines().filter(|l| !l.trim().is_empty()).count();
        if code != 3 || lines != 1 || !err.contains(op) || !err.contains(path) || !out.is_empty() {
            failures.push(format!(
                "{args:?}: status {code}, {lines} stderr lines '{}' (wanted '{op}' and '{path}')",
                err.trim()
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `LORENTZ_SIMD` naming an unknown path is refused like any bad input; naming `portable` runs
/// and says so in the metadata.
#[test]
fn simd_path_override_is_checked_and_reported() {
    let run = |v: &str| {
        Command::new(env!("CARGO_BIN_EXE_lorentz"))
            .args(words("diffusion --w 0.2 --collisions 4e5 --batches 4"))
            .args(["--json", "--quiet"])
            .env("LORENTZ_SIMD", v)
            .output()
            .expect("run lorentz")
    };
    let bad = run("avx9");
    let err = String::from_utf8_lossy(&bad.stderr);
    assert_eq!(bad.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("avx512, avx2 or portable"), "{err}");
    let good = run("portable");
    assert_eq!(good.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&good.stdout).unwrap();
    assert_eq!(v["meta"]["engine"], "simd");
    assert_eq!(v["meta"]["simd"], "portable");
}

/// One quick good run of every subcommand: exit 0, JSON with the shared metadata block, counts
/// written as 2e6 and 2_000_000, and --quiet accepted everywhere.
#[test]
fn every_command_accepts_json_quiet_and_scientific_counts_and_shares_one_metadata_block() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let runs: &[&str] = &[
        // 8 batches: the fewest the report's batch statistics judge (fewer: INCOMPLETE).
        "diffusion --w 0.2 --collisions 2e6 --batches 8 --window 2:8 --check-window 4:16",
        "audit --w 0.1 --collisions 2_000 --batches 2",
        "lyapunov --w 0.1 --collisions-per-batch 2e4 --batches 2 --starts 0",
        "certify --w 0.1 --collisions 50 --digits 20",
        "cycles --max-length 2",
        "backscatter --w 0.1 --particles 2e4 --batches 4",
        "hops --w 0.1 --collisions 1e6 --batches 4 --order 2",
        "theory --w 0.1 --collisions 1e6 --batches 4 --order 2",
        "lattice-walk --w 0.1 --collisions 1e6 --order 2",
        "constants --w 0.1 --precision 200",
        "escape --w 0.3 --widths 10,12,14 --particles-per-width 3.2e3",
        "figure backscatter-map --particles 1e3 --out fig",
        "bench --w 0.1 --collisions-per-thread 1e5 --repetitions 3",
        "sweep --w-from 0.1 --w-to 0.2 --steps 3 --runs 2 --collisions-per-run 1_000_000 \
         --batches-per-run 4 --out sweep",
        "shadow --w 0.1 --collisions-per-segment 20 --segments 2",
        "trajectory --scene square --radius 1/3 --start 1/2,1/10 --direction 1,1/7 --time 3",
        "report d.json --quick --out rep",
        "merge p0 p1 --out merged",
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 2 --out slurm",
    ];
    // What `merge` merges: the two parts of a sweep. (`report` audits the diffusion result the
    // first run below writes; `reproduce --json` takes minutes:
    // `report::quick_reproduction_writes_every_figure_and_resumes`, which CI runs with --ignored,
    // checks it.)
    for part in ["0", "1"] {
        let line = format!(
            "sweep --w-from 0.1 --w-to 0.2 --steps 3 --runs 2 --collisions-per-run 1e6 \
             --batches-per-run 4 --shard {part}/2 --out p{part} --quiet"
        );
        let (code, _, err) = lorentz_in(&dir, &words(&line));
        assert_eq!(code, 0, "{err}");
    }
    for line in runs {
        let args = words(line);
        let mut a = args.clone();
        a.push("--json");
        if args[0] != "constants" {
            a.push("--quiet");
        }
        let (code, out, err) = lorentz_in(&dir, &a);
        assert_eq!(code, 0, "{a:?}: {err}");
        if args[0] == "diffusion" {
            std::fs::write(dir.join("d.json"), &out).unwrap();
        }
        let v: serde_json::Value =
            serde_json::from_str(&out).unwrap_or_else(|e| panic!("{a:?}: {e}: {out}"));
        let meta = find_meta(&v).unwrap_or_else(|| panic!("{a:?}: no meta block in {out}"));
        for k in [
            "version",
            "seed",
            "batches",
            "precision",
            "engine",
            "threads",
            "command_line",
        ] {
            assert!(meta.get(k).is_some(), "{a:?}: meta lacks {k}");
        }
        assert_eq!(meta["version"], env!("CARGO_PKG_VERSION"));
        assert_eq!(meta["command_line"][1], args[0], "{a:?}");
    }
    // The figure's data file carries the same block.
    let fig: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("fig").join("fig5-backscatter-map.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(fig["meta"]["seed"], 1);
    // The sweep's grid point is the decimal asked for.
    let csv = std::fs::read_to_string(dir.join("sweep").join("sweep.csv")).unwrap();
    assert!(csv.contains("\n0.15,"), "{csv}");
    assert!(!csv.contains("0.15000000000000002"), "{csv}");
    let _ = std::fs::remove_dir_all(&dir);
}

fn find_meta(v: &serde_json::Value) -> Option<&serde_json::Value> {
    if let Some(m) = v.get("meta") {
        return Some(m);
    }
    v.as_object()?.values().find_map(|x| x.get("meta"))
}

/// Everything in a result except what describes the invocation (time, threads, command line).
fn physics(mut v: serde_json::Value) -> serde_json::Value {
    fn strip(v: &mut serde_json::Value) {
        if let Some(o) = v.as_object_mut() {
            // `w_exact` is the gap as typed: "0.1" and "1/10" are the same number; the precision
            // plan is timed at the run's speed.
            for k in [
                "meta",
                "seconds",
                "collisions_per_second",
                "w_exact",
                "plan",
            ] {
                o.remove(k);
            }
            for x in o.values_mut() {
                strip(x);
            }
        }
    }
    strip(&mut v);
    v
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    for base in [
        &["audit", "--w", "0.1", "--collisions", "1e5", "--json"][..],
        &words(
            "diffusion --w 0.2 --collisions 2e6 --batches 4 --window 2:8 --check-window 4:16 \
             --json",
        )[..],
        &words("hops --w 0.1 --collisions 1e6 --batches 4 --order 2 --json")[..],
    ] {
        let run = |t: &str| {
            let mut a = base.to_vec();
            a.extend(["--threads", t]);
            let (code, out, err) = lorentz_in(&dir, &a);
            assert_eq!(code, 0, "{a:?}: {err}");
            physics(serde_json::from_str(&out).unwrap())
        };
        let (one, two) = (run("1"), run("2"));
        assert!(
            one == two,
            "{base:?}: the result differs between --threads 1 and 2 (events {} vs {})",
            one["events"],
            two["events"]
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn json_outputs_have_the_documented_keys() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let v = crate::common::lorentz_json(
        &dir,
        &words(
            "diffusion --w 0.2 --collisions 2000000 --batches 4 --window 2:8 --check-window 4:16 \
             --json",
        ),
    );
    for k in [
        "w",
        "D",
        "D_err",
        "D_MZ",
        "mean_free_path",
        "mean_free_path_err",
        "mean_free_path_exact",
        "tau_hop",
        "tau_hop_err",
        "tau_hop_exact",
        "collisions",
        "seconds",
        "collisions_per_second",
    ] {
        assert!(v.get(k).is_some(), "missing key {k}");
    }
    assert_eq!(v["meta"]["precision"], "f64");
    assert_eq!(v["meta"]["seed"], 1);
    assert_eq!(v["meta"]["batches"], 4);
    // One spelling per value: the config's number type is the meta's.
    assert_eq!(v["config"]["precision"], "f64");
    assert_eq!(
        v["msd_over_4t"].as_array().map(Vec::len),
        v["msd_over_4t_err"].as_array().map(Vec::len)
    );
    // Numbers as JSON numbers, with every digit of the working precision.
    let (code, out, _) = lorentz_in(
        &dir,
        &["constants", "--w", "0.1", "--precision", "200", "--json"],
    );
    assert_eq!(code, 0);
    let c: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!((c["w_inf"].as_f64().unwrap() - 0.309_401_076_758_503).abs() < 1e-14);
    assert!(
        out.contains("\"w_inf\": 3.0940107675850305803659512200782982"),
        "{out}"
    );
    assert_eq!(c["meta"]["precision"], "200");
    // Estimates as flat x / x_err pairs, records with named keys.
    let t = crate::common::lorentz_json(
        &dir,
        &words("theory --w 0.1 --collisions 1e6 --batches 4 --order 2 --json --quiet"),
    );
    for k in [
        "p_bs",
        "p_bs_err",
        "p_cf",
        "p_cf_err",
        "p_cf_appendix_a",
        "p_cf_appendix_a_as_printed",
        "D_2_as_printed",
        "D_3_as_printed",
        "D_GK",
        "D_GK_err",
    ] {
        assert!(t[k].is_number(), "theory: {k} is not a number");
    }
    for k in ["k", "D_k", "D_k_combined", "D_lattice_walk"] {
        assert!(t["orders"][0][k].is_number(), "theory: orders lack {k}");
    }
    let b = crate::common::lorentz_json(
        &dir,
        &words("backscatter --w 0.1 --particles 2e4 --batches 4 --json --quiet"),
    );
    for k in ["p_bs", "p_l", "p_r", "p_cf"] {
        assert!(b[k].is_number(), "backscatter: {k}");
        assert!(b[format!("{k}_err")].is_number(), "backscatter: {k}_err");
    }
    assert_eq!(b["particles"], 20000);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A closed standard output (the reader of a pipe has gone) ends the program quietly with status
/// 0 — no panic, no backtrace; a standard output that cannot be written (a full device) is
/// reported on stderr with status 3; a closed standard error never panics.
#[test]
fn closed_or_failing_output_ends_quietly() {
    use std::process::Stdio;
    let args = words("diffusion --w 0.1 --collisions 4e6 --batches 4 --json --quiet");
    let mut child = Command::new(env!("CARGO_BIN_EXE_lorentz"))
        .args(&args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // the reader goes away before anything is written
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "stderr: {err}");
    assert!(!err.contains("panicked") && err.is_empty(), "stderr: {err}");
    if let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") {
        let out = Command::new(env!("CARGO_BIN_EXE_lorentz"))
            .args(&args)
            .stdout(full)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(3), "stderr: {err}");
        assert!(
            err.contains("cannot write to standard output") && !err.contains("panicked"),
            "{err}"
        );
    }
    let out = Command::new(env!("CARGO_BIN_EXE_lorentz"))
        .args(["diffusion", "--w", "0.5"])
        .stderr(Stdio::null())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}

/// A gap is an exact input: `--w 0.2` at 200 bits is 0.2 to the last digit (not the double
/// nearest 0.2), and `--w 1/10` is accepted and gives the bits of `--w 0.1` in an f64 run.
#[test]
fn gaps_are_exact_decimals_or_fractions() {
    let tmp = crate::common::scratch();
    let dir = tmp.path();
    // As text, every digit shown is one that 200 bits guarantee, and so is the decimal's.
    let (code, out, err) = lorentz_in(dir, &["constants", "--w", "0.2", "--precision", "200"]);
    assert_eq!(code, 0, "{err}");
    let shown = |key: &str| {
        let line = out
            .lines()
            .find(|l| l.split_whitespace().next() == Some(key));
        line.and_then(|l| l.split_whitespace().nth(1))
            .unwrap_or_else(|| panic!("no {key} row in {out}"))
            .to_string()
    };
    // ⌊199·log₁₀2⌋ = 59 significant digits.
    assert_eq!(shown("w"), format!("2.{}e-1", "0".repeat(58)));
    assert_eq!(shown("w_exact"), "1/5");
    let (code, out, err) = lorentz_in(
        dir,
        &["constants", "--w", "0.2", "--precision", "200", "--json"],
    );
    assert_eq!(code, 0, "{err}");
    // The JSON number as written (a parsed f64 would round it): 200 bits hold 60 digits, the
    // first 55 after the point are the decimal's zeros.
    let w = out
        .lines()
        .find_map(|l| l.trim().strip_prefix("\"w\": "))
        .expect("a w key")
        .trim_end_matches(',');
    assert!(
        w.starts_with(&format!("2.{}", "0".repeat(55))),
        "w = {w} is not 0.2 at 200 bits"
    );
    let run = |w: &str| {
        let args = [
            "diffusion",
            "--w",
            w,
            "--collisions",
            "4e6",
            "--batches",
            "4",
            "--json",
            "--quiet",
        ];
        let v = crate::common::lorentz_json(dir, &args);
        (v["w"].as_f64().unwrap(), v["D"].as_f64().unwrap().to_bits())
    };
    assert_eq!(run("1/10"), run("0.1"));
}

/// Every command that takes `--w` takes a fraction: `--w 1/10` gives exactly the result of
/// `--w 0.1` (in f64 analyses both are the double nearest 0.1; at MPFR precision both are 1/10
/// rounded at that precision), whatever the command (bench, a timing, only has to accept it).
#[test]
fn every_command_taking_w_takes_a_fraction_with_the_same_result() {
    let tmp = crate::common::scratch();
    let dir = tmp.path();
    // W is replaced by the gap as a decimal, then as a fraction.
    let commands = [
        "diffusion --w W --collisions 2e6 --batches 4 --window 2:8 --check-window 4:16",
        "audit --w W --collisions 2e3 --batches 2",
        "lyapunov --w W --collisions-per-batch 2e4 --batches 2 --starts 2",
        "certify --w W --collisions 50 --digits 20",
        "shadow --w W --collisions-per-segment 20 --segments 2",
        "backscatter --w W --particles 2e4 --batches 4",
        "hops --w W --collisions 1e6 --batches 4 --order 2",
        "theory --w W --collisions 1e6 --batches 4 --order 2",
        "lattice-walk --w W --collisions 1e6 --order 2",
        "constants --w W",
        "constants --w W --precision 300",
        "escape --w W --widths 10,12,14 --particles-per-width 3.2e3",
        "figure backscatter-map --w W --particles 1e3 --out fig",
        "trajectory --scene triangular --w W --start 0,1.5 --direction 1,1/7 --time 3",
        "bench --w W --collisions-per-thread 1e4 --repetitions 1",
        "sweep --w-from W --w-to 0.25 --steps 2 --runs 2 --collisions-per-run 2e6 \
         --batches-per-run 4 --out OUT",
    ];
    let mut failures = Vec::new();
    for line in commands {
        let run = |w: &str| {
            // A folder of its own for each spelling (a sweep resumes only its own grid).
            let out = format!("out-{}", w.replace('/', "-over-"));
            let mut args: Vec<&str> = line
                .split_whitespace()
                .map(|a| match a {
                    "W" => w,
                    "OUT" => &out,
                    _ => a,
                })
                .collect();
            args.push("--json");
            let (code, out, err) = lorentz_in(dir, &args);
            let v = serde_json::from_str::<serde_json::Value>(&out).map(physics);
            // A sweep records its ends as typed ("1/10" or "0.1"); its rows must agree.
            let v = v.map(|v| match line.starts_with("sweep") {
                true => v["rows"].clone(),
                false => v,
            });
            (code, v.map_err(|e| format!("{e}: {err}")))
        };
        let (decimal, fraction) = if line.starts_with("escape") {
            (run("0.3"), run("3/10"))
        } else {
            (run("0.1"), run("1/10"))
        };
        let same = line.starts_with("bench") || decimal.1.as_ref().ok() == fraction.1.as_ref().ok();
        if decimal.0 != 0 || fraction.0 != 0 || decimal.1.is_err() || !same {
            failures.push(format!("{line}: {decimal:?} against {fraction:?}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
