//! `lorentz shadow`: true orbits near f64 segments (Newton on the whole segment in MPFR).

use lorentz_gas::Error;
use lorentz_gas::scenes::motion::MotionInput;
use lorentz_gas::verification::shadowing::{self as shadowing, ShadowConfig};

use super::args::{
    ElectricArgs, OutputArgs, RunArgs, SceneArgs, SceneChoice, parse_count_u32, parse_count_usize,
    with_scene,
};
use super::output::emit;
use super::progress::Progress;

/// The gap of the triangular scene shadow takes.
const GAP_HELP: &str = "Gap w of the triangular scene, a decimal or a fraction such as 1/10: \
    0 < w < w_inf = 4/sqrt(3) - 2 = 0.3094...";

/// What `--electric` shadows here.
const ELECTRIC_HELP: &str = "A Gaussian-thermostatted electric field E in the plane (speed stays 1: dv/dt = E - \
    (E.v)v), its strength an exact decimal or fraction, 0 < |E| <= 10 (0: no field): segments of \
    thermostatted flights from equilibrium starts, shadowed by true thermostatted orbits.";

#[derive(clap::Args)]
#[command(mut_arg("w", |a| a.help(GAP_HELP)))]
#[command(mut_arg("electric", |a| a.help(ELECTRIC_HELP)))]
pub struct Args {
    #[command(flatten)]
    scene: SceneArgs,
    /// Collisions of each segment, 2 to 10000.
    #[arg(long, default_value = "1000", value_parser = parse_count_usize, allow_negative_numbers = true)]
    collisions_per_segment: usize,
    /// MPFR precision of the true orbit, in bits (128 or more); the residual is re-checked at
    /// twice this.
    #[arg(long, default_value = "128", value_parser = parse_count_u32, allow_negative_numbers = true)]
    reference_bits: u32,
    /// Segments (segment k starts from the equilibrium state of batch k of the seed), 1 to 10000.
    #[arg(long, default_value = "8", value_parser = parse_count_u32, allow_negative_numbers = true)]
    segments: u32,
    /// A uniform magnetic field B perpendicular to the plane, an exact decimal or fraction like
    /// --w (1e-3 <= |B| <= 1e3; 0 or absent: no field): segments on arcs from diffusing starts,
    /// shadowed by true orbits on arcs.
    #[arg(long, allow_hyphen_values = true, conflicts_with = "electric")]
    field: Option<String>,
    #[command(flatten)]
    electric: ElectricArgs,
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    output: OutputArgs,
}

/// The scene: the square one at any radius, the triangular one with its gap refused outside
/// (0, w_inf) with one line naming the range (decided on the exact text).
fn scene(a: &SceneArgs) -> Result<SceneChoice, Error> {
    if let Some(g) = &a.w {
        lorentz_gas::scenes::triangular::geometry::check_diffusive_gap_exact(
            g.value,
            g.exact.is_some().then_some(g.text.as_str()),
        )?;
    }
    a.resolve()
}

pub fn run(a: Args) -> Result<(), Error> {
    let scene = scene(&a.scene)?;
    // E = 0 is the run without a field, recorded as such (its bits are the straight run's).
    let motion = MotionInput {
        field: a.field.clone(),
        ..Default::default()
    };
    let motion = match a.electric.given() {
        Some((e, angle)) => motion.with_electric(e, angle),
        None => motion,
    };
    let request = ShadowConfig {
        collisions_per_segment: a.collisions_per_segment,
        segments: a.segments,
        seed: a.run.seed(),
        reference_bits: a.reference_bits,
        motion,
    };
    request.validate()?;
    let pb = Progress::new(
        a.collisions_per_segment as u64 * a.segments as u64,
        "collisions",
        a.output.quiet,
    );
    let opts = pb.options(a.run.threads());
    let r = with_scene!(&scene, |s| shadowing::run(s, &request, &opts))?;
    drop(opts);
    drop(pb);
    emit(a.output.json, &r, |r| {
        print!("{}", lorentz_gas::report::text::shadow::shadow(r));
    })
}
