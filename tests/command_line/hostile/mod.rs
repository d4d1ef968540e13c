//! A hostile user, one test per class of failure: an output directory holding links, foreign
//! files as checkpoints, two runs on one journal, a report that skipped checks, FIFOs, inputs
//! that could never finish, a newline in a Slurm path, a merge into its own part, duplicate
//! keys, and signals that must save and exit 130/143.
//!
//! The third round has a module per class, each broken on purpose once: [`grinding`] (what an
//! audit or a resume re-checks cannot be chosen by editing the file or retrying), [`field_parity`]
//! (the field goes through the field-free path's guards), [`cost_bounds`] (work priced before it
//! starts), [`files`] (no stream truncates, deletes or writes through what was there), [`signals`]
//! (every command honours the first signal within a second) and [`few_batches`] (no statistical
//! verdict from too few batches).

use std::os::unix::fs::{FileTypeExt, PermissionsExt, symlink};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::{lorentz_in as lorentz, scratch, words};

mod cost_bounds;
mod few_batches;
mod field_parity;
mod files;
mod grinding;
mod signals;

fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo").arg(path).status().expect("mkfifo");
    assert!(status.success());
}

/// A small diffusion result of 8 batches written to `dir/d.json`; its text.
fn small_result(dir: &Path) -> String {
    let args = "diffusion --w 0.2 --collisions 1e6 --batches 8 --json --quiet";
    let (code, out, err) = lorentz(dir, &args.split(' ').collect::<Vec<_>>());
    assert_eq!(code, 0, "{err}");
    std::fs::write(dir.join("d.json"), &out).unwrap();
    out
}

/// The first line of stderr, which every refusal is.
/// A sweep of `steps` points from w = 0.1 to 0.2 at tiny statistics, with `more` options, in `dir`.
fn small_sweep(dir: &Path, steps: &str, more: &[&str]) -> (i32, String, String) {
    let mut args = words("sweep --w-from 0.1 --w-to 0.2 --steps");
    args.push(steps);
    args.extend(words(
        "--runs 2 --collisions-per-run 1e5 --batches-per-run 4 --quiet",
    ));
    args.extend_from_slice(more);
    lorentz(dir, &args)
}

fn first(err: &str) -> &str {
    err.lines().next().unwrap_or("")
}

/// Asserts that a run (exit status, stdout, stderr) was refused: exit 2, `message` in the first
/// line of stderr.
fn assert_refused((code, _, err): (i32, String, String), message: &str) {
    assert_eq!(code, 2, "{err}");
    assert!(first(&err).contains(message), "{err}");
}

/// Runs `lorentz ARGS` in `dir`, which must be refused within a second with one line naming
/// `message`.
fn refused_at_once(dir: &Path, args: &[&str], message: &str) {
    let t = Instant::now();
    let (code, out, err) = lorentz(dir, args);
    assert!(t.elapsed() < Duration::from_secs(1), "{:?}", t.elapsed());
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert_refused((code, out, err), message);
}

#[test]
fn links_in_an_output_directory_are_refused_and_their_targets_untouched() {
    let tmp = scratch();
    let dir = tmp.path();
    std::fs::write(dir.join("victim"), "precious").unwrap();
    std::fs::create_dir(dir.join("elsewhere")).unwrap();
    let sweep = |out: &str| small_sweep(dir, "3", &["--out", out]);
    // A file the sweep writes, as a link to a file outside.
    std::fs::create_dir(dir.join("a")).unwrap();
    symlink(dir.join("victim"), dir.join("a/sweep.json")).unwrap();
    assert_refused(sweep("a"), "a/sweep.json: a symbolic link");
    // A directory the sweep makes, as a link to a directory outside.
    std::fs::create_dir(dir.join("b")).unwrap();
    symlink(dir.join("elsewhere"), dir.join("b/points")).unwrap();
    assert_refused(sweep("b"), "b/points: a symbolic link");
    assert_eq!(
        std::fs::read_to_string(dir.join("victim")).unwrap(),
        "precious"
    );
    assert_eq!(std::fs::read_dir(dir.join("elsewhere")).unwrap().count(), 0);
    // The report's own files too.
    small_result(dir);
    std::fs::create_dir(dir.join("rep")).unwrap();
    symlink(dir.join("victim"), dir.join("rep/report.md")).unwrap();
    let (code, _, err) = lorentz(dir, &["report", "d.json", "--quick", "--out", "rep"]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(
        std::fs::read_to_string(dir.join("victim")).unwrap(),
        "precious"
    );
}

#[test]
fn a_checkpoint_path_that_is_not_a_journal_is_refused_and_left_as_it_was() {
    let tmp = scratch();
    let dir = tmp.path();
    let run = |ckpt: &str| {
        lorentz(
            dir,
            &[
                "diffusion",
                "--w",
                "0.1",
                "--collisions",
                "1e6",
                "--batches",
                "4",
                "--quiet",
                "--checkpoint",
                ckpt,
            ],
        )
    };
    let foreign = [
        ("note.txt", "a one-line note without a newline"),
        ("min.json", "{\"D\":0.1}"),
        ("two.txt", "line one\nline two\n"),
    ];
    for (name, text) in foreign {
        std::fs::write(dir.join(name), text).unwrap();
        std::fs::set_permissions(dir.join(name), std::fs::Permissions::from_mode(0o640)).unwrap();
        let (code, _, err) = run(name);
        assert_eq!(code, 2, "{name}: {err}");
        assert!(first(&err).contains("not a lorentz journal"), "{err}");
        assert_eq!(std::fs::read_to_string(dir.join(name)).unwrap(), text);
        let mode = std::fs::metadata(dir.join(name))
            .unwrap()
            .permissions()
            .mode();
        assert_eq!(mode & 0o777, 0o640);
    }
    std::fs::write(dir.join("victim"), "precious").unwrap();
    symlink(dir.join("victim"), dir.join("link")).unwrap();
    assert_refused(run("link"), "a symbolic link");
    assert!(
        std::fs::symlink_metadata(dir.join("link"))
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("victim")).unwrap(),
        "precious"
    );
    assert_refused(run("/dev/null"), "a device");
    assert!(
        std::fs::metadata("/dev/null")
            .unwrap()
            .file_type()
            .is_char_device()
    );
    // A journal of this tool keeps its mode across a resume.
    let (code, _, err) = run("mine.ckpt");
    assert_eq!(code, 0, "{err}");
    std::fs::set_permissions(
        dir.join("mine.ckpt"),
        std::fs::Permissions::from_mode(0o600),
    )
    .unwrap();
    let (code, _, err) = run("mine.ckpt");
    assert_eq!(code, 0, "{err}");
    let mode = std::fs::metadata(dir.join("mine.ckpt"))
        .unwrap()
        .permissions()
        .mode();
    assert_eq!(mode & 0o777, 0o600);
    // No lock or temporary file is left behind.
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "link",
            "min.json",
            "mine.ckpt",
            "note.txt",
            "two.txt",
            "victim"
        ]
    );
}

#[test]
fn a_second_run_on_one_journal_is_refused_while_the_first_runs() {
    let tmp = scratch();
    let dir = tmp.path();
    let args = words(
        "diffusion --w 0.1 --collisions 2e10 --batches 4 --threads 1 --quiet --checkpoint run.ckpt",
    );
    let mut first_run = start_checkpointed(dir, &args, Stdio::null());
    let second = lorentz(dir, &args);
    first_run.kill().unwrap();
    first_run.wait().unwrap();
    assert_refused(second, "in use by another run");
}

#[test]
fn a_report_with_a_skipped_check_is_incomplete_not_a_pass() {
    let tmp = scratch();
    let dir = tmp.path();
    let out = small_result(dir);
    let (code, _, err) = lorentz(
        dir,
        &words("report d.json --quick --max-rerun-collisions 0 --out rep --quiet"),
    );
    assert_eq!(code, 5, "{err}");
    assert!(first(&err).contains("INCOMPLETE"), "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("rep/report.json")).unwrap())
            .unwrap();
    assert_eq!(v["verdict"], "INCOMPLETE");
    // A file claiming more work than the auditor's budget cannot PASS: its re-runs are skipped.
    let mut claims: serde_json::Value = serde_json::from_str(&out).unwrap();
    claims["config"]["collisions"] = serde_json::json!(1e15 as u64);
    std::fs::write(dir.join("claims.json"), claims.to_string()).unwrap();
    let (code, _, err) = lorentz(dir, &["report", "claims.json", "--quick", "--out", "rep2"]);
    assert_ne!(code, 0, "{err}");
    // A key given twice says two things: refused.
    let dup = out.replacen("\"D\":", "\"D\": 0.5, \"D\":", 1);
    std::fs::write(dir.join("dup.json"), dup).unwrap();
    assert_refused(
        lorentz(dir, &["report", "dup.json", "--quick", "--out", "rep3"]),
        "duplicate key `D`",
    );
}

#[test]
fn fifos_are_refused_without_blocking() {
    let tmp = scratch();
    let dir = tmp.path();
    mkfifo(&dir.join("fifo"));
    for args in [
        &["report", "fifo", "--quick", "--out", "rep"][..],
        &words("diffusion --w 0.1 --collisions 1e6 --checkpoint fifo")[..],
    ] {
        let t = Instant::now();
        let (code, _, err) = lorentz(dir, args);
        assert!(t.elapsed() < Duration::from_secs(5), "{args:?} blocked");
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(first(&err).contains("a FIFO"), "{err}");
    }
}

/// Inputs whose work is out of reach (or beyond the exact horizon) are refused at once, exit 2.
#[test]
fn inputs_that_could_never_finish_are_refused_at_once() {
    let tmp = scratch();
    let dir = tmp.path();
    let max = "18446744073709551615";
    let gap = "0.30940107675850306";
    let cases: &[&[&str]] = &[
        &["diffusion", "--w", gap],
        &["diffusion", "--w", gap, "--precision", "128"],
        &["hops", "--w", gap],
        &["theory", "--w", gap],
        &["lattice-walk", "--w", gap],
        &["backscatter", "--w", gap],
        &["escape", "--w", gap],
        &["sweep", "--w-from", "0.2", "--w-to", gap, "--out", "s"],
        &["bench", "--w", "1e300"],
        &["audit", "--w", "1e300"],
        &["lyapunov", "--w", "1e300"],
        &["certify", "--w", "1e300"],
        &["lyapunov", "--scene", "square", "--radius", "1e-300"],
        &["backscatter", "--w", "1e-12"],
        &["escape", "--w", "1e-6"],
        &["lyapunov", "--w", "0.1", "--collisions-per-batch", max],
        &["audit", "--w", "0.1", "--collisions", max],
        &["backscatter", "--w", "0.1", "--particles", max],
        &["diffusion", "--w", "0.1", "--collisions", max],
    ];
    for args in cases {
        let t = Instant::now();
        let (code, _, err) = lorentz(dir, args);
        assert!(
            t.elapsed() < Duration::from_secs(2),
            "{args:?} took {:?}",
            t.elapsed()
        );
        assert_eq!(code, 2, "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    }
    assert!(!dir.join("s").exists());
}

#[test]
fn a_newline_in_a_slurm_path_is_refused_before_a_script_is_written() {
    let tmp = scratch();
    let dir = tmp.path();
    let out = dir.join("x\n#SBATCH --mem=1\nrm -rf ~");
    let mut args = words("slurm sweep --w-from 0.1 --w-to 0.2 --array 2 --out");
    args.push(out.to_str().unwrap());
    assert_refused(lorentz(dir, &args), "control character");
    assert_eq!(std::fs::read_dir(dir).unwrap().count(), 0);
}

#[test]
fn a_merge_into_one_of_its_parts_is_refused() {
    let tmp = scratch();
    let dir = tmp.path();
    let (code, _, err) = small_sweep(dir, "2", &["--shard", "0/1", "--out", "part"]);
    assert_eq!(code, 0, "{err}");
    for out in ["part", "part/inner", "./part/"] {
        let (code, _, err) = lorentz(dir, &["merge", "part", "--out", out, "--quiet"]);
        assert_eq!(code, 2, "{out}: {err}");
        assert!(first(&err).contains("merging into a part"), "{err}");
    }
}

/// Starts `lorentz args` in `dir` (stderr to `stderr`) and returns once its journal `run.ckpt`
/// exists (or after 30 s).
fn start_checkpointed(dir: &Path, args: &[&str], stderr: Stdio) -> std::process::Child {
    let child = Command::new(env!("CARGO_BIN_EXE_lorentz"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(stderr)
        .spawn()
        .unwrap();
    let start = Instant::now();
    while !dir.join("run.ckpt").exists() && start.elapsed() < Duration::from_secs(30) {
        std::thread::sleep(Duration::from_millis(10));
    }
    child
}

/// Sends `signal` to a checkpointed run once its journal exists and some work is done; returns
/// the exit status.
fn stop_with(dir: &Path, args: &[&str], signal: i32) -> i32 {
    let child = start_checkpointed(dir, args, Stdio::piped());
    std::thread::sleep(Duration::from_millis(300));
    // SAFETY: `kill` takes a process id and a signal number; neither is a pointer.
    assert_eq!(unsafe { libc::kill(child.id() as i32, signal) }, 0);
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("saved in run.ckpt"), "{err}");
    out.status.code().unwrap_or(-1)
}

#[test]
fn sigint_and_sigterm_save_exit_130_and_143_and_resume_to_the_same_bits() {
    let tmp = scratch();
    let dir = tmp.path();
    // 32 batches fill the SIMD engine's 16 lanes on each of the 2 threads (4 batches ran at an
    // eighth of its speed): the run takes seconds, the signals come 0.3 s after it starts.
    let run = words("diffusion --w 0.1 --collisions 2e8 --batches 32 --threads 2 --json --quiet");
    let (code, reference, err) = lorentz(dir, &run);
    assert_eq!(code, 0, "{err}");
    let mut resumable = run.to_vec();
    resumable.extend(["--checkpoint", "run.ckpt", "--checkpoint-every", "1000"]);
    // The interval is long: what is saved is saved because of the signal.
    assert_eq!(stop_with(dir, &resumable, libc::SIGINT), 130);
    assert_eq!(stop_with(dir, &resumable, libc::SIGTERM), 143);
    let (code, resumed, err) = lorentz(dir, &resumable);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&resumed).unwrap();
    assert!(v["resumed_collisions"].as_u64().unwrap() > 0, "{v}");
    let physics = |s: &str| crate::common::physics_only(serde_json::from_str(s).unwrap());
    assert_eq!(physics(&resumed), physics(&reference));
}
