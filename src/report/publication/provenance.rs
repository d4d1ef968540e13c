//! Where a result and its report come from: the file's digest, this build, this machine, the
//! date, and the provenance check.

use super::{Checks, Provenance, Verdict};
use crate::engine::metadata::RunMeta;

/// Days since 1970-01-01 to (year, month, day) in the proleptic Gregorian calendar (H. Hinnant's
/// `civil_from_days`; written out because a date is all the report needs from a calendar crate).
pub(super) fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

fn now_utc() -> String {
    let t = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs() as i64)
        .unwrap_or(0);
    let (y, m, d) = civil_from_days(t.div_euclid(86_400));
    let s = t.rem_euclid(86_400);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        s / 3600,
        s / 60 % 60,
        s % 60
    )
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, v)| v.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string())
}

/// The provenance of a result file of `kind` with digest `sha` and recorded `meta`, and of this
/// report.
pub(super) fn provenance(
    result_file: String,
    sha: &str,
    kind: &str,
    recorded: Option<RunMeta>,
) -> Provenance {
    Provenance {
        result_file,
        sha256: sha.into(),
        kind: kind.into(),
        recorded,
        version: env!("CARGO_PKG_VERSION").into(),
        git_commit: env!("LORENTZ_GIT_COMMIT").into(),
        rustc: env!("LORENTZ_RUSTC_VERSION").into(),
        cpu: cpu_model(),
        date_utc: now_utc(),
    }
}

/// The provenance check: which result this is, by whom and how it was recorded (the recorded
/// command line is shown in the report, never run).
pub(super) fn identification_check(checks: &mut Checks, kind: &str, sha: &str, recorded: &RunMeta) {
    checks.add(
        "provenance",
        "result file identified",
        Verdict::Pass,
        format!(
            "{kind} result, SHA-256 {sha}; recorded by lorentz {} ({} engine{}, {}, seed {})",
            recorded.version,
            recorded.engine,
            recorded
                .simd
                .as_ref()
                .map_or(String::new(), |s| format!(" {s}")),
            recorded
                .threads
                .map_or("? threads".into(), |t| crate::report::counted(
                    t as u64, "thread"
                )),
            recorded.seed.map_or("-".into(), |s| s.to_string()),
        ),
        &[],
    );
}
