//! `lorentz constants`: every closed form at gap w, at any precision.

use serde_json::json;

use lorentz_gas::engine::metadata::RunMeta;
use lorentz_gas::numbers::precision::{AtPrecision, Precision};
use lorentz_gas::numbers::real::Real;
use lorentz_gas::scenes::triangular::geometry::Geometry;
use lorentz_gas::Error;

use super::args::{GapArg, PrecisionArg};
use super::output::to_json;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    gap: GapArg,
    #[command(flatten)]
    precision: PrecisionArg,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
}

pub fn run(a: Args) -> Result<(), Error> {
    let p: Precision = a.precision.precision;
    p.dispatch(Constants {
        w: a.gap.w,
        json: a.json,
        precision: p,
    })
}

struct Constants {
    w: f64,
    json: bool,
    precision: Precision,
}

impl AtPrecision for Constants {
    type Output = Result<(), Error>;
    fn at<T: Real>(self, ctx: T::Ctx) -> Result<(), Error> {
        let g = Geometry::new(T::from_f64(ctx, self.w))?;
        let rows: Vec<(&str, &str, T)> = vec![
            ("w", "gap", g.gap()),
            ("a", "lattice spacing 2 + w", g.spacing()),
            ("n", "number density 2/(sqrt3 a^2)", g.density()),
            (
                "w_inf",
                "horizon threshold 4/sqrt3 - 2",
                Geometry::<T>::w_inf(ctx),
            ),
            (
                "w_0",
                "collisionless-flight onset 2/sqrt3 - 1",
                Geometry::<T>::w_0(ctx),
            ),
            ("trap_area", "A = sqrt3 a^2/4 - pi/2", g.trap_area()),
            (
                "free_area_per_disk",
                "|Q| = 1/n - pi = 2A",
                g.free_area_per_disk(),
            ),
            ("boundary_per_disk", "|dQ| = 2 pi", g.boundary_per_disk()),
            (
                "mean_free_path",
                "Santalo pi|Q|/|dQ| = A",
                g.mean_free_path(),
            ),
            ("trap_distance", "l = a/sqrt3", g.trap_distance()),
            ("tau_hop", "tau = pi A/(3w)", g.hop_time()),
            ("collisions_per_hop", "pi/(3w)", g.collisions_per_hop()),
            ("D_MZ", "Machta-Zwanzig l^2/(4 tau)", g.d_mz()),
            ("D_Bo", "Boltzmann (3/16)(1/n - pi)", g.d_bo()),
        ];
        let horizon_finite = g.gap() < Geometry::<T>::w_inf(ctx);
        let lmax = g.max_free_path_bound();
        if self.json {
            let mut m = serde_json::Map::new();
            for (k, _, v) in &rows {
                m.insert((*k).into(), json!(v.to_decimal()));
            }
            m.insert(
                "max_free_path_bound".into(),
                json!(lmax.as_ref().map(|v| v.to_decimal())),
            );
            m.insert("finite_horizon".into(), json!(horizon_finite));
            m.insert("precision_bits".into(), json!(T::bits(ctx)));
            m.insert(
                "meta".into(),
                serde_json::to_value(RunMeta::new(None, None, self.precision, None))
                    .map_err(|e| Error::Io(e.to_string()))?,
            );
            println!("{}", to_json(&m)?);
        } else {
            for (k, d, v) in &rows {
                println!("{k:<20} {:<45} {d}", v.to_decimal());
            }
            match lmax {
                Some(l) => println!(
                    "{:<20} {:<45} proven bound on any free path: sqrt3 a below w_0, 12 a below w_inf",
                    "max_free_path_bound",
                    l.to_decimal()
                ),
                None => println!(
                    "w >= w_inf: infinite horizon, free paths are unbounded and D does not exist"
                ),
            }
        }
        Ok(())
    }
}
