//! Campaigns on Slurm, the scheduler HPC users already have: a sweep dealt into the parts of a
//! job array ([`crate::campaigns::shard::Shard`]), and a merge job that starts only when every part has
//! succeeded (`--dependency=afterok`). This module only writes the batch scripts; Slurm runs them.
//!
//! Each array task runs `lorentz sweep … --shard $SLURM_ARRAY_TASK_ID/N --out OUT/shard-$ID`
//! (resumable: a requeued or resubmitted task reuses its finished points) — a sweep over w with
//! its flags, a sweep in a field with `--config OUT/slurm/sweep-config.json`, the validated
//! configuration written beside the scripts ([`crate::estimators::sweep::SweepConfig::read`]; a table given as data travels in
//! it) — and the merge job runs `lorentz merge OUT/shard-0 … OUT/shard-(N−1) --out OUT`, which
//! writes the same tables, JSON and figures as the sweep run in one piece
//! ([`crate::campaigns::merge::run`]).
//!
//! Slurm's default `MaxArraySize` is 1001 (tasks 0 … 1000); a site may set it lower or higher.

use std::path::{Path, PathBuf};

use crate::Error;
use crate::engine::Engine;
use crate::estimators::sweep::{GapGrid, Grid, SweepConfig};

/// The configuration file of a sweep in a field, in `OUT/slurm/`.
pub const CONFIG_FILE: &str = "sweep-config.json";

/// A sweep as a Slurm campaign: the job array of its parts and the dependent merge job.
#[derive(Debug, Clone)]
pub struct SweepCampaign {
    /// The whole sweep.
    pub sweep: SweepConfig,
    /// Parts (array tasks), 1 … the sweep's points.
    pub parts: u32,
    /// Output directory of the merged sweep; part i writes `OUT/shard-i`, the scripts and the
    /// jobs' logs go to `OUT/slurm`. Absolute: the jobs may start in another directory.
    pub out: PathBuf,
    /// The `lorentz` binary the jobs run (absolute; visible on the compute nodes).
    pub binary: PathBuf,
    /// `--engine` of the parts: the same bits on every engine.
    pub engine: Engine,
    /// CPUs per array task (the part's `--threads`).
    pub cpus_per_task: u32,
    /// Slurm partition, if not the default one.
    pub partition: Option<String>,
    /// Wall-time limit of each task (Slurm's formats, e.g. `2:00:00` or `1-00:00:00`).
    pub time: Option<String>,
    /// The account the jobs are charged to, if not the user's default one.
    pub account: Option<String>,
    /// Memory of each job (per node), in Slurm's form: a whole number with an optional unit
    /// K, M, G or T (`4G`, `500M`).
    pub mem: Option<String>,
    /// Further `#SBATCH` directives of both jobs, each in option syntax `--key=value` (or a flag
    /// `--key`), e.g. `--qos=long`, `--constraint=avx2`.
    pub extra: Vec<String>,
}

/// The `#SBATCH` options the campaign writes itself (or takes as its own options): an extra
/// directive may not set them again.
pub const OWN_DIRECTIVES: [&str; 11] = [
    "job-name",
    "output",
    "error",
    "array",
    "ntasks",
    "cpus-per-task",
    "dependency",
    "partition",
    "time",
    "account",
    "mem",
];

/// Checks an extra directive: `--key=value` or `--key`, the key lowercase letters, digits and
/// `-`, the value letters, digits and `_ . , : = + @ / % -` (no space, quote or other shell or
/// line syntax), and not one of the campaign's own ([`OWN_DIRECTIVES`]).
///
/// # Examples
///
/// ```
/// use lorentz_gas::campaigns::slurm::check_directive;
/// assert!(check_directive("--qos=long").is_ok());
/// assert!(check_directive("--exclusive").is_ok());
/// assert!(check_directive("--qos=long; rm -rf ~").is_err());
/// assert!(check_directive("qos=long").is_err());
/// assert!(check_directive("--array=0-99").is_err());
/// ```
pub fn check_directive(d: &str) -> Result<(), Error> {
    const FORM: &str = "use option syntax --key=value (or a flag --key): the key lowercase \
                        letters, digits and '-', the value letters, digits and _ . , : = + @ / % - \
                        (no spaces, quotes or other shell characters)";
    let (key, value) = match d.strip_prefix("--") {
        Some(rest) => rest
            .split_once('=')
            .map_or((rest, None), |(k, v)| (k, Some(v))),
        None => return Err(Error::parameter("sbatch", format!("{d:?}"), FORM)),
    };
    let key_ok = key.starts_with(|c: char| c.is_ascii_lowercase())
        && key
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-');
    let value_ok = value.is_none_or(|v| {
        !v.is_empty()
            && v.chars()
                .all(|c| c.is_ascii_alphanumeric() || "_.,:=+@/%-".contains(c))
    });
    if !key_ok || !value_ok {
        return Err(Error::parameter("sbatch", format!("{d:?}"), FORM));
    }
    if OWN_DIRECTIVES.contains(&key) {
        return Err(Error::parameter(
            "sbatch",
            format!("{d:?}"),
            format!(
                "--{key} is written by the campaign itself or has its own option; extra \
                 directives may not set any of --{}",
                OWN_DIRECTIVES.join(", --")
            ),
        ));
    }
    Ok(())
}

/// Most CPUs per task accepted: more than any node has today, so larger is a typo.
pub const MAX_CPUS_PER_TASK: u32 = 1024;

/// Quotes `s` for a POSIX shell: single quotes, with each `'` written as `'\''`.
///
/// # Examples
///
/// ```
/// use lorentz_gas::campaigns::slurm::shell_quote;
/// assert_eq!(shell_quote("a b"), "'a b'");
/// assert_eq!(shell_quote("it's"), "'it'\\''s'");
/// ```
pub fn shell_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', "'\\''"))
}

/// Checks `--mem`: a whole number of megabytes, or with a unit K, M, G or T.
fn check_mem(m: &str) -> Result<(), Error> {
    let digits = m.strip_suffix(['K', 'M', 'G', 'T']).unwrap_or(m);
    if digits.is_empty() || !digits.chars().all(|c| c.is_ascii_digit()) {
        return Err(Error::parameter(
            "mem",
            format!("{m:?}"),
            "use Slurm's form: a whole number with an optional unit K, M, G or T, e.g. 4G or \
             500M (megabytes without a unit)",
        ));
    }
    Ok(())
}

fn checked(
    what: &'static str,
    value: &str,
    allowed: &str,
    ok: impl Fn(char) -> bool,
) -> Result<(), Error> {
    if value.is_empty() || !value.chars().all(ok) {
        return Err(Error::parameter(
            what,
            format!("{value:?}"),
            format!("use {allowed}"),
        ));
    }
    Ok(())
}

impl SweepCampaign {
    /// Checks the campaign before anything is written.
    pub fn validate(&self) -> Result<(), Error> {
        self.sweep.validate()?;
        let points = self.sweep.steps();
        if self.parts == 0 || self.parts > points {
            return Err(Error::out_of_range(
                "array",
                self.parts,
                format!(
                    "use 1 to {points} parts (the sweep has {points} points; every part needs one)"
                ),
            ));
        }
        if self.cpus_per_task == 0 || self.cpus_per_task > MAX_CPUS_PER_TASK {
            return Err(Error::out_of_range(
                "cpus_per_task",
                self.cpus_per_task,
                format!("use 1 to {MAX_CPUS_PER_TASK}"),
            ));
        }
        if let Some(p) = &self.partition {
            checked(
                "partition",
                p,
                "letters, digits, '_', '-', '.' and ','",
                |c| c.is_ascii_alphanumeric() || "_-.,".contains(c),
            )?;
        }
        if let Some(t) = &self.time {
            checked(
                "time",
                t,
                "Slurm's forms such as 90, 2:00:00 or 1-12:00:00",
                |c| c.is_ascii_digit() || c == ':' || c == '-',
            )?;
        }
        if let Some(a) = &self.account {
            checked("account", a, "letters, digits, '_', '-' and '.'", |c| {
                c.is_ascii_alphanumeric() || "_-.".contains(c)
            })?;
        }
        if let Some(m) = &self.mem {
            check_mem(m)?;
        }
        for d in &self.extra {
            check_directive(d)?;
        }
        for (what, p) in [("out", &self.out), ("binary", &self.binary)] {
            if !p.is_absolute() {
                return Err(Error::parameter(
                    what,
                    p.display(),
                    "must be an absolute path (the jobs start elsewhere)",
                ));
            }
            if p.to_str().is_none() {
                return Err(Error::parameter(
                    what,
                    p.display(),
                    "must be valid UTF-8 to go into a batch script",
                ));
            }
            // A newline would end an `#SBATCH` line (and start a command); no quoting survives
            // Slurm's own reading of those lines, so control characters are refused.
            if p.to_str().is_some_and(|t| t.chars().any(char::is_control)) {
                return Err(Error::parameter(
                    what,
                    format!("{:?}", p.display().to_string()),
                    "a path with a newline or another control character cannot go into a batch \
                     script; choose a path without them",
                ));
            }
        }
        Ok(())
    }

    fn q(p: &Path) -> String {
        shell_quote(p.to_str().unwrap_or_default())
    }

    fn header(&self, name: &str, out: &str) -> String {
        let mut s = format!(
            "#!/bin/bash\n#SBATCH --job-name={name}\n#SBATCH --output={}\n",
            self.out.join("slurm").join(out).display()
        );
        if let Some(p) = &self.partition {
            s += &format!("#SBATCH --partition={p}\n");
        }
        if let Some(t) = &self.time {
            s += &format!("#SBATCH --time={t}\n");
        }
        if let Some(a) = &self.account {
            s += &format!("#SBATCH --account={a}\n");
        }
        if let Some(m) = &self.mem {
            s += &format!("#SBATCH --mem={m}\n");
        }
        for d in &self.extra {
            s += &format!("#SBATCH {d}\n");
        }
        s
    }

    /// The job array: task i computes part i/N of the sweep into `OUT/shard-i`.
    pub fn array_script(&self) -> String {
        let n = self.parts;
        let mut s = self.header("lorentz-sweep", "sweep-%A_%a.out");
        s += &format!(
            "#SBATCH --array=0-{}\n#SBATCH --ntasks=1\n#SBATCH --cpus-per-task={}\n",
            n - 1,
            self.cpus_per_task
        );
        s += &format!(
            "# Part $SLURM_ARRAY_TASK_ID of {n} of {}.\n\
             # Resumable: a requeued or resubmitted task reuses the part's finished points.\n\
             set -euo pipefail\n",
            self.sweep.describe()
        );
        s += &format!(
            "exec {} sweep {} \\\n  \
             --engine {} --threads \"${{SLURM_CPUS_PER_TASK:-{}}}\" --shard \"$SLURM_ARRAY_TASK_ID/{n}\" \\\n  \
             --out {}/shard-\"$SLURM_ARRAY_TASK_ID\" --quiet\n",
            Self::q(&self.binary),
            self.sweep_arguments(),
            self.engine.name(),
            self.cpus_per_task,
            Self::q(&self.out),
        );
        s
    }

    /// What the parts' `lorentz sweep` is given for the sweep: the flags of a sweep over w, the
    /// configuration file of a sweep in a field.
    fn sweep_arguments(&self) -> String {
        match &self.sweep.grid {
            Grid::Gaps(g) => over_w_arguments(&self.sweep, g),
            Grid::InField(_) | Grid::Driven(_) => {
                format!(
                    "--config {}",
                    Self::q(&self.out.join("slurm").join(CONFIG_FILE))
                )
            }
        }
    }

    /// The merge job: combines the parts into `OUT` (submitted with `--dependency=afterok` on
    /// the array by [`SweepCampaign::submit_script`]).
    pub fn merge_script(&self) -> String {
        let mut s = self.header("lorentz-sweep-merge", "merge-%j.out");
        s += "#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=1\n";
        s += &format!(
            "# Combines the {} parts into the sweep's CSV, JSON and figures; fails, naming them, if points are missing.\n\
             set -euo pipefail\n\
             out={}\n\
             parts=()\n\
             for i in $(seq 0 {}); do parts+=(\"$out/shard-$i\"); done\n\
             exec {} merge \"${{parts[@]}}\" --out \"$out\" --quiet\n",
            self.parts,
            Self::q(&self.out),
            self.parts - 1,
            Self::q(&self.binary),
        );
        s
    }

    /// Submits the array, then the merge job depending on it; prints both job ids.
    pub fn submit_script(&self) -> String {
        "#!/bin/sh\n\
         # Submits the sweep's job array, then the merge job, which starts only when every task has\n\
         # succeeded (afterok). Prints: array JOBID merge JOBID.\n\
         set -eu\n\
         cd \"$(dirname \"$0\")\"\n\
         array=$(sbatch --parsable sweep-array.sbatch)\n\
         array=${array%%;*}\n\
         merge=$(sbatch --parsable --dependency=afterok:\"$array\" merge.sbatch)\n\
         merge=${merge%%;*}\n\
         echo \"array $array merge $merge\"\n"
            .to_string()
    }

    /// Writes `sweep-array.sbatch`, `merge.sbatch` and `submit.sh` into `OUT/slurm/` and returns
    /// their paths (submit with `sh OUT/slurm/submit.sh`).
    pub fn write(&self) -> Result<Vec<PathBuf>, Error> {
        self.validate()?;
        let dir = self.out.join("slurm");
        crate::files::create_dir_all(&self.out)?;
        crate::files::create_subdir(&dir)?;
        let mut written = Vec::new();
        let mut files = vec![
            ("sweep-array.sbatch", self.array_script()),
            ("merge.sbatch", self.merge_script()),
            ("submit.sh", self.submit_script()),
        ];
        if matches!(&self.sweep.grid, Grid::InField(_) | Grid::Driven(_)) {
            files.push((CONFIG_FILE, self.sweep.to_json()?));
        }
        for (name, text) in files {
            let path = dir.join(name);
            crate::files::write(&path, text)?;
            written.push(path);
        }
        Ok(written)
    }
}

/// The flags of a sweep over w, for its parts.
fn over_w_arguments(c: &SweepConfig, g: &GapGrid) -> String {
    format!(
        "--w-from {} --w-to {} --steps {} --runs {} --collisions-per-run {} \\\n  \
         --batches-per-run {} --seed {}",
        shell_quote(&g.w_from),
        shell_quote(&g.w_to),
        g.steps,
        g.runs,
        c.collisions,
        c.batches,
        c.seed,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn campaign() -> SweepCampaign {
        SweepCampaign {
            sweep: SweepConfig {
                grid: Grid::Gaps(GapGrid {
                    w_from: "0.2".into(),
                    w_to: "0.3".into(),
                    steps: 21,
                    runs: 10,
                }),
                collisions: 2_000_000_000,
                batches: 16,
                seed: 5,
            },
            parts: 7,
            out: PathBuf::from("/scratch/it's here"),
            binary: PathBuf::from("/opt/lorentz/bin/lorentz"),
            engine: Engine::Auto,
            cpus_per_task: 2,
            partition: Some("short".into()),
            time: Some("2:00:00".into()),
            account: Some("phys-42".into()),
            mem: Some("4G".into()),
            extra: vec!["--qos=long".into(), "--exclusive".into()],
        }
    }

    #[test]
    fn array_script_reproduces_the_sweep_and_deals_it_into_parts() {
        let s = campaign().array_script();
        assert!(s.contains("#SBATCH --array=0-6\n"), "{s}");
        assert!(
            s.contains(
                "#SBATCH --partition=short\n#SBATCH --time=2:00:00\n#SBATCH --account=phys-42\n\
                 #SBATCH --mem=4G\n#SBATCH --qos=long\n#SBATCH --exclusive\n"
            ),
            "{s}"
        );
        // The merge job is charged and placed as the array is.
        assert!(campaign().merge_script().contains("#SBATCH --qos=long\n"));
        assert!(s.contains("--w-from '0.2' --w-to '0.3' --steps 21 --runs 10 --collisions-per-run 2000000000 \\\n  --batches-per-run 16 --seed 5"), "{s}");
        assert!(s.contains("--shard \"$SLURM_ARRAY_TASK_ID/7\""), "{s}");
        assert!(
            s.contains("--out '/scratch/it'\\''s here'/shard-\"$SLURM_ARRAY_TASK_ID\""),
            "{s}"
        );
    }

    #[test]
    fn a_field_sweeps_parts_read_its_configuration_beside_the_scripts() {
        use crate::estimators::sweep::field::FieldGrid;
        let field = SweepConfig {
            grid: Grid::InField(FieldGrid {
                gaps: Vec::new(),
                radius: Some("1/4".into()),
                fields: ["-1", "1", "2"].map(String::from).to_vec(),
                localization_samples: 1000,
                table: None,
            }),
            collisions: 1_000_000,
            batches: 8,
            seed: 3,
        };
        let c = SweepCampaign {
            sweep: field,
            parts: 3,
            ..campaign()
        };
        assert!(c.validate().is_ok());
        let s = c.array_script();
        assert!(
            s.contains("sweep --config '/scratch/it'\\''s here/slurm/sweep-config.json' \\\n"),
            "{s}"
        );
        assert!(
            s.contains("square lattice at radius 1/4 (fields -1, 1, 2; 3 points"),
            "{s}"
        );
        assert!(!s.contains("--w-from"), "{s}");
        // Three points: at most three parts.
        assert!(SweepCampaign { parts: 4, ..c }.validate().is_err());
    }

    #[test]
    fn merge_waits_for_every_task() {
        let c = campaign();
        assert!(c.merge_script().contains("for i in $(seq 0 6)"));
        assert!(
            c.submit_script()
                .contains("--dependency=afterok:\"$array\" merge.sbatch")
        );
    }

    #[test]
    fn refuses_what_would_break_the_scripts() {
        let mut c = campaign();
        c.parts = 22;
        assert!(c.validate().is_err());
        let mut c = campaign();
        c.partition = Some("a\n#SBATCH --mem=1".into());
        assert!(c.validate().is_err());
        let mut c = campaign();
        c.out = PathBuf::from("relative/out");
        assert!(c.validate().is_err());
        let mut c = campaign();
        c.cpus_per_task = 0;
        assert!(c.validate().is_err());
        assert!(campaign().validate().is_ok());
    }

    #[test]
    fn account_memory_and_extra_directives_cannot_inject_lines_or_commands() {
        let refused = |f: &dyn Fn(&mut SweepCampaign)| {
            let mut c = campaign();
            f(&mut c);
            let e = c.validate().unwrap_err().to_string();
            assert!(!e.contains('\n'), "{e}");
            e
        };
        for a in ["a\n#SBATCH --mem=1", "a b", "a;id", "$(id)", ""] {
            let e = refused(&|c| c.account = Some(a.into()));
            assert!(
                e.contains("account") && e.contains("letters, digits"),
                "{e}"
            );
        }
        for m in ["4GB", "4 G", "-1", "G", "4G\n#", "1e3"] {
            let e = refused(&|c| c.mem = Some(m.into()));
            assert!(e.contains("mem") && e.contains("K, M, G or T"), "{e}");
        }
        for d in [
            "--qos=long\n#SBATCH --array=0-99",
            "--qos=long\rx",
            "--qos=long;id",
            "--qos=$(id)",
            "--qos=`id`",
            "--qos='a'",
            "--qos=a b",
            "--mail-user=a|b",
            "-q long",
            "qos=long",
            "--QOS=long",
            "--=x",
            "--qos=",
            "#SBATCH --qos=long",
        ] {
            let e = refused(&|c| c.extra = vec![d.into()]);
            assert!(e.contains("--key=value"), "{d:?}: {e}");
        }
        for own in [
            "--array=0-3",
            "--output=/tmp/x",
            "--dependency=afterok:1",
            "--mem=1G",
        ] {
            let e = refused(&|c| c.extra = vec![own.into()]);
            assert!(e.contains("written by the campaign"), "{own:?}: {e}");
        }
        for ok in [
            "--gres=gpu:1",
            "--mail-user=me@example.org",
            "--mail-type=END,FAIL",
        ] {
            let mut c = campaign();
            c.extra = vec![ok.into()];
            assert!(c.validate().is_ok(), "{ok}");
        }
    }

    #[test]
    fn newline_in_out_or_binary_is_refused_before_a_script_is_written() {
        // A newline in the output directory would end the `#SBATCH --output` line and put a
        // command into the script; every `#SBATCH` line after it would be ignored.
        for (out, binary) in [
            ("/scratch/x\nrm -rf ~\n#", "/opt/lorentz"),
            ("/scratch/x", "/opt/lorentz\r"),
            ("/scratch/\tx", "/opt/lorentz"),
        ] {
            let mut c = campaign();
            c.out = PathBuf::from(out);
            c.binary = PathBuf::from(binary);
            let e = c.validate().unwrap_err().to_string();
            assert!(e.contains("control character"), "{e}");
            assert!(c.write().is_err());
        }
    }
}
