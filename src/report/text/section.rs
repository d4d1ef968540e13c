//! The text `lorentz section` prints (a Poincaré section in Birkhoff coordinates): the command
//! line writes it to stdout, and Python's `str()` of the result is the same text.

use super::line;
use crate::estimators::section::{Component, SectionResult};

/// The text of a section, line by line as the command line prints it.
pub fn section(r: &SectionResult) -> String {
    let mut out = String::new();
    let c = &r.config;
    let field = match (c.table.field(), r.cyclotron_radius) {
        (Some(b), Some(rho)) => format!(", B = {b} (cyclotron radius {rho:.6})"),
        _ => ", no field".to_string(),
    };
    let classify = if r.limit.is_some() {
        format!(" and {} flown to classify", c.classify_collisions)
    } else {
        String::new()
    };
    line!(
        out,
        "Poincaré section in Birkhoff coordinates, {}{field}  (seed {}, {} trajectories, {} collisions \
         recorded{} per trajectory, {:.3e} collisions, {:.1} s)",
        r.scene,
        c.seed,
        c.trajectories,
        c.collisions,
        classify,
        r.collisions as f64,
        r.seconds
    );
    line!(
        out,
        "trajectories: {} pinned, {} skipping, {} bounded (regular islands), {} diffusing  ({} points)",
        r.pinned,
        r.skipping,
        r.bounded,
        r.diffusing,
        r.theta.len()
    );
    match r.limit {
        Some(limit) => {
            line!(
                out,
                "excursion limit {limit:.6}: a trajectory that stays within it is bounded; largest \
                 reach of a bounded one {}, smallest of a diffusing one {}",
                extreme(r, Component::Bounded, f64::max),
                extreme(r, Component::Diffusing, f64::min)
            );
        }
        None => line!(out, "without a field every orbit diffuses"),
    }
    let ambiguous: Vec<String> = (r.ambiguous.iter().enumerate())
        .filter(|(_, a)| **a)
        .map(|(i, _)| format!("{i} (reach {:.3})", r.reach[i]))
        .collect();
    if !ambiguous.is_empty() {
        line!(
            out,
            "ambiguous: {} diffusing trajectories within {} limits: {} — use more --classify-collisions",
            ambiguous.len(),
            crate::observers::excursion::Excursion::AMBIGUOUS,
            ambiguous.join(", ")
        );
    }
    out
}

/// The largest (`pick` = max) or smallest reach of the orbits of component `c`, or "none".
fn extreme(r: &SectionResult, c: Component, pick: fn(f64, f64) -> f64) -> String {
    (r.component.iter().zip(&r.reach))
        .filter(|(x, _)| **x == c)
        .map(|(_, d)| *d)
        .reduce(pick)
        .map_or("none".into(), |d| format!("{d:.3}"))
}
