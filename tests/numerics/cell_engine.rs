//! The SIMD lanes of a convex cell (`engine::cells`) reproduce the generic kernel bit for bit,
//! lane by lane, event by event, on every instruction path this machine has: on the shipped
//! two-radius table and on twelve random sheared tables of one to three disks (with their
//! images, up to 16 disks in the cell), from starts drawn from the invariant measure, with
//! unequal quotas so that lanes finish at different steps; and D on a table has the same bits on
//! both engines at any thread count.

use lorentz_gas::engine::cells;
use lorentz_gas::engine::simd::BLOCK;
use lorentz_gas::engine::{Engine, SimdPath};
use lorentz_gas::estimators::diffusion::Sampling;
use lorentz_gas::estimators::diffusion::scene::run_on;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::table::PeriodicTable;

use super::engine::{available_paths, compare_on};
use super::scene_diffusion::two_radius;
use super::tables::random_table;

/// Every event of `BLOCK` lanes of `table` on `path` against the scalar kernel.
fn lanes_of(path: SimdPath, table: &PeriodicTable, seed: u64, quota: u64) -> usize {
    let lat = table.lattice::<f64>(()).unwrap();
    let starts: Vec<_> = (0..BLOCK)
        .map(|l| table.sample(&mut stream(seed, l as u64)))
        .collect();
    let quotas: Vec<u64> = (0..BLOCK).map(|l| quota + 37 * l as u64).collect();
    compare_on(path, (&lat, lat.cell()), &starts, &quotas, &table.label())
}

#[test]
fn every_lane_of_a_table_reproduces_the_scalar_kernel_on_every_available_path() {
    let mut rng = stream(99, 0);
    let mut tables = vec![two_radius()];
    while tables.len() < 13 {
        if let Some((t, _)) = random_table(&mut rng)
            && t.finite_horizon()
            && cells::fits(t.lattice::<f64>(()).unwrap().cell())
        {
            tables.push(t);
        }
    }
    for path in available_paths("every_lane_of_a_table_reproduces_the_scalar_kernel") {
        let total: usize = tables
            .iter()
            .enumerate()
            .map(|(k, t)| lanes_of(path, t, 400 + k as u64, 4000))
            .sum();
        eprintln!("{path}: {total} events identical");
        assert!(total >= 800_000, "{total}");
    }
}

/// D on the shipped table: the scalar engine and the SIMD lanes on one, two and three threads
/// give every field of the result with the same bits (timing and metadata aside).
#[test]
fn d_on_a_table_has_the_same_bits_on_both_engines_and_any_thread_count() {
    let table = two_radius();
    let cfg = Sampling {
        collisions: 1_600_000,
        batches: 20,
        ..Sampling::default()
    };
    let on = crate::common::on_engine;
    let physics = |engine, threads| {
        let r = run_on(&table, &cfg, &on(engine, threads)).unwrap();
        let mut v = serde_json::to_value(&r).unwrap();
        let name = v["meta"]["engine"].as_str().unwrap().to_string();
        for k in ["seconds", "meta"] {
            v.as_object_mut().unwrap().remove(k);
        }
        (v, name)
    };
    let (scalar, name) = physics(Engine::Scalar, 1);
    assert_eq!(name, "scalar");
    for threads in [1, 2, 3] {
        let (simd, name) = physics(Engine::Simd, threads);
        assert_eq!(name, "simd");
        assert_eq!(scalar, simd, "{threads} threads");
    }
}
