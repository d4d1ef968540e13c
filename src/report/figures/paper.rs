//! The paper's figures regenerated from this crate's own numbers (data in CSV and JSON next to each
//! PNG/SVG, with seed and version). Figs. 2, 7, 8 come from [`crate::estimators::sweep`].

use std::path::Path;

use serde::Serialize;
use serde_json::json;

use super::{PlotSpec, Series, plot};
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::estimators::diffusion::DiffusionConfig;
use crate::estimators::hops::backscatter::{self, BackscatterConfig};
use crate::estimators::hops::{HopsConfig, theory};
use crate::numbers::exact::decimal_grid;
use crate::numbers::precision::Precision;
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::scenes::single_trap::SingleTrap;
use crate::scenes::spec::Table;
use crate::scenes::symbols::Symbol;

/// Default injections of Fig. 5: enough points to show the backscattering regions' shape.
pub const MAP_SAMPLES: u64 = 60_000;
/// Injections between two progress reports of Fig. 5 (a few milliseconds of work).
const MAP_PROGRESS_CHUNK: u64 = 4096;
/// Default injections per gap of Fig. 4a: p_bs to about ±0.001 (binomial, p ≈ 0.37).
pub const CURVE_SAMPLES: u64 = 200_000;
/// Batches per gap of Fig. 4a (errors over 16 batches: 15 degrees of freedom).
pub const CURVE_BATCHES: u32 = 16;
/// Default collisions per gap of Figs. 3, 4b, 6 (for the hop statistics, and again for D).
pub const HIERARCHY_COLLISIONS: u64 = 20_000_000;
/// Batches per gap of Figs. 3, 4b, 6.
pub const HIERARCHY_BATCHES: u32 = 8;
/// Highest order of the lattice walks in Fig. 6b.
pub const HIERARCHY_ORDER: usize = 4;

/// The grids of Fig. 4a: w = 0.01 … 0.30 in steps of 0.01 (all below w∞ = 0.3094), and the inset
/// around the maximum, w = 0.040 … 0.070 in steps of 0.001 — exact decimals.
pub fn backscatter_grids() -> Result<[Vec<f64>; 2], Error> {
    Ok([
        decimal_grid("0.01", "0.30", 30)?,
        decimal_grid("0.04", "0.07", 31)?,
    ])
}

/// The grid of Figs. 3, 4b, 6: w = 0.02 … 0.30 in steps of 0.02.
pub fn hierarchy_grid() -> Result<Vec<f64>, Error> {
    decimal_grid("0.02", "0.30", 15)
}

/// What a figure command wrote.
#[derive(Debug, Clone, Serialize)]
pub struct FigureReport {
    /// Files written (names inside the output directory).
    pub files: Vec<String>,
    /// Version, seed, batches, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// The data file of a figure: its rows (or summary) with the metadata block.
fn write_json(path: &Path, data: serde_json::Value, meta: &RunMeta) -> Result<(), Error> {
    let v = json!({ "data": data, "meta": meta });
    crate::files::write(
        path,
        serde_json::to_string_pretty(&v).map_err(Error::encode)?,
    )?;
    Ok(())
}

fn files(stem: &str) -> Vec<String> {
    ["csv", "json", "png", "svg"]
        .iter()
        .map(|e| format!("{stem}.{e}"))
        .collect()
}

/// Checks, before any work, the directory `dir` and the files `names` a figure writes in it
/// ([`crate::files::check_outputs`]).
fn check_outputs(dir: &Path, names: &[String]) -> Result<(), Error> {
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let mut outputs = vec![crate::files::Output::Dir(dir.to_path_buf())];
    outputs.extend(crate::files::Output::files_in(dir, &names));
    crate::files::check_outputs(&[], &outputs)
}

/// The files [`hierarchy`] writes.
fn hierarchy_files() -> Vec<String> {
    let mut written = vec![
        "fig3-4b-6-hierarchy.csv".to_string(),
        "fig3-4b-6-hierarchy.json".to_string(),
    ];
    for stem in HIERARCHY_STEMS {
        written.push(format!("{stem}.png"));
        written.push(format!("{stem}.svg"));
    }
    written
}

/// Fig. 5: injection conditions (2x/w, sin α) that backscatter at gap `w` (`particles` injected),
/// on one thread. `opts.progress` receives injections done; `opts.stop` ends it within a chunk
/// of injections.
pub fn backscatter_map(
    w: f64,
    particles: u64,
    seed: u64,
    dir: &Path,
    opts: &RunOptions,
) -> Result<FigureReport, Error> {
    let progress = opts.progress;
    crate::scenes::triangular::geometry::check_diffusive_gap(w)?;
    if particles == 0 {
        return Err(Error::Zero { what: "particles" });
    }
    let scene = SingleTrap::new(w)?;
    check_outputs(dir, &files("fig5-backscatter-map"))?;
    crate::files::create_dir_all(dir)?;
    let mut rng = StreamKey::new(seed, Purpose::Injection, 0).rng();
    let mut pts = Vec::new();
    let mut csv = String::from("x_2_over_w,sin_alpha,exit\n");
    for k in 1..=particles {
        if k % MAP_PROGRESS_CHUNK == 0 {
            progress(MAP_PROGRESS_CHUNK);
            if let Some(stop) = &opts.stop {
                stop.check()?;
            }
        }
        let v = scene.random_visit(&mut rng)?;
        csv.push_str(&format!("{},{},{}\n", v.x, v.sin_alpha, v.exit));
        if v.exit == Symbol::Z {
            pts.push((v.x, v.sin_alpha, 0.0));
        }
    }
    progress(particles % MAP_PROGRESS_CHUNK);
    let meta = RunMeta::new(Some(seed), None, Precision::F64, Some(1));
    crate::files::write(dir.join("fig5-backscatter-map.csv"), csv)?;
    write_json(
        &dir.join("fig5-backscatter-map.json"),
        json!({"w": w, "particles": particles, "backscattered": pts.len()}),
        &meta,
    )?;
    plot(
        &dir.join("fig5-backscatter-map"),
        &PlotSpec::new(
            &format!("Injections that backscatter, w = {w} (paper Fig. 5)"),
            "2x/w",
            "sin(alpha)",
        ),
        &[Series {
            label: format!("backscattered ({} of {particles})", pts.len()),
            points: pts,
            notes: Vec::new(),
            line: false,
        }],
    )?;
    Ok(FigureReport {
        files: files("fig5-backscatter-map"),
        meta,
    })
}

/// Fig. 4a: p_bs against w on [`backscatter_grids`] (the curve and the paper's inset), by
/// injection of `particles_per_gap` particles at each gap. Point i of the curve is run i of `seed`, point j of
/// the inset run (curve length + j): no two points share a stream. `opts`: threads, progress (in
/// injections) and stop.
pub fn backscatter_curve(
    particles_per_gap: u64,
    seed: u64,
    dir: &Path,
    opts: &RunOptions,
) -> Result<FigureReport, Error> {
    let threads = opts.threads;
    if particles_per_gap < CURVE_BATCHES as u64 {
        return Err(Error::TooFew {
            what: "particles per gap",
            min: CURVE_BATCHES as u64,
            got: particles_per_gap,
        });
    }
    let [grid, inset] = backscatter_grids()?;
    let mut names = files("fig4a-p-bs");
    names.extend(files("fig4a-inset-p-bs"));
    check_outputs(dir, &names)?;
    crate::files::create_dir_all(dir)?;
    let meta = RunMeta::new(
        Some(seed),
        Some(CURVE_BATCHES as u64),
        Precision::F64,
        Some(threads),
    );
    let curve = Curve {
        particles_per_gap,
        seed,
        dir,
        meta: &meta,
        opts,
    };
    let mut written = Vec::new();
    for (name, ws, first_run) in [
        ("fig4a-p-bs", &grid, 0u64),
        ("fig4a-inset-p-bs", &inset, grid.len() as u64),
    ] {
        curve.panel(name, ws, first_run)?;
        written.extend(files(name));
    }
    Ok(FigureReport {
        files: written,
        meta,
    })
}

/// What the panels of Fig. 4a share: injections per gap, seed, output folder, metadata and run
/// options.
struct Curve<'a> {
    particles_per_gap: u64,
    seed: u64,
    dir: &'a Path,
    meta: &'a RunMeta,
    opts: &'a RunOptions<'a>,
}

impl Curve<'_> {
    /// One panel `name` of Fig. 4a over the gaps `ws` (point i is run `first_run` + i): its CSV,
    /// JSON and figure.
    fn panel(&self, name: &str, ws: &[f64], first_run: u64) -> Result<(), Error> {
        let dir = self.dir;
        let mut rows = Vec::new();
        for (i, &w) in ws.iter().enumerate() {
            let cfg = BackscatterConfig {
                table: Table::triangular_at(w),
                particles: self.particles_per_gap,
                batches: CURVE_BATCHES,
                seed: self.seed,
                run: first_run + i as u64,
                precision: Precision::F64,
            };
            let r = backscatter::run(&cfg, self.opts)?;
            rows.push((w, r.p_bs, r.p_bs_err));
        }
        let mut csv = String::from("w,p_bs,p_bs_err\n");
        for r in &rows {
            csv.push_str(&format!("{},{},{}\n", r.0, r.1, r.2));
        }
        crate::files::write(dir.join(format!("{name}.csv")), csv)?;
        write_json(
            &dir.join(format!("{name}.json")),
            json!({
                "rows": rows
                    .iter()
                    .map(|r| json!({"w": r.0, "p_bs": r.1, "p_bs_err": r.2}))
                    .collect::<Vec<_>>(),
                "particles_per_gap": self.particles_per_gap
            }),
            self.meta,
        )?;
        let third: Vec<(f64, f64, f64)> = ws.iter().map(|&w| (w, 1.0 / 3.0, 0.0)).collect();
        plot(
            &dir.join(name),
            &PlotSpec::new(
                "Backscattering probability (paper Fig. 4a)",
                "gap w",
                "p_bs",
            ),
            &[
                Series {
                    label: "p_bs by injection (error bars: SE)".into(),
                    points: rows,
                    notes: Vec::new(),
                    line: true,
                },
                Series {
                    label: "1/3 (Machta-Zwanzig)".into(),
                    points: third,
                    notes: Vec::new(),
                    line: true,
                },
            ],
        )
    }
}

/// Figs. 3, 4b and 6: on a grid of w, the measured p_cf against App. A (corrected and as printed),
/// D against D_MZ, D_cf, D_bs (Figs. 3b, 4b), the hierarchy D_1 … D_3 combined with collisionless
/// flights (Fig. 6a) and the exact order-k lattice walks k = 1 … 4 (Fig. 6b). D is the Einstein value.
///
/// On [`hierarchy_grid`], `collisions` per gap for the hop statistics (run i of `seed`) and again
/// for D (run grid length + i). Every gap is checked before anything runs. `opts`: threads,
/// progress (in collisions) and stop.
pub fn hierarchy(
    collisions: u64,
    seed: u64,
    dir: &Path,
    opts: &RunOptions,
) -> Result<FigureReport, Error> {
    let threads = opts.threads;
    use crate::estimators::diffusion::run;
    let grid = hierarchy_grid()?;
    let runs = HierarchyRuns {
        collisions,
        seed,
        points: grid.len() as u64,
    };
    for (i, &w) in grid.iter().enumerate() {
        runs.hops(i, w).validate()?;
        runs.einstein(i, w).validate()?;
    }
    check_outputs(dir, &hierarchy_files())?;
    crate::files::create_dir_all(dir)?;
    let mut rows = Vec::new();
    for (i, &w) in grid.iter().enumerate() {
        let t = theory::run(&runs.hops(i, w), opts)?;
        let d = run(&runs.einstein(i, w), opts)?;
        rows.push((w, t, d.D, d.D_err));
    }
    crate::files::write(dir.join("fig3-4b-6-hierarchy.csv"), hierarchy_csv(&rows))?;
    let meta = RunMeta::new(
        Some(seed),
        Some(HIERARCHY_BATCHES as u64),
        Precision::F64,
        Some(threads),
    );
    write_json(
        &dir.join("fig3-4b-6-hierarchy.json"),
        json!({"grid": grid, "collisions_per_gap": collisions}),
        &meta,
    )?;
    hierarchy_plots(&rows, dir)?;
    Ok(FigureReport {
        files: hierarchy_files(),
        meta,
    })
}

/// The figures [`hierarchy`] draws, in order.
const HIERARCHY_STEMS: [&str; 4] = [
    "fig3a-p-cf",
    "fig3b-4b-corrections",
    "fig6a-hierarchy",
    "fig6b-lattice-walks",
];

/// The runs of [`hierarchy`]: `collisions` per gap from `seed` on a grid of `points` gaps.
struct HierarchyRuns {
    collisions: u64,
    seed: u64,
    points: u64,
}

impl HierarchyRuns {
    /// The Einstein D at gap `w`, point `i` (run grid length + i).
    fn einstein(&self, i: usize, w: f64) -> DiffusionConfig {
        let mut c = DiffusionConfig::new(w);
        c.collisions = self.collisions;
        c.batches = HIERARCHY_BATCHES;
        c.seed = self.seed;
        c.run = self.points + i as u64;
        c
    }

    /// The hop statistics at gap `w`, point `i` (run i).
    fn hops(&self, i: usize, w: f64) -> HopsConfig {
        HopsConfig {
            table: Table::triangular_at(w),
            collisions: self.collisions,
            batches: HIERARCHY_BATCHES,
            order: HIERARCHY_ORDER,
            seed: self.seed,
            run: i as u64,
        }
    }
}

/// (w, theory, Einstein D, its error) of one grid point.
type HierarchyRow = (f64, theory::TheoryReport, f64, f64);

/// The CSV of [`hierarchy`]: one line per gap.
fn hierarchy_csv(rows: &[HierarchyRow]) -> String {
    let mut csv = String::from(
        "w,D,D_err,D_MZ,D_cf,D_bs,D_1,D_2,D_3,walk_1,walk_2,walk_3,walk_4,p_cf,p_cf_err,p_cf_app_a,p_cf_app_a_printed\n",
    );
    for (w, t, d, e) in rows {
        csv.push_str(&format!(
            "{w},{d},{e},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            t.D_MZ,
            t.D_cf,
            t.D_bs,
            t.D_1,
            t.orders[1].D_k_combined,
            t.orders[2].D_k_combined,
            t.orders[0].D_lattice_walk,
            t.orders[1].D_lattice_walk,
            t.orders[2].D_lattice_walk,
            t.orders[3].D_lattice_walk,
            t.p_cf,
            t.p_cf_err,
            t.p_cf_appendix_a,
            t.p_cf_appendix_a_as_printed
        ));
    }
    csv
}

/// The four figures of [`hierarchy`] ([`HIERARCHY_STEMS`]) into `dir`.
fn hierarchy_plots(rows: &[HierarchyRow], dir: &Path) -> Result<(), Error> {
    let ser = |label: &str, f: &dyn Fn(&HierarchyRow) -> (f64, f64, f64)| Series {
        label: label.into(),
        points: rows.iter().map(f).collect(),
        notes: Vec::new(),
        line: true,
    };
    let d = |label: &str| ser(label, &|r| (r.0, r.2, r.3));
    let spec = |title: &'static str, y: &'static str| PlotSpec::new(title, "gap w", y);
    plot(
        &dir.join("fig3a-p-cf"),
        &spec(
            "Collisionless flights across a trap (paper Fig. 3a)",
            "p_cf",
        ),
        &[
            ser("measured", &|r| (r.0, r.1.p_cf, r.1.p_cf_err)),
            ser("App. A (flux integral corrected)", &|r| {
                (r.0, r.1.p_cf_appendix_a, 0.0)
            }),
            ser("App. A as printed", &|r| {
                (r.0, r.1.p_cf_appendix_a_as_printed, 0.0)
            }),
        ],
    )?;
    plot(
        &dir.join("fig3b-4b-corrections"),
        &spec("D against D_MZ, D_cf (Fig. 3b) and D_bs (Fig. 4b)", "D"),
        &[
            d("D (Einstein)"),
            ser("D_MZ", &|r| (r.0, r.1.D_MZ, 0.0)),
            ser("D_cf (eq. 4)", &|r| (r.0, r.1.D_cf, 0.0)),
            ser("D_bs (eq. 5)", &|r| (r.0, r.1.D_bs, 0.0)),
        ],
    )?;
    plot(
        &dir.join("fig6a-hierarchy"),
        &spec("Corrected Machta-Zwanzig hierarchy (paper Fig. 6a)", "D"),
        &[
            d("D (Einstein)"),
            ser("D_MZ", &|r| (r.0, r.1.D_MZ, 0.0)),
            ser("D_1 (eq. 6)", &|r| (r.0, r.1.D_1, 0.0)),
            ser("D_2 (App. B corrected)", &|r| {
                (r.0, r.1.orders[1].D_k_combined, 0.0)
            }),
            ser("D_3 (App. B corrected)", &|r| {
                (r.0, r.1.orders[2].D_k_combined, 0.0)
            }),
        ],
    )?;
    plot(
        &dir.join("fig6b-lattice-walks"),
        &spec("Correlated lattice walks, exact D (paper Fig. 6b)", "D"),
        &[
            d("D (Einstein)"),
            ser("order 1", &|r| (r.0, r.1.orders[0].D_lattice_walk, 0.0)),
            ser("order 2", &|r| (r.0, r.1.orders[1].D_lattice_walk, 0.0)),
            ser("order 3", &|r| (r.0, r.1.orders[2].D_lattice_walk, 0.0)),
            ser("order 4", &|r| (r.0, r.1.orders[3].D_lattice_walk, 0.0)),
        ],
    )
}
