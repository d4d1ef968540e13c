//! Options shared by the subcommands (defined once, flattened into each command) and the value
//! parsers for counts and thread numbers.

use clap::Args;

use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::hops::HopsConfig;
use lorentz_gas::numbers::precision::Precision;
use lorentz_gas::scenes::spec::{Motion, SceneSpec, Table};

pub use lorentz_gas::numbers::count::{
    parse_count, parse_count_u32, parse_count_usize, parse_threads,
};

pub use lorentz_gas::numbers::exact::ExactInput as Exact;

/// Parses `--w` and `--radius`: a decimal (`0.1`, `1.5e-1`) or a fraction (`1/10`), exactly.
pub fn parse_exact_arg(s: &str) -> Result<Exact, String> {
    Exact::parse(s).map_err(|e| e.to_string())
}

/// A gap at which D exists, decided on the exact text typed (0 < w < w_inf), before any work.
pub fn parse_diffusive_gap(s: &str) -> Result<Exact, String> {
    let e = Exact::parse(s).map_err(|e| e.to_string())?;
    lorentz_gas::scenes::triangular::geometry::check_diffusive_gap_exact(
        e.value,
        e.exact.is_some().then_some(e.text.as_str()),
    )
    .map_err(|e| e.to_string())?;
    Ok(e)
}

/// The gap between neighbouring disks.
#[derive(Args, Debug, Clone)]
pub struct GapArg {
    /// Gap w between neighbouring disks (radius 1), a decimal or a fraction such as 1/10:
    /// 0 < w < w_inf = 4/sqrt(3) - 2 = 0.3094...
    #[arg(long = "w", value_name = "W", value_parser = parse_diffusive_gap, allow_hyphen_values = true)]
    pub gap: Exact,
}

impl GapArg {
    /// The triangular gas at the gap exactly as typed, without a field.
    pub fn table(&self) -> Table {
        table_at(&self.gap)
    }
}

/// The triangular gas at the gap `w` exactly as typed (already parsed: its text is a number),
/// without a field.
pub fn table_at(w: &Exact) -> Table {
    Table {
        scene: SceneSpec::Triangular { w: w.text.clone() },
        motion: Motion::Straight,
    }
}

/// The billiard table of a command that works on any scene (`audit`, `lyapunov`, `certify`).
#[derive(Args, Debug, Clone)]
pub struct SceneArgs {
    /// The scene: `triangular` (disks of radius 1 at spacing 2 + w, needs --w) or `square`
    /// (disks of radius r at unit spacing, needs --radius).
    #[arg(long, default_value = "triangular")]
    pub scene: SceneName,
    /// Gap w of the triangular scene, a decimal or a fraction such as 1/10: w > 0 (the horizon is
    /// finite below w_inf = 4/sqrt(3) - 2 = 0.3094..., infinite above).
    #[arg(long, value_parser = parse_exact_arg, allow_hyphen_values = true)]
    pub w: Option<Exact>,
    /// Disk radius of the square scene, a decimal or a fraction such as 1/3: 0 < r < 1/2.
    #[arg(long, value_parser = parse_exact_arg, allow_hyphen_values = true)]
    pub radius: Option<Exact>,
    /// Any periodic table of disks, from a TOML file: a `[lattice]` with e1 = (a, 0) and e2 =
    /// (b, h), h > 0, and `[[disks]]` each with a centre and a radius, every number exact text
    /// (examples/tables/). Instead of --scene, --w and --radius.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["scene", "w", "radius"])]
    pub table: Option<std::path::PathBuf>,
}

/// The scenes a command can run on.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum SceneName {
    /// The triangular Lorentz gas of the paper.
    Triangular,
    /// The square Lorentz gas (Sinai billiard).
    Square,
}

pub use lorentz_gas::scenes::spec::SceneChoice;
pub(crate) use lorentz_gas::with_scene;

impl SceneArgs {
    /// The scene the options describe ([`SceneSpec`]), the parameter kept exactly as typed.
    pub fn spec(&self) -> Result<SceneSpec, lorentz_gas::Error> {
        if let Some(path) = &self.table {
            let table = lorentz_gas::scenes::table::spec::TableSpec::read(path)?;
            return Ok(SceneSpec::Table(table));
        }
        let name = match self.scene {
            SceneName::Triangular => "triangular",
            SceneName::Square => "square",
        };
        let text = |e: &Option<Exact>| e.as_ref().map(|e| e.text.clone());
        SceneSpec::parse(
            name,
            text(&self.w).as_deref(),
            text(&self.radius).as_deref(),
        )
    }

    /// The scene the options describe, with every parameter checked. The scene keeps the gap or
    /// radius exactly as typed: an analysis at P bits rounds it once at P bits (`--w 0.1` at 256
    /// bits is 1/10 to 256 bits, not the double nearest 0.1).
    pub fn resolve(&self) -> Result<SceneChoice, lorentz_gas::Error> {
        self.spec()?.resolve()
    }
}

/// The measurement of hop statistics along lattice trajectories (`hops`, `theory`, `lattice-walk`).
#[derive(Args, Debug, Clone)]
pub struct HopArgs {
    /// Lorentz-gas collisions in all, over every batch (2e8, 2_000_000_000, ...).
    #[arg(long, default_value = "2e8", value_parser = parse_count, allow_negative_numbers = true)]
    pub collisions: u64,
    /// Independent batches (trajectories), at least 2; every error bar is over them.
    #[arg(long, default_value = "16", value_parser = parse_count_u32, allow_negative_numbers = true)]
    pub batches: u32,
    // The help of `hops`; `theory` and `lattice-walk` replace it with their own use of the order
    // (`ORDER_HELP` of each module, applied in `Cmd`).
    /// Longest symbol sequence counted (1 to 7).
    #[arg(long, default_value = "4", value_parser = parse_count_usize, allow_negative_numbers = true)]
    pub order: usize,
}

/// The whole command line of a hop analysis: gap, measurement, seed and threads, output.
#[derive(Args, Debug, Clone)]
pub struct HopCommand {
    #[command(flatten)]
    gap: GapArg,
    #[command(flatten)]
    hop: HopArgs,
    #[command(flatten)]
    resumable: ResumableArgs,
}

impl HopCommand {
    /// The configuration these options give.
    pub fn config(&self) -> HopsConfig {
        HopsConfig {
            table: self.gap.table(),
            collisions: self.hop.collisions,
            batches: self.hop.batches,
            order: self.hop.order,
            seed: self.resumable.run.seed(),
            run: 0,
        }
    }

    /// Runs `analysis` with a progress bar over the collisions and prints its result.
    pub fn run<R: serde::Serialize>(
        &self,
        engine: lorentz_gas::engine::Engine,
        analysis: impl FnOnce(&HopsConfig, &RunOptions) -> Result<R, lorentz_gas::Error>,
        print: impl FnOnce(&R),
    ) -> Result<(), lorentz_gas::Error> {
        let cfg = self.config();
        self.resumable.run(
            self.hop.collisions,
            "collisions",
            engine,
            |opts| analysis(&cfg, opts),
            print,
        )
    }
}

/// Seed and threads, checkpoint and output of a resumable analysis that reports one result.
#[derive(Args, Debug, Clone)]
pub struct ResumableArgs {
    #[command(flatten)]
    pub run: RunArgs,
    #[command(flatten)]
    pub checkpoint: CheckpointArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

impl ResumableArgs {
    /// Runs `analysis` on `engine` with a progress bar over `total` `unit`s, these threads and
    /// this checkpoint, then prints (or emits as JSON) its result.
    pub fn run<R: serde::Serialize>(
        &self,
        total: u64,
        unit: &str,
        engine: lorentz_gas::engine::Engine,
        analysis: impl FnOnce(&RunOptions) -> Result<R, lorentz_gas::Error>,
        print: impl FnOnce(&R),
    ) -> Result<(), lorentz_gas::Error> {
        let pb = super::progress::Progress::new(total, unit, self.output.quiet);
        let opts = self.checkpoint.apply(RunOptions {
            engine,
            ..pb.options(self.run.threads())
        });
        let r = analysis(&opts)?;
        drop(opts);
        drop(pb);
        super::output::emit(self.output.json, &r, print)
    }
}

/// The Gaussian-thermostatted electric field of a command that takes one (`diffusion`,
/// `lyapunov`, `bench`); each says what it measures there (`mut_arg("electric", ...)`).
#[derive(Args, Debug, Clone)]
pub struct ElectricArgs {
    /// A Gaussian-thermostatted electric field E in the plane (speed stays 1: dv/dt = E -
    /// (E.v)v), its strength an exact decimal or fraction, 0 < |E| <= 10; 0 is the run without a
    /// field.
    #[arg(long, allow_hyphen_values = true)]
    pub electric: Option<String>,
    /// With --electric: the field's angle from the x axis in degrees, an exact decimal or
    /// fraction.
    #[arg(
        long,
        default_value = "0",
        allow_hyphen_values = true,
        requires = "electric"
    )]
    pub electric_angle: String,
}

impl ElectricArgs {
    /// The thermostat these options give (`None` without `--electric`): strength and angle as
    /// typed.
    pub fn given(&self) -> Option<(&str, &str)> {
        (self.electric.as_deref()).map(|e| (e, self.electric_angle.as_str()))
    }
}

/// The seed of a stochastic computation.
#[derive(Args, Debug, Clone)]
pub struct SeedArg {
    /// Seed of the random streams (same seed, same bits, on any number of threads).
    #[arg(long, default_value = "1", value_parser = parse_count, allow_negative_numbers = true)]
    pub seed: u64,
}

/// The worker threads of a computation.
#[derive(Args, Debug, Clone)]
pub struct ThreadsArg {
    /// Worker threads, 1 to 4 per core (default: all cores); never changes the result.
    #[arg(long, value_parser = parse_threads, allow_negative_numbers = true)]
    pub threads: Option<usize>,
}

impl ThreadsArg {
    /// The requested thread count, or every core.
    pub fn threads(&self) -> usize {
        self.threads
            .unwrap_or_else(lorentz_gas::numbers::count::cores)
    }
}

/// Seed and threads of a stochastic computation.
#[derive(Args, Debug, Clone)]
pub struct RunArgs {
    #[command(flatten)]
    seed_arg: SeedArg,
    #[command(flatten)]
    threads_arg: ThreadsArg,
}

impl RunArgs {
    /// The seed.
    pub fn seed(&self) -> u64 {
        self.seed_arg.seed
    }
    /// The requested thread count, or every core.
    pub fn threads(&self) -> usize {
        self.threads_arg.threads()
    }
}

/// Where a resumable run keeps its work (`--checkpoint FILE`) and how often it saves the
/// trajectories in flight (`--checkpoint-every`), for every command that resumes.
#[derive(Args, Debug, Clone)]
pub struct CheckpointArgs {
    // `escape`, which saves finished particles rather than trajectories in flight, replaces this
    // help with its own (`escape::Args`).
    /// Keep the run's work in this file, saved as batches finish and every --checkpoint-every
    /// (the trajectories in flight); a rerun with the same parameters resumes to the same bits.
    #[arg(long)]
    pub checkpoint: Option<std::path::PathBuf>,
    #[command(flatten)]
    pub every: CheckpointEveryArg,
}

impl CheckpointArgs {
    /// Checks the checkpoint before any work ([`lorentz_gas::files::check_outputs`]): a regular
    /// file or nothing, and none of the command's `inputs` (a `--table` file).
    pub fn check(&self, inputs: &[&std::path::Path]) -> Result<(), lorentz_gas::Error> {
        let Some(p) = &self.checkpoint else {
            return Ok(());
        };
        let output = lorentz_gas::files::Output::File(p.clone());
        lorentz_gas::files::check_outputs(inputs, &[output])
    }

    /// `options` resuming from and saving to the checkpoint at its interval.
    pub fn apply<'a>(&self, options: RunOptions<'a>) -> RunOptions<'a> {
        if let Some(p) = &self.checkpoint {
            super::signals::keeping(p);
        }
        RunOptions {
            resume: self.checkpoint.clone(),
            checkpoint_every: self.every.checkpoint_every,
            ..options
        }
    }
}

/// How often a resumable run saves its trajectories in flight.
#[derive(Args, Debug, Clone)]
pub struct CheckpointEveryArg {
    // `sweep` (no --checkpoint: its work is in --out) and `escape` (finished particles) replace
    // this help with their own.
    /// With --checkpoint: save the whole state of every trajectory in flight every SECONDS of
    /// wall time (0 to 86400; a kill loses at most about this much work). Finished batches are
    /// saved as they finish.
    #[arg(long, value_name = "SECONDS", default_value = "60", value_parser = parse_interval, allow_negative_numbers = true)]
    pub checkpoint_every: std::time::Duration,
}

/// A checkpoint interval in seconds, 0 to a day.
fn parse_interval(text: &str) -> Result<std::time::Duration, String> {
    let max = lorentz_gas::engine::options::MAX_CHECKPOINT_EVERY.as_secs();
    let s: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number of seconds: use 0 to {max}"))?;
    if !(0.0..=max as f64).contains(&s) {
        return Err(format!("{s} s is out of range: use 0 to {max} seconds"));
    }
    Ok(std::time::Duration::from_secs_f64(s))
}

/// How straight flights cross the lattice (`lyapunov`, `superdiffusion`, `free-paths`; `audit`
/// says how each kind is replayed in its own words).
#[derive(Args, Debug, Clone)]
pub struct FlightsArg {
    /// How straight flights cross the lattice: jump (straight to the cell of the first disk they
    /// can meet; the square scene with 2^-32 <= radius <= 1/4, the triangular one with
    /// w_inf < w <= 2^20 - 2), walk (cell by cell, the reference), or auto (jump with
    /// 2^-32 <= radius <= 1/8 and w >= 6, where jumps are faster; walk elsewhere). Recorded in
    /// the result as `flights`.
    #[arg(long, default_value = "auto")]
    pub flights: lorentz_gas::engine::long_flight::Flights,
}

/// Engine choice.
#[derive(Args, Debug, Clone)]
pub struct EngineArg {
    /// Engine: auto (SIMD for f64, scalar for MPFR), scalar (one trajectory at a time), or simd
    /// (16 trajectories per core in vector lanes, f64). All give the same bits. The SIMD
    /// instructions are chosen at run time (AVX-512, AVX2 or portable; LORENTZ_SIMD forces one).
    #[arg(long, value_enum, default_value = "auto")]
    pub engine: lorentz_gas::engine::Engine,
}

/// The run's number type.
#[derive(Args, Debug, Clone)]
pub struct PrecisionArg {
    /// The run's number type: f64, or MPFR with this many bits (53 or more).
    #[arg(long, default_value = "f64")]
    pub precision: Precision,
}

/// The MPFR precision of a reference (the replay of an audit, a true orbit of a shadow), in bits.
#[derive(Args, Debug, Clone)]
pub struct ReferenceBitsArg {
    /// MPFR precision of the reference the f64 run is checked against, in bits (128 or more).
    #[arg(long, default_value = "128", value_parser = parse_count_u32, allow_negative_numbers = true)]
    pub reference_bits: u32,
}

/// How results are shown.
#[derive(Args, Debug, Clone)]
pub struct OutputArgs {
    /// Machine-readable output (JSON with a `meta` block) on stdout.
    #[arg(long)]
    pub json: bool,
    /// No progress on stderr (neither the bar on a terminal nor the lines printed to a file or pipe).
    #[arg(long)]
    pub quiet: bool,
}
