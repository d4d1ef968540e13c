//! `lorentz constants`: every closed form at gap w, at any precision.

use std::collections::BTreeMap;

use serde::Serialize;
use serde_json::value::RawValue;

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
        w: a.gap.w(),
        exact: a.gap.gap.exact.clone(),
        json: a.json,
        precision: p,
    })
}

/// `constants --json`: every closed form by name, then the horizon bound and the metadata.
#[derive(Serialize)]
struct ConstantsJson {
    #[serde(flatten)]
    numbers: BTreeMap<&'static str, Box<RawValue>>,
    /// The gap exactly, as a reduced fraction (`"1/5"`); `w` is it at the working precision.
    w_exact: Option<String>,
    /// Proven bound on any free path (null at infinite horizon).
    max_free_path_bound: Option<Box<RawValue>>,
    finite_horizon: bool,
    precision_bits: u32,
    meta: RunMeta,
}

struct Constants {
    w: f64,
    /// The gap exactly as typed: every closed form starts from it at the working precision.
    exact: Option<rug::Rational>,
    json: bool,
    precision: Precision,
}

impl AtPrecision for Constants {
    type Output = Result<(), Error>;
    fn at<T: Real>(self, ctx: T::Ctx) -> Result<(), Error> {
        let w = match &self.exact {
            Some(q) => T::from_rational(ctx, q),
            None => T::from_f64(ctx, self.w),
        };
        let g = Geometry::new(w)?;
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
            // Every number as a JSON number with all the digits of the working precision.
            let number = |v: &T| -> Result<Box<RawValue>, Error> {
                RawValue::from_string(v.to_decimal()).map_err(Error::encode)
            };
            let mut numbers = BTreeMap::new();
            for (k, _, v) in &rows {
                numbers.insert(*k, number(v)?);
            }
            let out = ConstantsJson {
                numbers,
                w_exact: self.exact.as_ref().map(|q| q.to_string()),
                max_free_path_bound: lmax.as_ref().map(number).transpose()?,
                finite_horizon: horizon_finite,
                precision_bits: T::bits(ctx),
                meta: RunMeta::new(None, None, self.precision, None),
            };
            println!("{}", to_json(&out)?);
        } else {
            // Text shows the digits the working precision guarantees; JSON carries every digit.
            let shown = |v: &T| significant(v, T::bits(ctx));
            if let Some(q) = &self.exact {
                println!(
                    "{:<20} {:<45} gap as typed, exactly",
                    "w_exact",
                    q.to_string()
                );
            }
            for (k, d, v) in &rows {
                println!("{k:<20} {:<45} {d}", shown(v));
            }
            match lmax {
                Some(l) => println!(
                    "{:<20} {:<45} proven bound on any free path: sqrt3 a below w_0, 12 a below w_inf",
                    "max_free_path_bound",
                    shown(&l)
                ),
                None => println!(
                    "w >= w_inf: infinite horizon, free paths are unbounded and D does not exist"
                ),
            }
        }
        Ok(())
    }
}

/// `v` to the decimal digits that `bits` bits guarantee, ⌊(bits − 1)·log₁₀ 2⌋: a value within
/// half an ulp of the exact one rounds to these digits up to one unit in the last (so the gap 0.2
/// at 200 bits shows as 2.000…0e-1, not the binary number's 2.000…03e-1 of the round-trip form).
fn significant<T: Real>(v: &T, bits: u32) -> String {
    let digits = ((bits - 1) as f64 * std::f64::consts::LOG10_2).floor() as usize;
    v.to_mpfr(bits).to_string_radix(10, Some(digits.max(1)))
}
