//! Errors: bad input (each names the valid range), I/O (each names its operation and path),
//! run-time failures, and FAIL verdicts.
//!
//! Every failure is one of four kinds, and the command line maps each kind to one exit status
//! ([`Error::kind`]): bad input, an I/O failure, a computation that started and could not finish
//! correctly, and a verification whose verdict is FAIL.

use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Everything that can go wrong. Never a panic, never a silent NaN.
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The gap `w` is NaN or infinite.
    #[error("{what} must be a finite number")]
    NotFinite {
        /// Which parameter.
        what: &'static str,
    },
    /// `w ≤ 0`: the disks touch or overlap and the particle is trapped, there is no diffusion.
    #[error(
        "w = {w:?} is not > 0: at w <= 0 the disks touch and the particle is trapped in one \
         triangle, there is no diffusion (valid range: 0 < w < 4/sqrt(3) - 2 = 0.3094...)"
    )]
    Trapped {
        /// The offending gap.
        w: f64,
    },
    /// `w ≥ w∞ = 4/√3 − 2`: the horizon is infinite and D does not exist.
    #[error(
        "w = {w:?} is not < w_inf = 4/sqrt(3) - 2 = {w_inf:.17}: the horizon is infinite, \
         free flights are unbounded and the diffusion coefficient does not exist \
         (valid range: 0 < w < {w_inf:.6}; the superdiffusion analysis measures the t ln t \
         growth against the exact corridor constants, which the constants analysis lists)"
    )]
    InfiniteHorizon {
        /// The offending gap.
        w: f64,
        /// w∞ in f64.
        w_inf: f64,
    },
    /// Precision below 53 bits or above [`crate::numbers::precision::MAX_RUN_BITS`].
    #[error(
        "precision {bits} bits is out of range: use 'f64' or a number of bits from 53 to {}",
        crate::numbers::precision::MAX_RUN_BITS
    )]
    Precision {
        /// The requested number of bits.
        bits: u32,
    },
    /// A count that must be positive is zero.
    #[error("{what} must be at least 1")]
    Zero {
        /// Which parameter.
        what: &'static str,
    },
    /// A count too small for the requested analysis.
    #[error("{what} = {got} is too small: at least {min} is needed")]
    TooFew {
        /// Which parameter.
        what: &'static str,
        /// The smallest accepted value.
        min: u64,
        /// The value given.
        got: u64,
    },
    /// A parameter outside its valid range, as data: the parameter (a configuration's field),
    /// the value as given and the valid range. Each front end names the parameter in its own
    /// terms ([`Error::presented`]: `--octaves 30` on the command line, `octaves=30` in Python).
    #[error("{}", out_of_range_text(parameter, value, range, &|p| p.to_string()))]
    OutOfRange {
        /// The parameter, as the configuration spells it (`octaves`, `points_per_octave`).
        parameter: &'static str,
        /// The value given.
        value: String,
        /// The valid range, as advice (`use 1 to 20 (the longest lag is 2^octaves mean free
        /// times)`).
        range: String,
    },
    /// A table given as data that is not a valid table ([`crate::scenes::table::TableError`]:
    /// the disks that overlap, the radius, the basis).
    #[error("{0}")]
    Table(Box<crate::scenes::table::TableError>),
    /// A scene whose horizon is infinite, given to an analysis that needs a finite one, with the
    /// widest corridor that makes it so.
    #[error(
        "{scene} has an infinite horizon: {corridor} is free of disks, so free flights are \
         unbounded and the diffusion coefficient does not exist (a finite horizon needs every \
         corridor closed; in a magnetic field every table has a finite horizon)"
    )]
    OpenCorridor {
        /// The scene's label.
        scene: String,
        /// Its widest corridor.
        corridor: Box<crate::scenes::table::horizon::Corridor>,
    },
    /// An analysis given a scene that lacks what it needs ([`Capability`]).
    #[error("{scene} lacks {capability}, which the {analysis} analysis needs")]
    Lacks {
        /// The scene (its name).
        scene: String,
        /// What it lacks.
        capability: Capability,
        /// The analysis that needs it.
        analysis: &'static str,
    },
    /// Text that is not an exact number (a decimal or a fraction), before it is known which
    /// parameter it is: [`Error::named`] makes it an [`Error::Parameter`].
    #[error("'{text}' {why}")]
    NotANumber {
        /// The text.
        text: String,
        /// Why it is not a number, as advice (`is not a decimal number (such as 0.15)`).
        why: &'static str,
    },
    /// A parameter (a configuration's field) whose value is not accepted here, with the reason
    /// and what to give instead. Each front end names the parameter in its own terms
    /// ([`Error::presented`]: `--flights jump` on the command line, `flights=jump` in Python).
    #[error("{}", parameter_text(parameter, value, why, &|p| p.to_string()))]
    Parameter {
        /// The parameter, as the configuration spells it (`flights`, `threads`, `field`).
        parameter: &'static str,
        /// The value given (empty: none was given, [`Error::missing`]).
        value: String,
        /// Why it is not accepted here, as advice (`arcs in a field cross the lattice cell by
        /// cell; use walk or auto`).
        why: String,
    },
    /// A file whose contents are not what they should be: an edited, damaged or foreign file,
    /// or one of another kind or version.
    #[error("{}: {why}", path.display())]
    Malformed {
        /// The file (or directory).
        path: PathBuf,
        /// What is wrong with it, and what to do.
        why: String,
    },
    /// Data read back without a path at hand that is not what it should be: a checkpoint's or
    /// journal's saved state that does not fit the run, a result's contents.
    #[error("{0}")]
    Invalid(String),
    /// An environment variable whose value is not accepted (`LORENTZ_SIMD=avx9`).
    #[error("{variable}={value}: {why}")]
    Environment {
        /// The variable.
        variable: &'static str,
        /// Its value.
        value: String,
        /// Why it is not accepted, as advice.
        why: String,
    },
    /// A run whose estimated work is beyond the limit ([`crate::engine::work`]), with the
    /// parameters that set it; each front end names them in its own terms.
    #[error("{}", too_much_work_text(estimate, lower, *raise, &|p| p.to_string()))]
    TooMuchWork {
        /// What the run would compute, and how long it would take.
        estimate: String,
        /// The parameters to lower (their configuration's fields).
        lower: &'static [&'static str],
        /// A parameter to raise instead, if any.
        raise: Option<&'static str>,
    },
    /// A path the crate will not read, write or replace: a symbolic link, a device, a FIFO, a
    /// directory, or a file that is not one it made ([`crate::files`]).
    #[error("{}: {found}: {why}", path.display())]
    UnsafePath {
        /// The path.
        path: PathBuf,
        /// What is there ("a symbolic link", "a FIFO", "not a lorentz journal (…)", …).
        found: String,
        /// What to do instead.
        why: &'static str,
    },
    /// A file or directory could not be read, created, written or renamed.
    #[error("cannot {op} {}: {source}", path.display())]
    Io {
        /// What was being done: "read", "create", "write", "rename", "create directory", ...
        op: &'static str,
        /// The file or directory.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: Arc<std::io::Error>,
    },
    /// A computation that started could not finish correctly: a re-run that does not reproduce,
    /// an identity violated during a run, a resumed run that fails its checks, a lost event.
    #[error("{0}")]
    Failed(String),
    /// A verification ran and its verdict is FAIL (not bad input: exit status 1).
    #[error("{0}")]
    CheckFailed(String),
    /// A verification ran, no check failed, but some were skipped: the result is not verified
    /// (the message names where the report lists them).
    #[error("{0}")]
    Incomplete(String),
    /// A scene given another scene's parameter, or none: each front end names the parameters in
    /// its own terms (`--w`, `w=`).
    #[error("{}", scene_parameter_text(scene, parameter, needs, range, *missing, &|p| p.to_string()))]
    SceneParameter {
        /// The scene.
        scene: &'static str,
        /// The parameter given that the scene does not take, or (`missing`) the one it needs.
        parameter: &'static str,
        /// The parameter the scene takes.
        needs: &'static str,
        /// Its valid range.
        range: &'static str,
        /// `true`: the scene's parameter is missing; `false`: `parameter` does not apply.
        missing: bool,
    },
    /// A run option that the analysis does not use was set: it would be ignored. Each front end
    /// names the option in its own terms (the command line's flag, Python's keyword).
    #[error("{}", unused_option_text(analysis, *option, &|p| format!("`{p}`")))]
    UnusedOption {
        /// The analysis.
        analysis: &'static str,
        /// The option it does not use.
        option: crate::engine::options::RunOption,
    },
    /// The run was asked to stop ([`crate::engine::options::StopFlag`]) before it finished;
    /// a checkpoint, if the run kept one, holds the work up to its last save.
    #[error("interrupted: the run was stopped before it finished")]
    Interrupted,
}

/// What only some scenes have, and some analyses need ([`Error::Lacks`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Capability {
    /// Every closed form of `lorentz constants` (the triangular and square scenes).
    ClosedForms,
    /// One disk per cell, at the lattice points (the exact corridor constants; true shadowing,
    /// which labels a disk by its lattice point).
    OneDiskPerCell,
    /// Trap symbols and the paper's hierarchy (the triangular scene).
    TrapSymbols,
    /// A finite horizon: no collision-free corridor (the diffusion coefficient exists).
    FiniteHorizon,
    /// An infinite horizon: open corridors, along which the mean squared displacement grows
    /// like t ln t (the triangular scene above w∞, the square one).
    InfiniteHorizon,
    /// Disks of one radius (true shadowing's).
    OneRadius,
    /// A lattice: periodic copies of a cell (an open table has none; only the escape analysis
    /// takes one).
    Lattice,
}

impl std::fmt::Display for Capability {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Capability::ClosedForms => "the closed forms of the shipped scenes",
            Capability::OneDiskPerCell => "one disk per cell, at the lattice points",
            Capability::TrapSymbols => "trap symbols (the triangular scene's)",
            Capability::FiniteHorizon => {
                "a finite horizon (along collision-free corridors the mean squared displacement \
                 grows like t ln t and the diffusion coefficient does not exist: use a \
                 finite-horizon scene, such as the triangular one with 0 < w < w_inf = \
                 0.3094..., or the superdiffusion analysis, which measures the t ln t growth \
                 against the exact corridor constants that the constants analysis lists; in a \
                 magnetic field every scene has a finite horizon)"
            }
            Capability::InfiniteHorizon => {
                "an infinite horizon (where the horizon is finite the mean squared displacement \
                 grows like t and the diffusion analysis measures D; superdiffusion needs \
                 w > w_inf = 0.3094... or the square scene)"
            }
            Capability::OneRadius => "disks of one radius",
            Capability::Lattice => {
                "a lattice (an open table has finitely many disks and no lattice: the escape \
                 analysis takes it, as lorentz escape --repeller or --open FILE)"
            }
        })
    }
}

/// The message of [`Error::SceneParameter`], the parameters spelled by `name`.
fn scene_parameter_text(
    scene: &str,
    parameter: &str,
    needs: &str,
    range: &str,
    missing: bool,
    name: &dyn Fn(&str) -> String,
) -> String {
    if missing {
        format!("the {scene} scene needs {}: {range}", name(needs))
    } else {
        format!(
            "{} does not apply to the {scene} scene: give {} ({range})",
            name(parameter),
            name(needs)
        )
    }
}

/// `parameter` given `value`, spelled by `name`: `--octaves 30` for a flag, `octaves=30` for a
/// keyword, `octaves = 30` otherwise.
fn assignment(parameter: &str, value: &str, name: &dyn Fn(&str) -> String) -> String {
    let n = name(parameter);
    if n.ends_with('=') {
        format!("{n}{value}")
    } else if n.starts_with("--") {
        format!("{n} {value}")
    } else {
        format!("{n} = {value}")
    }
}

/// The message of [`Error::OutOfRange`], the parameter spelled by `name`.
fn out_of_range_text(
    parameter: &str,
    value: &str,
    range: &str,
    name: &dyn Fn(&str) -> String,
) -> String {
    format!(
        "{} is out of range: {range}",
        assignment(parameter, value, name)
    )
}

/// The message of [`Error::Parameter`], the parameter spelled by `name` (without a value: the
/// parameter is missing).
fn parameter_text(
    parameter: &str,
    value: &str,
    why: &str,
    name: &dyn Fn(&str) -> String,
) -> String {
    if value.is_empty() {
        let n = name(parameter);
        format!("{} is missing: {why}", n.trim_end_matches('='))
    } else {
        format!("{}: {why}", assignment(parameter, value, name))
    }
}

/// The message of [`Error::TooMuchWork`], the parameters spelled by `name`.
fn too_much_work_text(
    estimate: &str,
    lower: &[&str],
    raise: Option<&str>,
    name: &dyn Fn(&str) -> String,
) -> String {
    let names: Vec<String> = lower.iter().map(|p| name(p)).collect();
    let list = match names.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => "the run's counts".into(),
    };
    let raise = raise.map_or(String::new(), |p| format!(" (or raise {})", name(p)));
    format!("{estimate}; lower {list}{raise}")
}

/// The message of [`Error::UnusedOption`], the option spelled by `name`.
fn unused_option_text(
    analysis: &str,
    option: crate::engine::options::RunOption,
    name: &dyn Fn(&str) -> String,
) -> String {
    format!(
        "{analysis} does not take {}: leave it out",
        name(option.field())
    )
}

/// The four kinds of failure, one exit status each on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// The input is outside its valid range (the message names the range).
    BadInput,
    /// A file or directory (or standard output) could not be read or written.
    Io,
    /// A computation that started could not finish correctly.
    Failed,
    /// A verification's verdict is FAIL.
    CheckFailed,
    /// A verification's verdict is INCOMPLETE: checks were skipped.
    Incomplete,
    /// The run was asked to stop before it finished.
    Interrupted,
}

impl Error {
    /// The I/O error of operation `op` on `path`, for `.map_err(Error::io("read", &path))`.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::Error;
    /// let e = std::fs::read("/nonexistent/x.json").map_err(Error::io("read", "/nonexistent/x.json"));
    /// let text = e.unwrap_err().to_string();
    /// assert!(text.starts_with("cannot read /nonexistent/x.json: "), "{text}");
    /// ```
    pub fn io<P: AsRef<Path>>(op: &'static str, path: P) -> impl FnOnce(std::io::Error) -> Error {
        move |source| Error::Io {
            op,
            path: path.as_ref().to_path_buf(),
            source: Arc::new(source),
        }
    }

    /// The message, with every parameter a typed error names spelled by `name` (its field or
    /// keyword in the library's terms: `w`, `radius`, `resume`, …): the command line passes its
    /// flags, Python its keywords. Other errors give their message unchanged.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::engine::options::RunOption;
    /// use lorentz_gas::Error;
    /// let e = Error::UnusedOption { analysis: "lyapunov", option: RunOption::Resume };
    /// assert_eq!(e.to_string(), "lyapunov does not take `resume`: leave it out");
    /// let flag = |p: &str| format!("--{}", p.replace('_', "-"));
    /// assert_eq!(e.presented(&flag), "lyapunov does not take --resume: leave it out");
    /// let e = Error::OutOfRange { parameter: "points_per_octave", value: "17".into(), range: "use 1 to 16".into() };
    /// assert_eq!(e.to_string(), "points_per_octave = 17 is out of range: use 1 to 16");
    /// assert_eq!(e.presented(&flag), "--points-per-octave 17 is out of range: use 1 to 16");
    /// assert_eq!(e.presented(&|p| format!("{p}=")), "points_per_octave=17 is out of range: use 1 to 16");
    /// let e = Error::parameter("flights", "jump", "arcs in a field cross the lattice cell by cell; use walk or auto");
    /// assert_eq!(e.to_string(), "flights = jump: arcs in a field cross the lattice cell by cell; use walk or auto");
    /// assert_eq!(e.presented(&flag), "--flights jump: arcs in a field cross the lattice cell by cell; use walk or auto");
    /// assert_eq!(e.presented(&|p| format!("{p}=")), "flights=jump: arcs in a field cross the lattice cell by cell; use walk or auto");
    /// ```
    pub fn presented(&self, name: &dyn Fn(&str) -> String) -> String {
        match self {
            Error::SceneParameter {
                scene,
                parameter,
                needs,
                range,
                missing,
            } => scene_parameter_text(scene, parameter, needs, range, *missing, name),
            Error::UnusedOption { analysis, option } => unused_option_text(analysis, *option, name),
            Error::OutOfRange {
                parameter,
                value,
                range,
            } => out_of_range_text(parameter, value, range, name),
            Error::Parameter {
                parameter,
                value,
                why,
            } => parameter_text(parameter, value, why, name),
            Error::TooMuchWork {
                estimate,
                lower,
                raise,
            } => too_much_work_text(estimate, lower, *raise, name),
            other => other.to_string(),
        }
    }

    /// Which kind of failure this is.
    pub fn kind(&self) -> ErrorKind {
        match self {
            Error::Io { .. } => ErrorKind::Io,
            Error::Failed(_) => ErrorKind::Failed,
            Error::CheckFailed(_) => ErrorKind::CheckFailed,
            Error::Incomplete(_) => ErrorKind::Incomplete,
            Error::Interrupted => ErrorKind::Interrupted,
            Error::NotFinite { .. }
            | Error::Trapped { .. }
            | Error::InfiniteHorizon { .. }
            | Error::Precision { .. }
            | Error::Zero { .. }
            | Error::TooFew { .. }
            | Error::OutOfRange { .. }
            | Error::Parameter { .. }
            | Error::NotANumber { .. }
            | Error::Malformed { .. }
            | Error::TooMuchWork { .. }
            | Error::Environment { .. }
            | Error::UnusedOption { .. }
            | Error::SceneParameter { .. }
            | Error::Table(_)
            | Error::OpenCorridor { .. }
            | Error::Lacks { .. }
            | Error::UnsafePath { .. }
            | Error::Invalid(_) => ErrorKind::BadInput,
        }
    }

    /// [`Error::OutOfRange`]: `parameter` (a configuration's field) given `value`, and the valid
    /// range as advice (`"use 1 to 20"`).
    pub fn out_of_range(
        parameter: &'static str,
        value: impl std::fmt::Display,
        range: impl Into<String>,
    ) -> Error {
        Error::OutOfRange {
            parameter,
            value: value.to_string(),
            range: range.into(),
        }
    }

    /// `Ok` where `value` of `parameter` lies in `range`, else [`Error::OutOfRange`] advising
    /// "use LO to HI" followed by `then` (a unit or a reason: `" bits"`, `""`): the one check of
    /// a parameter's bounds.
    ///
    /// # Errors
    /// As above.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::Error;
    /// assert!(Error::unless_in("segments", 3, 1..=8, "").is_ok());
    /// let e = Error::unless_in("bits", 4000, 64..=2048, " bits").unwrap_err();
    /// assert_eq!(e.to_string(), "bits = 4000 is out of range: use 64 to 2048 bits");
    /// ```
    pub fn unless_in<T: PartialOrd + std::fmt::Display>(
        parameter: &'static str,
        value: T,
        range: std::ops::RangeInclusive<T>,
        then: &str,
    ) -> Result<(), Error> {
        if range.contains(&value) {
            return Ok(());
        }
        let advice = format!("use {} to {}{then}", range.start(), range.end());
        Err(Error::out_of_range(parameter, value, advice))
    }

    /// [`Error::Parameter`]: `parameter` (a configuration's field) given `value`, and why it is
    /// not accepted here, as advice.
    pub fn parameter(
        parameter: &'static str,
        value: impl std::fmt::Display,
        why: impl Into<String>,
    ) -> Error {
        Error::Parameter {
            parameter,
            value: value.to_string(),
            why: why.into(),
        }
    }

    /// This error as a refusal of `parameter`: text that is not a number
    /// ([`Error::NotANumber`]) becomes [`Error::Parameter`] naming it; any other error is
    /// unchanged.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::Error;
    /// let e = lorentz_gas::numbers::exact::parse_exact("1/0").unwrap_err().named("field");
    /// assert_eq!(
    ///     e.presented(&|p| format!("{p}=")),
    ///     "field=1/0: '1/0' divides by zero: use a decimal such as 0.25 or a fraction such as 1/3"
    /// );
    /// ```
    pub fn named(self, parameter: &'static str) -> Error {
        match self {
            Error::NotANumber { ref text, .. } => Error::Parameter {
                parameter,
                value: text.clone(),
                why: self.to_string(),
            },
            other => other,
        }
    }

    /// [`Error::Parameter`] without a value: `parameter` is missing, and `why` it is needed.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::Error;
    /// let e = Error::missing("w_from", "a sweep over w needs both ends");
    /// assert_eq!(e.to_string(), "w_from is missing: a sweep over w needs both ends");
    /// let flag = |p: &str| format!("--{}", p.replace('_', "-"));
    /// assert_eq!(e.presented(&flag), "--w-from is missing: a sweep over w needs both ends");
    /// assert_eq!(e.presented(&|p| format!("{p}=")), "w_from is missing: a sweep over w needs both ends");
    /// ```
    pub fn missing(parameter: &'static str, why: impl Into<String>) -> Error {
        Error::parameter(parameter, "", why)
    }

    /// A result that could not be encoded as JSON (a run-time failure: results are plain data).
    pub fn encode(e: serde_json::Error) -> Error {
        Error::Failed(format!("cannot encode the result as JSON: {e}"))
    }

    /// [`Error::Malformed`]: a file whose contents are not what they should be (bad input
    /// naming the file).
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::{Error, ErrorKind};
    /// let e = Error::malformed("points/point-0003.json".as_ref(), "a damaged point file");
    /// assert_eq!(e.to_string(), "points/point-0003.json: a damaged point file");
    /// assert_eq!(e.kind(), ErrorKind::BadInput);
    /// ```
    pub fn malformed(path: &Path, why: impl std::fmt::Display) -> Error {
        Error::Malformed {
            path: path.to_path_buf(),
            why: why.to_string(),
        }
    }
}
