//! The recorded command line checked against the recorded configuration: a front end that owns
//! a command-line parser ([`ReadCommandLine`]) parses `meta.command_line` — never running it —
//! into the configuration it would give, and the check FAILs, naming the first field that
//! differs, when that is not the file's `config` or not a command that writes this kind of
//! result. Without a parser, or for a result recorded by another program (a Python session), the
//! check is a SKIP saying why.

use serde_json::Value;

use super::{Checks, Verdict};
use crate::engine::metadata::RunMeta;

/// What a front end reads from a recorded command line.
#[derive(Debug, Clone, PartialEq)]
pub enum CommandLine {
    /// A command line of this front end: its command (`diffusion`, `figure`, …), the kind of
    /// result it writes, and, for a command that writes it from its own options, the
    /// configuration it gives (`None` for a command such as `merge`, whose configuration is its
    /// inputs').
    Parsed {
        /// The command's name.
        command: String,
        /// The kind of result it writes (`diffusion`, `sweep`, …), `None` for none of the
        /// audited kinds.
        writes: Option<String>,
        /// The configuration, as the result file records it.
        config: Option<Value>,
    },
    /// Not a command line of this front end (recorded by another program): why.
    Foreign(String),
    /// A command line of this front end that its parser refuses: the parser's reason.
    Refused(String),
}

/// A front end's reader of its own command lines.
pub type ReadCommandLine<'a> = &'a (dyn Fn(&[String]) -> CommandLine + Sync);

/// The check that `recorded.command_line` gives the file's configuration `config` and writes a
/// result of `kind`; a command line planned for a relative error (`--rel-err`) gives the plain
/// run its recorded `pilot` planned.
pub(super) fn check(
    checks: &mut Checks,
    kind: &str,
    (config, pilot): (Option<&Value>, Option<&Value>),
    recorded: &RunMeta,
    reader: Option<ReadCommandLine>,
) {
    let name = "recorded command line gives the recorded configuration";
    let shown = recorded.command_line.join(" ");
    let program = recorded
        .command_line
        .first()
        .and_then(|p| std::path::Path::new(p).file_stem())
        .map(|s| s.to_string_lossy().to_string());
    if recorded.command_line.iter().all(|a| a.trim().is_empty()) {
        // Every run records its process's command line (a Python session's too): a missing or
        // emptied one hides where the result came from, so the check cannot be made — and is
        // not "not applicable".
        let why = "the result records no command line (every run records its process's own): \
                   where it came from cannot be checked"
            .to_string();
        checks.add("provenance", name, Verdict::Skip, why, &[]);
        return;
    }
    if program.as_deref() != Some("lorentz") {
        let why = format!(
            "recorded by `{}`, not by the lorentz command line: nothing to parse",
            recorded.command_line.first().map_or("", String::as_str)
        );
        checks.add("provenance", name, Verdict::NotApplicable, why, &[]);
        return;
    }
    let (verdict, detail) = match reader.map(|r| r(&recorded.command_line)) {
        None => (
            Verdict::Skip,
            "a lorentz command line, but no command-line parser was given to this audit (a \
             library or Python call): the command line's own report parses it"
                .into(),
        ),
        Some(CommandLine::Foreign(why)) => (Verdict::NotApplicable, why),
        Some(CommandLine::Refused(why)) => (
            Verdict::Fail,
            format!("`{shown}` is not a command line the parser accepts: {why}"),
        ),
        Some(CommandLine::Parsed {
            command,
            writes,
            config: c,
        }) => match c.map(|c| planned(c, pilot)).transpose() {
            Ok(c) => judge(kind, config, &command, writes.as_deref(), c),
            Err(why) => (Verdict::Fail, why),
        },
    };
    checks.add("provenance", name, verdict, detail, &[]);
}

/// The configuration a parsed command line gives once its plan is known: without `rel_err`, the
/// parsed one; with it (its `collisions` the pilot's), the plain run of the recorded `pilot`'s
/// planned size — the pilot's size and target must be the command line's.
fn planned(mut given: Value, pilot: Option<&Value>) -> Result<Value, String> {
    let Some(target) = given.get("rel_err").filter(|r| !r.is_null()).cloned() else {
        return Ok(given);
    };
    let Some(p) = pilot.filter(|p| !p.is_null()) else {
        return Err(
            "the recorded command line plans for a relative error (--rel-err), but the file \
             records no pilot"
                .into(),
        );
    };
    if p.get("collisions") != given.get("collisions") || p.get("rel_err_target") != Some(&target) {
        return Err(format!(
            "the recorded pilot ({} collisions for {}) is not the command line's ({} for {target})",
            p.get("collisions").unwrap_or(&Value::Null),
            p.get("rel_err_target").unwrap_or(&Value::Null),
            given.get("collisions").unwrap_or(&Value::Null),
        ));
    }
    if let Some(o) = given.as_object_mut() {
        o.remove("rel_err");
        o.insert(
            "collisions".into(),
            p.get("planned_collisions").cloned().unwrap_or(Value::Null),
        );
    }
    Ok(given)
}

/// The verdict on a parsed command line of `command` giving `given` for a `kind` result whose
/// file records `config`.
fn judge(
    kind: &str,
    config: Option<&Value>,
    command: &str,
    writes: Option<&str>,
    given: Option<Value>,
) -> (Verdict, String) {
    if writes != Some(kind) {
        return (
            Verdict::Fail,
            format!(
                "the recorded command line runs `{command}`, which does not write this {kind} result"
            ),
        );
    }
    let (Some(given), Some(config)) = (given, config) else {
        return (
            Verdict::NotApplicable,
            format!("`{command}` takes its configuration from its inputs, not from its options"),
        );
    };
    match crate::engine::resume::difference(config, &given) {
        None => (
            Verdict::Pass,
            format!(
                "the recorded `{command}` command line gives the file's configuration, field for field (parsed, not run)"
            ),
        ),
        Some(d) => (
            Verdict::Fail,
            format!("the recorded command line does not give the file's configuration: {d}"),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_command_line_of_another_command_or_configuration_fails() {
        let cfg = serde_json::json!({"w": 0.1, "collisions": 1000});
        let d = Some("diffusion");
        let (v, _) = judge("diffusion", Some(&cfg), "diffusion", d, Some(cfg.clone()));
        assert_eq!(v, Verdict::Pass);
        let (v, why) = judge("hops", Some(&cfg), "figure", None, None);
        assert_eq!(v, Verdict::Fail);
        assert!(why.contains("`figure`"), "{why}");
        assert_eq!(
            judge("hops", Some(&cfg), "diffusion", d, Some(cfg.clone())).0,
            Verdict::Fail
        );
        // A planned run: the pilot's size and target on the command line, the plan in the file.
        let line = serde_json::json!({"w": 0.1, "collisions": 500, "rel_err": 0.01});
        let pilot = serde_json::json!({"collisions": 500, "rel_err_target": 0.01,
            "planned_collisions": 1000});
        assert_eq!(planned(line.clone(), Some(&pilot)), Ok(cfg.clone()));
        assert!(
            planned(line.clone(), None)
                .unwrap_err()
                .contains("no pilot")
        );
        let other_pilot = serde_json::json!({"collisions": 400, "rel_err_target": 0.01,
            "planned_collisions": 1000});
        assert!(planned(line, Some(&other_pilot)).is_err());
        let other = serde_json::json!({"w": 0.1, "collisions": 2000});
        let (v, why) = judge("diffusion", Some(&cfg), "diffusion", d, Some(other));
        assert_eq!(v, Verdict::Fail);
        assert!(why.contains("collisions"), "{why}");
        let merge = judge("sweep", Some(&cfg), "merge", Some("sweep"), None);
        assert_eq!(merge.0, Verdict::NotApplicable);
    }
}
