//! The orbits that never diffuse in a uniform magnetic field, by exact geometry
//! (`proofs-notes/magnetic-localized.md`).
//!
//! A phase point (x, v) in the field B has the cyclotron centre z = x + Jv/B and radius
//! ρ = 1/|B|. For every direction, (x, v) ↦ (z, v) is a translation, so the invariant measure
//! (uniform in the free area |Q| of a cell and in the direction) is uniform in z too, and for a
//! fixed z the particle is uniformly anywhere on its circle. The disks of a cell (radius r_m at
//! c_m) repeat on a lattice; the **reach** of disk m is R_m = min |c_m − c'| − r' over every other
//! disk c' (its own images included: A − r for equal disks A apart).
//!
//! * **Pinned**: the circle meets no disk: |z − c| ∉ [ρ − r, ρ + r] for every disk. The set P
//!   of such centres is periodic, every point of its circles is free, so the pinned share of
//!   phase space is |P ∩ cell| / |Q|. It is computed as ∫ L(y) dy over one period of heights,
//!   L(y) the free length of the line at height y (one period of x) left by the annuli of all
//!   disks: a piecewise smooth integrand, cut at every height where it is not smooth (a circle
//!   tangent to the line, two circles crossing on the boundary of the covered set) and
//!   integrated piece by piece by [`super::quadrature::integrate_smooth`] to rounding
//!   (`shares`; checked against Green's theorem on the boundary arcs in `green`).
//! * **Skipping**: the circle cuts one disk c (|ρ − r| < D = |z − c| < ρ + r) and its orbit
//!   stays out of reach of every other: D + ρ < R. Every return to c is the same arc turned about
//!   c, so the orbit circles c for ever within the annulus D + ρ about it. For fixed z the share
//!   of the circle outside the disk is 1 − ψ/π, cos ψ = (D² + ρ² − r²)/(2Dρ), so the skipping
//!   share is Σ_m (2π/|Q|) ∫ D (1 − ψ(D)/π) dD over |ρ − r_m| < D < min(ρ + r_m, R_m − ρ), in
//!   closed form by Fubini (`shares`: π(hi² − lo²) − lens(hi, r, ρ) + lens(lo, r, ρ)). Where
//!   the annulus reaches another disk (D + ρ > R) the turn per bounce is irrational for almost
//!   every D, the arcs fill the annulus, and the orbit meets it: not localized.
//! * **Kac's lemma** for the part that is neither (the diffusing part): its mean free time
//!   between collisions is its phase volume over its boundary flux,
//!   τ = 2π|Q|(1 − f_pinned − f_skipping) / (4πΣr − Σ π|B|(D_hi² − D_lo²)); the skipping orbits
//!   at distance D carry the flux 2π|B|D dD (phase volume over return time), the whole boundary
//!   4πΣr.

use std::f64::consts::PI;

use crate::Error;
use crate::scenes::Scene;
use crate::scenes::lattice::LatticeState;
use crate::scenes::magnetic::DiskLattice;

#[cfg(test)]
mod green;
mod shares;

pub use shares::lens;

/// What an orbit in the field does, decided from its cyclotron circle alone.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Orbit {
    /// Its circle meets no disk: it never collides.
    Pinned,
    /// It circles one disk for ever, bouncing on it.
    Skipping,
    /// Neither: the part of phase space whose transport the estimators measure.
    Diffusing,
}

/// The exact geometry of a disk lattice in the field `field` (≠ 0).
#[derive(Debug, Clone, PartialEq)]
pub struct FieldGeometry {
    lattice: DiskLattice,
    field: f64,
    rho: f64,
    /// For each disk m, its reach min |c − c'| − r' ([`DiskLattice::reach`], found once: every
    /// classification needs it).
    reach: Vec<f64>,
    /// Every orbit is localized ([`FieldGeometry::all_localized`]), decided once.
    all_localized: bool,
    /// The exact pinned share, integrated once when first asked for (its quadrature grows as a
    /// cube of the rows within ρ + r: a run in a field asks for it five times).
    pinned: std::sync::OnceLock<f64>,
}

/// Whether 2ρ ≤ R_m − r_m for every disk m: exactly, with ρ = 1/|B| for the double B the run
/// uses, where the array is known exactly (so that a boundary such as 2ρ = A − 2r, where every
/// orbit is localized, is not turned by rounding); in `f64` otherwise.
fn all_localized(lattice: &DiskLattice, reach: &[f64], field: f64, rho: f64) -> bool {
    let exact = |m: usize| {
        let b = rug::Rational::from_f64(field.abs())?;
        let r = &lattice.exact.as_ref()?.disks[m].1;
        let d = rug::Rational::from(2) / b + r;
        lattice.reaches_at_least(m, &d)
    };
    (lattice.disks.iter().zip(reach).enumerate())
        .all(|(m, (d, reach))| exact(m).unwrap_or(2.0 * rho <= reach - d.radius))
}

/// Absolute accuracy of the exact shares, a bound with a wide margin: they are measured within
/// 2·10⁻¹⁵ of Green's theorem and the closed forms (`green`); where ρ + r spans many cells the
/// free length's rounding, and the quadrature's test with it, grow as ((ρ + r)/a)^{3/2}.
pub const SHARE_TOLERANCE: f64 = 1e-12;

/// The error of a share sampled from `samples` phase points against the exact share `exact`:
/// the binomial standard error plus the exact share's own tolerance ([`SHARE_TOLERANCE`]; an
/// exact share of 1 may round to 1 + 2⁻⁵², where the binomial variance would be negative).
pub fn sampled_share_err(exact: f64, samples: f64) -> f64 {
    (exact * (1.0 - exact)).max(0.0).sqrt() / samples.sqrt() + SHARE_TOLERANCE
}

impl FieldGeometry {
    /// The geometry of `lattice` in the field `field`.
    ///
    /// # Errors
    /// A field that is zero or not finite (B = 0 has no cyclotron circle).
    pub fn new(lattice: DiskLattice, field: f64) -> Result<Self, Error> {
        if !field.is_finite() || field == 0.0 {
            return Err(Error::out_of_range(
                "field",
                field,
                "a nonzero finite field has a cyclotron circle",
            ));
        }
        let reach: Vec<f64> = (0..lattice.disks.len()).map(|m| lattice.reach(m)).collect();
        let rho = 1.0 / field.abs();
        let all_localized = all_localized(&lattice, &reach, field, rho);
        Ok(FieldGeometry {
            lattice,
            field,
            rho,
            reach,
            all_localized,
            pinned: std::sync::OnceLock::new(),
        })
    }

    /// The field B.
    pub fn field(&self) -> f64 {
        self.field
    }

    /// The cyclotron radius ρ = 1/|B|.
    pub fn cyclotron_radius(&self) -> f64 {
        self.rho
    }

    /// The disk array.
    pub fn lattice(&self) -> &DiskLattice {
        &self.lattice
    }

    /// `true` if every orbit is localized: 2ρ ≤ reach − r for every disk (A − 2r for equal disks
    /// A apart), so that every cyclotron circle that meets a disk stays out of reach of the others
    /// (it skips round it) and every other one is pinned.
    pub fn all_localized(&self) -> bool {
        self.all_localized
    }

    /// The range (D_lo, D_hi) of centre distances of the orbits skipping round disk `m` (empty
    /// if D_hi ≤ D_lo).
    pub fn skipping_range(&self, m: usize) -> (f64, f64) {
        let (rho, r) = (self.rho, self.lattice.disks[m].radius);
        let reach = self.reach[m] - rho;
        ((rho - r).abs(), (rho + r).min(reach))
    }

    /// What the orbit of the lattice state `s` does: [`FieldGeometry::classify`] of its world
    /// position and velocity (the cell's frame turned by the cell's orientation).
    pub fn classify_state<K: crate::kernel::cell::CellKernel<f64>>(
        &self,
        lattice: &crate::scenes::lattice::Lattice<f64, K>,
        s: &LatticeState<f64>,
    ) -> Orbit {
        let p = lattice.world(s);
        let sg = s.cell.sign();
        self.classify(p.x, p.y, sg * s.flight.vel.x, sg * s.flight.vel.y)
    }

    /// What the orbit through the world point (x, y) with unit velocity (vx, vy) does.
    pub fn classify(&self, x: f64, y: f64, vx: f64, vy: f64) -> Orbit {
        let (zx, zy) = (x - vy / self.field, y + vx / self.field);
        if self.skips(zx, zy) {
            return Orbit::Skipping;
        }
        if self.circle_meets_a_disk(zx, zy) {
            Orbit::Diffusing
        } else {
            Orbit::Pinned
        }
    }

    /// `true` if the circle about (zx, zy) skips round a disk: its centre at a distance in the
    /// disk's skipping range. Such a disk is the nearest of its own lattice (D_hi is at most half
    /// their distance), so only the points within D_hi are looked at.
    fn skips(&self, zx: f64, zy: f64) -> bool {
        let mut skips = false;
        for (m, d) in self.lattice.disks.iter().enumerate() {
            let (lo, hi) = self.skipping_range(m);
            if hi <= lo {
                continue;
            }
            let (x, y) = (zx - d.centre[0], zy - d.centre[1]);
            self.lattice.points_near((x, y), hi, |i, j| {
                let (cx, cy) = self.lattice.point(i, j);
                // Squared distances (lo ≥ 0) order as the distances do, up to rounding ties,
                // without a `hypot` per point.
                let d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
                skips |= d2 > lo * lo && d2 < hi * hi;
            });
        }
        skips
    }

    /// The lattice rows within `outer` of the height `y`, from the outermost in (where a large
    /// circle most often meets a disk): (dy, shift, xo, xi) — the height above the row, the x of
    /// its lattice point 0, and the half-widths of the annulus inner ≤ |z − c| ≤ outer about its
    /// points on the line (xi = 0 where the inner circle does not reach it): for a disk of radius
    /// r, outer = ρ + r and inner = ρ − r.
    fn rows(
        &self,
        y: f64,
        outer: f64,
        inner: f64,
    ) -> impl Iterator<Item = (f64, f64, f64, f64)> + '_ {
        let l = &self.lattice;
        let (j_lo, j_hi) = (((y - outer) / l.h).ceil(), ((y + outer) / l.h).floor());
        let rows = ((j_hi - j_lo) as i64 + 1).max(0);
        (0..rows).map(move |k| {
            let j = if k % 2 == 0 {
                j_hi - (k / 2) as f64
            } else {
                j_lo + (k / 2) as f64
            };
            let dy = y - l.h * j;
            let xo = (outer * outer - dy * dy).max(0.0).sqrt();
            let xi = if inner > 0.0 && dy.abs() < inner {
                (inner * inner - dy * dy).sqrt()
            } else {
                0.0
            };
            (dy, l.beta * l.a * j, xo, xi)
        })
    }

    /// `true` if the circle of radius ρ about (zx, zy) meets a disk: for some disk of the cell, a
    /// point of its lattice at a distance in [ρ − r, ρ + r].
    fn circle_meets_a_disk(&self, zx: f64, zy: f64) -> bool {
        self.lattice
            .disks
            .iter()
            .any(|d| self.meets_one(zx - d.centre[0], zy - d.centre[1], d.radius))
    }

    /// `true` if the circle of radius ρ about (zx, zy) meets a disk of radius `r` at a lattice
    /// point. Rows are scanned from the outermost in, where a large circle most often meets one.
    fn meets_one(&self, zx: f64, zy: f64, r: f64) -> bool {
        self.in_annuli(zx, zy, self.rho + r, self.rho - r)
    }

    /// `true` if (zx, zy) is in the closed annulus inner ≤ |z − c| ≤ outer about a lattice point
    /// (the whole disk where inner ≤ 0).
    fn in_annuli(&self, zx: f64, zy: f64, outer: f64, inner: f64) -> bool {
        let l = &self.lattice;
        for (dy, shift, xo, xi) in self.rows(zy, outer, inner) {
            for side in [-1.0, 1.0] {
                // Lattice points at x = shift + i·a with |x − zx| in [xi, xo] on this side.
                let (near, far) = (zx + side * xi, zx + side * xo);
                let (lo, hi) = if side < 0.0 { (far, near) } else { (near, far) };
                let first = ((lo - shift) / l.a).ceil();
                let last = ((hi - shift) / l.a).floor();
                let mut i = first;
                while i <= last {
                    let cx = shift + l.a * i;
                    // As squares (inner < 0 where ρ < r: every distance is beyond it).
                    let dist2 = (zx - cx) * (zx - cx) + dy * dy;
                    if dist2 <= outer * outer && (inner <= 0.0 || dist2 >= inner * inner) {
                        return true;
                    }
                    i += 1.0;
                }
            }
        }
        false
    }

    /// The localized share: pinned plus skipping.
    pub fn localized_fraction(&self) -> f64 {
        self.pinned_fraction() + self.skipping_fraction()
    }

    /// The lattice rows within ρ + r of a height, summed over the disks, that each evaluation of
    /// the exact pinned share's quadrature scans — if a line is left free by the annuli (probed
    /// at 64 heights), else 0: a line found covered returns at once, and the quadrature is quick.
    /// Beyond 10⁵ rows no probe is made (their quadrature is out of reach either way).
    pub fn quadrature_rows(&self) -> f64 {
        const PROBES: u32 = 64;
        let l = &self.lattice;
        let rows: f64 = l
            .disks
            .iter()
            .map(|d| (2.0 * (self.rho + d.radius) / l.h).floor() + 1.0)
            .sum();
        if rows > 1e5 {
            return rows;
        }
        let height = |k: u32| (f64::from(k) + 0.5) / f64::from(PROBES) * l.h;
        let free = (0..PROBES).any(|k| self.free_length(height(k)) > 0.0);
        if free { rows } else { 0.0 }
    }

    /// The floors on the set-up of a run in this field, (on its threads, on one): the
    /// classification of `samples` orbits and the exact pinned share
    /// ([`classification_seconds`], [`quadrature_seconds`]).
    ///
    /// [`classification_seconds`]: crate::engine::work::classification_seconds
    /// [`quadrature_seconds`]: crate::engine::work::quadrature_seconds
    pub fn setup_seconds(&self, samples: f64) -> (f64, f64) {
        use crate::engine::work::{classification_seconds, quadrature_seconds};
        let rows = self.quadrature_rows();
        let classify = classification_seconds(samples);
        (classify, quadrature_seconds(rows))
    }

    /// The boundary flux of the skipping orbits per cell, Σ π|B|(D_hi² − D_lo²) over the disks
    /// (0 if none).
    pub fn skipping_flux(&self) -> f64 {
        let mut flux = 0.0;
        for m in 0..self.lattice.disks.len() {
            let (lo, hi) = self.skipping_range(m);
            if hi > lo {
                flux += PI * self.field.abs() * (hi * hi - lo * lo);
            }
        }
        flux
    }

    /// Kac's mean free time between collisions of the diffusing part (see the module
    /// documentation); infinite if nothing diffuses.
    pub fn diffusing_mean_free_time(&self) -> f64 {
        let l = &self.lattice;
        let volume = 2.0 * PI * l.free_area() * (1.0 - self.localized_fraction());
        let flux = 4.0 * PI * l.radius_sum() - self.skipping_flux();
        if flux <= 0.0 || volume <= 0.0 {
            return f64::INFINITY;
        }
        volume / flux
    }

    /// A start of `scene` drawn from the invariant measure restricted to the diffusing orbits (by
    /// rejection with `rng`: pinned and skipping starts are drawn again), and the number of
    /// localized starts set aside. Every estimator in a field starts its trajectories here, so
    /// batch k of a transport run, a Lyapunov orbit and a shadowed segment start alike.
    ///
    /// # Errors
    /// No diffusing start in [`MAX_STARTS`] draws (almost every orbit localized), or a bad scene.
    pub fn diffusing_start<S: Scene>(
        &self,
        scene: &S,
        rng: &mut rand_xoshiro::Xoshiro256PlusPlus,
    ) -> Result<(LatticeState<f64>, u64), Error> {
        let lattice = scene.lattice::<f64>(())?;
        for rejected in 0..MAX_STARTS {
            let s = scene.sample(rng);
            if self.classify_state(&lattice, &s) == Orbit::Diffusing {
                return Ok((s, rejected));
            }
        }
        Err(Error::Failed(format!(
            "no diffusing start in {MAX_STARTS} draws: almost every orbit is localized at this field"
        )))
    }
}

/// Most starts drawn for one trajectory before a diffusing one is found (the localized share
/// would have to exceed 1 − 10⁻⁶ for this to be reached by chance even once in 10⁴ batches).
pub const MAX_STARTS: u64 = 20_000_000;

#[cfg(test)]
mod tests {

    /// At 2ρ = A − 2r exactly every orbit is localized (a skipping annulus just touches the next
    /// disk): square r = 2/5 at B = 10 and the triangular gap w = 1/5 at B = 10, where the f64
    /// comparison (0.2 ≤ 1 − 0.8 = 0.19999999999999996) would say otherwise. A field one part in
    /// 10³ weaker is not all localized.
    #[test]
    fn every_orbit_is_localized_at_the_exact_boundary_2rho_equal_to_a_minus_2r() {
        use crate::scenes::square::SquareScene;
        use crate::scenes::triangular::TriangularScene;
        let q = |s: &str| crate::numbers::exact::parse_exact(s).unwrap();
        let square = SquareScene::exact(q("2/5"))
            .unwrap()
            .disk_lattice()
            .unwrap();
        let tri = TriangularScene::exact(q("1/5"))
            .unwrap()
            .disk_lattice()
            .unwrap();
        // Without the exact array, rounding decides the square's boundary the other way.
        let rounded = DiskLattice {
            exact: None,
            ..square.clone()
        };
        assert!(!FieldGeometry::new(rounded, 10.0).unwrap().all_localized());
        for lattice in [square, tri] {
            let at = |b: f64| {
                FieldGeometry::new(lattice.clone(), b)
                    .unwrap()
                    .all_localized()
            };
            assert!(at(10.0) && at(-10.0), "{lattice:?}");
            assert!(!at(9.99), "{lattice:?}");
        }
    }
    use super::*;

    fn triangular(w: f64) -> DiskLattice {
        let a = 2.0 + w;
        DiskLattice::equal(a, 0.5, a * 3f64.sqrt() / 2.0, 1.0)
    }

    #[test]
    fn a_weak_field_pins_and_skips_nothing_in_a_finite_horizon() {
        let g = FieldGeometry::new(triangular(0.1), 0.1).unwrap();
        assert_eq!(g.pinned_fraction(), 0.0);
        assert_eq!(g.skipping_fraction(), 0.0);
        assert!((g.diffusing_mean_free_time() - g.lattice.free_area() / 2.0).abs() < 1e-12);
    }

    #[test]
    fn a_small_circle_between_disks_is_pinned_with_the_exact_area() {
        // ρ = 0.01 at w = 0.3: the excluded centres are disks of radius 1.01 about the lattice
        // points, disjoint (a = 2.3 > 2.02): |P| = ah − π·1.01².
        let l = triangular(0.3);
        let g = FieldGeometry::new(l.clone(), 100.0).unwrap();
        let exact = (l.cell_area() - PI * 1.01 * 1.01) / l.free_area();
        assert!(
            (g.pinned_fraction() - exact).abs() < 1e-14,
            "{}",
            g.pinned_fraction()
        );
        // The skipping centres: 0.99 < D < 1.01 (A − r − ρ = 1.29 is no limit).
        assert!(g.skipping_fraction() > 0.0);
        let sum = g.localized_fraction();
        assert!(sum > 0.0 && sum <= 1.0, "{sum}");
    }
}
