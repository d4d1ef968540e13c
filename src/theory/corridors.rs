//! The corridors of an infinite-horizon lattice Lorentz gas and the constants of its
//! superdiffusion, exactly (`proofs-notes/corridors.md` derives every factor).
//!
//! A corridor is a free strip between two neighbouring rows of disks: for a primitive lattice
//! vector v the lattice points lie on parallel lines in direction v, spaced d = A/|v| (A the
//! area of the unit cell), and disks of radius r leave strips of width W = d − 2r free when
//! d > 2r. Existence is decided exactly (a comparison of rationals: d² > 4r² ⇔ A² > 4r²|v|²),
//! so the list is complete for the given radius; widths and constants are computed at the
//! working precision. With |Q| = A − πr² the free area and |∂Q| = 2πr the boundary per cell
//! (one disk per cell), the sums S = Σ_v |v|W_v² (over unoriented directions) give
//!
//! * the free-flight tail under the flow, P(τ > s) ≈ C_flow/s, C_flow = S/(π|Q|);
//! * under the billiard map, μ(τ > s) ≈ C_map/s², C_map = S/|∂Q| (= ℓ·C_flow, ℓ = π|Q|/|∂Q|);
//! * the limit law Δr/√(t ln t) → N(0, Σ) with Σ = Σ_v |v|W_v² u_v u_vᵀ/(π|Q|) (u_v = v/|v|);
//!   `D_sup` is Σ_xx, the variance of Δx/√(t ln t);
//! * the velocity autocorrelation t·C_xx(t) → Σ_xx, and so ⟨Δx²⟩ ≈ 2Σ_xx·t ln t and
//!   ⟨|Δr|²⟩ ≈ 2C_flow·t ln t: the mean squared displacement is twice the limit law's variance.

use rug::{Integer, Rational};
use serde::{Deserialize, Serialize};

use crate::Error;
use crate::numbers::exact::parse_exact;
use crate::numbers::real::Real;
use crate::scenes::spec::SceneSpec;

/// A lattice of disks, one per cell, given exactly.
#[derive(Debug, Clone, PartialEq)]
pub enum LatticeGas {
    /// Disks of radius `r` (0 < r < 1/2) at the integer points of the plane.
    Square {
        /// The radius.
        r: Rational,
    },
    /// Disks of radius 1 at the points of the triangular lattice of spacing 2 + w (w > 0).
    Triangular {
        /// The gap.
        w: Rational,
    },
}

/// One corridor: its direction, the lattice period along it, its width, at the working precision.
#[derive(Debug, Clone, PartialEq)]
pub struct Corridor<T> {
    /// The primitive lattice vector (m, n) = m e₁ + n e₂ (one of ±v).
    pub direction: [i64; 2],
    /// |v|²/s², an integer: p² + q² (square), m² + mn + n² (triangular), s the lattice spacing.
    pub norm2: i64,
    /// The unit vector u = v/|v| in world coordinates.
    pub unit: [T; 2],
    /// |v|: the distance between consecutive disks along each wall.
    pub period: T,
    /// W = A/|v| − 2r: the width of the free strip.
    pub width: T,
}

/// A corridor as the JSON of `lorentz constants` and `lorentz superdiffusion` shows it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CorridorJson {
    /// The primitive lattice vector (m, n).
    pub direction: [i64; 2],
    /// The angle of the corridor to the x axis, in degrees, in [0, 180).
    pub angle_degrees: f64,
    /// The lattice period along it.
    pub period: f64,
    /// Its width.
    pub width: f64,
}

/// The constants of the superdiffusive regime at the working precision.
#[derive(Debug, Clone, PartialEq)]
pub struct Superdiffusion<T> {
    /// Every corridor, by increasing |v| (then direction).
    pub corridors: Vec<Corridor<T>>,
    /// |Q|: the free area per cell.
    pub free_area: T,
    /// |∂Q|: the boundary length per cell.
    pub boundary: T,
    /// P(τ > s) ≈ C_flow/s under the flow (τ the time to the next collision).
    pub c_flow: T,
    /// μ(τ > s) ≈ C_map/s² under the billiard map (τ the free path after a collision).
    pub c_map: T,
    /// Σ_xx: Δx/√(t ln t) → N(0, Σ_xx); also lim t·⟨v_x(0)v_x(t)⟩.
    pub d_sup_xx: T,
    /// Σ_yy.
    pub d_sup_yy: T,
    /// Σ_xy.
    pub d_sup_xy: T,
}

impl<T: Real> Superdiffusion<T> {
    /// The coefficient of t ln t in ⟨Δx²⟩: 2Σ_xx.
    pub fn msd_x_coefficient(&self) -> T {
        self.d_sup_xx.clone().scale(2.0)
    }
    /// The coefficient of t ln t in ⟨|Δr|²⟩: 2C_flow = 2(Σ_xx + Σ_yy).
    pub fn msd_r_coefficient(&self) -> T {
        self.c_flow.clone().scale(2.0)
    }
    /// Whether the horizon is infinite (some corridor exists).
    pub fn infinite_horizon(&self) -> bool {
        !self.corridors.is_empty()
    }
}

/// Most corridors enumerated: beyond this the radius is so small that the list (about
/// 0.24/r² directions on the square lattice) stops being useful.
pub const MAX_CORRIDORS: usize = 1 << 20;

/// Largest |v|²/s² searched: 2²⁰ (square lattice: radius ≥ 1/2048; triangular: w ≤ 2362),
/// about a million directions at most, enumerated in well under a second.
pub const MAX_NORM2: i64 = 1 << 20;

impl LatticeGas {
    /// The lattice of a scene description ([`SceneSpec`]), its parameter exact as typed and
    /// checked.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::scenes::spec::SceneSpec;
    /// use lorentz_gas::theory::corridors::LatticeGas;
    /// let gas = LatticeGas::of(&SceneSpec::Square { radius: "1/4".into() }).unwrap();
    /// assert_eq!(gas, LatticeGas::Square { r: rug::Rational::from((1, 4)) });
    /// assert!(LatticeGas::of(&SceneSpec::Square { radius: "1/2".into() }).is_err());
    /// ```
    ///
    /// # Errors
    /// A parameter that is not a decimal or a fraction, or out of range.
    pub fn of(scene: &SceneSpec) -> Result<Self, Error> {
        let gas = match scene {
            SceneSpec::Triangular { w } => LatticeGas::Triangular {
                w: parse_exact(w).map_err(|e| e.named("w"))?,
            },
            SceneSpec::Square { radius } => LatticeGas::Square {
                r: parse_exact(radius).map_err(|e| e.named("radius"))?,
            },
            SceneSpec::Table(t) => {
                return Err(Error::Lacks {
                    scene: t.title().to_string(),
                    capability: crate::Capability::OneDiskPerCell,
                    analysis: "superdiffusion",
                });
            }
            SceneSpec::Open(t) => {
                return Err(Error::Lacks {
                    scene: t.title(),
                    capability: crate::Capability::Lattice,
                    analysis: "superdiffusion",
                });
            }
        };
        gas.validate()?;
        Ok(gas)
    }

    /// The refusal of this lattice's radius or gap, `why`.
    fn refuse(&self, why: String) -> Error {
        match self {
            LatticeGas::Square { r } => Error::parameter("radius", r, why),
            LatticeGas::Triangular { w } => Error::parameter("w", w, why),
        }
    }

    /// Checks the radius or gap (exactly).
    pub fn validate(&self) -> Result<(), Error> {
        match self {
            LatticeGas::Square { r } => crate::scenes::square::check_radius(r)?,
            LatticeGas::Triangular { w } => {
                if *w <= 0 {
                    return Err(Error::Trapped { w: w.to_f64() });
                }
            }
        }
        Ok(())
    }

    /// Corridor in direction (m, n) iff 4r²|v|² < A², all exact: the square lattice has A = 1,
    /// |v|² = N; the triangular one (radius 1) A² = 3a⁴/4, |v|² = a²N, so 16N < 3a².
    fn open(&self, norm2: i64) -> bool {
        let n = Rational::from(norm2);
        match self {
            LatticeGas::Square { r } => Rational::from(4) * r.clone() * r * n < 1,
            LatticeGas::Triangular { w } => {
                let a = Rational::from(2) + w;
                Rational::from(16) * n < Rational::from(3) * a.clone() * &a
            }
        }
    }

    /// The largest N = |v|²/s² a corridor can have, and the bound on |m|, |n| that covers it.
    fn search_bounds(&self) -> Result<(i64, i64), Error> {
        // N_max: square 1/(4r²), triangular 3a²/16, rounded up.
        let nmax: Rational = match self {
            LatticeGas::Square { r } => Rational::from(1) / (Rational::from(4) * r.clone() * r),
            LatticeGas::Triangular { w } => {
                let a = Rational::from(2) + w;
                Rational::from(3) * a.clone() * &a / Rational::from(16)
            }
        };
        let nmax = nmax.ceil().numer().to_i64().filter(|&n| n <= MAX_NORM2);
        let Some(nmax) = nmax else {
            return Err(self.refuse(format!(
                "the radius is too small (or the gap too large) to list every corridor (about \
                 a million or more): use radius >= 1/2048 on the square lattice, w <= 2362 on \
                 the triangular one (corridors up to |v|^2 = {MAX_NORM2} lattice spacings^2)"
            )));
        };
        // p² + q² ≥ max(p, q)²; m² + mn + n² ≥ (3/4) max(|m|, |n|)².
        let coordinate = (((4 * nmax) as f64 / 3.0).sqrt().ceil() as i64) + 1;
        Ok((nmax, coordinate))
    }
}

/// Every corridor of `gas` (exactly decided) and the superdiffusion constants at precision
/// `ctx`. A finite horizon has no corridor and every constant 0.
///
/// # Errors
/// A radius or gap out of range, or so small a radius that the list would be unbounded.
///
/// # Examples
///
/// ```
/// use lorentz_gas::theory::corridors::{superdiffusion, LatticeGas};
/// use rug::Rational;
/// // r = 1/4: the axes (width 1/2) and the diagonals (width 1/√2 − 1/2).
/// let s = superdiffusion::<f64>((), &LatticeGas::Square { r: Rational::from((1, 4)) }).unwrap();
/// assert_eq!(s.corridors.len(), 4);
/// assert!((s.corridors[0].width - 0.5).abs() < 1e-15);
/// ```
pub fn superdiffusion<T: Real>(ctx: T::Ctx, gas: &LatticeGas) -> Result<Superdiffusion<T>, Error> {
    gas.validate()?;
    let (nmax, c) = gas.search_bounds()?;
    let mut dirs: Vec<([i64; 2], i64)> = Vec::new();
    for m in 0..=c {
        for n in -c..=c {
            // One of ±v: the first nonzero coordinate positive.
            if (m == 0 && n <= 0) || Integer::from(m).gcd(&Integer::from(n)) != 1 {
                continue;
            }
            let norm2 = match gas {
                LatticeGas::Square { .. } => m * m + n * n,
                LatticeGas::Triangular { .. } => m * m + m * n + n * n,
            };
            if norm2 <= nmax && gas.open(norm2) {
                dirs.push(([m, n], norm2));
                if dirs.len() > MAX_CORRIDORS {
                    return Err(gas.refuse(format!(
                        "more than {MAX_CORRIDORS} corridors: use a larger radius (or a smaller gap)"
                    )));
                }
            }
        }
    }
    dirs.sort_by_key(|&(d, n2)| (n2, d));
    Ok(assemble(ctx, gas, &dirs))
}

/// The corridors of `dirs` and the constants, at precision `ctx`.
fn assemble<T: Real>(ctx: T::Ctx, gas: &LatticeGas, dirs: &[([i64; 2], i64)]) -> Superdiffusion<T> {
    let pi = T::pi(ctx);
    let (radius, spacing, cell_area) = match gas {
        LatticeGas::Square { r } => (T::from_rational(ctx, r), T::one(ctx), T::one(ctx)),
        LatticeGas::Triangular { w } => {
            let a = T::from_rational(ctx, &(Rational::from(2) + w));
            let area = a.clone() * &a * &T::sqrt3(ctx) / &T::from_i32(ctx, 2);
            (T::one(ctx), a, area)
        }
    };
    let free_area = cell_area.clone() - &(pi.clone() * &radius * &radius);
    let boundary = pi.clone() * &radius.clone().scale(2.0);
    let mut sums = [T::zero(ctx), T::zero(ctx), T::zero(ctx), T::zero(ctx)];
    let mut corridors = Vec::with_capacity(dirs.len());
    for &([m, n], norm2) in dirs {
        let root = T::from_f64(ctx, norm2 as f64).sqrt();
        let period = spacing.clone() * &root;
        let width = cell_area.clone() / &period - &radius.clone().scale(2.0);
        let (ux, uy) = match gas {
            LatticeGas::Square { .. } => (T::from_f64(ctx, m as f64), T::from_f64(ctx, n as f64)),
            LatticeGas::Triangular { .. } => (
                T::from_f64(ctx, m as f64) + &T::from_f64(ctx, n as f64).scale(0.5),
                T::from_f64(ctx, n as f64) * &T::sqrt3(ctx).scale(0.5),
            ),
        };
        let unit = [ux / &root, uy / &root];
        let weight = period.clone() * &width * &width;
        sums[0] += &weight;
        sums[1] += &(weight.clone() * &unit[0] * &unit[0]);
        sums[2] += &(weight.clone() * &unit[1] * &unit[1]);
        sums[3] += &(weight * &unit[0] * &unit[1]);
        corridors.push(Corridor {
            direction: [m, n],
            norm2,
            unit,
            period,
            width,
        });
    }
    let flow = pi * &free_area;
    let [s, sxx, syy, sxy] = sums;
    Superdiffusion {
        corridors,
        c_map: s.clone() / &boundary,
        c_flow: s / &flow,
        d_sup_xx: sxx / &flow,
        d_sup_yy: syy / &flow,
        d_sup_xy: sxy / &flow,
        free_area,
        boundary,
    }
}

impl<T: Real> Corridor<T> {
    /// The corridor as JSON numbers (doubles).
    pub fn to_json(&self) -> CorridorJson {
        let angle = self.unit[1]
            .to_f64()
            .atan2(self.unit[0].to_f64())
            .to_degrees();
        CorridorJson {
            direction: self.direction,
            angle_degrees: if angle < 0.0 { angle + 180.0 } else { angle },
            period: self.period.to_f64(),
            width: self.width.to_f64(),
        }
    }
}
