//! The sweep of the driven gas (`estimators::sweep::driven`): every point is the run under the
//! thermostat of its own configuration bit for bit, an interrupted sweep resumes to the same bits
//! at another thread count, J(−E) = −J(E) holds over ±E, and the Einstein extrapolations of the
//! mobility reach the field-free D.

use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::current;
use lorentz_gas::estimators::sweep::driven::{self, DrivenGrid};
use lorentz_gas::estimators::sweep::point_grid::PointGrid;
use lorentz_gas::estimators::sweep::{Grid, SweepConfig};

use crate::common::{scratch, threads};
use crate::field_sweep::loses_a_point_and_refuses_an_edit;

fn grid(electric: &[&str], collisions: u64, batches: u32) -> SweepConfig {
    SweepConfig {
        grid: Grid::Driven(DrivenGrid {
            gaps: vec!["1/5".into()],
            electric: electric.iter().map(|e| e.to_string()).collect(),
            electric_angle: "0".into(),
        }),
        collisions,
        batches,
        seed: 7,
    }
}

#[test]
fn a_driven_sweep_is_its_points_runs_and_resumes_to_the_same_bits() {
    let cfg = grid(&["3/10", "-3/10", "1/10"], 300_000, 8);
    let tmp = scratch();
    let dir = tmp.path().join("sweep");
    let with_dir = |t: usize| RunOptions {
        resume: Some(dir.clone()),
        ..threads(t)
    };
    let full = driven::run(&cfg, &with_dir(2)).unwrap();
    assert_eq!(full.resumed_points, 0);
    let g = DrivenGrid::of(&cfg).unwrap();
    for (i, row) in full.rows.iter().enumerate() {
        let alone = current::run(&g.point(&cfg, i).unwrap(), &threads(1)).unwrap();
        assert_eq!(row.steady, alone.steady, "point {i}");
        assert_eq!(row.batch_J_parallel, alone.batch_J_parallel, "point {i}");
    }
    // Distinct streams per point: ±E are independent runs, not one run mirrored.
    assert_ne!(full.rows[0].steady.mobility, full.rows[1].steady.mobility);
    // J(−E) = −J(E): the mobilities along ±E agree (at the sweep's Bonferroni bound).
    assert_eq!(full.odd.len(), 1);
    assert!(full.odd_agrees, "{:?}", full.odd);
    let rows = loses_a_point_and_refuses_an_edit::<DrivenGrid, _>(&dir, "\"mobility\": 0.", |t| {
        driven::run(&cfg, &with_dir(t)).map(|r| (r.rows, r.resumed_points))
    });
    assert_eq!(rows, full.rows);
}

#[test]
fn a_driven_sweep_refuses_a_zero_field_and_a_repeated_point() {
    let zero = grid(&["0", "1/10"], 100_000, 2)
        .validate()
        .unwrap_err()
        .to_string();
    assert!(
        zero.contains("electric") && zero.contains("0 < |E| <= 10"),
        "{zero}"
    );
    let twice = grid(&["1/10", "0.1"], 100_000, 2)
        .validate()
        .unwrap_err()
        .to_string();
    assert!(twice.contains("appears twice"), "{twice}");
}
