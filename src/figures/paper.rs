//! The paper's figures regenerated from this crate's own numbers (data in CSV and JSON next to each
//! PNG/SVG, with seed and version). Figs. 2, 7, 8 come from [`crate::sweep`].

use std::path::Path;

use serde_json::json;

use super::{plot, PlotSpec, Series};
use crate::error::Error;
use crate::hopping::backscatter;
use crate::sampling::stream;
use crate::scenes::single_trap::SingleTrap;
use crate::symbols::Symbol;

fn write_json(path: &Path, v: &serde_json::Value) -> Result<(), Error> {
    std::fs::write(
        path,
        serde_json::to_string_pretty(v).map_err(|e| Error::Io(e.to_string()))?,
    )?;
    Ok(())
}

/// Fig. 5: injection conditions (2x/w, sin α) that backscatter at gap `w` (`samples` injections).
pub fn backscatter_map(w: f64, samples: u64, seed: u64, dir: &Path) -> Result<(), Error> {
    crate::geometry::check_diffusive_gap(w)?;
    std::fs::create_dir_all(dir)?;
    let scene = SingleTrap::new(w)?;
    let mut rng = stream(seed, 0);
    let mut pts = Vec::new();
    let mut csv = String::from("x_2_over_w,sin_alpha,exit\n");
    for _ in 0..samples {
        let v = scene.random_visit(&mut rng)?;
        csv.push_str(&format!("{},{},{}\n", v.x, v.sin_alpha, v.exit));
        if v.exit == Symbol::Z {
            pts.push((v.x, v.sin_alpha, 0.0));
        }
    }
    std::fs::write(dir.join("fig5-backscatter-map.csv"), csv)?;
    write_json(
        &dir.join("fig5-backscatter-map.json"),
        &json!({"w": w, "samples": samples, "backscattered": pts.len(), "seed": seed, "precision": "f64", "version": env!("CARGO_PKG_VERSION")}),
    )?;
    plot(
        &dir.join("fig5-backscatter-map"),
        &PlotSpec {
            title: &format!("Injections that backscatter, w = {w} (paper Fig. 5)"),
            x_label: "2x/w",
            y_label: "sin(alpha)",
            log_x: false,
            log_y: false,
        },
        &[Series {
            label: format!("backscattered ({} of {samples})", pts.len()),
            points: pts,
            notes: Vec::new(),
            line: false,
        }],
    )
}

/// Fig. 4a: p_bs against w on `grid`, and the fine grid `inset` (the paper's inset), by injection.
pub fn backscatter_curve(
    grid: &[f64],
    inset: &[f64],
    visits: u64,
    seed: u64,
    threads: usize,
    dir: &Path,
) -> Result<(), Error> {
    std::fs::create_dir_all(dir)?;
    for (name, ws) in [("fig4a-p-bs", grid), ("fig4a-inset-p-bs", inset)] {
        let mut rows = Vec::new();
        for (i, &w) in ws.iter().enumerate() {
            let r = backscatter(w, visits, 16, seed + i as u64, threads)?;
            rows.push((w, r.p_bs, r.p_bs_err));
        }
        let mut csv = String::from("w,p_bs,p_bs_err\n");
        for r in &rows {
            csv.push_str(&format!("{},{},{}\n", r.0, r.1, r.2));
        }
        std::fs::write(dir.join(format!("{name}.csv")), csv)?;
        write_json(
            &dir.join(format!("{name}.json")),
            &json!({"rows": rows, "visits_per_point": visits, "seed": seed, "precision": "f64", "version": env!("CARGO_PKG_VERSION")}),
        )?;
        let third: Vec<(f64, f64, f64)> = ws.iter().map(|&w| (w, 1.0 / 3.0, 0.0)).collect();
        plot(
            &dir.join(name),
            &PlotSpec {
                title: "Backscattering probability (paper Fig. 4a)",
                x_label: "gap w",
                y_label: "p_bs",
                log_x: false,
                log_y: false,
            },
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
        )?;
    }
    Ok(())
}

/// Figs. 3, 4b and 6: on a grid of w, the measured p_cf against App. A (corrected and as printed),
/// D against D_MZ, D_cf, D_bs (Figs. 3b, 4b), the hierarchy D_1 … D_3 combined with collisionless
/// flights (Fig. 6a) and the exact order-k lattice walks k = 1 … 4 (Fig. 6b). D is the Einstein value.
pub fn hierarchy(
    grid: &[f64],
    collisions: u64,
    seed: u64,
    threads: usize,
    dir: &Path,
) -> Result<(), Error> {
    use crate::diffusion::{run, DiffusionConfig};
    use crate::hopping::theory;
    std::fs::create_dir_all(dir)?;
    let mut rows = Vec::new();
    for (i, &w) in grid.iter().enumerate() {
        let t = theory(w, collisions, 8, 4, seed + i as u64, threads, &|_| {})?;
        let mut c = DiffusionConfig::new(w);
        c.collisions = collisions;
        c.batches = 8;
        c.seed = seed + 100 + i as u64;
        let d = run(&c, threads, None, &|_| {})?;
        rows.push((w, t, d.D, d.D_err));
    }
    let mut csv = String::from("w,D,D_err,D_MZ,D_cf,D_bs,D_1,D_2,D_3,walk_1,walk_2,walk_3,walk_4,p_cf,p_cf_err,p_cf_app_a,p_cf_app_a_printed\n");
    for (w, t, d, e) in &rows {
        csv.push_str(&format!(
            "{w},{d},{e},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            t.D_MZ,
            t.D_cf,
            t.D_bs,
            t.D_1,
            t.D_k[1].2,
            t.D_k[2].2,
            t.lattice_gas_exact[0].1,
            t.lattice_gas_exact[1].1,
            t.lattice_gas_exact[2].1,
            t.lattice_gas_exact[3].1,
            t.p_cf.value,
            t.p_cf.err,
            t.p_cf_appendix_a.0,
            t.p_cf_appendix_a.1
        ));
    }
    std::fs::write(dir.join("fig3-4b-6-hierarchy.csv"), csv)?;
    write_json(
        &dir.join("fig3-4b-6-hierarchy.json"),
        &json!({"grid": grid, "collisions_per_point": collisions, "seed": seed, "precision": "f64", "version": env!("CARGO_PKG_VERSION")}),
    )?;
    /// (w, theory, Einstein D, its error) of one grid point.
    type Row = (f64, crate::hopping::TheoryReport, f64, f64);
    let ser = |label: &str, f: &dyn Fn(&Row) -> (f64, f64, f64)| Series {
        label: label.into(),
        points: rows.iter().map(f).collect(),
        notes: Vec::new(),
        line: true,
    };
    let d = |label: &str| ser(label, &|r| (r.0, r.2, r.3));
    let spec = |title: &'static str, y: &'static str| PlotSpec {
        title,
        x_label: "gap w",
        y_label: y,
        log_x: false,
        log_y: false,
    };
    plot(
        &dir.join("fig3a-p-cf"),
        &spec(
            "Collisionless flights across a trap (paper Fig. 3a)",
            "p_cf",
        ),
        &[
            ser("measured", &|r| (r.0, r.1.p_cf.value, r.1.p_cf.err)),
            ser("App. A (flux integral corrected)", &|r| {
                (r.0, r.1.p_cf_appendix_a.0, 0.0)
            }),
            ser("App. A as printed", &|r| (r.0, r.1.p_cf_appendix_a.1, 0.0)),
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
            ser("D_2 (App. B corrected)", &|r| (r.0, r.1.D_k[1].2, 0.0)),
            ser("D_3 (App. B corrected)", &|r| (r.0, r.1.D_k[2].2, 0.0)),
        ],
    )?;
    plot(
        &dir.join("fig6b-lattice-walks"),
        &spec("Correlated lattice walks, exact D (paper Fig. 6b)", "D"),
        &[
            d("D (Einstein)"),
            ser("order 1", &|r| (r.0, r.1.lattice_gas_exact[0].1, 0.0)),
            ser("order 2", &|r| (r.0, r.1.lattice_gas_exact[1].1, 0.0)),
            ser("order 3", &|r| (r.0, r.1.lattice_gas_exact[2].1, 0.0)),
            ser("order 4", &|r| (r.0, r.1.lattice_gas_exact[3].1, 0.0)),
        ],
    )
}
