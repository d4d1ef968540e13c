//! True shadowing of `f64` orbit segments: Grebogi–Hammel–Yorke–Sauer refinement by Newton's
//! method on the whole segment, in MPFR (`proofs-notes/shadowing.md`).
//!
//! An `f64` segment of N collisions is a pseudo-orbit y⁰ = (x₀, …, x_{N−1}) in Birkhoff
//! coordinates x_k = (s_k, p_k) on the recorded disks c_k (s the polar angle of the contact
//! point, p = sin φ of the outgoing velocity). With T_k the exact billiard map from disk c_k to
//! the *recorded* next disk c_{k+1}, the one-step defects are
//!
//! F_k(y) = T_k(x_k) − x_{k+1},  k = 0 … N−2  (the s component reduced to (−π, π]).
//!
//! A true orbit with the same disk sequence is a zero of F: ℝ^{2N} → ℝ^{2(N−1)}. Newton's method
//! with the minimum-norm correction solves the block-bidiagonal linear system
//!
//! A_k e_k − e_{k+1} = −F_k(y),  A_k = DT_k(x_k) (analytic, at the working precision),
//!
//! as e = −Jᵀ(JJᵀ)⁻¹F: JJᵀ is block tridiagonal with diagonal blocks A_kA_kᵀ + I and
//! off-diagonal blocks −A_{k+1}ᵀ, so a block LDLᵀ sweep solves it in O(N) (no dense N×N
//! solve). Its pivots S_{k+1} = A_{k+1}(I − S_k⁻¹)A_{k+1}ᵀ + I are all ≥ I, so the sweep is
//! stable however hyperbolic the A_k are.
//!
//! **The proof.** At the final iterate y*, with ε = ‖F(y*)‖₂ (evaluated again at twice the
//! working precision) and K ≥ ‖J⁺‖₂ = 1/σ_min(J) (certified by Sylvester's law of inertia: the
//! block LDLᵀ of JJᵀ − μI has positive definite pivots, so λ_min(JJᵀ) > μ and K = 1/√μ), the
//! Newton–Kantorovich argument for a right inverse gives a zero of F within 2Kε of y* provided
//! 4MK²ε ≤ 1, M a Lipschitz constant of DF (i.e. a bound on ‖D²T‖) on that ball. Everything
//! but M is computed (up to MPFR rounding, for which explicit allowances are added); M is
//! *estimated* from the secants of DT along the Newton path and compared with the allowance
//! 1/(4K²ε), which is typically 10³⁰ times larger. δ = max_k ‖x*_k − x⁰_k‖₂ (Euclidean in
//! (s, p)) is then the distance from the `f64` segment to a true orbit up to 2Kε.

use rug::Float;
use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::parallel::par_batches;
use crate::kernel::flight::EventKind;
use crate::kernel::vec2::Vec2;
use crate::scenes::Scene;
use crate::scenes::lattice::LatticeState;
use crate::scenes::motion::MotionInput;
use crate::scenes::sampling::stream;
use crate::verification::curved::ExactMotion;

mod arc;
mod clearance;
mod linear;
mod newton;
mod segment;
mod table;
mod thermo;

use arc::*;
use clearance::*;
use linear::*;
use newton::*;
use segment::*;
use table::*;
use thermo::*;

pub use segment::{f64_segment, f64_segment_in_field, f64_segment_in_thermostat};

// What the certified periodic orbits (`verification::cycles`) share with the shadows.
pub(crate) use clearance::segment_gap;
pub(crate) use linear::{V2, m_mul, m_norm, mv, norm2};
pub(crate) use newton::{Evaluation, evaluate};
pub(crate) use table::{M2, StepFailure};

// The table keeps its one public path, `verification::shadowing::Table` (its module is private).
pub use table::Table;

/// Smallest working precision: 128 bits leave ~75 bits between the `f64` defects (~2⁻⁵³) and
/// the rounding level, room for the quadratic convergence to show and for the proof's margins.
pub const MIN_SHADOW_BITS: u32 = 128;
/// Largest working precision accepted (the cost of one map grows like bits^1.6).
pub const MAX_SHADOW_BITS: u32 = 1 << 16;
/// Longest segment: the range. The cost is O(N) per Newton iteration (about 0.1 s per
/// 10⁴ collisions at 128 bits), so longer segments would work; 10⁴ keeps the memory and time of
/// `--segments` runs predictable.
pub const MAX_COLLISIONS: usize = 10_000;
/// Most Newton iterations: quadratic convergence from ~10⁻¹⁵ reaches the 128-bit rounding level
/// in 2–3 iterations; more than [`MAX_ITERATIONS`] means the linearisation is too poor
/// (near-grazing collisions).
pub const MAX_ITERATIONS: usize = 12;
/// Converged when every defect is below 2^(CONVERGENCE_SLACK_BITS − P)·max(1, 1/cos φ_min):
/// one evaluation of T rounds ~20 operations, amplified by 1/cos φ at the arrival.
pub const CONVERGENCE_SLACK_BITS: i32 = 24;

/// A collision point: the disk (lattice indices (i, j), centre a(i + βj, 0) + (0, hj)) and the
/// Birkhoff coordinates s = θ (polar angle of the contact point) and p = sin φ (outgoing
/// velocity, φ from the outward normal, counter-clockwise).
#[derive(Debug, Clone)]
pub struct OrbitPoint {
    /// Lattice indices (i, j) of the disk.
    pub disk: [i64; 2],
    /// Polar angle θ of the contact point (radians).
    pub s: Float,
    /// sin φ of the outgoing velocity.
    pub p: Float,
}

/// The shadow of one pseudo-orbit: convergence, δ and the ingredients of the proof.
///
/// Norms: a collision point is x = (s, p) ∈ ℝ² with the Euclidean norm (s reduced mod 2π);
/// a segment lives in ℝ^{2N} with the ℓ² norm, F in ℝ^{2(N−1)} likewise.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Shadow {
    /// Collisions N in the segment.
    pub collisions: usize,
    /// Working precision P (bits).
    pub precision_bits: u32,
    /// Newton reached the rounding level (max_k ‖F_k‖ ≤ 2^(24−P)·max(1, 1/cos φ_min)) and the
    /// orbit found is a billiard orbit (no flight passes through another disk).
    pub converged: bool,
    /// Newton corrections applied.
    pub iterations: usize,
    /// δ = max_k ‖x*_k − x⁰_k‖₂ in (s, p) between the shadow and the pseudo-orbit.
    pub delta: Option<f64>,
    /// max_k ‖F_k‖₂ at the last iterate (re-evaluated at 2P bits when converged).
    pub residual: Option<f64>,
    /// ε = ‖F(y*)‖₂ (2P bits) plus the rounding allowance √(N−1)·2^(24−2P)·max(1, 1/cos φ_min).
    pub residual_l2: Option<f64>,
    /// max_k ‖F_k(y⁰)‖₂: the one-step defect of the pseudo-orbit.
    pub pseudo_orbit_defect: Option<f64>,
    /// 2K‖F(y⁰)‖₂: the shadowing lemma's bound on δ (K at y*, an estimate of K at y⁰).
    pub a_priori_bound: Option<f64>,
    /// K ≥ ‖J⁺‖₂ at y*, certified by the inertia of JJᵀ − μI.
    pub inverse_bound: Option<f64>,
    /// 2Kε: an exact orbit lies within this of y* (given the Lipschitz condition below).
    pub correction_bound: Option<f64>,
    /// 1/(4K²ε): the Newton–Kantorovich argument holds if ‖D²T‖ ≤ this on the ball.
    pub lipschitz_allowance: Option<f64>,
    /// Secant estimate of ‖D²T‖: max_k ‖DT(x*_k) − DT(x⁰_k)‖_F / ‖x*_k − x⁰_k‖ (not a bound).
    pub second_derivative_estimate: Option<f64>,
    /// max_k ‖DT(x*_k)‖_F.
    pub max_jacobian_norm: Option<f64>,
    /// Smallest cos φ over the collisions of the last iterate.
    pub min_cos_phi: Option<f64>,
    /// The event of the smallest cos φ.
    pub min_cos_phi_event: Option<usize>,
    /// Smallest distance of a flight of y* from the surface of any other disk.
    pub min_clearance: Option<f64>,
    /// Converged, K certified, 4·(100·M_est)·K²ε ≤ 1, and the ball of radius 2Kε (times
    /// 1 + max‖DT‖) stays away from grazing and from other disks.
    pub certified: bool,
    /// `None`, or why the segment was not shadowed (or not certified).
    pub failure: Option<String>,
    /// The last iterate (the true orbit when converged), at P bits.
    #[serde(skip)]
    pub orbit: Vec<OrbitPoint>,
}

impl Shadow {
    fn failed(n: usize, bits: u32, iterations: usize, y: Vec<OrbitPoint>, why: String) -> Self {
        Shadow {
            collisions: n,
            precision_bits: bits,
            converged: false,
            iterations,
            delta: None,
            residual: None,
            residual_l2: None,
            pseudo_orbit_defect: None,
            a_priori_bound: None,
            inverse_bound: None,
            correction_bound: None,
            lipschitz_allowance: None,
            second_derivative_estimate: None,
            max_jacobian_norm: None,
            min_cos_phi: None,
            min_cos_phi_event: None,
            min_clearance: None,
            certified: false,
            failure: Some(why),
            orbit: y,
        }
    }
}

fn describe(k: usize, e: &StepFailure, y: &[OrbitPoint]) -> String {
    match e {
        StepFailure::Grazing(c) => format!(
            "grazing collision at event {k}: cos phi = {:.3e} (|sin phi| = {:.17}; the map's derivative grows like 1/cos phi)",
            c.to_f64(),
            y[k].p.to_f64().abs()
        ),
        StepFailure::Miss => format!(
            "the flight from event {k} misses the recorded disk ({}, {}): a near-tangent flight, the f64 disk sequence has no true orbit within reach",
            y[k + 1].disk[0],
            y[k + 1].disk[1]
        ),
    }
}

/// The public form of the defects: max-free list of ‖F_k(y)‖₂ for k = 0 … N−2 on the table of
/// `scene` at `bits` (the points are taken exactly if their precision is ≤ `bits`).
///
/// # Errors
/// If `y` has fewer than 2 points, or a step grazes or misses its recorded disk.
pub fn defects<S: Scene>(scene: &S, y: &[OrbitPoint], bits: u32) -> Result<Vec<f64>, Error> {
    if y.len() < 2 {
        return Err(Error::TooFew {
            what: "collisions",
            min: 2,
            got: y.len() as u64,
        });
    }
    let table = Table::new(scene, bits)?;
    let ev = evaluate(&table, y).map_err(|(k, e)| Error::Failed(describe(k, &e, y)))?;
    Ok(ev.f.iter().map(|v| norm2(v).to_f64()).collect())
}

/// Shadows the pseudo-orbit `orbit` (N ≥ 2 collision points with their disks) by a true orbit of
/// `scene` with the same disk sequence, at `bits` ≥ [`MIN_SHADOW_BITS`] of precision.
///
/// A pseudo-orbit that cannot be shadowed (grazing, a missed or blocked flight, no convergence)
/// is an `Ok` with `converged = false` and the reason in `failure`.
///
/// # Errors
/// If N < 2, N > [`MAX_COLLISIONS`], or `bits` is outside [[`MIN_SHADOW_BITS`], [`MAX_SHADOW_BITS`]].
pub fn shadow_pseudo_orbit<S: Scene>(
    scene: &S,
    orbit: &[OrbitPoint],
    bits: u32,
) -> Result<Shadow, Error> {
    shadow_pseudo_orbit_in_field(scene, orbit, bits, None)
}

/// As [`shadow_pseudo_orbit`], in the field `field` (exact; `None` or zero: straight flights):
/// the true orbit's flights are arcs of its cyclotron circles, with the same disk sequence.
///
/// # Errors
/// As [`shadow_pseudo_orbit`].
pub fn shadow_pseudo_orbit_in_field<S: Scene>(
    scene: &S,
    orbit: &[OrbitPoint],
    bits: u32,
    field: Option<&rug::Rational>,
) -> Result<Shadow, Error> {
    let motion = field
        .filter(|q| q.cmp0() != std::cmp::Ordering::Equal)
        .map(|q| ExactMotion::Field(q.clone()));
    shadow_pseudo_orbit_in_motion(scene, orbit, bits, motion.as_ref())
}

/// As [`shadow_pseudo_orbit`], under `motion` (`None`: straight flights): the true orbit's
/// flights are arcs of the magnetic field, or the flights of the thermostatted electric field,
/// with the same disk sequence.
///
/// # Errors
/// As [`shadow_pseudo_orbit`].
pub fn shadow_pseudo_orbit_in_motion<S: Scene>(
    scene: &S,
    orbit: &[OrbitPoint],
    bits: u32,
    motion: Option<&ExactMotion>,
) -> Result<Shadow, Error> {
    check_request(orbit.len(), bits)?;
    let n = orbit.len();
    let table = Table::in_motion(scene, bits, motion)?;
    let lift = |x: &OrbitPoint| OrbitPoint {
        disk: x.disk,
        s: Float::with_val(bits, &x.s),
        p: Float::with_val(bits, &x.p),
    };
    let y0: Vec<OrbitPoint> = orbit.iter().map(lift).collect();
    let mut y = y0.clone();
    let Converged {
        first,
        last,
        iterations,
    } = match newton(&table, &mut y, bits) {
        Ok(c) => c,
        Err((iterations, why)) => return Ok(Shadow::failed(n, bits, iterations, y, why)),
    };
    let mut sh = Shadow::failed(n, bits, iterations, Vec::new(), String::new());
    sh.failure = None;
    sh.converged = true;
    // The defect at twice the precision (the points are exact at 2P).
    let table2 = Table::in_motion(scene, 2 * bits, motion)?;
    let ev2 = match evaluate(&table2, &y) {
        Ok(ev) => ev,
        Err((k, e)) => {
            let why = describe(k, &e, &y);
            return Ok(Shadow::failed(n, bits, iterations, y, why));
        }
    };
    let (eps, f0_l2) = record_defects(&mut sh, &ev2, &first, &last, bits);
    let m_est = record_distance(&mut sh, &y, &y0, &first, &last, bits);
    let amax = last.jac.iter().map(m_norm).fold(0.0, f64::max);
    sh.max_jacobian_norm = Some(amax);
    sh.min_cos_phi = Some(last.cos_min.0);
    sh.min_cos_phi_event = Some(last.cos_min.1);
    let (gap, blocked) = match (&table.omega, &table.thermo) {
        (Some(omega), _) => arc_clearance(&table, &y, &last.tau, omega),
        (None, Some(th)) => thermo_clearance(&table, &y, &last.tau, th),
        (None, None) => clearance(&table, &y, &last.tau),
    };
    sh.min_clearance = Some(gap);
    if let Some((k, d, g)) = blocked {
        sh.converged = false;
        sh.failure = Some(format!(
            "the flight from event {k} passes through disk ({}, {}) (clearance {g:.3e}): a near-tangent flight past a second disk, the f64 disk sequence is not that of a true orbit",
            d[0], d[1]
        ));
        sh.orbit = y;
        return Ok(sh);
    }
    let estimates = Estimates {
        eps,
        f0_l2,
        m_est,
        amax,
        gap,
    };
    certify(&mut sh, &last, bits, &estimates);
    sh.orbit = y;
    Ok(sh)
}
/// Refuses a segment length or precision outside the supported ranges, naming them.
pub fn check_request(n: usize, bits: u32) -> Result<(), Error> {
    Error::unless_in(
        "collisions_per_segment",
        n,
        2..=MAX_COLLISIONS,
        " (a segment needs one step; longer segments: split them)",
    )?;
    Error::unless_in(
        "reference_bits",
        bits,
        MIN_SHADOW_BITS..=MAX_SHADOW_BITS,
        " bits",
    )?;
    Ok(())
}

/// Most segments per run: each keeps its result (and, while it runs, its orbit) in memory.
pub const MAX_SEGMENTS: u32 = 10_000;

/// One shadowed segment of a seeded run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SegmentShadow {
    /// Segment index k: its start is the equilibrium state of `sampling::stream(seed, k)` (the
    /// start of batch k of `lorentz diffusion --seed SEED`), run to its first collision.
    pub segment: u32,
    /// The seed.
    pub start_seed: u64,
    /// The shadow.
    #[serde(flatten)]
    pub shadow: Shadow,
}

/// Shadows of `segments` seeded segments, with a summary.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ShadowReport {
    /// The scene ([`Scene::label`]).
    pub scene: String,
    /// Segments that converged.
    pub converged: u32,
    /// Segments whose shadow is certified (see [`Shadow::certified`]).
    pub certified: u32,
    /// What was run: collisions per segment, segments, seed, working precision.
    pub config: ShadowConfig,
    /// Median δ over the converged segments.
    pub median_delta: Option<f64>,
    /// Largest δ over the converged segments.
    pub max_delta: Option<f64>,
    /// The segments, in order.
    pub segments: Vec<SegmentShadow>,
    /// Version, seed, segments, precision, threads, command line.
    pub meta: RunMeta,
}

/// What [`run`] is asked for.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShadowConfig {
    /// Collisions N of each segment, 2 to [`MAX_COLLISIONS`].
    pub collisions_per_segment: usize,
    /// Segments, 1 to [`MAX_SEGMENTS`].
    pub segments: u32,
    /// Seed of the start streams.
    pub seed: u64,
    /// MPFR working precision P of the true orbit (bits), [`MIN_SHADOW_BITS`] to
    /// [`MAX_SHADOW_BITS`].
    pub reference_bits: u32,
    /// The motion, each parameter an exact decimal or fraction (flattened: the keys `field`,
    /// `electric` and `electric_angle`): a uniform field B with 10⁻³ ≤ |B| ≤ 10³ — the segments
    /// `f64` arc orbits started in the diffusing part (segment k where batch k of the transport
    /// run in the field starts), their shadows true orbits on arcs — or a thermostatted electric
    /// field with 0 < |E| ≤ 10 — `f64` thermostatted orbits from equilibrium starts and true
    /// thermostatted shadows; none: straight flights.
    #[serde(flatten)]
    pub motion: MotionInput,
}

/// The fields true shadowing takes: 10⁻³ ≤ |B| ≤ 10³, those of the transport runs whose segments
/// it shadows.
pub const SHADOW_FIELD_RANGE: (f64, f64) = (1e-3, 1e3);

impl ShadowConfig {
    /// The field, exact, if there is one (`None` for an absent or zero field).
    ///
    /// # Errors
    /// A field that is not an exact decimal or fraction, or outside [`SHADOW_FIELD_RANGE`].
    pub fn field_exact(&self) -> Result<Option<rug::Rational>, Error> {
        super::exact_field(self.motion.field.as_deref(), SHADOW_FIELD_RANGE)
    }

    /// Checks every parameter; errors name the valid range.
    ///
    /// # Errors
    /// A segment length, precision, segment count or field out of range.
    pub fn validate(&self) -> Result<(), Error> {
        check_request(self.collisions_per_segment, self.reference_bits)?;
        Error::unless_in("segments", self.segments, 1..=MAX_SEGMENTS, "")?;
        self.exact_motion()?;
        Ok(())
    }

    /// The motion, exact: the magnetic field, the thermostatted electric one, or `None`
    /// (straight flights).
    ///
    /// # Errors
    /// Both fields, an angle without a strength, or a field not exact or out of its range.
    pub fn exact_motion(&self) -> Result<Option<ExactMotion>, Error> {
        ExactMotion::of(&self.motion, SHADOW_FIELD_RANGE)
    }
}

/// The field of `config` with its exact geometry on `scene`.
///
/// # Errors
/// A bad field, a scene without a disk lattice, or a field in which every orbit is localized.
fn field_of<S: Scene>(
    scene: &S,
    config: &ShadowConfig,
) -> Result<Option<(rug::Rational, crate::theory::magnetic::FieldGeometry)>, Error> {
    let Some(q) = config.field_exact()? else {
        return Ok(None);
    };
    let disks = crate::scenes::require_one_disk_per_cell(scene, "shadow")?;
    let geometry =
        crate::theory::magnetic::FieldGeometry::new(disks, crate::numbers::exact::nearest_f64(&q))?;
    if geometry.all_localized() {
        return Err(Error::parameter(
            "field",
            config.motion.field.as_deref().unwrap_or_default(),
            "every orbit is localized here (pinned or skipping), so no segment diffuses; use a \
             weaker field",
        ));
    }
    Ok(Some((q, geometry)))
}

/// Shadows `segments` segments of `collisions_per_segment` collisions each; segment k starts from the
/// equilibrium state of stream (seed, k). The result does not depend on `options.threads`;
/// `options.progress` receives collision counts.
///
/// # Errors
/// If a parameter is out of range ([`check_request`], 1 ≤ segments ≤ [`MAX_SEGMENTS`]).
pub fn run<S: Scene>(
    scene: &S,
    request: &ShadowConfig,
    options: &RunOptions,
) -> Result<ShadowReport, Error> {
    options.accept("shadow", &[])?;
    request.validate()?;
    let (threads, progress) = (options.threads, options.progress);
    let (collisions, segments, bits) = (
        request.collisions_per_segment,
        request.segments,
        request.reference_bits,
    );
    // Straight flights are shadowed about the disks at the lattice points, arcs by the field's
    // exact geometry: either way a disk is labelled by its lattice point.
    crate::scenes::require_one_disk_per_cell(scene, "shadow")?;
    use crate::engine::work::{Work, mpfr_seconds_per_collision, shadow_collisions_per_collision};
    let lower = &["segments", "collisions_per_segment", "reference_bits"];
    Work::new("shadow", lower, f64::from(segments) * collisions as f64)
        .costing(shadow_collisions_per_collision(bits) * mpfr_seconds_per_collision(bits))
        .check(threads)?;
    let field = field_of(scene, request)?;
    let motion = request.exact_motion()?;
    let out = par_batches(threads, segments, |k| {
        let orbit = seeded_segment(scene, request, field.as_ref(), motion.as_ref(), k)?;
        let mut shadow = shadow_pseudo_orbit_in_motion(scene, &orbit, bits, motion.as_ref())?;
        shadow.orbit = Vec::new();
        progress(collisions as u64);
        Ok(SegmentShadow {
            segment: k,
            start_seed: request.seed,
            shadow,
        })
    })?;
    let mut deltas: Vec<f64> = out
        .iter()
        .filter(|s| s.shadow.converged)
        .filter_map(|s| s.shadow.delta)
        .collect();
    deltas.sort_by(f64::total_cmp);
    let median_delta = (!deltas.is_empty()).then(|| {
        let m = deltas.len();
        if m % 2 == 1 {
            deltas[m / 2]
        } else {
            0.5 * (deltas[m / 2 - 1] + deltas[m / 2])
        }
    });
    Ok(ShadowReport {
        scene: scene.label(),
        config: request.clone(),
        converged: out.iter().filter(|s| s.shadow.converged).count() as u32,
        certified: out.iter().filter(|s| s.shadow.certified).count() as u32,
        median_delta,
        max_delta: deltas.last().copied(),
        segments: out,
        meta: RunMeta::new(
            Some(request.seed),
            Some(segments as u64),
            bits,
            Some(threads),
        ),
    })
}
