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

fn lorentz(args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_lorentz"))
        .args(args)
        .output()
        .expect("run lorentz");
    assert!(
        out.status.success(),
        "lorentz {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
#[ignore = "needs a local Slurm (scripts/slurm-local.sh); CI runs it with --ignored"]
fn sweep_sharded_over_a_real_slurm_cluster_equals_the_sweep_in_one_piece() {
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
    let started = Command::new(script())
        .arg("start")
        .arg(&cluster.dir)
        .output()
        .expect("run slurm-local.sh");
    assert!(
        started.status.success(),
        "the local cluster did not start: {}",
        String::from_utf8_lossy(&started.stderr)
    );
    let conf = cluster.dir.join("slurm.conf");

    let sweep = [
        "--w-from",
        "0.2",
        "--w-to",
        "0.3",
        "--steps",
        "6",
        "--runs",
        "2",
        "--collisions-per-run",
        "3e5",
        "--batches-per-run",
        "4",
        "--seed",
        "11",
    ];
    let campaign = root.join("campaign");
    let whole = root.join("whole");
    let mut args = vec!["slurm", "sweep"];
    args.extend(sweep);
    args.extend(["--array", "4", "--out", campaign.to_str().unwrap()]);
    lorentz(&args);

    let submit = Command::new("sh")
        .arg(campaign.join("slurm/submit.sh"))
        .env("SLURM_CONF", &conf)
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

    // Meanwhile, the same sweep in one piece, here.
    let mut args = vec!["sweep"];
    args.extend(sweep);
    args.extend([
        "--threads",
        "1",
        "--quiet",
        "--out",
        whole.to_str().unwrap(),
    ]);
    lorentz(&args);

    let t0 = Instant::now();
    loop {
        let m = job_state(&conf, &merge);
        if m == "COMPLETED" {
            break;
        }
        let logs = || {
            std::fs::read_dir(campaign.join("slurm"))
                .map(|d| {
                    d.flatten()
                        .filter(|e| e.path().extension().is_some_and(|x| x == "out"))
                        .map(|e| std::fs::read_to_string(e.path()).unwrap_or_default())
                        .collect::<Vec<_>>()
                        .join("\n")
                })
                .unwrap_or_default()
        };
        assert!(
            ![
                "FAILED",
                "CANCELLED",
                "TIMEOUT",
                "NODE_FAIL",
                "OUT_OF_MEMORY"
            ]
            .contains(&m.as_str()),
            "merge job {merge} ended {m} (array {array}: {}); logs:\n{}",
            job_state(&conf, &array),
            logs()
        );
        assert!(
            t0.elapsed() < CAMPAIGN_TIMEOUT,
            "the campaign did not finish in {CAMPAIGN_TIMEOUT:?}: merge {m}, array {}; logs:\n{}",
            job_state(&conf, &array),
            logs()
        );
        std::thread::sleep(Duration::from_millis(250));
    }
    assert_eq!(job_state(&conf, &array), "COMPLETED");
    eprintln!(
        "Slurm campaign (4 array tasks + merge) finished {:.1} s after submission",
        t0.elapsed().as_secs_f64()
    );

    for f in [
        "sweep.csv",
        "fig2-D-vs-w.svg",
        "fig7-boltzmann.svg",
        "fig8-residuals.svg",
    ] {
        assert!(
            std::fs::read(whole.join(f)).unwrap() == std::fs::read(campaign.join(f)).unwrap(),
            "{f} differs between the Slurm campaign and the sweep in one piece"
        );
    }
    let science = |d: &Path| {
        let mut v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.join("sweep.json")).unwrap()).unwrap();
        let o = v.as_object_mut().unwrap();
        o.remove("meta");
        o.remove("resumed_points");
        v
    };
    assert_eq!(science(&whole), science(&campaign));
    drop(cluster);
    let _ = std::fs::remove_dir_all(&root);
}
