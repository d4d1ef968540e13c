//! The cost model's constants measured on this machine (`lorentz bench --costs`): each measured
//! cost beside its floor in [`crate::engine::work`], which should be about half of it (a floor
//! above what is measured would refuse runs this machine could finish).

use std::time::Instant;

use rug::Rational;
use serde::{Deserialize, Serialize};

use super::{ThroughputConfig, median};
use crate::Error;
use crate::engine::Engine;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::work::{self, crossings_per_collision};
use crate::estimators::throughput::long_flights::{self, LongFlightBenchConfig};
use crate::numbers::precision::Precision;
use crate::scenes::Scene;
use crate::scenes::spec::Table;
use crate::scenes::square::SquareScene;
use crate::scenes::triangular::TriangularScene;
use crate::theory::magnetic::FieldGeometry;

/// The precisions MPFR collisions are timed at, with the collisions timed at each.
pub const MPFR_POINTS: [(u32, u64); 4] =
    [(64, 20_000), (1024, 5_000), (16_384, 300), (262_144, 12)];

/// What `lorentz bench --costs` measures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CostsConfig {
    /// Repetitions of each timing (the median is reported), 1 to 1000.
    pub repetitions: usize,
    /// Seed of the starts.
    pub seed: u64,
}

impl Default for CostsConfig {
    fn default() -> Self {
        CostsConfig {
            repetitions: 3,
            seed: 1,
        }
    }
}

/// One constant of the cost model: what was measured and the floor the crate uses.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CostRow {
    /// The cost, in words.
    pub cost: String,
    /// Seconds measured on this machine, one thread (median of the repetitions).
    pub measured: f64,
    /// The floor in `engine::work`, in seconds.
    pub floor: f64,
    /// The floor over the measured cost (about 1/2 by design; above 1 the floor would refuse
    /// work this machine can do).
    pub floor_over_measured: f64,
}

/// The fit a + b·(p/1024)^α of the MPFR collisions measured at 1024 bits and above, the
/// constant term from the lowest precision.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct MpfrFit {
    /// a, seconds.
    pub a: f64,
    /// b, seconds.
    pub b: f64,
    /// α.
    pub alpha: f64,
}

/// The report of `lorentz bench --costs`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Costs {
    /// Each constant, measured and floor.
    pub rows: Vec<CostRow>,
    /// The MPFR fit of the measured collisions (the floors are a fit at about half of it).
    pub mpfr_fit: MpfrFit,
    /// How the numbers were computed.
    pub meta: RunMeta,
}

/// Measures every constant of the cost model on one thread.
///
/// # Errors
/// Repetitions out of range, an interruption, or a failed timing run.
pub fn run(cfg: &CostsConfig, options: &RunOptions) -> Result<Costs, Error> {
    options.accept("the bench of costs", &[])?;
    let mut rows = Vec::new();
    let mut row = |cost: &str, measured: f64, floor: f64| {
        rows.push(CostRow {
            cost: cost.into(),
            measured,
            floor,
            floor_over_measured: floor / measured,
        })
    };
    let w = Table::triangular("1/10")?;
    let simd = throughput(cfg, &w, Precision::F64, None, Engine::Auto, 2_000_000)?;
    row(
        "collision, SIMD engine, f64, w = 0.1",
        simd,
        work::SIMD_SECONDS_PER_COLLISION,
    );
    let scalar = throughput(cfg, &w, Precision::F64, None, Engine::Scalar, 500_000)?;
    row(
        "collision, scalar engine, f64",
        scalar,
        work::SCALAR_SECONDS_PER_COLLISION,
    );
    let mut mpfr = Vec::new();
    for (bits, n) in MPFR_POINTS {
        let t = throughput(cfg, &w, Precision::Bits(bits), None, Engine::Scalar, n)?;
        let floor = work::mpfr_seconds_per_collision(bits);
        row(&format!("collision, MPFR {bits} bits"), t, floor);
        mpfr.push((f64::from(bits), t));
    }
    let arcs = throughput(cfg, &w, Precision::F64, Some(1.0), Engine::Auto, 1_000_000)?;
    row(
        "collision on arcs, SIMD arc engine, B = 1",
        arcs,
        work::ARC_SIMD_SECONDS_PER_COLLISION,
    );
    let arcs1 = throughput(cfg, &w, Precision::F64, Some(1.0), Engine::Scalar, 200_000)?;
    row(
        "collision on arcs, scalar, B = 1",
        arcs1,
        work::ARC_SCALAR_SECONDS_PER_COLLISION,
    );
    let (square, triangular) = walks(cfg, options)?;
    row(
        "cell edge, square walk, r = 1e-4",
        square,
        work::SECONDS_PER_CROSSING,
    );
    row(
        "cell edge, triangular walk, w = 1000",
        triangular,
        work::TRIANGULAR_SECONDS_PER_CROSSING,
    );
    let arc_walk = arc_walk(cfg)?;
    row(
        "cell edge, arcs, square r = 1/1000, B = 1/10",
        arc_walk,
        work::ARC_SECONDS_PER_CROSSING,
    );
    let (row_s, quadrature) = classification(cfg)?;
    row(
        "classification of an orbit in a field",
        row_s,
        work::SECONDS_PER_CLASSIFICATION,
    );
    row(
        "pinned share's quadrature per rows^3, square r = 1/50, B = 1/5",
        quadrature,
        work::QUADRATURE_SECONDS_PER_ROW_POWER,
    );
    Ok(Costs {
        rows,
        mpfr_fit: fit(&mpfr),
        meta: RunMeta::new(Some(cfg.seed), None, Precision::F64, Some(1)),
    })
}

/// Seconds per collision of the throughput bench on `table`, one thread.
fn throughput(
    cfg: &CostsConfig,
    table: &Table,
    precision: Precision,
    field: Option<f64>,
    engine: Engine,
    collisions: u64,
) -> Result<f64, Error> {
    let c = ThroughputConfig {
        precision,
        field,
        collisions_per_thread: collisions,
        repetitions: cfg.repetitions,
        seed: cfg.seed,
        ..ThroughputConfig::new(table.clone())
    };
    let one = RunOptions {
        threads: 1,
        engine,
        ..RunOptions::default()
    };
    Ok(super::run(&c, &one)?.ns_per_collision * 1e-9)
}

/// Seconds per cell edge of the walks (square at r = 10⁻⁴, triangular at w = 1000): a walked
/// collision's time over its crossings, ⟨ℓ⟩/τ.
fn walks(cfg: &CostsConfig, options: &RunOptions) -> Result<(f64, f64), Error> {
    let bench = |radii: Vec<String>, gaps: Vec<String>| {
        let c = LongFlightBenchConfig {
            radii,
            gaps,
            collisions: 10_000,
            walk_collisions: 1_000,
            repetitions: cfg.repetitions,
            seed: cfg.seed,
        };
        let one = RunOptions {
            threads: 1,
            stop: options.stop.clone(),
            ..RunOptions::default()
        };
        let r = long_flights::run(&c, &one)?;
        Ok::<f64, Error>(r.rows[0].walk_ns_per_collision.unwrap_or(f64::NAN) * 1e-9)
    };
    let square = SquareScene::exact(Rational::from((1, 10_000)))?;
    let tri = TriangularScene::exact(Rational::from(1000))?;
    let s = bench(vec!["1/10000".into()], Vec::new())? / crossings_per_collision(&square);
    let t = bench(Vec::new(), vec!["1000".into()])? / crossings_per_collision(&tri);
    Ok((s, t))
}

/// Seconds per cell edge crossed by an arc, collisions and observers included (square lattice,
/// r = 1/1000, B = 1/10: tens of edges a collision), one thread: the difference of two runs'
/// times over the difference of their edges, collisions times the measured mean free time
/// over τ.
fn arc_walk(cfg: &CostsConfig) -> Result<f64, Error> {
    let scene = SquareScene::exact(Rational::from((1, 1000)))?;
    let tau = scene.crossing_time().unwrap_or(f64::NAN);
    let table = Table {
        scene: crate::scenes::spec::SceneSpec::parse("square", None, Some("1/1000"))?,
        motion: crate::scenes::spec::Motion::in_field("1/10"),
    };
    let one = RunOptions {
        threads: 1,
        ..RunOptions::default()
    };
    let timed = |collisions: u64| {
        let c = crate::estimators::diffusion::DiffusionConfig {
            collisions,
            batches: 16,
            seed: cfg.seed,
            localization_samples: Some(1000),
            ..crate::estimators::diffusion::DiffusionConfig::on(table.clone())
        };
        let start = Instant::now();
        let r = crate::estimators::field::run(&c, &one)?;
        let crossings = r.collisions as f64 * r.point.mean_free_time / tau;
        Ok::<_, Error>((start.elapsed().as_secs_f64(), crossings))
    };
    // Two lengths, the set-up (the pinned share, the classification) the same in both.
    let mut times = Vec::new();
    for _ in 0..cfg.repetitions {
        let ((t1, c1), (t2, c2)) = (timed(50_000)?, timed(250_000)?);
        times.push((t2 - t1) / (c2 - c1));
    }
    Ok(median(&times))
}

/// Seconds per classification of an orbit in a field (square lattice, r = 1/4, B = 10⁻³), and of the exact pinned share's quadrature per power 3 of its rows
/// (r = 1/50, B = 1/5).
fn classification(cfg: &CostsConfig) -> Result<(f64, f64), Error> {
    let lattice = |r: i32| {
        let s = SquareScene::exact(Rational::from((1, r)))?;
        s.disk_lattice()
            .ok_or_else(|| Error::Failed("the square lattice has no disk lattice".into()))
    };
    let wide = FieldGeometry::new(lattice(4)?, 1e-3)?;
    let n = 2_000;
    let mut times = Vec::new();
    for rep in 0..cfg.repetitions {
        let start = Instant::now();
        let mut k = 0;
        for i in 0..n {
            let phi = f64::from(i) * 2.399_963 + rep as f64;
            let o = wide.classify(0.5, 0.01 * f64::from(i), phi.cos(), phi.sin());
            k += o as usize;
        }
        std::hint::black_box(k);
        times.push(start.elapsed().as_secs_f64());
    }
    let per_orbit = median(&times) / f64::from(n);
    let narrow = FieldGeometry::new(lattice(50)?, 0.2)?;
    let start = Instant::now();
    std::hint::black_box(narrow.pinned_fraction());
    let rows = narrow.quadrature_rows();
    Ok((
        per_orbit,
        start.elapsed().as_secs_f64() / rows.powf(work::QUADRATURE_EXPONENT),
    ))
}

/// The fit a + b·(p/1024)^α: α by least squares of log t against log p at 1024 bits and above,
/// b their geometric mean of t/(p/1024)^α, a what is left at the lowest precision.
fn fit(points: &[(f64, f64)]) -> MpfrFit {
    let high: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.0 >= 1024.0)
        .map(|&(p, t)| ((p / 1024.0).ln(), t.ln()))
        .collect();
    let n = high.len() as f64;
    let (mx, my) = (
        high.iter().map(|p| p.0).sum::<f64>() / n,
        high.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxy: f64 = high.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = high.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let alpha = sxy / sxx;
    let b = high.iter().map(|p| p.1 - alpha * p.0).sum::<f64>() / n;
    let b = b.exp();
    let (p0, t0) = points[0];
    let a = (t0 - b * (p0 / 1024.0).powf(alpha)).max(0.0);
    MpfrFit { a, b, alpha }
}
