//! The command line: every subcommand refuses bad input with exit status 2 and one line naming the
//! valid range — never a panic, an abort or a file written — and every result carries the same
//! metadata block; counts are typed as physicists type them; results do not depend on --threads.

use std::process::Command;

use crate::common::{lorentz_in, words};

/// (command line, split at white space; a word the one-line message must contain)
const BAD: &[(&str, &str)] = &[
    // diffusion
    ("diffusion --w 0", "0 < w < 4/sqrt(3) - 2"),
    ("diffusion --w -0.1", "trapped"),
    ("diffusion --w 0.31", "0.309"),
    ("diffusion --w 0.3094010767585031", "infinite"),
    ("diffusion --w NaN", "finite"),
    ("diffusion --w inf", "finite"),
    ("diffusion --w abc", "invalid value"),
    (
        "diffusion --w 1e-300 --collisions 1000",
        "more than any run",
    ),
    ("diffusion --w 0.1 --precision 52", "53"),
    ("diffusion --w 0.1 --rel-err 0", "[1e-7, 0.5]"),
    ("diffusion --w 0.1 --rel-err 0.7", "[1e-7, 0.5]"),
    ("diffusion --w 0.1 --rel-err NaN", "[1e-7, 0.5]"),
    ("diffusion --w 0.1 --rel-err 1e-9", "[1e-7, 0.5]"),
    ("diffusion --w 0.1 --precision double", "f64"),
    (
        "diffusion --w 0.1 --msd-grid fine",
        "use fit (the fit windows' lags), log",
    ),
    (
        "diffusion --w 0.1 --field 1 --msd-grid log",
        "measured without a field",
    ),
    ("diffusion --w 0.1 --collisions 0", "collisions"),
    ("diffusion --w 0.1 --collisions -5", "whole number"),
    ("diffusion --w 0.1 --collisions 1.5", "whole number"),
    ("diffusion --w 0.1 --collisions 1e20", "too large"),
    ("diffusion --w 0.1 --batches 0", "batches"),
    ("diffusion --w 0.1 --engine gpu", "simd"),
    (
        "diffusion --w 0.1 --engine simd --precision 128",
        "f64 only",
    ),
    ("diffusion --w 0.1 --collisions 1e18 --batches 2", "2^50"),
    ("hops --w 0.1 --engine fast", "scalar"),
    ("bench --w 0.1 --observe all", "diffusion"),
    ("diffusion --w 0.1 --batches 1", "batches"),
    ("diffusion --w 0.1 --batches 5e9", "4294967295"),
    (
        "diffusion --w 0.1 --batches 4e9 --collisions 1e19",
        "at most 1048576",
    ),
    (
        "sweep --w-from 0.1 --w-to 0.2 --steps 4e9 --out out",
        "2 to 10000",
    ),
    (
        "audit --w 0.1 --batches 4e9 --collisions 1e19",
        "at most 1048576",
    ),
    ("diffusion --w 0.1 --collisions 1000", "too small"),
    ("diffusion --w 0.1 --threads 0", "threads must be from 1"),
    ("diffusion --w 0.1 --threads 1e9", "threads must be from 1"),
    ("diffusion --w 0.1 --threads 4096", "4 per core"),
    ("bench --w 0.1 --threads 4096", "4 per core"),
    ("diffusion --w 0.1 --window 40:10", "window"),
    ("diffusion --w 0.1 --audit 2", "(0, 1]"),
    ("diffusion --w 0.1 --audit 0.1 --reference-bits 64", "128"),
    // audit
    ("audit --w 0", "trapped"),
    ("audit --w 0.1 --collisions 0", "collisions"),
    ("audit --w 0.1 --batches 0", "batches"),
    ("audit --w 0.1 --sample 0", "(0, 1]"),
    ("audit --w 0.1 --sample 1.5", "(0, 1]"),
    ("audit --w 0.1 --reference-bits 64", "128"),
    ("audit --w 0.1 --field 1e7", "1e6"),
    ("audit --w 0.1 --field -1e-7", "1e-6"),
    ("audit --w 0.1 --field one", "field"),
    ("diffusion --w 0.1 --field one", "field"),
    ("audit --w 0.1 --reference-bits 4000000000", "65536"),
    // scenes
    ("audit --scene square --radius 0.5", "0 < radius < 1/2"),
    ("audit --scene square --radius -1/3", "0 < radius < 1/2"),
    ("audit --scene square --radius 1/0", "divides by zero"),
    ("audit --scene square --radius x", "not a decimal"),
    ("audit --scene square", "needs --radius"),
    (
        "certify --scene square --radius inf",
        "radius must be a finite number",
    ),
    ("shadow --w nan", "w must be a finite number"),
    ("shadow --w 1/0", "divides by zero"),
    (
        "figure backscatter-map --w 1/0 --out out",
        "divides by zero",
    ),
    (
        "trajectory --scene square --radius nan --start 0,0 --direction 1,0 --time 1",
        "radius must be a finite number",
    ),
    (
        "audit --scene square --radius 0.3 --w 0.1",
        "does not apply",
    ),
    ("audit --scene hexagonal --w 0.1", "triangular"),
    ("lyapunov --w 0.1 --radius 0.3", "does not apply"),
    ("certify --scene square --radius 0.7", "0 < radius < 1/2"),
    (
        "diffusion --scene square --radius 1/3",
        "in a magnetic field every scene has a finite horizon",
    ),
    (
        "diffusion --scene square --radius 1/3 --field 1 --rel-err 1e-3",
        "not planned for a relative error",
    ),
    ("diffusion --collisions 1e6", "needs --w"),
    (
        "sweep --scene square --radius 1/4 --w-from 0.1 --w-to 0.2",
        "sweep over w without a field is the triangular scene's",
    ),
    (
        "sweep --scene square --fields=1,2",
        "the square scene needs --radius",
    ),
    // superdiffusion
    ("superdiffusion --w 0.1", "finite horizon"),
    (
        "superdiffusion --scene square --radius 1/2",
        "0 < radius < 1/2",
    ),
    (
        "superdiffusion --scene square --radius 1/4 --batches 4",
        "at least 16",
    ),
    ("superdiffusion --w 0.5 --msd-fit 64:8", "FROM:TO"),
    ("superdiffusion --w 0.5 --vacf-fit 64:8192", "2^octaves"),
    ("superdiffusion --w 0.5 --collisions 1e5", "per batch"),
    // lyapunov
    ("lyapunov --w -0.4", "trapped"),
    ("lyapunov --w 0.1 --batches 1", "batches"),
    ("lyapunov --w 0.1 --collisions-per-batch 0", "collisions"),
    ("lyapunov --w 0.1 --starts 1e6", "starts"),
    // certify
    ("certify --w 0", "trapped"),
    ("certify --w 0.1 --collisions 0", "collisions"),
    ("certify --w 0.1 --digits 0", "digits"),
    ("certify --w 0.1 --digits -3", "whole number"),
    ("diffusion --w 0.1 --seed -1", "whole number"),
    (
        "certify --w 0.1 --collisions 100000000000",
        "use at most 33007 collisions (where the memory limit of 4 GiB binds)",
    ),
    ("certify --w 0.1 --collisions 200000 --digits 10", "memory"),
    // shadow
    ("shadow --w 0.4", "0 < w < 0.309401"),
    (
        "shadow --w 0.1 --collisions-per-segment 0",
        "use 2 to 10000",
    ),
    (
        "shadow --w 0.1 --collisions-per-segment 2e4",
        "use 2 to 10000",
    ),
    ("shadow --w 0.1 --reference-bits 64", "use 128 to"),
    ("shadow --w 0.1 --segments 0", "use 1 to 10000"),
    // backscatter
    ("backscatter --w 0", "trapped"),
    ("backscatter --w 0.1 --particles 0", "particles"),
    ("backscatter --w 0.1 --batches 1", "batches"),
    ("backscatter --w 0.1 --precision 20", "53"),
    // hops
    ("hops --w 0.35", "infinite"),
    ("hops --w 0.1 --collisions 0", "collisions"),
    ("hops --w 0.1 --order 0", "order"),
    ("hops --w 0.1 --order 100", "order"),
    ("hops --w 0.1 --batches 1", "batches"),
    // checkpoint intervals
    ("diffusion --w 0.1 --checkpoint-every -1", "0 to 86400"),
    ("hops --w 0.1 --checkpoint-every 1e6", "0 to 86400"),
    ("escape --w 0.1 --checkpoint-every soon", "0 to 86400"),
    (
        "sweep --w-from 0.1 --w-to 0.2 --checkpoint-every NaN",
        "0 to 86400",
    ),
    // lyapunov in a field
    (
        "lyapunov --scene triangular --w 0.1 --field 1 --starts 4",
        "not measured in a field",
    ),
    (
        "lyapunov --scene triangular --w 0.1 --field 5000",
        "1e-3 <= |field| <= 1e3",
    ),
    // trajectory in a field
    (
        "trajectory --scene triangular --w 0.1 --start 1.05,0 --direction 0,1 --time 1 \
         --field 2000000",
        "|field| <= 1e6",
    ),
    // sweep in a field
    (
        "sweep --w 0.1 --fields=0,1 --out out",
        "1e-3 <= |field| <= 1e3",
    ),
    ("sweep --w 0.1 --fields=1,1 --out out", "appears twice"),
    (
        "sweep --w 0.1 --fields=1 --runs 2 --out out",
        "--runs 2: not used by a sweep in a field",
    ),
    (
        "sweep --w 0.1 --w-from 0.1 --w-to 0.2 --field 1",
        "not both",
    ),
    ("sweep --w 0.1 --out out", "--fields"),
    ("sweep --w 0.1 --field 1 --fields=2 --out out", "not both"),
    (
        "sweep --w-from 0.1 --w-to 0.2 --field 1 --shard 0/2000",
        "has parts 0 to N-1",
    ),
    // sweep
    ("sweep --w-from 0.1 --w-to 0.5 --out out", "infinite"),
    ("sweep --w-from 0.1 --w-to 0.2 --steps 1 --out out", "steps"),
    ("sweep --w-from 0.1 --w-to 0.2 --runs 0 --out out", "runs"),
    (
        "sweep --w-from 0.1 --w-to 0.2 --batches-per-run 1 --out out",
        "batches",
    ),
    ("sweep --w-from abc --w-to 0.2 --out out", "decimal"),
    (
        "sweep --w-from 0.1 --w-to 0.1 --steps 3 --out out",
        "distinct w",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.1 --array 2 --out out",
        "distinct w",
    ),
    (
        "sweep --w-from 0.1 --w-to 0.2 --collisions-per-run 1000 --out out",
        "too small",
    ),
    (
        "sweep --w-from 0.1 --w-to 0.2 --shard 3/3 --out out",
        "0 to N-1",
    ),
    ("sweep --w-from 0.1 --w-to 0.2 --shard a/b --out out", "I/N"),
    (
        "sweep --w-from 0.1 --w-to 0.2 --shard 11/12 --out out",
        "every part needs a point",
    ),
    // report, reproduce
    ("report r.json --reference-bits 64", "128 to 65536"),
    ("report r.json --reference-bits 1e6", "128 to 65536"),
    ("report r.json --seed 2", "unexpected argument '--seed'"),
    ("reproduce --budget huge --out out", "invalid value"),
    (
        "reproduce --budget quick --threads 0 --out out",
        "threads must be from 1 to",
    ),
    ("reproduce --seed -1 --out out", "is not a count"),
    // trajectory: the start, the direction, the time and the digits
    (
        "trajectory --scene square --radius 1/3 --start 0,0 --direction 1,0 --time 1",
        "distance >= the radius",
    ),
    (
        "trajectory --scene square --radius 1/3 --start 1/2 --direction 1,0 --time 1",
        "--start '1/2': not a pair",
    ),
    (
        "trajectory --scene square --radius 1/3 --start 1/2,1/10 --direction 0,0 --time 1",
        "use a nonzero direction",
    ),
    (
        "trajectory --scene square --radius 1/3 --start 1/2,1/10 --direction 1,0 --time 0",
        "use a time > 0",
    ),
    (
        "trajectory --scene square --radius 1/3 --start 1/2,1/10 --direction 1,0 --time 1e30",
        "use a shorter time",
    ),
    (
        "trajectory --scene square --radius 1/3 --start 1/2,1/10 --direction 1,0 --time 1 \
         --digits 20000",
        "use 1 to 10000",
    ),
    // one value is not an error bar; a check window equal to the fit window checks nothing
    (
        "lyapunov --w 0.1 --starts 1",
        "use 0 (no divergence measurement) or 2 to",
    ),
    (
        "diffusion --w 0.1 --window 10:40 --check-window 10:40",
        "is the fit window 10:40",
    ),
    ("sweep --w-from 1/0 --w-to 0.2 --out out", "divides by zero"),
    // merge
    ("merge no-such-dir --out out", "no sweep points"),
    ("merge --out out", "required"),
    ("merge d --seed 2", "unexpected argument '--seed'"),
    // slurm
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 0 --out out",
        "1 to 11 parts",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 12 --out out",
        "1 to 11 parts",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 4 --time 2h --out out",
        "2:00:00",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 4 --cpus-per-task 0 --out out",
        "cpus-per-task",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.5 --array 4 --out out",
        "infinite",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 4 --threads 2 --out out",
        "unexpected argument '--threads'",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 4 --account a;id --out out",
        "letters, digits",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 4 --mem 4GB --out out",
        "K, M, G or T",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 4 --sbatch=--qos=$(id) --out out",
        "--key=value",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 4 --sbatch=--array=0-99 --out out",
        "written by the campaign",
    ),
    // figure
    ("figure fig9 --out out", "unrecognized subcommand"),
    (
        "figure backscatter --w 0.1 --out out",
        "unexpected argument '--w'",
    ),
    (
        "figure hierarchy --particles-per-gap 10 --out out",
        "unexpected argument",
    ),
    ("figure backscatter-map --w 0 --out out", "trapped"),
    (
        "figure backscatter-map --particles 0 --out out",
        "particles",
    ),
    // theory
    ("theory --w 0", "trapped"),
    ("theory --w 0.1 --order 0", "order"),
    ("theory --w 0.1 --order 100", "order"),
    // lattice-walk
    ("lattice-walk --w 0", "trapped"),
    ("lattice-walk --w 0.1 --order 0", "order"),
    ("lattice-walk --w 0.1 --order 100", "order"),
    // escape
    ("escape --w 0", "trapped"),
    (
        "escape --w 0.1 --widths 3,20,30",
        "--widths 3 is out of range: use widths L from",
    ),
    ("escape --w 0.1 --widths 20,30", "3 distinct"),
    ("escape --w 0.1 --particles-per-width 0", "particles"),
    ("escape --w 0.1 --particles-per-width 1e12", "particles"),
    // constants
    ("constants --w 0", "trapped"),
    ("constants --scene square --radius 1/2", "0 < radius < 1/2"),
    ("constants --scene square --w 0.1", "--radius"),
    ("constants --scene square --radius 1/4096", "1/2048"),
    ("constants --w 10000", "w <= 2362"),
    ("constants --w 0.1 --precision 20", "53"),
    ("constants --w 0.1 --precision 2000000000", "1048576"),
    ("diffusion --w 0.1 --precision 99999999999", "1048576"),
    // bench
    ("bench --w 0.1 --collisions-per-thread 0", "collisions"),
    ("bench --w 0.1 --collisions 1e5", "unexpected argument"),
    ("bench --w -1", "trapped"),
    (
        "bench --w 0.1 --repetitions 0",
        "--repetitions 0 is out of range: use 1 to",
    ),
    ("bench --w 0.1 --threads 0", "threads"),
    (
        "bench --w 0.1 --observer-costs --repetitions 0",
        "--repetitions 0 is out of range: use 1 to",
    ),
    (
        "bench --w 0.1 --observer-costs --precision 128",
        "cannot be used with",
    ),
    ("bench --long-flights 1/4,1/3", "use 2^-32 <= radius <= 1/4"),
    (
        "bench --long-flights 1/4,r",
        "--long-flights r: 'r' is not a decimal number",
    ),
    (
        "bench --long-flights 1/4 --threads 2",
        "cannot be used with",
    ),
    ("bench --long-flights 1/4 --w 0.1", "cannot be used with"),
    (
        "bench --walk-collisions 10 --w 0.1",
        "--walk-collisions 10: applies with --long-flights only",
    ),
    (
        "bench --scene square --w 0.1",
        "--scene square: applies with --long-flights only",
    ),
    (
        "bench --scene triangular --long-flights 10,0.2",
        "use w_inf = 4/sqrt(3) - 2 < w <= 2^20 - 2",
    ),
    ("bench", "--w"),
];

/// [`BAD`] for arguments with white space in them.
const BAD_WITH_SPACES: &[(&[&str], &str)] = &[(
    &[
        "slurm",
        "sweep",
        "--w-from",
        "0.1",
        "--w-to",
        "0.2",
        "--array",
        "4",
        "--partition",
        "a b",
        "--out",
        "out",
    ],
    "partition",
)];

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
