//! Every closed form of the triangular gas at gap w, at any precision (`lorentz constants`):
//! the table the command line prints and the JSON it and the Python package return.

use std::collections::BTreeMap;

use serde::Serialize;
use serde_json::value::RawValue;

use crate::engine::metadata::RunMeta;
use crate::numbers::exact::check_exact;
use crate::numbers::precision::{AtPrecision, Precision};
use crate::numbers::real::Real;
use crate::scenes::triangular::geometry::Geometry;
use crate::Error;

/// The gap and the working precision.
#[derive(Debug, Clone, PartialEq)]
pub struct ConstantsConfig {
    /// The gap's nearest double.
    pub w: f64,
    /// The gap exactly as typed (a decimal or a fraction): every closed form starts from it at
    /// the working precision (`None`: from `w`).
    pub w_exact: Option<String>,
    /// The working precision.
    pub precision: Precision,
}

/// One closed form.
#[derive(Debug, Clone, PartialEq)]
pub struct Constant {
    /// Its key (`D_MZ`, `mean_free_path`, ...).
    pub name: &'static str,
    /// What it is, with its formula.
    pub formula: &'static str,
    /// Every digit of the working precision (a JSON number).
    pub digits: String,
    /// The digits the precision guarantees, ⌊(P − 1)·log₁₀ 2⌋ (for text).
    pub shown: String,
}

/// The closed forms at one gap and precision.
#[derive(Debug, Clone)]
pub struct ConstantsReport {
    /// The closed forms, in the command line's order.
    pub rows: Vec<Constant>,
    /// The gap exactly, as a reduced fraction (`"1/5"`).
    pub w_exact: Option<String>,
    /// The proven bound on any free path (`None` at infinite horizon).
    pub max_free_path_bound: Option<Constant>,
    /// Whether w < w_inf.
    pub finite_horizon: bool,
    /// The working precision in bits.
    pub precision_bits: u32,
    /// How it was computed.
    pub meta: RunMeta,
}

/// `constants --json`: every closed form by name, then the horizon bound and the metadata.
#[derive(Serialize)]
struct ConstantsJson<'a> {
    #[serde(flatten)]
    numbers: BTreeMap<&'static str, Box<RawValue>>,
    w_exact: &'a Option<String>,
    max_free_path_bound: Option<Box<RawValue>>,
    finite_horizon: bool,
    precision_bits: u32,
    meta: &'a RunMeta,
}

impl ConstantsReport {
    /// The JSON of `lorentz constants --json`: every number with all the digits of the
    /// working precision.
    pub fn to_json(&self) -> Result<String, Error> {
        let number = |c: &Constant| RawValue::from_string(c.digits.clone()).map_err(Error::encode);
        let mut numbers = BTreeMap::new();
        for c in &self.rows {
            numbers.insert(c.name, number(c)?);
        }
        let out = ConstantsJson {
            numbers,
            w_exact: &self.w_exact,
            max_free_path_bound: self.max_free_path_bound.as_ref().map(number).transpose()?,
            finite_horizon: self.finite_horizon,
            precision_bits: self.precision_bits,
            meta: &self.meta,
        };
        serde_json::to_string_pretty(&out).map_err(Error::encode)
    }
}

/// The closed forms at `cfg`'s gap and precision.
///
/// # Errors
/// A gap that is not a positive finite number, a `w_exact` that is not exact or not `w`.
///
/// # Examples
///
/// ```
/// use lorentz_gas::numbers::precision::Precision;
/// use lorentz_gas::theory::constants::{run, ConstantsConfig};
/// let cfg = ConstantsConfig { w: 0.2, w_exact: Some("1/5".into()), precision: Precision::F64 };
/// let r = run(&cfg).unwrap();
/// assert_eq!(r.w_exact.as_deref(), Some("1/5"));
/// assert!(r.finite_horizon);
/// ```
pub fn run(cfg: &ConstantsConfig) -> Result<ConstantsReport, Error> {
    check_exact("w", cfg.w, cfg.w_exact.as_deref())?;
    let exact = cfg
        .w_exact
        .as_deref()
        .map(crate::numbers::exact::parse_exact)
        .transpose()?;
    cfg.precision.dispatch(Table {
        w: cfg.w,
        exact,
        precision: cfg.precision,
    })
}

struct Table {
    w: f64,
    exact: Option<rug::Rational>,
    precision: Precision,
}

impl AtPrecision for Table {
    type Output = Result<ConstantsReport, Error>;
    fn at<T: Real>(self, ctx: T::Ctx) -> Result<ConstantsReport, Error> {
        let w = match &self.exact {
            Some(q) => T::from_rational(ctx, q),
            None => T::from_f64(ctx, self.w),
        };
        let g = Geometry::new(w)?;
        let bits = T::bits(ctx);
        let row = |name: &'static str, formula: &'static str, v: T| Constant {
            name,
            formula,
            digits: v.to_decimal(),
            shown: significant(&v, bits),
        };
        let rows = vec![
            row("w", "gap", g.gap()),
            row("a", "lattice spacing 2 + w", g.spacing()),
            row("n", "number density 2/(sqrt3 a^2)", g.density()),
            row(
                "w_inf",
                "horizon threshold 4/sqrt3 - 2",
                Geometry::<T>::w_inf(ctx),
            ),
            row(
                "w_0",
                "collisionless-flight onset 2/sqrt3 - 1",
                Geometry::<T>::w_0(ctx),
            ),
            row("trap_area", "A = sqrt3 a^2/4 - pi/2", g.trap_area()),
            row(
                "free_area_per_disk",
                "|Q| = 1/n - pi = 2A",
                g.free_area_per_disk(),
            ),
            row("boundary_per_disk", "|dQ| = 2 pi", g.boundary_per_disk()),
            row(
                "mean_free_path",
                "Santalo pi|Q|/|dQ| = A",
                g.mean_free_path(),
            ),
            row("trap_distance", "l = a/sqrt3", g.trap_distance()),
            row("tau_hop", "tau = pi A/(3w)", g.hop_time()),
            row("collisions_per_hop", "pi/(3w)", g.collisions_per_hop()),
            row("D_MZ", "Machta-Zwanzig l^2/(4 tau)", g.d_mz()),
            row("D_Bo", "Boltzmann (3/16)(1/n - pi)", g.d_bo()),
        ];
        let finite_horizon = g.gap() < Geometry::<T>::w_inf(ctx);
        let bound = g.max_free_path_bound().map(|l| {
            row(
                "max_free_path_bound",
                "proven bound on any free path: sqrt3 a below w_0, 12 a below w_inf",
                l,
            )
        });
        Ok(ConstantsReport {
            rows,
            w_exact: self.exact.as_ref().map(|q| q.to_string()),
            max_free_path_bound: bound,
            finite_horizon,
            precision_bits: bits,
            meta: RunMeta::new(None, None, self.precision, None),
        })
    }
}

/// `v` to the decimal digits that `bits` bits guarantee, ⌊(bits − 1)·log₁₀ 2⌋: a value within
/// half an ulp of the exact one rounds to these digits up to one unit in the last (so the gap 0.2
/// at 200 bits shows as 2.000…0e-1, not the binary number's 2.000…03e-1 of the round-trip form).
fn significant<T: Real>(v: &T, bits: u32) -> String {
    let digits = ((bits - 1) as f64 * std::f64::consts::LOG10_2).floor() as usize;
    v.to_mpfr(bits).to_string_radix(10, Some(digits.max(1)))
}
