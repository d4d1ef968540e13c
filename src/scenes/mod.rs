//! Scenes: what a billiard table supplies to the generic kernel, and nothing more.
//!
//! A [`Scene`] supplies its cell (a [`ConvexCell`](crate::kernel::cell::ConvexCell): a convex polygon,
//! its disks with exact centres and radius, its edges with the exact maps into the neighbouring
//! cell and the integer steps for unwrapping) through a cell kernel at any working precision,
//! the invariant-measure sampler, and its exact identities. Everything above — observables,
//! estimators, the shadow audit, the fuzz oracle, Lyapunov exponents, reversal, certification —
//! is written once against this trait.
//!
//! * [`lattice`]: the periodic walk over the cells of any kernel (exact integer cell indices,
//!   bounded offsets, unwrapped positions).
//! * [`triangular`]: the triangular lattice of disks of radius 1 at spacing 2 + w (the paper),
//!   on the trap's fused kernel.
//! * [`square`]: disks of radius 0 < r < 1/2 on the unit square lattice (the Sinai billiard;
//!   always infinite horizon), on the generic kernel.
//! * [`magnetic`]: the lattice walked along arcs in a uniform magnetic field, and the disk array
//!   the field's exact geometry needs.
//! * [`spec`], [`motion`]: a table's description — which geometry, and how the particle moves
//!   (straight, in a magnetic field, thermostatted) — each parameter exactly as typed.
//! * [`single_trap`]: one trap of three disks and its gaps, for injection experiments.
//! * [`table`]: any periodic table of disks given as data (a lattice by exact basis vectors,
//!   disks by exact centres and radii), validated exactly, on the generic kernel.
//! * [`strip`]: the triangular lattice between two absorbing vertical lines x = 0 and x = L, for
//!   the escape-rate estimator of D.
//!
//! A new scene is one file implementing [`Scene`]; it never touches [`crate::kernel`].

pub mod lattice;
pub mod long_flight;
pub mod magnetic;
pub mod motion;
pub mod open;
pub mod sampling;
pub mod single_trap;
pub mod spec;
pub mod square;
pub mod strip;
pub mod symbols;
pub mod table;
pub mod thermostat;
pub mod triangular;

use rand::Rng;
use rug::Rational;

use crate::Error;
use crate::kernel::cell::CellKernel;
use crate::kernel::vec2::Vec2;
use crate::numbers::real::Real;
use lattice::{CellIndex, Lattice, LatticeState};

/// Largest |coordinate| of a world point [`Scene::locate`] accepts: cell indices stay far inside
/// the integers an `f64` and an `i64` hold exactly, and the absolute error of the cell offset
/// (|x|·2⁻ᴾ) stays negligible.
pub const MAX_WORLD_COORDINATE: f64 = 1e12;

/// Refuses a world point with a coordinate beyond ±[`MAX_WORLD_COORDINATE`] (a start: the one
/// point a user gives).
pub fn check_world_point(x: &Rational, y: &Rational) -> Result<(), Error> {
    check_pair("start", x, y, "coordinates")
}

/// Refuses the pair `(x, y)` given as `parameter` with a component beyond
/// ±[`MAX_WORLD_COORDINATE`] (`what`: what its components are, for the range).
pub fn check_pair(
    parameter: &'static str,
    x: &Rational,
    y: &Rational,
    what: &str,
) -> Result<(), Error> {
    let limit = Rational::from_f64(MAX_WORLD_COORDINATE).expect("finite constant");
    if x.clone().abs() > limit || y.clone().abs() > limit {
        return Err(Error::out_of_range(
            parameter,
            format!(
                "{},{}",
                crate::numbers::exact::nearest_f64(x),
                crate::numbers::exact::nearest_f64(y)
            ),
            format!("use {what} from -{MAX_WORLD_COORDINATE:e} to {MAX_WORLD_COORDINATE:e}"),
        ));
    }
    Ok(())
}

/// The scene's disks as a periodic array ([`Scene::disk_lattice`]), which `analysis` needs.
///
/// # Errors
/// [`Error::Lacks`] naming the capability, for a scene that is not such an array.
pub fn require_disk_lattice<S: Scene>(
    scene: &S,
    analysis: &'static str,
) -> Result<magnetic::DiskLattice, Error> {
    let lacks = || Error::Lacks {
        scene: scene.label(),
        capability: crate::Capability::OneDiskPerCell,
        analysis,
    };
    scene.disk_lattice().ok_or_else(lacks)
}

/// The scene's disks as one disk at every lattice point, which `analysis` needs (true
/// shadowing labels a disk by its lattice point).
///
/// # Errors
/// [`Error::Lacks`] naming the capability, for a scene with several disks per cell or its disk
/// off the lattice points.
pub fn require_one_disk_per_cell<S: Scene>(
    scene: &S,
    analysis: &'static str,
) -> Result<magnetic::DiskLattice, Error> {
    let disks = require_disk_lattice(scene, analysis)?;
    match disks.disks.as_slice() {
        [d] if d.centre == [0.0, 0.0] => Ok(disks),
        _ => Err(Error::Lacks {
            scene: scene.label(),
            capability: crate::Capability::OneDiskPerCell,
            analysis,
        }),
    }
}

/// Where [`Scene::locate`] puts a world point: its cell, and the point in that cell's frame.
pub type Located<T> = Result<(CellIndex, Vec2<T>), Error>;

/// The walk that crosses a scene's cells between collisions, each with its cost per crossing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Walk {
    /// The triangular lattice's walk through its traps.
    Triangular,
    /// The generic walk through convex cells (the square lattice, tables given as data).
    Cell,
}

/// A billiard table made of congruent convex cells.
pub trait Scene: Clone + std::fmt::Debug + Send + Sync {
    /// The kernel that runs the scene's cell at number type `T` (the generic
    /// [`ConvexCell`](crate::kernel::cell::ConvexCell) or a bit-identical fused path).
    type Kernel<T: Real>: CellKernel<T> + 'static;

    /// A short description with the parameters, e.g. `triangular w=0.1`.
    fn label(&self) -> String;

    /// The scene's cell kernel with every constant at the working precision `ctx`, computed from
    /// the exact parameters (never through `f64` when `T` is wider).
    fn kernel<T: Real>(&self, ctx: T::Ctx) -> Result<Self::Kernel<T>, Error>;

    /// The cell containing the world point (x, y), given exactly, and the point in that cell's
    /// frame at precision `ctx` (its world image is (x, y) up to the rounding of the offset,
    /// never through `f64` when `T` is wider). The cell is decided at the working precision; a
    /// point on a cell boundary may be placed in either neighbouring cell — both describe the
    /// same world point, and the kernel continues identically from either. Whether the point is
    /// free (outside every disk) is left to the caller, and so is the velocity: in a cell of
    /// orientation s = −1 (`down`) the frame velocity is minus the world velocity.
    ///
    /// # Errors
    /// If a coordinate exceeds ±[`MAX_WORLD_COORDINATE`].
    fn locate<T: Real>(&self, ctx: T::Ctx, x: &Rational, y: &Rational) -> Located<T>;

    /// The periodic lattice of the scene's cells at precision `ctx`.
    fn lattice<T: Real>(&self, ctx: T::Ctx) -> Result<Lattice<T, Self::Kernel<T>>, Error> {
        Ok(Lattice::from_kernel(self.kernel(ctx)?))
    }

    /// A state drawn from the invariant measure (uniform position in the free part of the cell
    /// with index (0, 0), uniform direction).
    fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> LatticeState<f64>;

    /// Santaló's mean free path ⟨ℓ⟩ = π|Q|/|∂Q| (|Q| the free area of a cell, |∂Q| the length of
    /// the disk boundary inside it), in closed form.
    fn mean_free_path(&self) -> f64;

    /// `true` if every free flight is bounded (no collision-free corridor): only then does the
    /// diffusion coefficient exist as a finite Einstein limit.
    fn finite_horizon(&self) -> bool;

    /// The mean time between crossings of the cell's edges at speed 1, in closed form:
    /// τ = π|Q|/L, |Q| the free area of a cell and L the free length of its edges (the part of
    /// each edge outside every disk; `proofs-notes/crossing-time.md`). The diffusion estimator
    /// samples the MSD on a grid of this unit and checks the measured τ against it. `None`
    /// (the default): the scene does not supply it, and time is measured in mean free times.
    fn crossing_time(&self) -> Option<f64> {
        None
    }

    /// Which walk crosses the cells between collisions (for the cost of a crossing,
    /// `engine::work`): the generic convex cell's, unless the scene has a faster one.
    fn walk(&self) -> Walk {
        Walk::Cell
    }

    /// The table as written, for a table given as data (results record it, so that a run can be
    /// repeated from its result), or `None` (the default: the scene's label says it all).
    fn table_spec(&self) -> Option<&table::spec::TableSpec> {
        None
    }

    /// `true` if the scene's symmetry makes every symmetric tensor of its transport isotropic
    /// (D_xx = D_yy, no symmetric off-diagonal part): a rotation of order above 2 maps it onto
    /// itself. The triangular and square scenes are; a table given as data is if a quarter turn
    /// maps it onto itself ([`table::PeriodicTable::quarter_turn_symmetric`]). `false` (the
    /// default) claims nothing.
    fn isotropic(&self) -> bool {
        false
    }

    /// The widest collision-free corridor of an infinite horizon, where the scene names it (a
    /// table given as data decides it exactly: [`table::horizon`]), or `None` (the default).
    fn widest_corridor(&self) -> Option<table::horizon::Corridor> {
        None
    }

    /// The scene's disks as a periodic array (what a magnetic field's exact geometry of pinned
    /// and skipping orbits needs: `crate::theory::magnetic`), or `None` (the default) if the
    /// scene is not such an array.
    fn disk_lattice(&self) -> Option<magnetic::DiskLattice> {
        None
    }

    /// The radius of the scene's disks if its straight flights can go straight to the first disk
    /// they can meet ([`long_flight::jump`]: disks at the integer points, [`long_flight::MIN_RADIUS`] ≤ r ≤
    /// [`long_flight::MAX_RADIUS`]), or `None` (the default): flights walk cell by cell.
    fn long_flight_radius(&self) -> Option<f64> {
        None
    }

    /// The long flights the scene admits ([`long_flight::LongFlights`]): by default the square
    /// search at [`Scene::long_flight_radius`], if any.
    fn long_flights(&self) -> Option<long_flight::LongFlights> {
        self.long_flight_radius()
            .map(|radius| long_flight::LongFlights::Square { radius })
    }
}
