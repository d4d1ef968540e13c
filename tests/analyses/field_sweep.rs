//! The sweep in a field (`estimators::sweep::field`): every point is the transport run of its own
//! configuration bit for bit, an interrupted sweep resumes to the same bits at another thread
//! count, an edited point file is refused, and Onsager–Casimir holds over ±B.

use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::field;
use lorentz_gas::estimators::sweep::field::{self as sweep, FieldGrid, FieldSweepRow};
use lorentz_gas::estimators::sweep::point_grid::{PointGrid, point_path};
use lorentz_gas::estimators::sweep::{Grid, SweepConfig};

use crate::common::{scratch, threads};

fn config() -> SweepConfig {
    grid(&["0.1"], &["-1", "1", "5/2"], 1_000_000, 8)
}

fn grid(gaps: &[&str], fields: &[&str], collisions: u64, batches: u32) -> SweepConfig {
    SweepConfig {
        grid: Grid::InField(FieldGrid {
            gaps: gaps.iter().map(|g| g.to_string()).collect(),
            radius: None,
            fields: fields.iter().map(|f| f.to_string()).collect(),
            localization_samples: 20_000,
            table: None,
        }),
        collisions,
        batches,
        seed: 5,
    }
}

#[test]
fn a_field_sweep_is_its_points_runs_and_resumes_to_the_same_bits() {
    let cfg = config();
    let tmp = scratch();
    let dir = tmp.path().join("sweep");
    let with_dir = |t: usize| RunOptions {
        resume: Some(dir.clone()),
        ..threads(t)
    };
    let full = sweep::run(&cfg, &with_dir(2)).unwrap();
    assert_eq!(full.resumed_points, 0);
    let fg = cfg.field_grid().unwrap();
    for (i, (g, f)) in fg.grid().into_iter().enumerate() {
        let alone = field::run(&fg.point_config(&cfg, i, (g, f)).unwrap(), &threads(1)).unwrap();
        let row = &full.rows[i];
        assert_eq!(
            (
                row.D_xx.to_bits(),
                row.D_xy.to_bits(),
                row.D_xx_err.to_bits()
            ),
            (
                alone.point.D_xx.to_bits(),
                alone.point.D_xy.to_bits(),
                alone.point.D_xx_err.to_bits()
            ),
            "point {i}"
        );
        assert_eq!(row.localized_fraction, alone.point.localized_fraction);
    }
    // Distinct streams per point: ±B are independent runs, not one run mirrored.
    assert_ne!(full.rows[0].D_xx, full.rows[1].D_xx);
    let p = loses_a_point_and_refuses_an_edit::<FieldGrid, _>(&dir, "\"D_xx\": 0.", |t| {
        sweep::run(&cfg, &with_dir(t)).map(|r| (r.rows, r.resumed_points))
    });
    assert_eq!(p, full.rows);
    // A directory of another sweep is refused.
    let other = SweepConfig {
        seed: 6,
        ..cfg.clone()
    };
    let err = sweep::run(&other, &with_dir(1)).unwrap_err().to_string();
    assert!(
        err.contains("another sweep") && err.contains("seed"),
        "{err}"
    );
}

#[test]
fn the_sweep_checks_onsager_casimir_over_plus_and_minus_b() {
    let cfg = grid(&["0.1", "0.3"], &["-1", "1", "1/2"], 4_000_000, 16);
    let r = sweep::run(&cfg, &threads(2)).unwrap();
    // One check per gap with ±1; 1/2 has no partner.
    assert_eq!(r.onsager.len(), 2);
    assert!(r.onsager_agrees, "{:#?}", r.onsager);
    for o in &r.onsager {
        assert_eq!(o.field, 1.0);
        // The check has power: a sum that forgot the sign of B, D_xy(B) − D_xy(−B) ≈ 2D_xy,
        // would be far outside the bound.
        let row = r
            .rows
            .iter()
            .find(|x| x.w == o.w && x.field == 1.0)
            .unwrap();
        assert!(
            2.0 * row.D_xy.abs() > 3.0 * o.d_xy_odd.bound * o.d_xy_odd.err,
            "{row:?}"
        );
    }
}

/// The rows of a field sweep for the Onsager–Casimir pairing (no run).
fn onsager_row(w: f64, field: f64, d_xx: f64, d_xy: f64, err: f64) -> FieldSweepRow {
    FieldSweepRow {
        w: Some(w),
        radius: None,
        field,
        cyclotron_radius: 1.0 / field.abs(),
        D_xx: d_xx,
        D_xx_err: err,
        D_xy: d_xy,
        D_xy_err: err,
        pinned_fraction_exact: 0.0,
        skipping_fraction_exact: 0.0,
        localized_fraction_exact: 0.0,
        localized_fraction: 0.0,
        localized_fraction_err: 0.0,
        all_localized: false,
        mean_free_time: 1.0,
        mean_free_time_err: 0.0,
        mean_free_time_exact: 1.0,
        batch_D_xx: Vec::new(),
        batch_D_xy: Vec::new(),
        components: Default::default(),
    }
}

#[test]
fn onsager_pairs_b_with_minus_b_at_the_same_gap_and_catches_a_violation() {
    let rows = [
        onsager_row(0.1, 1.0, 0.10, 0.05, 0.001),
        onsager_row(0.1, -1.0, 0.1005, -0.0495, 0.001),
        onsager_row(0.2, -1.0, 0.3, 0.0, 0.001),
        onsager_row(0.1, 2.0, 0.07, 0.08, 0.001),
    ];
    let c = sweep::onsager(&rows, 16);
    assert_eq!(c.len(), 1);
    assert_eq!((c[0].w, c[0].field), (Some(0.1), 1.0));
    assert!((c[0].d_xx_even.difference + 0.0005).abs() < 1e-15);
    assert!((c[0].d_xy_odd.difference - 0.0005).abs() < 1e-15);
    assert!((c[0].d_xx_even.err - 0.001 * 2f64.sqrt()).abs() < 1e-15);
    assert!(c[0].d_xx_even.agrees() && c[0].d_xy_odd.agrees());
    // A Hall part even in B (the same sign at ±B) is 70 errors from 0.
    let even = [
        onsager_row(0.1, 1.0, 0.10, 0.05, 0.001),
        onsager_row(0.1, -1.0, 0.10, 0.05, 0.001),
    ];
    let c = sweep::onsager(&even, 16);
    assert!(c[0].d_xx_even.agrees() && !c[0].d_xy_odd.agrees(), "{c:?}");
}

/// A sweep whose point 1 was lost (killed mid-sweep) recomputes it and reuses the other two, on
/// one thread, to the same rows (returned); point 2 edited at `key` (its digest left) is refused,
/// naming its file, and left edited.
pub(crate) fn loses_a_point_and_refuses_an_edit<G: PointGrid, R>(
    dir: &std::path::Path,
    key: &str,
    run: impl Fn(usize) -> Result<(Vec<R>, u32), lorentz_gas::Error>,
) -> Vec<R>
where
    R: std::fmt::Debug,
{
    std::fs::remove_file(point_path::<G>(dir, 1)).unwrap();
    let (rows, resumed) = run(1).unwrap();
    assert_eq!(resumed, 2);
    let p = point_path::<G>(dir, 2);
    let text = std::fs::read_to_string(&p).unwrap();
    let edited = text.replacen(key, &key.replace(" 0.", " 1."), 1);
    assert_ne!(edited, text, "{key} is not in the point file");
    std::fs::write(&p, edited).unwrap();
    let err = run(1).unwrap_err().to_string();
    assert!(
        err.contains("point-0002.json") && err.contains("digest"),
        "{err}"
    );
    std::fs::write(&p, text).unwrap();
    rows
}
