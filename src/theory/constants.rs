//! Every closed form of a scene at any precision (`lorentz constants`): the triangular gas at
//! gap w, or the square lattice at radius r, with the corridors and the superdiffusion
//! constants of an infinite horizon ([`crate::theory::corridors`]); the table the command line
//! prints and the JSON it and the Python package return.

use std::collections::BTreeMap;

use serde::Serialize;
use serde_json::value::RawValue;

use crate::Capability;
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::numbers::exact::{ExactInput, parse_exact};
use crate::numbers::precision::{AtPrecision, Precision};
use crate::numbers::real::Real;
use crate::scenes::spec::SceneSpec;
use crate::scenes::triangular::geometry::Geometry;
use crate::theory::corridors::{self, CorridorJson, LatticeGas, Superdiffusion};
use rug::Rational;

/// The scene and the working precision.
#[derive(Debug, Clone, PartialEq)]
pub struct ConstantsConfig {
    /// The triangular gas at a gap (any w > 0: beyond w_inf the corridors are listed), or the
    /// square lattice at a radius, each exactly as typed: every closed form starts from it at
    /// the working precision.
    pub scene: SceneSpec,
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
    /// The gap exactly, as a reduced fraction (`"1/5"`; `None` for the square scene).
    pub w_exact: Option<String>,
    /// The radius exactly, as a reduced fraction (the square scene).
    pub radius_exact: Option<String>,
    /// The corridors and the superdiffusion constants (`None` at a finite horizon).
    pub superdiffusion: Option<SuperdiffusionRows>,
    /// The proven bound on any free path (`None` at infinite horizon).
    pub max_free_path_bound: Option<Constant>,
    /// Whether w < w_inf.
    pub finite_horizon: bool,
    /// The working precision in bits.
    pub precision_bits: u32,
    /// How it was computed.
    pub meta: RunMeta,
}

/// The superdiffusive regime of an infinite horizon: its constants as rows and its corridors.
#[derive(Debug, Clone)]
pub struct SuperdiffusionRows {
    /// C_flow, C_map, D_sup, the t ln t coefficients.
    pub rows: Vec<Constant>,
    /// Every corridor.
    pub corridors: Vec<CorridorJson>,
}

/// `constants --json`: every closed form by name, then the horizon bound and the metadata.
#[derive(Serialize)]
struct ConstantsJson<'a> {
    #[serde(flatten)]
    numbers: BTreeMap<&'static str, Box<RawValue>>,
    /// Omitted for the square scene; null for a gap not typed exactly.
    #[serde(skip_serializing_if = "Option::is_none")]
    w_exact: Option<Option<&'a String>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    radius_exact: Option<&'a String>,
    superdiffusion: Option<SuperdiffusionJson<'a>>,
    max_free_path_bound: Option<Box<RawValue>>,
    finite_horizon: bool,
    precision_bits: u32,
    meta: &'a RunMeta,
}

/// The superdiffusion block of the JSON.
#[derive(Serialize)]
struct SuperdiffusionJson<'a> {
    #[serde(flatten)]
    numbers: BTreeMap<&'static str, Box<RawValue>>,
    corridors: &'a [CorridorJson],
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
        let superdiffusion = match &self.superdiffusion {
            Some(sd) => {
                let mut numbers = BTreeMap::new();
                for c in &sd.rows {
                    numbers.insert(c.name, number(c)?);
                }
                Some(SuperdiffusionJson {
                    numbers,
                    corridors: &sd.corridors,
                })
            }
            None => None,
        };
        let out = ConstantsJson {
            numbers,
            w_exact: if self.radius_exact.is_some() {
                None
            } else {
                Some(self.w_exact.as_ref())
            },
            radius_exact: self.radius_exact.as_ref(),
            superdiffusion,
            max_free_path_bound: self.max_free_path_bound.as_ref().map(number).transpose()?,
            finite_horizon: self.finite_horizon,
            precision_bits: self.precision_bits,
            meta: &self.meta,
        };
        serde_json::to_string_pretty(&out).map_err(Error::encode)
    }
}

/// The closed forms of `cfg`'s scene at its precision.
///
/// # Errors
/// A gap or radius that is not a number or out of range.
///
/// # Examples
///
/// ```
/// use lorentz_gas::numbers::precision::Precision;
/// use lorentz_gas::scenes::spec::SceneSpec;
/// use lorentz_gas::theory::constants::{run, ConstantsConfig};
/// let scene = SceneSpec::Triangular { w: "0.2".into() };
/// let r = run(&ConstantsConfig { scene, precision: Precision::F64 }).unwrap();
/// assert_eq!(r.w_exact.as_deref(), Some("1/5"));
/// assert!(r.finite_horizon && r.superdiffusion.is_none());
/// let scene = SceneSpec::Square { radius: "1/4".into() };
/// let r = run(&ConstantsConfig { scene, precision: Precision::F64 }).unwrap();
/// assert_eq!(r.superdiffusion.unwrap().corridors.len(), 4);
/// ```
pub fn run(cfg: &ConstantsConfig) -> Result<ConstantsReport, Error> {
    let table = match &cfg.scene {
        SceneSpec::Triangular { w } => Table::Triangular {
            w: (ExactInput::parse(w).map_err(|e| e.named("w"))?).rational("w")?,
        },
        SceneSpec::Square { radius } => Table::Square {
            r: parse_exact(radius).map_err(|e| e.named("radius"))?,
        },
        SceneSpec::Table(t) => {
            return Err(Error::Lacks {
                scene: t.title().to_string(),
                capability: Capability::ClosedForms,
                analysis: "constants",
            });
        }
        SceneSpec::Open(t) => {
            return Err(Error::Lacks {
                scene: t.title(),
                capability: Capability::Lattice,
                analysis: "constants",
            });
        }
    };
    cfg.precision.dispatch(Tabulate {
        table,
        precision: cfg.precision,
    })
}

/// A scene, its parameter exact.
enum Table {
    Triangular { w: Rational },
    Square { r: Rational },
}

struct Tabulate {
    table: Table,
    precision: Precision,
}

/// A row maker at `bits` bits.
fn row<T: Real>(bits: u32) -> impl Fn(&'static str, &'static str, T) -> Constant {
    move |name, formula, v: T| Constant {
        name,
        formula,
        digits: v.to_decimal(),
        shown: significant(&v, bits),
    }
}

impl AtPrecision for Tabulate {
    type Output = Result<ConstantsReport, Error>;
    fn at<T: Real>(self, ctx: T::Ctx) -> Result<ConstantsReport, Error> {
        let bits = T::bits(ctx);
        let meta = RunMeta::new(None, None, self.precision, None);
        match self.table {
            Table::Triangular { w } => triangular::<T>(ctx, w, meta),
            Table::Square { r } => {
                let gas = LatticeGas::Square { r: r.clone() };
                let sd = corridors::superdiffusion::<T>(ctx, &gas)?;
                let row = row::<T>(bits);
                let radius = T::from_rational(ctx, &r);
                let ell = T::pi(ctx) * &sd.free_area / &sd.boundary;
                let rows = vec![
                    row("radius", "disk radius r (lattice spacing 1)", radius),
                    row(
                        "free_area_per_disk",
                        "|Q| = 1 - pi r^2",
                        sd.free_area.clone(),
                    ),
                    row("boundary_per_disk", "|dQ| = 2 pi r", sd.boundary.clone()),
                    row("mean_free_path", "Santalo pi|Q|/|dQ|", ell),
                ];
                Ok(ConstantsReport {
                    rows,
                    w_exact: None,
                    radius_exact: Some(r.to_string()),
                    superdiffusion: Some(superdiffusion_rows(&sd, bits)),
                    max_free_path_bound: None,
                    finite_horizon: false,
                    precision_bits: bits,
                    meta,
                })
            }
        }
    }
}

/// The superdiffusion constants as rows, and the corridors.
fn superdiffusion_rows<T: Real>(sd: &Superdiffusion<T>, bits: u32) -> SuperdiffusionRows {
    let row = row::<T>(bits);
    SuperdiffusionRows {
        rows: vec![
            row(
                "C_flow",
                "flow tail P(tau > s) ~ C_flow/s, sum |v| W^2/(pi|Q|)",
                sd.c_flow.clone(),
            ),
            row(
                "C_map",
                "map tail mu(tau > s) ~ C_map/s^2, sum |v| W^2/|dQ|",
                sd.c_map.clone(),
            ),
            row(
                "D_sup",
                "dx/sqrt(t ln t) -> N(0, D_sup); t C_xx(t) -> D_sup",
                sd.d_sup_xx.clone(),
            ),
            row(
                "msd_x_t_ln_t",
                "<dx^2> ~ 2 D_sup t ln t",
                sd.msd_x_coefficient(),
            ),
            row(
                "msd_r_t_ln_t",
                "<|dr|^2> ~ 2 C_flow t ln t",
                sd.msd_r_coefficient(),
            ),
        ],
        corridors: sd.corridors.iter().map(|c| c.to_json()).collect(),
    }
}

/// The triangular gas's closed forms at the exact gap `exact`.
fn triangular<T: Real>(
    ctx: T::Ctx,
    exact: Rational,
    meta: RunMeta,
) -> Result<ConstantsReport, Error> {
    let w = T::from_rational(ctx, &exact);
    let g = Geometry::new(w)?;
    let bits = T::bits(ctx);
    let row = row::<T>(bits);
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
    let superdiffusion = if finite_horizon {
        None
    } else {
        let gas = LatticeGas::Triangular { w: exact.clone() };
        let sd = corridors::superdiffusion::<T>(ctx, &gas)?;
        Some(superdiffusion_rows(&sd, bits))
    };
    Ok(ConstantsReport {
        rows,
        w_exact: Some(exact.to_string()),
        radius_exact: None,
        superdiffusion,
        max_free_path_bound: bound,
        finite_horizon,
        precision_bits: bits,
        meta,
    })
}

/// `v` to the decimal digits that `bits` bits guarantee, ⌊(bits − 1)·log₁₀ 2⌋: a value within
/// half an ulp of the exact one rounds to these digits up to one unit in the last (so the gap 0.2
/// at 200 bits shows as 2.000…0e-1, not the binary number's 2.000…03e-1 of the round-trip form).
fn significant<T: Real>(v: &T, bits: u32) -> String {
    let digits = ((bits - 1) as f64 * std::f64::consts::LOG10_2).floor() as usize;
    v.to_mpfr(bits).to_string_radix(10, Some(digits.max(1)))
}
