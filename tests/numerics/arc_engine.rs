//! The arc engine (`lorentz_gas::engine::arcs`) against the scalar arc kernel: every lane, on
//! every instruction path this machine has, ends where the generic kernel ends after the same
//! events, bit for bit — from equilibrium starts over six decades of field, and from the fuzz
//! decoder's degenerate starts (grazing, on a surface, at corners, along edges).

use lorentz_gas::engine::SimdPath;
use lorentz_gas::engine::arcs::run_arc_block;
use lorentz_gas::engine::simd::BLOCK;
use lorentz_gas::kernel::cell::{CellKernel, ConvexCell};
use lorentz_gas::kernel::flight::EventKind;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::lattice::{Lattice, LatticeState};
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::square::SquareScene;
use lorentz_gas::scenes::triangular::TriangularScene;
use lorentz_gas::verification::oracle::{SceneParams, decode_field, decode_scene};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus as Gen;

use super::engine::available_paths;

/// The scalar arc kernel's run of `s` until `quota` collisions or `limit` events: its crossings
/// and the events made, and whether it then had no next event (the state is the one before).
fn scalar<K: CellKernel<f64>>(
    lat: &Lattice<f64, K>,
    w: f64,
    s: &mut LatticeState<f64>,
    quota: u64,
    limit: u64,
) -> (u64, u64, bool) {
    let (mut collisions, mut crossings) = (0, 0);
    for n in 0..limit {
        if collisions >= quota {
            return (crossings, n, false);
        }
        let Some(ev) = lat.next_event_in_field(s, &w) else {
            return (crossings, n, true);
        };
        lat.apply_in_field(s, &ev);
        match ev.kind {
            EventKind::Collision(_) => collisions += 1,
            EventKind::Crossing(_) => crossings += 1,
        }
    }
    (crossings, limit, false)
}

/// Runs `states` on `path` and on the scalar kernel and asserts the same end, lane by lane. A
/// lane without a next event stops the block at the step it fails (the lowest such lane is
/// reported); every other lane has then made one event more than that lane.
#[allow(clippy::too_many_arguments)]
fn agree<K: CellKernel<f64>>(
    path: SimdPath,
    cell: &ConvexCell<f64>,
    lat: &Lattice<f64, K>,
    w: f64,
    states: &[LatticeState<f64>],
    quota: u64,
    limit: u64,
    what: &str,
) -> bool {
    let mut lanes = states.to_vec();
    let quotas = vec![quota; states.len()];
    let got = run_arc_block(path, cell, w, &mut lanes, &quotas, limit);
    let runs: Vec<_> = states
        .iter()
        .map(|s| scalar(lat, w, &mut s.clone(), quota, limit))
        .collect();
    let first_lost = (0..states.len())
        .filter(|&l| runs[l].2)
        .min_by_key(|&l| (runs[l].1, l));
    let limit = first_lost.map_or(limit, |l| runs[l].1 + 1);
    let mut want = Vec::new();
    for (l, s) in states.iter().enumerate() {
        let mut s = s.clone();
        want.push(scalar(lat, w, &mut s, quota, limit).0);
        assert_eq!(lanes[l], s, "{what} on {path}: lane {l}");
    }
    match (got, first_lost) {
        (Ok(c), None) => assert_eq!(c, want, "{what} on {path}: crossings"),
        (Err(e), Some(l)) => assert!(
            e.to_string().contains(&format!("trajectory {l} ")),
            "{what} on {path}: {e}"
        ),
        (g, l) => panic!("{what} on {path}: engine {g:?}, scalar lost lane {l:?}"),
    }
    first_lost.is_some()
}

#[test]
fn every_arc_lane_reproduces_the_scalar_kernel_on_every_available_path() {
    let paths = available_paths("arc engine");
    for (i, &gap) in [0.1, 0.3].iter().enumerate() {
        let scene = TriangularScene::new(gap).unwrap();
        let lat = scene.lattice::<f64>(()).unwrap();
        let cell = lat.cell().clone();
        for (k, &b) in [0.1, 1.0, 10.0, -3.0, 1e-5, -300.0].iter().enumerate() {
            let seed = 100 + 10 * i as u64 + k as u64;
            // Starts off pinned orbits (a pinned circle has no event and would stop the block).
            let states: Vec<_> = (0..)
                .map(|l| scene.sample(&mut stream(seed, l)))
                .filter(|s| lat.next_event_in_field(s, &b).is_some())
                .take(BLOCK)
                .collect();
            for &p in &paths {
                let what = format!("w = {gap}, B = {b}");
                let lost = agree(p, &cell, &lat, b, &states, 2000, 200_000, &what);
                assert!(!lost, "{what}: a lane stopped the block");
            }
        }
    }
}

/// The inputs of the arc kernel's libFuzzer findings (`fuzz_oracle.rs`, `regression_arc_*`).
const FINDINGS: [&[u8]; 14] = [
    &[
        255, 48, 127, 0, 0, 0, 0, 0, 0, 2, 225, 102, 7, 0, 0, 1, 64, 53, 49, 0, 51, 53, 83, 202, 0,
        0, 0, 235, 172, 253, 20, 20, 20, 235, 22, 153, 153, 73, 213, 20, 50,
    ],
    &[
        2, 3, 1, 0, 255, 238, 30, 153, 248, 255, 1, 191, 1, 255, 127, 64, 8, 249, 0, 0, 36, 251,
        64, 0, 0, 0, 64, 0, 0, 129, 45, 1, 93, 21, 0,
    ],
    &[
        2, 83, 255, 2, 2, 83, 83, 2, 235, 255, 169, 169, 169, 169, 169, 169, 169, 34, 249, 245, 52,
        20, 20, 20, 2, 2, 20, 0, 166, 2, 29, 2, 83, 2, 235, 235, 255,
    ],
    &[
        2, 64, 126, 131, 2, 5, 126, 74, 12, 0, 223, 217, 217, 217, 217, 4, 0, 0, 217, 0, 0, 217,
        217, 0, 0, 0, 217, 217, 217, 217, 217, 217, 217, 223, 0, 223, 223, 223, 223, 223, 223, 223,
        223, 223, 20, 235, 22, 25, 235, 252,
    ],
    &[
        2, 172, 191, 255, 255, 2, 2, 1, 17, 26, 2, 255, 83, 235, 0, 0, 0, 0, 34, 0, 247, 0, 64, 0,
        219, 4, 119, 0, 129, 0, 0, 0, 0, 0, 1, 231, 32, 9, 238, 255, 21, 0, 37,
    ],
    &[
        254, 249, 252, 0, 0, 0, 255, 122, 6, 250, 0, 0, 1, 221, 255, 4, 0, 3, 0, 255, 225, 0,
    ],
    &[
        0, 64, 83, 126, 2, 131, 2, 19, 2, 17, 26, 26, 235, 26, 26, 126, 235, 25, 60, 235, 235, 86,
        255, 0, 0, 0, 0, 0, 0, 41, 0, 0, 0, 0, 0, 0, 232, 232, 45, 232, 232, 232, 229, 232, 232,
    ],
    &[
        63, 255, 255, 0, 0, 66, 214, 0, 0, 0, 2, 2, 3, 34, 83, 66, 0, 214, 0, 229, 255, 255, 255,
        255, 255, 127, 0, 250, 64, 64, 1, 1, 247, 2, 83, 2, 47, 2, 2, 2, 3, 2, 83, 83, 247, 2, 83,
        2, 83, 2, 47, 2, 2, 2, 3, 2, 83, 83, 2, 2,
    ],
    &[
        255, 171, 0, 129, 0, 0, 0, 231, 0, 0, 2, 104, 1, 0, 254, 254, 254, 254, 254, 0, 235, 254,
        254, 0, 0, 0, 225, 102,
    ],
    &[
        255, 255, 0, 127, 0, 255, 0, 0, 0, 255, 225, 102, 7, 0, 0, 0, 0, 58, 53, 53, 53, 50, 182,
        129, 253, 172, 253, 20, 20, 16, 172, 253, 20, 20, 0,
    ],
    &[
        255, 255, 127, 0, 0, 0, 0, 2, 0, 0, 225, 102, 7, 0, 0, 53, 0, 53, 53, 16, 53, 53, 50, 182,
        129, 253, 172, 45, 37, 20, 20, 16, 20, 0,
    ],
    &[
        2, 0, 127, 0, 0, 0, 0, 0, 0, 2, 225, 102, 7, 0, 0, 53, 0, 53, 53, 16, 53, 53, 0, 50, 4, 0,
        0, 0, 52, 253, 20, 20, 16, 20, 53,
    ],
    &[
        255, 255, 127, 0, 0, 64, 0, 0, 0, 2, 225, 102, 7, 0, 0, 255, 255, 254, 182, 48, 51, 255,
        34, 49, 16, 0, 0, 20, 0,
    ],
    &[
        255, 255, 134, 255, 1, 163, 0, 0, 122, 25, 134, 255, 1, 163, 0, 0, 122, 25, 1, 170, 170,
        170, 170, 170, 170, 170, 255, 255, 255, 255, 255, 255, 1, 170, 170, 170, 170, 170, 170,
        170, 255, 255, 255, 255, 255, 255, 40, 185, 0,
    ],
];

/// Every lane of `data`'s decoded start and field (other lanes hold its mirror image in v_x, so
/// that every lane position is used) on every path; `false` if it decodes to none.
fn decoded_agree(paths: &[SimdPath], data: &[u8], lane: usize) -> bool {
    let Ok(input) = decode_scene(data) else {
        return false;
    };
    let start = LatticeState {
        cell: input.cell,
        flight: input.primitive.flight.clone(),
    };
    let b = decode_field(data);
    match input.primitive.scene {
        SceneParams::Triangular { w } => TriangularScene::new(w)
            .map(|sc| scene_agree(paths, &sc, &start, b, lane, data))
            .is_ok(),
        SceneParams::Square { r } => SquareScene::new(r)
            .map(|sc| scene_agree(paths, &sc, &start, b, lane, data))
            .is_ok(),
    }
}

/// [`decoded_agree`] on a built scene.
fn scene_agree<S: Scene>(
    paths: &[SimdPath],
    scene: &S,
    start: &LatticeState<f64>,
    b: f64,
    lane: usize,
    data: &[u8],
) {
    let lat = scene.lattice::<f64>(()).unwrap();
    let cell = lat.cell().clone();
    let mut states = vec![start.clone(); lane + 1];
    for s in states.iter_mut().take(lane) {
        s.flight.vel.x = -s.flight.vel.x;
    }
    for &p in paths {
        let what = format!("decoded input {data:02x?} ({}, B = {b:e})", scene.label());
        let _ = agree(p, &cell, &lat, b, &states, u64::MAX >> 14, 256, &what);
    }
}

#[test]
fn the_arc_kernels_fuzz_findings_are_reproduced_on_every_available_path() {
    let paths = available_paths("arc engine, fuzz findings");
    let decoded = FINDINGS
        .iter()
        .enumerate()
        .filter(|(i, data)| decoded_agree(&paths, data, i % BLOCK))
        .count();
    assert_eq!(decoded, FINDINGS.len(), "findings that decode to a scene");
}

#[test]
fn degenerate_decoded_starts_are_reproduced_on_every_available_path() {
    let paths = available_paths("arc engine, decoded starts");
    let mut rng = Gen::seed_from_u64(33);
    let mut tried = 0;
    while tried < 1500 {
        let n = rng.random_range(24..72);
        let data: Vec<u8> = (0..n).map(|_| rng.random()).collect();
        if decoded_agree(&paths, &data, tried % BLOCK) {
            tried += 1;
        }
    }
}

#[test]
fn a_recording_block_records_the_scalar_kernels_events_and_a_retired_lane_makes_none() {
    use lorentz_gas::engine::arcs::{ArcBlock, ArcRecord};
    let scene = TriangularScene::new(0.2).unwrap();
    let lat = scene.lattice::<f64>(()).unwrap();
    let b = 1.5;
    // Fewer trajectories than lanes: the lanes beyond them make no event.
    let states: Vec<_> = (0..)
        .map(|l| scene.sample(&mut stream(77, l)))
        .filter(|s| lat.next_event_in_field(s, &b).is_some())
        .take(BLOCK - 3)
        .collect();
    for &p in &available_paths("recording arc block") {
        let mut block = ArcBlock::new(p, lat.cell(), b, &states).unwrap();
        let mut scalar_states = states.clone();
        let mut ring = vec![ArcRecord::default(); 7];
        let mut events = vec![0u32; states.len()];
        for round in 0..30 {
            if round == 10 {
                block.retire(2);
            }
            assert_eq!(block.advance(&mut ring), None, "{p}");
            for rec in &ring {
                for l in BLOCK - 3..BLOCK {
                    assert!(rec.event(l).is_none(), "{p}: lane {l} beyond the states");
                }
                for (l, s) in scalar_states.iter_mut().enumerate() {
                    let Some((before, recorded)) = rec.event(l) else {
                        assert!(l == 2 && round >= 10, "{p}: lane {l} made no event");
                        continue;
                    };
                    assert!(!(l == 2 && round >= 10), "{p}: a retired lane moved");
                    let ev = lat.next_event_in_field(s, &b).unwrap();
                    // The whole event, its velocity on arrival included.
                    assert_eq!((&before, &recorded), (&*s, &ev), "{p}: {l}");
                    lat.apply_in_field(s, &ev);
                    events[l] += 1;
                }
            }
        }
        for (l, s) in scalar_states.iter().enumerate() {
            assert_eq!(&block.state(l), s, "{p}: lane {l} after its events");
        }
        assert_eq!(events[2], 70, "{p}");
        assert!(events.iter().enumerate().all(|(l, &n)| l == 2 || n == 210));
    }
}
