//! Files: no output truncates, deletes or writes through what was there (a stream goes to a
//! temporary file renamed over its target only on success), no output replaces an input, every
//! read is capped by its kind, and every output path is checked before any work.
//!
//! Broken on purpose once each: `--events` written in place (`File::create` again) modifies the
//! hard-link partner and leaves a partial file on a full disk; without `check_outputs` in the
//! audit the report replaces its own input; without the cap a sparse checkpoint is read whole
//! (seconds, gigabytes); without the sweep's up-front check the link at `sweep.json` is found
//! after the run.

use std::os::unix::fs::symlink;
use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use super::{assert_refused, first, lorentz, refused_at_once, small_result, small_sweep};
use crate::common::{scratch, words};

/// Exit status, stdout and stderr.
type Output = (i32, String, String);

/// A trajectory from `start` whose events go to `events`, with `more` options (`--time 20`: 50
/// events, 5.8 kB).
fn trajectory(dir: &Path, events: &str, start: &str, time: &str, more: &[&str]) -> Output {
    let mut args = vec![
        "trajectory",
        "--scene",
        "triangular",
        "--w",
        "1/10",
        "--start",
        start,
        "--direction",
        "1,1/3",
        "--time",
        time,
        "--events",
        events,
        "--quiet",
    ];
    args.extend_from_slice(more);
    lorentz(dir, &args)
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn text(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap()
}

#[test]
fn an_events_file_is_replaced_only_by_a_finished_run_and_never_through_a_hard_link() {
    let tmp = scratch();
    let dir = tmp.path();
    std::fs::write(dir.join("f.csv"), "precious").unwrap();
    std::fs::hard_link(dir.join("f.csv"), dir.join("partner.csv")).unwrap();
    let before = names(dir);
    // Bad input: refused, the file neither deleted nor truncated.
    let (code, _, err) = trajectory(dir, "f.csv", "0,0", "20", &[]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert_eq!(text(&dir.join("f.csv")), "precious");
    assert_eq!(names(dir), before);
    // A full disk (a file size limit: writes fail with EFBIG): the old file is intact, no
    // partial file or temporary file is left.
    let mut full = Command::new(env!("CARGO_BIN_EXE_lorentz"));
    full.args(["trajectory", "--scene", "triangular", "--w", "1/10"])
        .args(["--start", "0,1.5", "--direction", "1,1/3", "--time", "20"])
        .args(["--events", "f.csv", "--quiet"])
        .current_dir(dir);
    // SAFETY: only async-signal-safe calls between fork and exec.
    let out = unsafe {
        full.pre_exec(|| {
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            let limit = libc::rlimit {
                rlim_cur: 1000,
                rlim_max: 1000,
            };
            if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        })
    }
    .output()
    .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(first(&err).contains("f.csv"), "{err}");
    assert_eq!(text(&dir.join("f.csv")), "precious");
    assert_eq!(names(dir), before);
    // A finished run replaces the name; the other hard link keeps the old contents.
    let (code, _, err) = trajectory(dir, "f.csv", "0,1.5", "20", &[]);
    assert_eq!(code, 0, "{err}");
    assert!(text(&dir.join("f.csv")).starts_with("kind,obstacle,x,y,time,vx,vy\n"));
    assert_eq!(text(&dir.join("partner.csv")), "precious");
    assert_eq!(names(dir), before);
    // A link at the path is refused before a run of seconds, its target untouched.
    symlink(dir.join("partner.csv"), dir.join("link.csv")).unwrap();
    let t = Instant::now();
    let out = trajectory(dir, "link.csv", "0,1.5", "3000", &["--digits", "60"]);
    assert!(t.elapsed() < Duration::from_secs(1), "{:?}", t.elapsed());
    assert_refused(out, "link.csv: a symbolic link");
    assert_eq!(text(&dir.join("partner.csv")), "precious");
}

#[test]
fn a_report_into_the_directory_of_its_input_never_replaces_it() {
    let tmp = scratch();
    let dir = tmp.path();
    let result = small_result(dir);
    std::fs::create_dir(dir.join("rr")).unwrap();
    std::fs::rename(dir.join("d.json"), dir.join("rr/report.json")).unwrap();
    refused_at_once(
        dir,
        &["report", "rr/report.json", "--out", "rr", "--quick"],
        "rr/report.json: the same file as the input rr/report.json",
    );
    assert_eq!(text(&dir.join("rr/report.json")), result);
    assert_eq!(names(&dir.join("rr")), ["report.json"]);
    // The same file under another name (a hard link) is the same input.
    std::fs::create_dir(dir.join("ss")).unwrap();
    std::fs::rename(dir.join("rr/report.json"), dir.join("ss/d.json")).unwrap();
    std::fs::hard_link(dir.join("ss/d.json"), dir.join("ss/report.json")).unwrap();
    assert_refused(
        lorentz(dir, &["report", "ss/d.json", "--out", "ss", "--quick"]),
        "ss/report.json: the same file as the input ss/d.json",
    );
    assert_eq!(text(&dir.join("ss/d.json")), result);
    assert_eq!(names(&dir.join("ss")), ["d.json", "report.json"]);
}

#[test]
fn a_six_gib_sparse_checkpoint_is_refused_from_its_size() {
    let tmp = scratch();
    let dir = tmp.path();
    let f = std::fs::File::create(dir.join("big.ckpt")).unwrap();
    f.set_len(6 << 30).unwrap();
    let t = Instant::now();
    let (code, _, err) = lorentz(
        dir,
        &words("diffusion --w 0.2 --collisions 1e6 --checkpoint big.ckpt --quiet"),
    );
    assert!(t.elapsed() < Duration::from_secs(1), "{:?}", t.elapsed());
    assert_eq!(code, 2, "{err}");
    assert_eq!(
        err.trim(),
        "error: big.ckpt: 6.0 GiB (6442450944 bytes), beyond the 1 GiB a checkpoint can be"
    );
    assert_eq!(
        std::fs::metadata(dir.join("big.ckpt")).unwrap().len(),
        6 << 30
    );
    // Every other input has its cap, named: a sweep's configuration.
    let f = std::fs::File::create(dir.join("sweep.json")).unwrap();
    f.set_len(2 << 20).unwrap();
    let t = Instant::now();
    let out = lorentz(dir, &["sweep", "--config", "sweep.json", "--quiet"]);
    assert!(t.elapsed() < Duration::from_secs(1));
    assert_refused(out, "beyond the 1 MiB a configuration file can be");
}

#[test]
fn a_linked_sweep_json_is_refused_before_any_work() {
    let tmp = scratch();
    let dir = tmp.path();
    std::fs::write(dir.join("victim"), "precious").unwrap();
    std::fs::create_dir(dir.join("out")).unwrap();
    symlink(dir.join("victim"), dir.join("out/sweep.json")).unwrap();
    // Seconds of work if it started: refused before it does.
    let sweep = "sweep --w-from 0.1 --w-to 0.2 --steps 3 --runs 2 --collisions-per-run 2e7 \
                 --batches-per-run 4 --out out --quiet";
    refused_at_once(dir, &words(sweep), "out/sweep.json: a symbolic link");
    assert_eq!(text(&dir.join("victim")), "precious");
    assert_eq!(names(&dir.join("out")), ["sweep.json"], "no point computed");
    // A FIFO where a figure goes, in a merge: refused before the merge.
    let (code, _, err) = small_sweep(dir, "2", &["--shard", "0/1", "--out", "part"]);
    assert_eq!(code, 0, "{err}");
    std::fs::create_dir(dir.join("merged")).unwrap();
    super::mkfifo(&dir.join("merged/fig8-residuals.svg"));
    assert_refused(
        lorentz(dir, &["merge", "part", "--out", "merged", "--quiet"]),
        "merged/fig8-residuals.svg: a FIFO",
    );
    assert_eq!(names(&dir.join("merged")), ["fig8-residuals.svg"]);
}
