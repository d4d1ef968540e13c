//! `lorentz trajectory`: one trajectory from exact initial conditions to certified digits.

use std::io::Write;
use std::path::{Path, PathBuf};

use rug::Rational;

use lorentz_gas::Error;
use lorentz_gas::estimators::trajectory::{
    self, MAX_DIGITS, TrajectoryInput, TrajectoryReport, plan,
};
use lorentz_gas::files::Output;
use lorentz_gas::numbers::exact::parse_exact;
use lorentz_gas::scenes::spec::SceneSpec;
use lorentz_gas::with_scene;

use super::args::{Exact, OutputArgs, SceneName, parse_count_u32, parse_exact_arg};
use super::output::emit;
use super::progress::Progress;

/// Estimated seconds above which a progress bar is shown.
const PROGRESS_SECONDS: f64 = 2.0;

#[derive(clap::Args)]
pub struct Args {
    /// The scene: `square` (disks of radius r at every integer point, needs --radius) or
    /// `triangular` (disks of radius 1 at spacing 2 + w, needs --w).
    #[arg(long)]
    scene: SceneName,
    /// Disk radius of the square scene, a decimal or a fraction such as 1/3: 0 < radius < 1/2.
    #[arg(long, value_parser = parse_exact_arg, allow_hyphen_values = true)]
    radius: Option<Exact>,
    /// Gap of the triangular scene, a decimal or a fraction such as 1/10: w > 0.
    #[arg(long, value_parser = parse_exact_arg, allow_hyphen_values = true)]
    w: Option<Exact>,
    /// Start x,y in world coordinates, exact (such as 0.5,0.1 or 1/2,1/10); outside every disk.
    #[arg(long, allow_hyphen_values = true)]
    start: String,
    /// Direction dx,dy, exact and nonzero (normalised at the working precision).
    #[arg(long, allow_hyphen_values = true)]
    direction: String,
    /// Total time T > 0 (speed 1), exact.
    #[arg(long, allow_hyphen_values = true)]
    time: String,
    /// Digits to certify, 1 to 10000.
    #[arg(long, default_value = "30", value_parser = parse_count_u32, allow_negative_numbers = true)]
    digits: u32,
    /// A uniform magnetic field B, exact (such as 1 or -1/3): flights are arcs turning
    /// counter-clockwise for B > 0 on circles of radius 1/|B|; 0 (the default) is straight.
    /// 1e-6 <= |B| <= 1e6.
    #[arg(long, value_parser = parse_exact_arg, allow_hyphen_values = true, conflicts_with = "electric")]
    field: Option<Exact>,
    /// A Gaussian-thermostatted electric field E in the plane (speed stays 1: dv/dt = E -
    /// (E.v)v), its strength exact, |E| <= 10: flights of the thermostat's kernel with certified
    /// events at every precision; 0 is the straight run.
    #[arg(long, value_parser = parse_exact_arg, allow_hyphen_values = true)]
    electric: Option<Exact>,
    /// With --electric: the field's angle from the x axis in degrees, an exact decimal or
    /// fraction.
    #[arg(
        long,
        default_value = "0",
        value_parser = parse_exact_arg,
        allow_hyphen_values = true,
        requires = "electric"
    )]
    electric_angle: Exact,
    /// Write every event of the final run (kind, obstacle, world x, world y, time, the world
    /// velocity vx, vy after it, and in a field the centre centre_x, centre_y of the arc that
    /// follows it, radius 1/|B|) to this CSV.
    #[arg(long)]
    events: Option<PathBuf>,
    #[command(flatten)]
    output: OutputArgs,
}

/// A pair `x,y` of exact numbers.
fn parse_pair(parameter: &'static str, s: &str) -> Result<(Rational, Rational), Error> {
    let bad = || {
        Error::parameter(
            parameter,
            format!("'{s}'"),
            "not a pair: use two exact numbers separated by a comma, such as 0.5,0.1 or 1/2,1/10",
        )
    };
    let (a, b) = s.split_once(',').ok_or_else(bad)?;
    if b.contains(',') {
        return Err(bad());
    }
    let number = |t: &str| parse_exact(t).map_err(|e| e.named(parameter));
    Ok((number(a)?, number(b)?))
}

pub fn run(a: Args) -> Result<(), Error> {
    if a.digits == 0 || a.digits > MAX_DIGITS {
        return Err(Error::out_of_range(
            "digits",
            a.digits,
            format!("use 1 to {MAX_DIGITS}"),
        ));
    }
    let (x, y) = parse_pair("start", &a.start)?;
    let (dx, dy) = parse_pair("direction", &a.direction)?;
    let input = TrajectoryInput {
        x,
        y,
        dx,
        dy,
        time: parse_exact(&a.time).map_err(|e| e.named("time"))?,
        digits: a.digits,
        record_events: a.events.is_some(),
        field: (a.field.as_ref())
            .map(|b| parse_exact(&b.text).map_err(|e| e.named("field")))
            .transpose()?,
        electric: (a.electric.as_ref())
            .map(|e| -> Result<_, Error> {
                let strength = parse_exact(&e.text).map_err(|e| e.named("electric"))?;
                let angle =
                    parse_exact(&a.electric_angle.text).map_err(|e| e.named("electric_angle"))?;
                Ok((strength, angle))
            })
            .transpose()?,
    };
    let name = match a.scene {
        SceneName::Triangular => "triangular",
        SceneName::Square => "square",
    };
    let text = |e: &Option<Exact>| e.as_ref().map(|e| e.text.clone());
    let spec = SceneSpec::parse(name, text(&a.w).as_deref(), text(&a.radius).as_deref())?;
    let choice = spec.resolve()?;
    // The events file is checked with the request, before the run, and written only after it
    // (see `write_events`).
    if let Some(path) = &a.events {
        lorentz_gas::files::check_outputs(&[], &[Output::File(path.clone())])?;
    }
    let report = with_scene!(&choice, |s| run_scene(s, &input, &a))?;
    emit(a.output.json, &report, |r| {
        print!(
            "{}",
            lorentz_gas::report::text::trajectory::trajectory(r, &a.time)
        );
    })
}

fn run_scene<S: lorentz_gas::scenes::Scene>(
    scene: &S,
    input: &TrajectoryInput,
    a: &Args,
) -> Result<TrajectoryReport, Error> {
    let p = plan(scene, input)?;
    let quiet = a.output.quiet || p.estimated_seconds < PROGRESS_SECONDS;
    // Two runs (P and 2P) when the first precision suffices.
    let pb = Progress::new(
        (2.0 * p.expected_collisions).ceil() as u64,
        "collisions",
        quiet,
    );
    let opts = pb.options(1);
    let report = trajectory::run(scene, input, &opts)?;
    if let Some(path) = &a.events {
        write_events(path, &report)?;
    }
    Ok(report)
}

/// Writes the events of `r` to `path` through a temporary file renamed over it once complete
/// (a failed write leaves what was at `path` as it was).
fn write_events(path: &Path, r: &TrajectoryReport) -> Result<(), Error> {
    let mut out = lorentz_gas::files::Stream::create(path)?;
    let write = |out: &mut lorentz_gas::files::Stream| -> std::io::Result<()> {
        // In a field each event also gives the centre of the arc that follows it.
        let field = r.events.iter().any(|e| e.centre.is_some());
        let extra = if field { ",centre_x,centre_y" } else { "" };
        writeln!(out, "kind,obstacle,x,y,time,vx,vy{extra}")?;
        for e in &r.events {
            let (k, o) = (e.kind, e.obstacle);
            write!(out, "{k},{o},{},{},{},{},{}", e.x, e.y, e.time, e.vx, e.vy)?;
            match &e.centre {
                Some((cx, cy)) => writeln!(out, ",{cx},{cy}")?,
                None => writeln!(out)?,
            }
        }
        Ok(())
    };
    write(&mut out).map_err(Error::io("write", path))?;
    out.commit()
}
