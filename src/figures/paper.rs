//! The paper's figures regenerated from this crate's own numbers (data in CSV and JSON next to each
//! PNG/SVG, with seed and version). Figs. 2, 7, 8 come from [`crate::sweep`].

use std::path::Path;

use serde_json::json;

use super::{plot, PlotSpec, Series};
use crate::error::Error;
use crate::hopping::backscatter;
use crate::sampling::stream;
use crate::scenes::single_trap::{Exit, SingleTrap};

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
        let e = match v.exit {
            Exit::Z => "z",
            Exit::L => "l",
            Exit::R => "r",
        };
        csv.push_str(&format!("{},{},{}\n", v.x, v.sin_alpha, e));
        if v.exit == Exit::Z {
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
