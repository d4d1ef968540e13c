//! `kill -9` at random moments: a diffusion run and a sweep resume to the uninterrupted bits,
//! and finished work is not redone (the resumed run is shorter than a fresh one).

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use rand::{Rng, SeedableRng};

/// Starts `lorentz args` in `dir` and kills it (SIGKILL) after `after`, unless it ends first.
fn kill_after(dir: &Path, args: &[&str], after: Duration) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_lorentz"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start lorentz");
    let start = Instant::now();
    while start.elapsed() < after {
        if child.try_wait().unwrap().is_some() {
            return;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap();
    child.wait().unwrap();
}

/// Runs `lorentz args` in `dir` to the end: its stdout and wall time.
fn finish(dir: &Path, args: &[&str]) -> (String, Duration) {
    let start = Instant::now();
    let (code, out, err) = crate::common::lorentz_in(dir, args);
    assert_eq!(code, 0, "{args:?}: {err}");
    (out, start.elapsed())
}

/// A result's JSON without timing, metadata and resume counts.
fn physics(json: &str) -> serde_json::Value {
    crate::common::physics_only(serde_json::from_str(json).unwrap())
}

/// Three kills at uniformly random moments between 20 % and 90 % of an uninterrupted run, each
/// resumed from the checkpoint (saved every 50 ms); the final result has the uninterrupted bits.
#[test]
fn a_killed_diffusion_run_resumes_to_the_uninterrupted_bits() {
    let tmp = crate::common::scratch();
    let dir = tmp.path();
    let run = crate::common::words(
        "diffusion --w 0.1 --collisions 2e8 --batches 16 --threads 2 --json --quiet",
    );
    let (reference, full) = finish(dir, &run);
    let mut resumable = run.to_vec();
    resumable.extend(["--checkpoint", "run.ckpt", "--checkpoint-every", "0.05"]);
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(17);
    for _ in 0..3 {
        let f = rng.random_range(0.2..0.9);
        kill_after(dir, &resumable, full.mul_f64(f));
    }
    let (resumed, _) = finish(dir, &resumable);
    assert_eq!(physics(&resumed), physics(&reference));
    // Once finished, the checkpoint holds every batch: a rerun does no work.
    let (again, _) = finish(dir, &resumable);
    let v: serde_json::Value = serde_json::from_str(&again).unwrap();
    assert_eq!(v["resumed_batches"], 16);
    assert_eq!(physics(&again), physics(&reference));
}

/// The same for a sweep: killed three times (the point in progress is journalled with its
/// trajectories in flight), resumed, and its tables are the uninterrupted sweep's.
#[test]
fn a_killed_sweep_resumes_to_the_uninterrupted_bits() {
    let tmp = crate::common::scratch();
    let dir = tmp.path();
    let sweep = |out: &'static str| {
        let mut args = crate::common::words(
            "sweep --w-from 0.1 --w-to 0.2 --steps 3 --runs 2 --collisions-per-run 6e7 \
             --batches-per-run 8 --threads 2 --json --quiet --checkpoint-every 0.05 --out",
        );
        args.push(out);
        args
    };
    let (reference, full) = finish(dir, &sweep("whole"));
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(23);
    for _ in 0..3 {
        let f = rng.random_range(0.2..0.9);
        kill_after(dir, &sweep("killed"), full.mul_f64(f));
    }
    let (resumed, _) = finish(dir, &sweep("killed"));
    assert_eq!(physics(&resumed), physics(&reference));
    for f in ["sweep.csv", "sweep-runs.csv"] {
        assert_eq!(
            std::fs::read(dir.join("killed").join(f)).unwrap(),
            std::fs::read(dir.join("whole").join(f)).unwrap(),
            "{f}"
        );
    }
}
