//! Checkpoints that keep the trajectories in flight: a run resumed from any prefix of its
//! checkpoint (any moment a kill could leave) gives the uninterrupted bits, on every engine,
//! thread count and precision; edited or forged checkpoints are refused.

use std::path::Path;
use std::time::Duration;

use lorentz_gas::Error;
use lorentz_gas::engine::Engine;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::engine::resume::sha256_hex;
use lorentz_gas::estimators::diffusion::{DiffusionConfig, run};
use lorentz_gas::estimators::escape::{self, EscapeConfig};
use lorentz_gas::estimators::hops::{self, HopsConfig};
use lorentz_gas::numbers::precision::Precision;
use lorentz_gas::scenes::spec::Table;
use rand::{Rng, SeedableRng};

/// The marker of a trajectory in flight in a checkpoint.
const IN_FLIGHT: &str = "\"in_flight\"";

/// Options that save everything a kill could leave: with `every` zero, every segment of every
/// trajectory.
fn options(engine: Engine, threads: usize, path: &Path, every: Duration) -> RunOptions<'static> {
    RunOptions {
        engine,
        threads,
        resume: Some(path.to_path_buf()),
        checkpoint_every: every,
        ..RunOptions::default()
    }
}

/// Runs an analysis (`analysis(options)`, seeded by `seed`) uninterrupted, then with a
/// checkpoint saved at every segment; then, for `cuts` random prefixes of that checkpoint (cut
/// anywhere, mid-line included), resumes on the other engine and thread count and compares
/// every physical field with the uninterrupted run. `saved`: a record's marker and how many the checkpoint must hold.
fn resumes_from_every_prefix<R: serde::Serialize>(
    analysis: impl Fn(&RunOptions) -> Result<R, Error>,
    seed: u64,
    saved: (&str, usize),
    engines: [(Engine, usize); 2],
    cuts: usize,
) {
    resume_with_interval(analysis, seed, saved, engines, cuts, Duration::ZERO)
}

/// [`resumes_from_every_prefix`] with the checkpoint saved every `every`.
fn resume_with_interval<R: serde::Serialize>(
    analysis: impl Fn(&RunOptions) -> Result<R, Error>,
    seed: u64,
    saved: (&str, usize),
    engines: [(Engine, usize); 2],
    cuts: usize,
    every: Duration,
) {
    let physics = |r: &R| crate::common::physics_only(serde_json::to_value(r).unwrap());
    let tmp = crate::common::scratch();
    let full_path = tmp.path().join("full.jsonl");
    let reference = physics(&analysis(&crate::common::threads(2)).unwrap());
    let (e0, t0) = engines[0];
    let checkpointed = analysis(&options(e0, t0, &full_path, every)).unwrap();
    assert_eq!(
        physics(&checkpointed),
        reference,
        "a checkpointed run has the bits"
    );
    let text = std::fs::read_to_string(&full_path).unwrap();
    let records = text.matches(saved.0).count();
    assert!(records >= saved.1, "{records} records {} saved", saved.0);
    let header = text.find('\n').unwrap() + 1;
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
    for k in 0..cuts {
        let cut = rng.random_range(header..text.len());
        let path = tmp.path().join(format!("cut-{k}.jsonl"));
        std::fs::write(&path, &text[..cut]).unwrap();
        let (e1, t1) = engines[k % 2];
        let resumed = analysis(&options(e1, t1, &path, every)).unwrap();
        assert_eq!(
            physics(&resumed),
            reference,
            "resumed at byte {cut} of {} on {e1:?} with {t1} threads",
            text.len()
        );
    }
}

/// f64 on the SIMD and scalar engines, 1 and 2 threads: 3·10⁶ collisions per trajectory, three
/// segments each, so the prefixes include trajectories in flight at several stages, finished
/// batches, and lines torn by the cut.
#[test]
fn f64_runs_resume_from_any_moment_to_the_uninterrupted_bits() {
    let cfg = crate::common::diffusion_config(0.12, 12_000_000, 4, 5);
    let engines = [(Engine::Auto, 2), (Engine::Scalar, 1)];
    resumes_from_every_prefix(|o| run(&cfg, o), cfg.seed, (IN_FLIGHT, 8), engines, 6);
}

/// The same with the MSD curve on its logarithmic grid (`--msd-grid log`): its lanes are saved
/// and restored exactly, so the curve, D by Green–Kubo and D keep the uninterrupted bits.
#[test]
fn runs_with_the_msd_curve_resume_from_any_moment_to_the_uninterrupted_bits() {
    let mut cfg = crate::common::diffusion_config(0.12, 12_000_000, 4, 6);
    cfg.msd_grid = lorentz_gas::estimators::diffusion::MsdGrid::Log;
    let engines = [(Engine::Auto, 2), (Engine::Scalar, 1)];
    resumes_from_every_prefix(|o| run(&cfg, o), cfg.seed, (IN_FLIGHT, 8), engines, 4);
}

/// The same with the MSD at the user's times (`--msd-grid 0,…`): each lane's ring of origins,
/// countdowns and sums are saved whole, so the curve keeps the uninterrupted bits.
#[test]
fn runs_at_the_users_times_resume_from_any_moment_to_the_uninterrupted_bits() {
    let mut cfg = DiffusionConfig::new(0.12);
    cfg.collisions = 12_000_000;
    cfg.batches = 4;
    cfg.seed = 7;
    cfg.msd_grid = "0,0.1,1,7.5,60,300".parse().unwrap();
    let engines = [(Engine::Auto, 2), (Engine::Scalar, 1)];
    resumes_from_every_prefix(|o| run(&cfg, o), cfg.seed, (IN_FLIGHT, 8), engines, 4);
}

/// MPFR: the saved states are exact rationals at the run's precision (segments of 2¹⁴
/// collisions).
#[test]
fn mpfr_runs_resume_from_any_moment_to_the_uninterrupted_bits() {
    let mut cfg = DiffusionConfig::new(0.2);
    cfg.collisions = 160_000;
    cfg.batches = 4;
    cfg.precision = Precision::Bits(80);
    cfg.window = "2:8".parse().unwrap();
    cfg.check_window = "4:16".parse().unwrap();
    let engines = [(Engine::Auto, 2), (Engine::Scalar, 1)];
    resumes_from_every_prefix(|o| run(&cfg, o), cfg.seed, (IN_FLIGHT, 8), engines, 3);
}

/// Hop statistics resume the same way (each lane's symbol history, sequence counts and
/// Green–Kubo ring are saved whole).
#[test]
fn hop_statistics_resume_from_any_moment_to_the_uninterrupted_bits() {
    let mut cfg = HopsConfig::new(Table::triangular_at(0.1));
    cfg.collisions = 12_000_000;
    cfg.batches = 4;
    cfg.seed = 8;
    let engines = [(Engine::Scalar, 2), (Engine::Auto, 1)];
    resumes_from_every_prefix(|o| hops::run(&cfg, o), cfg.seed, (IN_FLIGHT, 8), engines, 4);
}

/// Escape runs resume from consecutive chunks of finished particles (the starts of the particles
/// already followed are drawn again, not followed).
#[test]
fn escape_runs_resume_from_any_moment_to_the_uninterrupted_bits() {
    let mut cfg = EscapeConfig::new(Table::triangular_at(0.2));
    cfg.particles_per_width = 4000;
    cfg.seed = 4;
    let engines = [(Engine::Auto, 2), (Engine::Auto, 1)]; // escape runs the scalar kernel and takes no engine
    // Chunks, not trajectories in flight: the checkpoint holds no "in_flight" record. A chunk
    // every millisecond (a particle lives about as long), not one per particle.
    let every = Duration::from_millis(1);
    let chunks = ("\"task\"", 40);
    resume_with_interval(
        |o| escape::run(&cfg, o),
        cfg.seed,
        chunks,
        engines,
        4,
        every,
    );
}

/// The records of a checkpoint with their digests recomputed after `header` and `record` edited
/// them: what someone who knows the digest scheme could forge.
fn forge(
    text: &str,
    header: impl Fn(&mut serde_json::Value),
    record: impl Fn(&mut serde_json::Value),
) -> String {
    let digest = |salt: &str, v: &serde_json::Value| sha256_hex(format!("{salt}\n{v}").as_bytes());
    let mut lines = text.lines();
    let mut h: serde_json::Value = serde_json::from_str(lines.next().unwrap()).unwrap();
    let o = h.as_object_mut().unwrap();
    o.remove("digest");
    header(&mut h);
    let salt = digest("", &h);
    h["digest"] = serde_json::Value::String(salt.clone());
    let mut out = format!("{h}\n");
    for l in lines {
        let mut v: serde_json::Value = serde_json::from_str(l).unwrap();
        record(&mut v["record"]);
        let r = &v["record"];
        out.push_str(&format!(
            "{}\n",
            serde_json::json!({ "digest": digest(&salt, r), "record": r })
        ));
    }
    out
}

/// An edited record is refused naming the file and the line. A forged checkpoint passes the
/// digests, but the resumed run computes one finished batch again (drawn at random) and stops
/// with an error instead of reporting: batches of w = 0.1 under a header of w = 0.2, and every
/// batch's MSD raised by 5 % (a D 5 % too high, which the identities cannot see).
#[test]
fn edited_and_forged_checkpoints_are_refused() {
    let tmp = crate::common::scratch();
    let path = tmp.path().join("c.jsonl");
    let mut cfg = DiffusionConfig::new(0.1);
    cfg.collisions = 20_000_000;
    cfg.batches = 8;
    let opts = RunOptions {
        resume: Some(path.clone()),
        ..crate::common::threads(2)
    };
    let clean = run(&cfg, &opts).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    // One batch's flight time changed by 1 %: refused, naming file and line.
    let line = text
        .lines()
        .position(|l| l.contains("\"finished\""))
        .unwrap();
    let third = text.lines().nth(line).unwrap();
    let result = third.find("\"result\"").unwrap();
    let at = result + third[result..].find("\"time\":").unwrap() + 7;
    let end = at + third[at..].find([',', '}']).unwrap();
    let t: f64 = third[at..end].parse().unwrap();
    let edited = text.replacen(&third[at..end], &format!("{:?}", t * 1.01), 1);
    assert_ne!(edited, text);
    std::fs::write(&path, &edited).unwrap();
    let e = run(&cfg, &opts).unwrap_err().to_string();
    let named = format!("c.jsonl: line {}", line + 1);
    assert!(e.contains(&named) && e.contains("digest"), "{e}");
    // Forged: the digests hold, the physics does not.
    let mut cfg_02 = cfg.clone();
    cfg_02.table = lorentz_gas::scenes::spec::Table::triangular_at(0.2);
    let table_02 = serde_json::to_value(&cfg_02.table).unwrap();
    let at_02 = |h: &mut serde_json::Value| {
        h["config"]["w"] = table_02["w"].clone();
        h["config"]["w_exact"] = table_02["w_exact"].clone();
    };
    std::fs::write(&path, forge(&text, at_02, |_| {})).unwrap();
    let e = run(&cfg_02, &opts).unwrap_err();
    assert!(matches!(e, Error::Failed(_)), "{e}");
    let e = e.to_string();
    assert!(
        e.contains("c.jsonl") && e.contains("computed again from its seed"),
        "{e}"
    );
    let raised = |r: &mut serde_json::Value| {
        if let Some(msd) = r
            .pointer_mut("/finished/result/msd")
            .and_then(|m| m.as_array_mut())
        {
            for x in msd.iter_mut() {
                *x = serde_json::json!(x.as_f64().unwrap() * 1.05);
            }
        }
    };
    let forged = forge(&text, |_| {}, raised);
    assert_ne!(forged, text);
    std::fs::write(&path, forged).unwrap();
    let e = run(&cfg, &opts).unwrap_err().to_string();
    assert!(e.contains("computed again from its seed"), "{e}");
    // Each refused checkpoint was moved aside, never over another: retrying cannot draw again
    // until an honest batch comes up. The same run then starts afresh, to the clean bits.
    let aside = |name: &str| tmp.path().join(name);
    assert!(
        !path.exists(),
        "a refused checkpoint stays where it can be resumed"
    );
    assert!(aside("c.jsonl.refused").exists() && aside("c.jsonl.refused.1").exists());
    assert!(
        e.contains("c.jsonl.refused.1") && e.contains("starts afresh"),
        "{e}"
    );
    let again = run(&cfg, &opts).unwrap();
    assert_eq!(again.D.to_bits(), clean.D.to_bits());
}

/// A hops checkpoint whose finished batches were edited (one more back-scattering count each) and
/// whose digests were recomputed: the resumed run computes one batch again and refuses it.
#[test]
fn a_forged_hops_checkpoint_is_refused() {
    let tmp = crate::common::scratch();
    let path = tmp.path().join("h.jsonl");
    let mut cfg = HopsConfig::new(Table::triangular_at(0.1));
    cfg.collisions = 2_000_000;
    cfg.batches = 4;
    let opts = RunOptions {
        resume: Some(path.clone()),
        ..crate::common::threads(2)
    };
    let clean = hops::run(&cfg, &opts).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let more = |r: &mut serde_json::Value| {
        if let Some(v) = r.pointer_mut("/finished/result/visits") {
            *v = serde_json::json!(v.as_u64().unwrap() + 1000);
        }
    };
    let forged = forge(&text, |_| {}, more);
    assert_ne!(forged, text);
    std::fs::write(&path, forged).unwrap();
    let e = hops::run(&cfg, &opts).unwrap_err().to_string();
    assert!(
        e.contains("h.jsonl") && e.contains("computed again from its seed"),
        "{e}"
    );
    // The genuine checkpoint resumes to the same result.
    std::fs::write(&path, &text).unwrap();
    let again = hops::run(&cfg, &opts).unwrap();
    assert_eq!(again.p_bs.to_bits(), clean.p_bs.to_bits());
}

/// A stop request ends a run within about one segment with `Error::Interrupted`, keeping its
/// checkpoint, from which the rerun finishes to the uninterrupted bits; a flag that is never
/// requested changes no bit (the run is only cut into segments). The segment is 2²⁰ collisions
/// per trajectory: a 16-lane block at ≳ 5·10⁷ collisions/s (an unoptimised core) takes < 0.4 s,
/// so a 2 s bound on the stop leaves room for a loaded machine.
#[test]
fn a_stop_request_ends_a_run_that_then_resumes_to_the_uninterrupted_bits() {
    use lorentz_gas::engine::options::StopFlag;
    use std::time::Instant;
    // 1.25·10⁷ collisions per trajectory: about 12 segments, a second or two on one core.
    let cfg = crate::common::diffusion_config(0.1, 200_000_000, 16, 9);
    let plain = run(&cfg, &crate::common::threads(1)).unwrap();
    let watched = RunOptions {
        stop: Some(StopFlag::default()),
        ..crate::common::threads(1)
    };
    let unrequested = run(&cfg, &watched).unwrap();
    assert_eq!(plain.D.to_bits(), unrequested.D.to_bits());
    assert_eq!(plain.batch_D, unrequested.batch_D);

    let tmp = crate::common::scratch();
    let path = tmp.path().join("stopped.jsonl");
    let stop = StopFlag::default();
    let opts = RunOptions {
        stop: Some(stop.clone()),
        ..options(Engine::Auto, 1, &path, Duration::ZERO)
    };
    let requester = {
        let stop = stop.clone();
        std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(300));
            stop.request();
            Instant::now()
        })
    };
    let err = run(&cfg, &opts).unwrap_err();
    let stopped = requester.join().unwrap().elapsed();
    assert!(matches!(err, Error::Interrupted), "{err}");
    assert_eq!(err.kind(), lorentz_gas::ErrorKind::Interrupted);
    assert!(
        stopped < Duration::from_secs(2),
        "stopped {stopped:?} after the request"
    );
    let kept = std::fs::read_to_string(&path).unwrap();
    assert!(
        kept.contains(IN_FLIGHT),
        "the stopped run kept no trajectory in flight"
    );
    let resumed = run(&cfg, &options(Engine::Auto, 1, &path, Duration::ZERO)).unwrap();
    assert_eq!(plain.D.to_bits(), resumed.D.to_bits());
    assert_eq!(plain.batch_D, resumed.batch_D);
}

/// A checkpoint recorded before the gap was kept as typed (its configuration with the double `w`
/// alone) resumes a run at the same double: a hops run from `--w 0.1` in `f64`, and a diffusion
/// run at 128 bits whose gap is exactly that double; a 128-bit run at the gap 1/10, which is not
/// the double, is refused.
#[test]
fn a_checkpoint_recorded_before_the_exact_gap_resumes_the_same_trajectories() {
    let tmp = crate::common::scratch();
    let without_exact = |h: &mut serde_json::Value| {
        h["config"].as_object_mut().unwrap().remove("w_exact");
    };
    let opts = |path: &Path| RunOptions {
        resume: Some(path.to_path_buf()),
        ..crate::common::threads(2)
    };
    // Hops, f64 only: the old record named the double nearest the 0.1 typed now.
    let hops_path = tmp.path().join("hops.jsonl");
    let hops_cfg = HopsConfig {
        collisions: 2_000_000,
        batches: 4,
        ..HopsConfig::new(Table::triangular("0.1").unwrap())
    };
    let first = hops::run(&hops_cfg, &opts(&hops_path)).unwrap();
    let text = std::fs::read_to_string(&hops_path).unwrap();
    std::fs::write(&hops_path, forge(&text, without_exact, |_| {})).unwrap();
    // Refused, this would be an error naming the configuration; resumed, the same result.
    let again = hops::run(&hops_cfg, &opts(&hops_path)).unwrap();
    assert_eq!(again.p_bs.to_bits(), first.p_bs.to_bits());
    assert_eq!(
        serde_json::to_value(&again.pairs).unwrap(),
        serde_json::to_value(&first.pairs).unwrap()
    );
    // Diffusion at 128 bits: the gap that is exactly the double resumes; 1/10 does not.
    let path = tmp.path().join("d.jsonl");
    let cfg = DiffusionConfig {
        collisions: 40_000,
        batches: 2,
        precision: Precision::Bits(128),
        window: "2:8".parse().unwrap(),
        check_window: "3:9".parse().unwrap(),
        ..DiffusionConfig::new(0.1)
    };
    let first = run(&cfg, &opts(&path)).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, forge(&text, without_exact, |_| {})).unwrap();
    let again = run(&cfg, &opts(&path)).unwrap();
    assert_eq!(
        (again.resumed_batches, again.D.to_bits()),
        (2, first.D.to_bits())
    );
    let tenth = DiffusionConfig {
        table: Table::triangular("1/10").unwrap(),
        ..cfg.clone()
    };
    let e = run(&tenth, &opts(&path)).unwrap_err().to_string();
    assert!(
        e.contains("another configuration") && e.contains("w_exact"),
        "{e}"
    );
}
