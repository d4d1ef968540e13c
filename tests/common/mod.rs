//! Helpers shared by the test binaries (each binary uses some of them).
#![allow(dead_code)]

use std::path::Path;
use std::process::Command;

use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::statistics::{
    f_p_value, mean_se, normal_sigma_equivalent_t, normal_two_sided_tail, welch_dof,
};
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// Runs the `lorentz` binary with `args` in `dir`: (exit status, stdout, stderr).
pub fn lorentz_in(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lorentz"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run lorentz");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

/// The JSON a successful (exit 0) `lorentz ARGS` in `dir` prints.
pub fn lorentz_json(dir: &Path, args: &[&str]) -> serde_json::Value {
    let (code, out, err) = lorentz_in(dir, args);
    assert_eq!(code, 0, "{args:?}: {err}");
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("{args:?}: {e}: {out}"))
}

/// The words of a command line, split at white space (for [`lorentz_in`]).
pub fn words(line: &str) -> Vec<&str> {
    line.split_whitespace().collect()
}

/// A fresh temporary directory, removed when the returned guard is dropped — also when the test
/// fails (the panic unwinds through the guard).
pub fn scratch() -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix("lorentz-test-")
        .tempdir()
        .expect("a temporary directory")
}

/// The "4σ" bound of a mean of `n` independent batch means against an exact value: the
/// Student-t quantile with n − 1 degrees of freedom at the normal's two-sided 4σ tail probability
/// 6.3·10⁻⁵ (5.48 for 16 batches, 4.65 for 31 dof).
pub fn t4(n: u32) -> f64 {
    normal_sigma_equivalent_t(n as f64 - 1.0, 4.0)
}

/// The "4σ" bound of the difference of two independent batch means with standard errors `ea`,
/// `eb` over `na`, `nb` batches (Welch–Satterthwaite degrees of freedom).
pub fn t4_welch(ea: f64, na: u32, eb: f64, nb: u32) -> f64 {
    normal_sigma_equivalent_t(welch_dof(ea, na as f64, eb, nb as f64), 4.0)
}

/// How far apart two independent estimates a ± ea and b ± eb are, in units of the standard error
/// of their difference: |a − b|/√(ea² + eb²).
pub fn z(a: f64, ea: f64, b: f64, eb: f64) -> f64 {
    (a - b).abs() / (ea * ea + eb * eb).sqrt()
}

/// A proptest runner with `cases` cases, a fixed ChaCha seed (`seed` repeated), and no failure
/// files: the same cases on every run, shrinking on failure.
pub fn runner(cases: u32, seed: u8) -> TestRunner {
    let cfg = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    TestRunner::new_with_rng(cfg, TestRng::from_seed(RngAlgorithm::ChaCha, &[seed; 32]))
}

/// Checks `property` on `cases` cases of [`runner`]`(cases, seed)`: a scene parameter from
/// `parameter` and three numbers uniform in [0, 1) that pick a start. Panics with the shrunk
/// failing case.
pub fn check_starts(
    cases: u32,
    seed: u8,
    parameter: std::ops::Range<f64>,
    property: impl Fn((f64, f64, f64, f64)) -> Result<(), proptest::test_runner::TestCaseError>,
) {
    let strategy = (parameter, 0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0);
    runner(cases, seed).run(&strategy, property).unwrap();
}

/// Run options on `threads` threads, everything else default (auto engine, no progress, nothing
/// resumed, no audit).
pub fn threads(threads: usize) -> RunOptions<'static> {
    RunOptions {
        threads,
        ..RunOptions::default()
    }
}

/// Run options on `engine` with `threads` threads, everything else default.
pub fn on_engine(engine: lorentz_gas::engine::Engine, threads: usize) -> RunOptions<'static> {
    RunOptions {
        engine,
        threads,
        ..RunOptions::default()
    }
}

/// The diffusion at gap `w` of `collisions` collisions in `batches` batches, seed `seed`; every
/// other setting the default.
pub fn diffusion_config(
    w: f64,
    collisions: u64,
    batches: u32,
    seed: u64,
) -> lorentz_gas::estimators::diffusion::DiffusionConfig {
    let mut cfg = lorentz_gas::estimators::diffusion::DiffusionConfig::new(w);
    cfg.collisions = collisions;
    cfg.batches = batches;
    cfg.seed = seed;
    cfg
}

/// The shadow audit of `collisions` collisions over 2 batches (seed `seed`) on 2 threads, every
/// event replayed at 128 bits, in the field `field` (none: straight flights) with `flights`.
pub fn full_audit<S: lorentz_gas::scenes::Scene>(
    scene: &S,
    collisions: u64,
    seed: u64,
    field: Option<&str>,
    flights: lorentz_gas::engine::long_flight::Flights,
) -> lorentz_gas::verification::shadow_audit::AuditReport {
    let cfg = lorentz_gas::verification::shadow_audit::AuditConfig {
        motion: lorentz_gas::scenes::motion::MotionInput {
            field: field.map(Into::into),
            ..Default::default()
        },
        flights,
        ..audit_config(scene, collisions, seed)
    };
    lorentz_gas::verification::shadow_audit::run(scene, &cfg, &threads(2)).unwrap()
}

/// The audit of `collisions` collisions over 2 batches (seed `seed`) of straight flights on
/// `scene`, every event replayed at 128 bits: the base the audits' tests set their motion on.
pub fn audit_config<S: lorentz_gas::scenes::Scene>(
    scene: &S,
    collisions: u64,
    seed: u64,
) -> lorentz_gas::verification::shadow_audit::AuditConfig {
    lorentz_gas::verification::shadow_audit::AuditConfig {
        scene: scene.label(),
        collisions,
        batches: 2,
        sample: 1.0,
        reference_bits: 128,
        seed,
        motion: Default::default(),
        flights: Default::default(),
    }
}

/// Asserts that the audit `r` replayed at least `least` events and found none of them outside
/// the error model (the message names `what` and the first outside).
pub fn assert_audit_clean(
    r: &lorentz_gas::verification::shadow_audit::AuditReport,
    least: u64,
    what: &str,
) {
    let s = &r.summary;
    assert!(s.audited >= least, "{what}: {} events audited", s.audited);
    assert_eq!(s.outside, 0, "{what}: {:?}", s.outside_events.first());
}

/// A result's JSON without what differs between runs of the same bits: timing (with the precision
/// plan, whose time is this run's speed), metadata, and how much was resumed from a checkpoint.
pub fn physics_only(mut v: serde_json::Value) -> serde_json::Value {
    if let Some(m) = v.as_object_mut() {
        for k in [
            "meta",
            "seconds",
            "collisions_per_second",
            "plan",
            "resumed_batches",
            "resumed_collisions",
            "resumed_points",
        ] {
            m.remove(k);
        }
    }
    v
}

/// How a quantity's (value, error) is read from a run's report.
pub type Pick<R> = fn(&R) -> (f64, f64);

/// Whether reported errors are honest over independent runs: for each quantity (a name and
/// how to pick (value, error) from a run's report), the variance of the runs' values against the
/// mean of their squared errors is F(runs − 1, `error_dof`)-distributed if the errors are right.
/// Prints every ratio and returns those outside the central 1 − p of that F, p the normal 4σ
/// two-sided tail over the number of quantities (Bonferroni).
pub fn errors_outside_their_spread<R>(
    reports: &[R],
    quantities: &[(&str, Pick<R>)],
    error_dof: f64,
) -> Vec<String> {
    let p = normal_two_sided_tail(4.0) / quantities.len() as f64;
    let runs = reports.len() as f64;
    let mut failures = Vec::new();
    for (name, pick) in quantities {
        let (values, errs): (Vec<f64>, Vec<f64>) = reports.iter().map(pick).unzip();
        let (_, se) = mean_se(&values);
        let spread = se * se * runs;
        let reported = errs.iter().map(|e| e * e).sum::<f64>() / runs;
        let f = spread / reported;
        let upper = f_p_value(f, runs - 1.0, error_dof);
        let line = format!("{name}: spread²/error² = {f:.3} (P(F > f) = {upper:.2e})");
        eprintln!("{line}");
        if upper < p / 2.0 || upper > 1.0 - p / 2.0 {
            failures.push(line);
        }
    }
    failures
}

/// Asserts that no quantity's reported error is off its spread over the runs
/// ([`errors_outside_their_spread`]).
pub fn assert_errors_match_their_spread<R>(
    reports: &[R],
    quantities: &[(&str, Pick<R>)],
    error_dof: f64,
) {
    let failures = errors_outside_their_spread(reports, quantities, error_dof);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Below the gap no flight fits twice, so at a time t = f·⟨ℓ⟩ short of it the MSD is
/// t²(1 − 4f/9) and the velocity autocorrelation 1 − 4f/3 exactly (`proofs-notes/msd-curve.md`):
/// each measured value `(x, err)` within `k4` errors of them.
pub fn short_time_curve((t, f, k4): (f64, f64, f64), msd: (f64, f64), vacf: (f64, f64)) {
    let near = |(x, err): (f64, f64), want: f64| (x - want).abs() <= k4 * err;
    assert!(
        near(msd, t * t * (1.0 - 4.0 * f / 9.0)),
        "MSD({t}) = {}",
        msd.0
    );
    assert!(near(vacf, 1.0 - 4.0 * f / 3.0), "C({t}) = {}", vacf.0);
}
