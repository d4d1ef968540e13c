//! `lorentz sweep --w W --electric E1,E2,...`: the driven gas (the thermostatted electric field)
//! over E at one gap — the mobility J/E at every point, its polynomial χ² and Einstein
//! extrapolations, and J(−E) = −J(E) where both signs are given.

use lorentz_gas::Error;
use lorentz_gas::estimators::sweep::driven::{self, DrivenGrid, DrivenSweepReport};
use lorentz_gas::estimators::sweep::{Grid, SweepConfig};
use std::path::Path;

use super::GridArgs;
use crate::cli::output::emit;

/// A sweep of the driven gas.
#[derive(clap::Args)]
pub struct DrivenArgs {
    /// The fields E of a sweep of the driven gas at the gap --w (a Gaussian-thermostatted electric
    /// field; the speed stays 1): comma-separated exact decimals or fractions, 0 < |E| <= 10
    /// (with E and -E both given, J(-E) = -J(E) is checked), e.g. --electric=0.05,0.1,0.2.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        conflicts_with_all = ["field", "fields", "table", "radius"]
    )]
    pub(in crate::cli) electric: Vec<String>,
    /// With --electric: the fields' angle from the x axis in degrees, an exact decimal or
    /// fraction.
    #[arg(
        long,
        default_value = "0",
        allow_hyphen_values = true,
        requires = "electric"
    )]
    pub(in crate::cli) electric_angle: String,
}

impl DrivenArgs {
    /// `--electric` given.
    pub fn driven(&self) -> bool {
        !self.electric.is_empty()
    }
}

/// The driven sweep at the gap `w` of the fields `d`, with the run sizes of `g` and `seed`
/// (validated).
pub fn config(
    g: &GridArgs,
    w: Option<&str>,
    d: &DrivenArgs,
    seed: u64,
) -> Result<SweepConfig, Error> {
    const ONE_GAP: &str = "a driven sweep runs over E at one gap: give --w W --electric E1,E2,...";
    if let Some(runs) = g.runs {
        return Err(Error::parameter(
            "runs",
            runs,
            "not used by a driven sweep (one run of --collisions-per-run per point; its error \
             is over --batches-per-run)",
        ));
    }
    if let Some(end) = g.w_from.as_deref().or(g.w_to.as_deref()) {
        return Err(Error::parameter("w_from", end, ONE_GAP));
    }
    let Some(w) = w else {
        return Err(Error::missing("w", ONE_GAP));
    };
    let cfg = SweepConfig {
        grid: Grid::Driven(DrivenGrid {
            gaps: vec![w.trim().to_string()],
            electric: d.electric.iter().map(|e| e.trim().to_string()).collect(),
            electric_angle: d.electric_angle.trim().to_string(),
        }),
        collisions: g.collisions_per_run,
        batches: g.batches_per_run,
        seed,
    };
    cfg.validate()?;
    Ok(cfg)
}

/// Writes the tables and the figure of a finished driven sweep into `out`, prints it, and judges
/// J(−E) = −J(E) (a FAIL, exit 1, after everything is written).
pub fn finish(r: &DrivenSweepReport, out: &Path, json: bool) -> Result<(), Error> {
    driven::write_tables(r, out)?;
    lorentz_gas::report::figures::driven_sweep::write_driven_sweep_figures(r, out)?;
    emit(json, r, |r| {
        print!(
            "{}",
            lorentz_gas::report::text::driven_sweep::driven_sweep(r)
        );
        println!(
            "written: {}/driven-sweep.{{csv,json}}, driven-mobility (.png, .svg); points in {}/driven-points",
            out.display(),
            out.display()
        );
    })?;
    super::verdict(
        r.odd_agrees,
        "J(-E) = -J(E): the mobilities along E and -E are not consistent",
    )
}
