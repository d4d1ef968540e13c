//! Every command honours the first signal within a second: started with arguments that make it
//! run far longer, sent SIGINT (SIGTERM, SIGHUP) 2 s after it starts, it exits within 1 s of the
//! signal with 128 + the signal (130, 143, 129) and one line saying so, and every file it writes
//! holds its old content or nothing (no temporary file or lock is left beside it). The commands
//! run at once, each on one thread, so that the whole takes a few seconds.
//!
//! Not started here: `constants` and `slurm` (they finish in milliseconds, before any signal
//! could come), and `merge` (it only reads its parts and writes their points, figures and tables
//! again: about 10 ms per point, so running it for seconds needs parts of hundreds of points
//! that take longer to make than this whole test). Both are ended by the same mechanism as every
//! command that keeps nothing.

use std::io::Read;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::{lorentz_in as lorentz, scratch};

/// How long each command runs before its signal.
const BEFORE: Duration = Duration::from_secs(2);
/// How long it has to exit after the signal.
const WITHIN: Duration = Duration::from_secs(1);
/// What every output holds before the command starts.
const OLD: &str = "old content\n";

/// One command to stop.
struct Case {
    /// A name for the messages, and the case's directory.
    name: &'static str,
    args: Vec<&'static str>,
    /// The signals sent, 2 s after the start and 5 ms apart (two different ones may reach the
    /// command together, in either order: a case sends one kind).
    signals: Vec<i32>,
    /// Files it would write, seeded with [`OLD`] first: they must hold it afterwards, or a whole
    /// new file.
    outputs: Vec<&'static str>,
    /// Where it keeps its work (a checkpoint file or directory), which may hold new files.
    kept: Option<&'static str>,
    /// Started with SIGINT ignored, as a shell starts a background job.
    ignoring_sigint: bool,
}

fn case(name: &'static str, args: &'static str) -> Case {
    let mut args: Vec<&'static str> = args.split(' ').collect();
    args.push("--quiet");
    Case {
        name,
        args,
        signals: vec![libc::SIGINT],
        outputs: Vec::new(),
        kept: None,
        ignoring_sigint: false,
    }
}

impl Case {
    fn writing(mut self, outputs: &[&'static str]) -> Self {
        self.outputs = outputs.to_vec();
        self
    }
    fn keeping(mut self, kept: &'static str) -> Self {
        self.kept = Some(kept);
        self
    }
    fn signals(mut self, signals: &[i32]) -> Self {
        self.signals = signals.to_vec();
        self
    }
    fn ignoring_sigint(mut self) -> Self {
        self.ignoring_sigint = true;
        self
    }
}

/// Every command `lorentz --help` lists that can run for seconds, each far longer than 3 s.
fn every_command() -> Vec<Case> {
    vec![
        case("diffusion", "diffusion --w 0.1 --collisions 1e11 --threads 1 --checkpoint run.ckpt")
            .keeping("run.ckpt"),
        // The field's classification of 1e9 phase points, before any batch.
        case("diffusion-field", "diffusion --scene square --radius 0.3 --field 1 --localization-samples 1e9 --threads 1"),
        case("escape", "escape --w 0.1 --particles-per-width 2e7 --threads 1 --checkpoint run.ckpt")
            .keeping("run.ckpt"),
        case("audit", "audit --w 0.1 --collisions 1e9 --threads 1"),
        case("lyapunov", "lyapunov --w 0.1 --collisions-per-batch 1e8 --threads 1"),
        case("certify", "certify --w 0.1 --collisions 5000 --digits 30"),
        case("shadow", "shadow --w 0.1 --segments 100 --collisions-per-segment 2000 --threads 1"),
        case("superdiffusion", "superdiffusion --w 0.4 --collisions 1e10 --threads 1 --checkpoint run.ckpt")
            .keeping("run.ckpt"),
        case("free-paths", "free-paths --w 0.1 --collisions 1e10 --threads 1"),
        case("backscatter", "backscatter --w 0.1 --particles 1e10 --threads 1"),
        case("hops", "hops --w 0.1 --collisions 1e10 --threads 1 --checkpoint run.ckpt")
            .keeping("run.ckpt"),
        case("sweep", "sweep --w-from 0.1 --w-to 0.2 --steps 3 --collisions-per-run 1e9 --threads 1 --out sweep")
            .writing(&["sweep/sweep.json"])
            .keeping("sweep/points"),
        case("report", "report ../d.json --out rep --threads 1").writing(&["rep/report.md", "rep/report.json"]),
        case("reproduce", "reproduce --out repro --threads 1")
            .writing(&["repro/index.html"])
            .keeping("repro"),
        case("figure-backscatter", "figure backscatter --particles-per-gap 1e8 --threads 1 --out fig")
            .writing(&["fig/fig4a-p-bs.csv"]),
        case("figure-hierarchy", "figure hierarchy --collisions-per-gap 1e10 --threads 1 --out fig")
            .writing(&["fig/fig3-4b-6-hierarchy.csv"]),
        case("figure-backscatter-map", "figure backscatter-map --particles 1e9 --threads 1 --out fig")
            .writing(&["fig/fig5-backscatter-map.csv"]),
        case("theory", "theory --w 0.1 --collisions 1e10 --threads 1"),
        case("lattice-walk", "lattice-walk --w 0.1 --collisions 1e10 --threads 1 --checkpoint run.ckpt")
            .keeping("run.ckpt"),
        case("trajectory", "trajectory --scene square --radius 0.3 --start 0.5,0.1 --direction 1,1/3 --time 8000 --digits 30"),
        case("bench", "bench --w 0.1 --repetitions 20 --threads 1 --report --out bench")
            .writing(&["bench/speed-vs-error.md", "bench/speed-vs-error.json"]),
    ]
}

/// What became of a case.
struct Outcome {
    /// The exit status (`None`: killed by a signal, or still running and killed by the test).
    status: Option<i32>,
    /// From the (first) signal to the exit; `None`: it finished before the signal.
    after: Option<Duration>,
    stderr: String,
}

/// Starts `case` in `dir`, sends its signals [`BEFORE`] later, and waits for its exit (killing
/// it 5 s after the signal at the latest).
fn run_case(dir: &Path, case: &Case) -> Outcome {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_lorentz"));
    cmd.args(&case.args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    if case.ignoring_sigint {
        // SAFETY: `signal` is async-signal-safe, as code between fork and exec must be.
        unsafe {
            cmd.pre_exec(|| {
                libc::signal(libc::SIGINT, libc::SIG_IGN);
                Ok(())
            });
        }
    }
    let started = Instant::now();
    let mut child = cmd.spawn().expect("start lorentz");
    std::thread::sleep(BEFORE.saturating_sub(started.elapsed()));
    if let Ok(Some(status)) = child.try_wait() {
        return finished(&mut child, status.code(), None);
    }
    let sent = Instant::now();
    for (k, &sig) in case.signals.iter().enumerate() {
        if k > 0 {
            std::thread::sleep(Duration::from_millis(5));
        }
        // SAFETY: `kill` takes a process id and a signal number; neither is a pointer.
        unsafe { libc::kill(child.id() as i32, sig) };
    }
    loop {
        if let Ok(Some(status)) = child.try_wait() {
            return finished(&mut child, status.code(), Some(sent.elapsed()));
        }
        if sent.elapsed() > 5 * WITHIN {
            let _ = child.kill();
            let _ = child.wait();
            return finished(&mut child, None, Some(sent.elapsed()));
        }
        std::thread::sleep(Duration::from_millis(2));
    }
}

fn finished(child: &mut Child, status: Option<i32>, after: Option<Duration>) -> Outcome {
    let mut stderr = String::new();
    if let Some(mut e) = child.stderr.take() {
        let _ = e.read_to_string(&mut stderr);
    }
    Outcome {
        status,
        after,
        stderr,
    }
}

/// The regular files under `dir`, recursively.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return found;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            found.extend(files_under(&p));
        } else {
            found.push(p);
        }
    }
    found
}

/// What is wrong with `outcome` of `case` run in `dir` (nothing: empty).
fn faults(dir: &Path, case: &Case, outcome: &Outcome) -> Vec<String> {
    let mut bad = Vec::new();
    let expected = 128 + case.signals[0];
    let Some(after) = outcome.after else {
        return vec![format!(
            "finished before the signal (make it longer): {}",
            outcome.stderr
        )];
    };
    if outcome.status != Some(expected) {
        bad.push(format!("exit status {:?}, not {expected}", outcome.status));
    }
    if after > WITHIN {
        bad.push(format!(
            "exited {after:?} after the signal, not within {WITHIN:?}"
        ));
    }
    let lines = outcome
        .stderr
        .lines()
        .filter(|l| l.starts_with("stopped by "))
        .count();
    if lines != 1 {
        bad.push(format!(
            "{lines} lines saying why it stopped: {:?}",
            outcome.stderr
        ));
    }
    // A run that keeps its work saves it within the grace it is given (about 0.1 s), unless a
    // second signal ends it first.
    let saved = outcome.stderr.contains("the work done so far is saved in")
        || case.signals.len() > 1 && outcome.stderr.contains("keeps the work saved before");
    if case.kept.is_some() && !saved {
        bad.push(format!(
            "did not save its work in time: {:?}",
            outcome.stderr
        ));
    }
    for f in files_under(dir) {
        let rel = f.strip_prefix(dir).unwrap_or(&f);
        let name = rel.to_string_lossy();
        let kept = case.kept.is_some_and(|k| rel.starts_with(k));
        if name.ends_with(".tmp") || name.ends_with(".lock") {
            bad.push(format!("{name} was left behind"));
        } else if !kept && std::fs::read(&f).ok().as_deref() != Some(OLD.as_bytes()) && !whole(&f) {
            bad.push(format!("{name} is half-written"));
        }
    }
    bad
}

/// Whether the output `path` is a whole file of its kind (JSON that parses, a PNG up to its end
/// chunk, an SVG up to its closing tag, text up to its last line's end).
fn whole(path: &Path) -> bool {
    let Ok(bytes) = std::fs::read(path) else {
        return false;
    };
    match path.extension().and_then(|e| e.to_str()) {
        Some("json") => serde_json::from_slice::<serde_json::Value>(&bytes).is_ok(),
        Some("png") => bytes.ends_with(&[0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82]),
        Some("svg") => String::from_utf8_lossy(&bytes)
            .trim_end()
            .ends_with("</svg>"),
        _ => bytes.ends_with(b"\n"),
    }
}

/// Runs every case at once, each in its own directory under `root`, prints the time each took
/// from its signal to its exit, and fails with every fault found.
fn stop_all(root: &Path, cases: &[Case]) {
    for c in cases {
        let dir = root.join(c.name);
        std::fs::create_dir_all(&dir).unwrap();
        for o in &c.outputs {
            let p = dir.join(o);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, OLD).unwrap();
        }
    }
    let outcomes: Vec<Outcome> = std::thread::scope(|s| {
        let running: Vec<_> = cases
            .iter()
            .map(|c| s.spawn(|| run_case(&root.join(c.name), c)))
            .collect();
        running.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let mut all = Vec::new();
    for (c, o) in cases.iter().zip(&outcomes) {
        let ms = o.after.map_or(f64::NAN, |a| a.as_secs_f64() * 1e3);
        eprintln!(
            "{:24} status {:?} {ms:7.1} ms after the signal",
            c.name, o.status
        );
        all.extend(
            faults(&root.join(c.name), c, o)
                .into_iter()
                .map(|f| format!("{}: {f}", c.name)),
        );
    }
    assert!(all.is_empty(), "{}", all.join("\n"));
}

/// The result `report` audits, `root/d.json` (an audit of it takes about ten seconds on 2
/// cores).
fn result_to_audit(root: &Path) {
    let args = "diffusion --w 0.2 --collisions 1e6 --batches 8 --json --quiet";
    let (code, out, err) = lorentz(root, &args.split(' ').collect::<Vec<_>>());
    assert_eq!(code, 0, "{err}");
    std::fs::write(root.join("d.json"), out).unwrap();
}

#[test]
fn every_command_ends_within_a_second_of_sigint_with_130_and_nothing_half_written() {
    let tmp = scratch();
    result_to_audit(tmp.path());
    stop_all(tmp.path(), &every_command());
}

#[test]
fn sigterm_sighup_a_second_signal_and_an_ignored_sigint_end_a_run_too() {
    let tmp = scratch();
    result_to_audit(tmp.path());
    let (sigint, sigterm, sighup) = (libc::SIGINT, libc::SIGTERM, libc::SIGHUP);
    let checkpointed = "diffusion --w 0.1 --collisions 1e11 --threads 1 --checkpoint run.ckpt";
    stop_all(
        tmp.path(),
        &[
            case(
                "free-paths-sigterm",
                "free-paths --w 0.1 --collisions 1e10 --threads 1",
            )
            .signals(&[sigterm]),
            case(
                "lyapunov-sighup",
                "lyapunov --w 0.1 --collisions-per-batch 1e8 --threads 1",
            )
            .signals(&[sighup]),
            case("checkpointed-sighup", checkpointed)
                .keeping("run.ckpt")
                .signals(&[sighup]),
            // The second signal ends the process at once, with the first one's status and line.
            case("checkpointed-twice", checkpointed)
                .keeping("run.ckpt")
                .signals(&[sigint, sigint]),
            case("report-twice", "report ../d.json --out rep --threads 1")
                .writing(&["rep/report.md"])
                .signals(&[sigterm, sigterm]),
            case(
                "backscatter-ignoring",
                "backscatter --w 0.1 --particles 1e10 --threads 1",
            )
            .ignoring_sigint(),
        ],
    );
}

/// `f` run with a stop flag requested 0.3 s after it starts (as Python's Ctrl-C does through the
/// library): the time from the request to its return, and whether it returned `Interrupted`.
fn stopped_by_the_flag<R>(
    f: impl FnOnce(&lorentz_gas::engine::options::RunOptions) -> Result<R, lorentz_gas::Error>,
) -> (Duration, bool) {
    use lorentz_gas::engine::options::{RunOptions, StopFlag};
    let stop = StopFlag::default();
    let opts = RunOptions {
        threads: 1,
        stop: Some(stop.clone()),
        ..RunOptions::default()
    };
    std::thread::scope(|s| {
        let asked = s.spawn(|| {
            std::thread::sleep(Duration::from_millis(300));
            stop.request();
            Instant::now()
        });
        let r = f(&opts);
        let (returned, asked) = (Instant::now(), asked.join().unwrap());
        let interrupted = matches!(&r, Err(e) if e.kind() == lorentz_gas::ErrorKind::Interrupted);
        (returned.saturating_duration_since(asked), interrupted)
    })
}

#[test]
fn the_library_loops_the_python_package_stops_look_at_the_flag_often() {
    use lorentz_gas::estimators::diffusion::DiffusionConfig;
    use lorentz_gas::estimators::hops::backscatter::{self, BackscatterConfig};
    use lorentz_gas::scenes::spec::{Motion, SceneSpec, Table};
    // A field run's classification of its localized share, before any batch.
    let table = Table {
        scene: SceneSpec::Square {
            radius: "0.3".into(),
        },
        motion: Motion::Field("1".into()),
    };
    let cfg = DiffusionConfig {
        localization_samples: Some(1_000_000_000),
        ..DiffusionConfig::on(table)
    };
    let (after, interrupted) =
        stopped_by_the_flag(|o| lorentz_gas::estimators::field::run(&cfg, o));
    assert!(interrupted && after < WITHIN, "{after:?}");
    // Backscattering by injection, 1e10 particles (it looked only between batches).
    let cfg = BackscatterConfig {
        particles: 10_000_000_000,
        ..BackscatterConfig::new(Table::triangular("0.1").unwrap())
    };
    let (after, interrupted) = stopped_by_the_flag(|o| backscatter::run(&cfg, o));
    assert!(interrupted && after < WITHIN, "{after:?}");
}
