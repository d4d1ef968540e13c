//! A Poincaré section in Birkhoff coordinates: where phase space is mixed (a magnetic field's
//! regular islands among the chaotic sea), each orbit's collisions drawn as points coloured by
//! the component it belongs to (`proofs-notes/poincare-section.md`).
//!
//! Orbit i starts from the invariant measure (uniform position in the free part of a cell,
//! uniform direction; on the triangular lattice in an up or a down trap with probability ½) on
//! its own stream `(seed, Section, i)`, so that the same seed gives the
//! same bits at any thread count. In a field its cyclotron circle classifies it exactly
//! ([`FieldGeometry::classify`]): a **pinned** orbit never collides (no points); a **skipping**
//! orbit bounces round one disk for ever; every other orbit is flown `classify_collisions`
//! collisions and called **bounded** when the largest distance from its start that it reached
//! stays within the table's [`Excursion`] limit (a regular island), **diffusing** otherwise
//! (the chaotic sea), with an `ambiguous` flag where the split is not clear. Without a field
//! every orbit is diffusing (a dispersing billiard is ergodic) and is flown its recorded
//! collisions only.
//!
//! At each of an orbit's first `collisions` collisions the Birkhoff point is recorded (world
//! frame, [`birkhoff`]): θ, the polar angle of the contact point about the disk's centre in
//! [−π, π) (radians; the arc length is rθ), and p = sin α ∈ [−1, 1], α the angle of the outgoing
//! velocity to the outward normal counted counter-clockwise (the velocity's component along the
//! counter-clockwise tangent), with the disk of the table's array it is on. The billiard map
//! preserves cos α dα ds = dp ds, so the chaotic sea fills the (θ, p) rectangle evenly where it
//! is all of phase space.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::parallel::par_batches_watched;
use crate::engine::work::{Work, classification_seconds};
use crate::numbers::precision::Precision;
use crate::observers::excursion::{Component as Split, Excursion};
use crate::scenes::Scene;
use crate::scenes::spec::Table;
use crate::theory::magnetic::{FieldGeometry, Orbit};

mod orbit;

pub use orbit::birkhoff;
use orbit::{DiskLabels, Flown, Setup};

/// Orbits a section draws by default.
pub const DEFAULT_TRAJECTORIES: u32 = 64;
/// Collisions recorded per orbit by default.
pub const DEFAULT_COLLISIONS: u64 = 2_000;
/// Collisions flown per orbit to classify it, by default: a diffusing orbit at D ≈ 0.005 (the
/// slowest of the triangular gas in the fields of interest) spreads √(4Dt) ≈ 6 over 2·10⁵
/// collisions of mean free time ≈ 0.3–1, beyond the limit of about 7.4 at w = 0.2, B = 5/2 —
/// and most reach several limits ([`Excursion::AMBIGUOUS`] flags the others).
pub const DEFAULT_CLASSIFY_COLLISIONS: u64 = 200_000;
/// Most orbits.
pub const MAX_TRAJECTORIES: u32 = 100_000;
/// Most collisions recorded per orbit.
pub const MAX_COLLISIONS: u64 = 10_000_000;
/// Most collisions flown per orbit to classify it.
pub const MAX_CLASSIFY_COLLISIONS: u64 = 10_000_000_000;
/// Most points in all (orbits × collisions): each keeps 24 bytes until the end.
pub const MAX_POINTS: u64 = 20_000_000;

/// The configuration of a Poincaré section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SectionConfig {
    /// The table and the field B (none: straight flights), exactly as typed.
    #[serde(flatten)]
    pub table: Table,
    /// Orbits, 1 to [`MAX_TRAJECTORIES`].
    pub trajectories: u32,
    /// Collisions recorded per orbit, 1 to [`MAX_COLLISIONS`].
    pub collisions: u64,
    /// Collisions flown per orbit in a field to classify it (bounded or diffusing), at least
    /// `collisions`, at most [`MAX_CLASSIFY_COLLISIONS`].
    pub classify_collisions: u64,
    /// Seed of the orbits' starts.
    pub seed: u64,
}

impl SectionConfig {
    /// The section of `table` with the default counts and seed 1.
    pub fn new(table: Table) -> Self {
        SectionConfig {
            table,
            trajectories: DEFAULT_TRAJECTORIES,
            collisions: DEFAULT_COLLISIONS,
            classify_collisions: DEFAULT_CLASSIFY_COLLISIONS,
            seed: 1,
        }
    }

    /// Checks every parameter.
    ///
    /// # Errors
    /// A bad table or field, or a count out of its range.
    pub fn validate(&self) -> Result<(), Error> {
        self.table.motion_taken_by("section")?;
        self.table.scene.resolve()?;
        self.table.field_value()?;
        Error::unless_in("trajectories", self.trajectories, 1..=MAX_TRAJECTORIES, "")?;
        Error::unless_in(
            "collisions",
            self.collisions,
            1..=MAX_COLLISIONS,
            " collisions recorded per orbit",
        )?;
        if !(self.collisions..=MAX_CLASSIFY_COLLISIONS).contains(&self.classify_collisions) {
            return Err(Error::out_of_range(
                "classify_collisions",
                self.classify_collisions,
                format!(
                    "use collisions ({}) to {MAX_CLASSIFY_COLLISIONS}: every recorded collision \
                     is flown to classify the orbit",
                    self.collisions
                ),
            ));
        }
        let points = u64::from(self.trajectories) * self.collisions;
        if points > MAX_POINTS {
            return Err(Error::out_of_range(
                "collisions",
                self.collisions,
                format!(
                    "trajectories × collisions = {points} points: use at most {MAX_POINTS} in all \
                     (each is kept until the end)"
                ),
            ));
        }
        Ok(())
    }
}

/// The component of one orbit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Component {
    /// Its cyclotron circle meets no disk: it never collides.
    Pinned,
    /// It bounces round one disk for ever (exact, from its circle).
    Skipping,
    /// It stayed within the excursion limit: a regular island.
    Bounded,
    /// It went beyond it: the chaotic sea (every orbit without a field).
    Diffusing,
}

/// A Poincaré section.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SectionResult {
    /// The scene ([`Scene::label`]).
    pub scene: String,
    /// The field B as the nearest double (absent without one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub field: Option<f64>,
    /// The cyclotron radius 1/|B| (absent without a field).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cyclotron_radius: Option<f64>,
    /// The excursion limit ([`Excursion::of`], length; absent without a field).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limit: Option<f64>,
    /// Orbits pinned.
    pub pinned: u32,
    /// Orbits skipping.
    pub skipping: u32,
    /// Orbits bounded.
    pub bounded: u32,
    /// Orbits diffusing.
    pub diffusing: u32,
    /// Diffusing orbits whose reach is within [`Excursion::AMBIGUOUS`] limits.
    pub ambiguous_trajectories: u32,
    /// θ of each point: the polar angle of the contact point about its disk's centre, world
    /// frame, radians in [−π, π).
    pub theta: Vec<f64>,
    /// p of each point: sin of the outgoing angle to the normal, counter-clockwise, in [−1, 1].
    pub p: Vec<f64>,
    /// The orbit of each point.
    pub trajectory: Vec<u32>,
    /// The disk of each point: its index among the table's disks of one cell.
    pub disk: Vec<u32>,
    /// The component of each orbit.
    pub component: Vec<Component>,
    /// The largest distance from its start each orbit reached (length).
    pub reach: Vec<f64>,
    /// Whether each orbit is a diffusing one near the limit.
    pub ambiguous: Vec<bool>,
    /// Collisions flown in all.
    pub collisions: u64,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// The configuration.
    pub config: SectionConfig,
    /// Provenance.
    pub meta: RunMeta,
}

impl SectionResult {
    /// The number of orbits of component `c`.
    pub fn count(&self, c: Component) -> u32 {
        self.component.iter().filter(|x| **x == c).count() as u32
    }
}

/// Draws the section.
///
/// # Errors
/// An invalid configuration, options the analysis does not use, a field on a scene that is not
/// an array of disks, work beyond the limit, or an interruption.
pub fn run(cfg: &SectionConfig, opts: &RunOptions) -> Result<SectionResult, Error> {
    cfg.validate()?;
    opts.accept("section", &[])?;
    let scene = cfg.table.scene.resolve()?;
    crate::with_scene!(&scene, |s| run_on(s, cfg, opts))
}

/// The field's geometry on `scene`, if there is a field.
fn geometry_of<S: Scene>(scene: &S, cfg: &SectionConfig) -> Result<Option<FieldGeometry>, Error> {
    match cfg.table.field_value()? {
        Some(b) => {
            let disks = crate::scenes::require_disk_lattice(scene, "section")?;
            Ok(Some(FieldGeometry::new(disks, b)?))
        }
        None => Ok(None),
    }
}

/// The work of the section `cfg`, before it starts.
///
/// # Errors
/// A bad table or field.
pub fn work(cfg: &SectionConfig) -> Result<Work<'static>, Error> {
    let scene = cfg.table.scene.resolve()?;
    crate::with_scene!(&scene, |s| Ok(work_on(
        s,
        cfg,
        geometry_of(s, cfg)?.as_ref()
    )))
}

/// [`work`] on the resolved scene: every orbit flown its classification in a field (a floor:
/// pinned and skipping orbits fly less), its recorded collisions without.
fn work_on<S: Scene>(scene: &S, cfg: &SectionConfig, g: Option<&FieldGeometry>) -> Work<'static> {
    const LOWER: &[&str] = &["trajectories", "classify_collisions"];
    let orbits = f64::from(cfg.trajectories);
    match g {
        Some(g) => Work::new("section", LOWER, orbits * cfg.classify_collisions as f64).in_field(
            scene,
            g.cyclotron_radius(),
            false,
            (classification_seconds(orbits), 0.0),
        ),
        None => Work::new(
            "section",
            &["trajectories", "collisions"],
            orbits * cfg.collisions as f64,
        )
        .walking(scene),
    }
}

fn run_on<S: Scene>(
    scene: &S,
    cfg: &SectionConfig,
    opts: &RunOptions,
) -> Result<SectionResult, Error> {
    let geometry = geometry_of(scene, cfg)?;
    work_on(scene, cfg, geometry.as_ref()).check(opts.threads)?;
    let started = Instant::now();
    let lattice = scene.lattice::<f64>(())?;
    let disks = match &geometry {
        Some(g) => Some(g.lattice().clone()),
        None => scene.disk_lattice(),
    };
    let labels = DiskLabels::new(&lattice, disks.as_ref());
    let setup = Setup {
        scene,
        lattice: &lattice,
        field: geometry.as_ref().map(|g| (g, g.field())),
        labels: &labels,
        two_orientations: orbit::two_orientations(&lattice),
        collisions: cfg.collisions,
        classify: cfg.classify_collisions,
        seed: cfg.seed,
        stop: opts.stop.as_ref(),
        progress: opts.progress,
    };
    let flown = par_batches_watched(opts.threads, cfg.trajectories, opts.stop.as_ref(), |i| {
        orbit::fly(&setup, u64::from(i))
    })?;
    let excursion = geometry
        .as_ref()
        .map(|g| Excursion::of(g.lattice(), g.cyclotron_radius()));
    let mut r = collect(scene, cfg, &flown, excursion, geometry.as_ref());
    r.seconds = started.elapsed().as_secs_f64();
    r.meta = RunMeta::new(
        Some(cfg.seed),
        Some(u64::from(cfg.trajectories)),
        Precision::F64,
        Some(opts.threads),
    );
    Ok(r)
}

/// The component of a flown orbit, and whether it is ambiguous.
fn component_of(f: &Flown, excursion: Option<Excursion>) -> (Component, bool) {
    match (f.orbit, excursion) {
        (Some(Orbit::Pinned), _) => (Component::Pinned, false),
        (Some(Orbit::Skipping), _) => (Component::Skipping, false),
        (_, Some(ex)) => match ex.classify(&f.reach) {
            Split::Bounded => (Component::Bounded, false),
            Split::Diffusing => (Component::Diffusing, ex.ambiguous(&f.reach)),
        },
        (_, None) => (Component::Diffusing, false),
    }
}

/// The result of the flown orbits (seconds and provenance left to the caller).
fn collect<S: Scene>(
    scene: &S,
    cfg: &SectionConfig,
    flown: &[Flown],
    excursion: Option<Excursion>,
    g: Option<&FieldGeometry>,
) -> SectionResult {
    let points: usize = flown.iter().map(|f| f.theta.len()).sum();
    let mut r = SectionResult {
        scene: scene.label(),
        field: g.map(FieldGeometry::field),
        cyclotron_radius: g.map(FieldGeometry::cyclotron_radius),
        limit: excursion.map(|e| e.limit),
        pinned: 0,
        skipping: 0,
        bounded: 0,
        diffusing: 0,
        ambiguous_trajectories: 0,
        theta: Vec::with_capacity(points),
        p: Vec::with_capacity(points),
        trajectory: Vec::with_capacity(points),
        disk: Vec::with_capacity(points),
        component: Vec::with_capacity(flown.len()),
        reach: Vec::with_capacity(flown.len()),
        ambiguous: Vec::with_capacity(flown.len()),
        collisions: flown.iter().map(|f| f.collisions).sum(),
        seconds: 0.0,
        config: cfg.clone(),
        meta: RunMeta::new(None, None, Precision::F64, None),
    };
    for (i, f) in flown.iter().enumerate() {
        let (c, ambiguous) = component_of(f, excursion);
        r.theta.extend_from_slice(&f.theta);
        r.p.extend_from_slice(&f.p);
        r.disk.extend_from_slice(&f.disk);
        r.trajectory
            .extend(std::iter::repeat_n(i as u32, f.theta.len()));
        r.component.push(c);
        r.reach.push(f.reach.largest());
        r.ambiguous.push(ambiguous);
    }
    r.pinned = r.count(Component::Pinned);
    r.skipping = r.count(Component::Skipping);
    r.bounded = r.count(Component::Bounded);
    r.diffusing = r.count(Component::Diffusing);
    r.ambiguous_trajectories = r.ambiguous.iter().filter(|a| **a).count() as u32;
    r
}
