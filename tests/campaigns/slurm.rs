//! A sweep campaign on a real single-node Slurm cluster: `lorentz slurm sweep` writes the job
//! array and the dependent merge job, Slurm runs them, and the merged sweep equals the sweep run in
//! one piece bit for bit.
//!
//! The cluster is Debian's munge, slurmctld and slurmd, started in a private directory by
//! `scripts/slurm-local.sh` (as root, without systemd) and stopped by the PIDs it saved. The
//! test is `#[ignore]`d, so a plain `cargo test` reports it as ignored rather than passed;
//! `.ci/run` installs the packages and runs it with `cargo test --release --test campaigns slurm
//! -- --ignored`, where a missing Slurm (or not being root) is a failure naming what is missing.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

/// Longest wait for the campaign: the four tasks and the merge take ~10 s on an idle node.
const CAMPAIGN_TIMEOUT: Duration = Duration::from_secs(300);

fn script() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/slurm-local.sh")
}

/// Stops the cluster however the test ends.
struct Cluster {
    dir: PathBuf,
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = Command::new(script()).arg("stop").arg(&self.dir).status();
    }
}

fn slurm_available() -> Result<(), String> {
    let on_path = |p: &str| {
        Command::new("sh")
            .args(["-c", &format!("command -v {p} || test -x /usr/sbin/{p}")])
            .output()
            .is_ok_and(|o| o.status.success())
    };
    for p in ["sbatch", "scontrol", "slurmctld", "slurmd", "munged"] {
        if !on_path(p) {
            return Err(format!(
                "{p} not found (apt-get install slurmctld slurmd slurm-client munge)"
            ));
        }
    }
    let uid = Command::new("id")
        .arg("-u")
        .output()
        .map_err(|e| e.to_string())?;
    if String::from_utf8_lossy(&uid.stdout).trim() != "0" {
        return Err("not root (slurmd must start jobs)".into());
    }
    Ok(())
}

fn job_state(conf: &Path, id: &str) -> String {
    let out = Command::new("scontrol")
        .args(["show", "job", id])
        .env("SLURM_CONF", conf)
        .output()
        .expect("scontrol");
    let text = String::from_utf8_lossy(&out.stdout);
    // An array job shows one record per task; any task not COMPLETED decides.
    let states: Vec<&str> = text
        .split_whitespace()
        .filter_map(|w| w.strip_prefix("JobState="))
        .collect();
    states
        .iter()
        .find(|s| **s != "COMPLETED")
        .or(states.first())
        .unwrap_or(&"UNKNOWN")
        .to_string()
}

/// Runs `command`, which must succeed (else the failure names `what` and its stderr): its output.
fn succeeds(command: &mut Command, what: &str) -> std::process::Output {
    let out = command
        .output()
        .unwrap_or_else(|e| panic!("run {what}: {e}"));
    assert!(
        out.status.success(),
        "{what}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn lorentz(args: &[&str]) {
    succeeds(
        Command::new(env!("CARGO_BIN_EXE_lorentz")).args(args),
        &format!("lorentz {args:?}"),
    );
}

/// Writes the campaign of `lorentz slurm sweep ARGS --array PARTS --out OUT`, submits it and
/// waits until its merge job has completed (failing on any other end, with the jobs' logs).
fn run_campaign(conf: &Path, args: &[&str], parts: &str, out: &Path) {
    let mut all = vec!["slurm", "sweep"];
    all.extend(args);
    all.extend(["--array", parts, "--out", out.to_str().unwrap()]);
    lorentz(&all);
    let submit = Command::new("sh")
        .arg(out.join("slurm/submit.sh"))
        .env("SLURM_CONF", conf)
        .output()
        .expect("submit");
    let said = String::from_utf8_lossy(&submit.stdout).to_string();
    assert!(
        submit.status.success(),
        "submit.sh: {said} {}",
        String::from_utf8_lossy(&submit.stderr)
    );
    let words: Vec<&str> = said.split_whitespace().collect();
    let (array, merge) = match words[..] {
        ["array", a, "merge", m] => (a.to_string(), m.to_string()),
        _ => panic!("submit.sh printed {said:?}"),
    };
    let logs = || {
        std::fs::read_dir(out.join("slurm"))
            .map(|d| {
                d.flatten()
                    .filter(|e| e.path().extension().is_some_and(|x| x == "out"))
                    .map(|e| std::fs::read_to_string(e.path()).unwrap_or_default())
                    .collect::<Vec<_>>()
                    .join("\n")
            })
            .unwrap_or_default()
    };
    let t0 = Instant::now();
    loop {
        let m = job_state(conf, &merge);
        if m == "COMPLETED" {
            break;
        }
        let ended = [
            "FAILED",
            "CANCELLED",
            "TIMEOUT",
            "NODE_FAIL",
            "OUT_OF_MEMORY",
        ];
        assert!(
            !ended.contains(&m.as_str()),
            "merge job {merge} ended {m} (array {array}: {}); logs:\n{}",
            job_state(conf, &array),
            logs()
        );
        assert!(
            t0.elapsed() < CAMPAIGN_TIMEOUT,
            "the campaign did not finish in {CAMPAIGN_TIMEOUT:?}: merge {m}, array {}; logs:\n{}",
            job_state(conf, &array),
            logs()
        );
        std::thread::sleep(Duration::from_millis(250));
    }
    assert_eq!(job_state(conf, &array), "COMPLETED");
    eprintln!(
        "Slurm campaign ({parts} array tasks + merge) finished {:.1} s after submission",
        t0.elapsed().as_secs_f64()
    );
}

/// The files `files` of `a` and `b` are equal byte for byte, and so are their JSON results
/// `json` without what depends on where and how they ran.
fn same_results(a: &Path, b: &Path, files: &[&str], json: &str) {
    for f in files {
        assert!(
            std::fs::read(a.join(f)).unwrap() == std::fs::read(b.join(f)).unwrap(),
            "{f} differs between the Slurm campaign and the sweep in one piece"
        );
    }
    let science = |d: &Path| {
        let text = std::fs::read_to_string(d.join(json)).unwrap();
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        let o = v.as_object_mut().unwrap();
        for k in ["meta", "resumed_points", "seconds"] {
            o.remove(k);
        }
        v
    };
    assert_eq!(science(a), science(b));
}

/// `lorentz sweep ARGS --threads 1 --quiet --out OUT`: the sweep in one piece.
fn in_one_piece(args: &[&str], out: &Path) {
    let mut all = vec!["sweep"];
    all.extend(args);
    all.extend(["--threads", "1", "--quiet", "--out", out.to_str().unwrap()]);
    lorentz(&all);
}

#[test]
#[ignore = "needs a local Slurm (scripts/slurm-local.sh); CI runs it with --ignored"]
fn sweeps_sharded_over_a_real_slurm_cluster_equal_the_sweeps_in_one_piece() {
    if let Err(why) = slurm_available() {
        panic!(
            "no Slurm here: {why}; this test needs Debian's munge, slurmctld and slurmd, run as \
             root (`.ci/run` installs them)"
        );
    }
    let tmp = crate::common::scratch();
    let root = tmp.path().to_path_buf();
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    let cluster = Cluster {
        dir: root.join("cluster"),
    };
    succeeds(
        Command::new(script()).arg("start").arg(&cluster.dir),
        "the local cluster did not start (slurm-local.sh)",
    );
    let conf = cluster.dir.join("slurm.conf");

    // A sweep over w.
    let sweep = crate::common::words(
        "--w-from 0.2 --w-to 0.3 --steps 6 --runs 2 --collisions-per-run 3e5 --batches-per-run 4 \
         --seed 11",
    );
    run_campaign(&conf, &sweep, "4", &root.join("campaign"));
    in_one_piece(&sweep, &root.join("whole"));
    let figures = [
        "sweep.csv",
        "fig2-D-vs-w.svg",
        "fig7-boltzmann.svg",
        "fig8-residuals.svg",
    ];
    same_results(
        &root.join("whole"),
        &root.join("campaign"),
        &figures,
        "sweep.json",
    );

    // A sweep over the field of a table given as data: its configuration travels beside the
    // scripts.
    let table = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/tables/two-radius-square.toml"
    );
    let field = [
        "--table",
        table,
        "--fields=-1,1,2",
        "--collisions-per-run",
        "2e5",
        "--batches-per-run",
        "4",
        "--localization-samples",
        "1e4",
        "--seed",
        "11",
    ];
    run_campaign(&conf, &field, "2", &root.join("field-campaign"));
    in_one_piece(&field, &root.join("field-whole"));
    let files = ["field-sweep.csv", "field-D_xx.svg", "field-D_xy.svg"];
    same_results(
        &root.join("field-whole"),
        &root.join("field-campaign"),
        &files,
        "field-sweep.json",
    );
    drop(cluster);
    let _ = std::fs::remove_dir_all(&root);
}
