//! The text `lorentz sweep` prints in a magnetic field (the tensor over gaps or a radius and
//! fields, with the Onsager–Casimir checks): the command line writes it to stdout, then the
//! files it wrote, and Python's `str()` of the result is the same text.

use super::line;
use crate::estimators::sweep::field::FieldSweepReport;

/// The sweep's table and its Onsager–Casimir checks.
pub fn field_sweep(r: &FieldSweepReport) -> String {
    let mut out = String::new();
    let c = &r.config;
    let g = match c.field_grid() {
        Ok(g) => g,
        Err(e) => return format!("{e}\n"),
    };
    let (place, scenes) = match (&g.table, &g.radius) {
        (Some(t), _) => ("", t.title().to_string()),
        (None, Some(r)) => ("radius", format!("square lattice, r = {r}")),
        (None, None) => ("w", format!("{} gap(s)", g.gaps.len())),
    };
    // A table has no scene parameter: its rows and checks name the field only.
    let at = |v: f64| {
        if place.is_empty() {
            String::new()
        } else {
            format!("{place} = {v}, ")
        }
    };
    line!(
        out,
        "sweep in a magnetic field: {scenes} x {} field(s), {} collisions in {} batches per point, seed {} ({} points resumed)",
        g.fields.len(),
        c.collisions,
        c.batches,
        c.seed,
        r.resumed_points
    );
    line!(
        out,
        "{place:>8}          B      D_xx         +-        D_xy (Hall)  +-        localized exact  sampled +-"
    );
    for x in &r.rows {
        line!(
            out,
            "{:>8}  {:>9}  {:.6}  {:.6}  {:+.6}  {:.6}  {:.6}         {:.6} {:.6}{}",
            if place.is_empty() {
                String::new()
            } else {
                x.place().to_string()
            },
            x.field,
            x.D_xx,
            x.D_xx_err,
            x.D_xy,
            x.D_xy_err,
            x.localized_fraction_exact,
            x.localized_fraction,
            x.localized_fraction_err,
            if x.all_localized {
                "  (every orbit localized: D = 0 exactly)"
            } else {
                ""
            }
        );
    }
    for o in &r.onsager {
        line!(
            out,
            "Onsager-Casimir at {}|B| = {}: D_xx(B) - D_xx(-B) = {:+.6} {}; D_xy(B) + D_xy(-B) = {:+.6} {}",
            at(o.w.or(o.radius).unwrap_or(0.0)),
            o.field,
            o.d_xx_even.difference,
            o.d_xx_even.describe("Welch"),
            o.d_xy_odd.difference,
            o.d_xy_odd.describe("Welch")
        );
    }
    out
}
