//! The SIMD engine reproduces the scalar kernel bit for bit, lane by lane, event by event, on
//! every instruction path this machine has of AVX-512, AVX2 and portable (the portable path runs
//! everywhere; the paths the host lacks are named on stderr, not silently passed over), and the
//! production observables have the same bits on every engine and thread count.

use lorentz_gas::engine::observe::{EventLanes, Observer};
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::engine::simd::BLOCK;
use lorentz_gas::engine::{BlockKernel, SimdPath, run_block};
use lorentz_gas::kernel::cell::CellKernel;
use lorentz_gas::kernel::trap::Trap;
use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::kernel::{flight::Event, flight::Flight};
use lorentz_gas::scenes::lattice::{CellIndex, Lattice, LatticeState, TriangularLattice};
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::spec::Table;
use lorentz_gas::scenes::triangular::equilibrium_state;

/// Every event of every lane, as bits.
struct Record {
    events: Vec<Vec<[u64; 9]>>,
}

fn bits(s: &LatticeState<f64>, e: &Event<f64>) -> [u64; 9] {
    let f = &s.flight;
    let code = match e.kind {
        lorentz_gas::kernel::flight::EventKind::Collision(m) => m as u64,
        lorentz_gas::kernel::flight::EventKind::Crossing(k) => 64 + k as u64,
    };
    [
        e.time.to_bits(),
        code,
        f.pos.x.to_bits(),
        f.pos.y.to_bits(),
        f.vel.x.to_bits(),
        f.vel.y.to_bits(),
        f.excluded_disk.map_or(9, u64::from) * 16 + f.excluded_edge.map_or(9, u64::from),
        s.cell.i as u64,
        s.cell.j as u64 * 2 + s.cell.down as u64,
    ]
}

impl<const L: usize> Observer<L> for Record {
    fn observe<V: lorentz_gas::numbers::lanes::Lanes>(&mut self, steps: &[EventLanes<L>]) {
        for e in steps {
            for l in 0..L {
                if e.is_live(l) {
                    self.events[l].push(bits(&e.state(l), &e.event(l)));
                }
            }
        }
    }
}

/// Runs `starts` on the scalar kernel and on `path`, comparing every event and the final states.
pub(crate) fn compare(
    path: SimdPath,
    w: f64,
    starts: &[LatticeState<f64>],
    quotas: &[u64],
) -> usize {
    let lat = TriangularLattice::new(w).unwrap();
    compare_on(path, (&lat, lat.trap()), starts, quotas, &format!("w={w}"))
}

/// Runs `starts` on the scalar kernel of `lat` and on the lanes of `kernel` (the same kernel) on
/// `path`, comparing every event and the final states; `what` names the case.
pub(crate) fn compare_on<K: CellKernel<f64>, B: BlockKernel>(
    path: SimdPath,
    (lat, kernel): (&Lattice<f64, K>, &B),
    starts: &[LatticeState<f64>],
    quotas: &[u64],
    what: &str,
) -> usize {
    let mut rec = Record {
        events: vec![Vec::new(); BLOCK],
    };
    let mut states = starts.to_vec();
    run_block(path, kernel, &mut states, quotas, &mut rec, &|_| {}).unwrap();
    let mut n = 0;
    for (l, s0) in starts.iter().enumerate() {
        let mut s = s0.clone();
        let mut c = 0;
        let mut k = 0;
        while c < quotas[l] {
            let ev = lat.next_event(&s).unwrap();
            let want = bits(&s, &ev);
            assert_eq!(
                rec.events[l].get(k),
                Some(&want),
                "{path} {what} lane {l} event {k}"
            );
            if let lorentz_gas::kernel::flight::EventKind::Collision(_) = ev.kind {
                c += 1;
            }
            lat.apply(&mut s, &ev);
            k += 1;
        }
        assert_eq!(
            rec.events[l].len(),
            k,
            "{path} {what} lane {l}: extra events"
        );
        assert_eq!(states[l], s, "{path} {what} lane {l}: final state");
        n += k;
    }
    n
}

const GAPS: [f64; 7] = [0.001, 0.02, 0.05, 0.1, 0.15, 0.25, 0.3];

/// The instruction paths this host can run, after naming on stderr those it cannot (a test
/// that compares paths checks only these); the portable path is always among them.
pub(crate) fn available_paths(test: &str) -> Vec<SimdPath> {
    let (run, skipped): (Vec<SimdPath>, Vec<SimdPath>) =
        SimdPath::ALL.into_iter().partition(|p| p.available());
    if !skipped.is_empty() {
        let names: Vec<String> = skipped.iter().map(|p| p.to_string()).collect();
        eprintln!(
            "{test}: skipped the paths this host lacks: {}",
            names.join(", ")
        );
    }
    assert!(
        run.contains(&SimdPath::Portable),
        "{test}: the portable path must always run"
    );
    run
}

#[test]
fn every_lane_reproduces_the_scalar_kernel_on_every_available_path() {
    let paths = available_paths("every_lane_reproduces_the_scalar_kernel");
    let mut ran = Vec::new();
    for path in paths {
        let mut total = 0;
        for (g, &w) in GAPS.iter().enumerate() {
            let trap = Trap::new(w).unwrap();
            let starts: Vec<_> = (0..BLOCK)
                .map(|l| equilibrium_state(&trap, &mut stream(100 + g as u64, l as u64)))
                .collect();
            // Unequal quotas: lanes finish at different steps and must then stand still.
            let quotas: Vec<u64> = (0..BLOCK).map(|l| 8000 + 97 * l as u64).collect();
            total += compare(path, w, &starts, &quotas);
        }
        eprintln!("{path}: {total} events identical");
        assert!(total >= 1_000_000);
        ran.push(path);
    }
    assert!(
        ran.contains(&SimdPath::Portable),
        "the portable path did not run"
    );
}

/// The hard cases of `tests/numerics/hard_cases.rs` and near-grazing starts, one per lane: the gap
/// widths w = 10⁻⁶, w₀ and just below w∞; the exact periodic orbit along a gap edge (starting
/// on a disk's surface); rays aimed at the corners where a gap meets a disk; flights that graze a
/// disk within a few ulps of tangency from either side; starts exactly on an edge.
#[test]
fn hard_cases_and_grazing_starts_are_reproduced_on_every_available_path() {
    use lorentz_gas::scenes::triangular::geometry::Geometry;
    let w_inf = Geometry::<f64>::w_inf(());
    let w0 = Geometry::<f64>::w_0(());
    let paths = available_paths("hard_cases_and_grazing_starts_are_reproduced");
    let mut ran = Vec::new();
    for path in paths {
        let mut total = 0;
        for w in [1e-6, 0.01, w0, 0.1, w_inf - 1e-9] {
            let trap = Trap::new(w).unwrap();
            let (a, h) = (trap.a(), trap.h());
            let unit = |x: f64, y: f64| {
                let n = (x * x + y * y).sqrt();
                Vec2::new(x / n, y / n)
            };
            let mut starts = Vec::new();
            let lane = |f: Flight<f64>| LatticeState {
                cell: CellIndex::default(),
                flight: f,
            };
            // Along the gap edge, bouncing head-on between P₀ and P₁ (on P₀'s surface).
            let mut f = Flight::new(Vec2::new(1.0, 0.0), Vec2::new(1.0, 0.0));
            f.excluded_disk = Some(0);
            starts.push(lane(f));
            // At the gap–disk corners, from the trap centre.
            let centre = Vec2::new(a / 2.0, h / 3.0);
            for corner in [
                Vec2::new(1.0, 0.0),
                Vec2::new(0.5, 3f64.sqrt() / 2.0),
                Vec2::new(a - 1.0, 0.0),
            ] {
                let d = corner.sub(&centre);
                starts.push(lane(Flight::new(centre.clone(), unit(d.x, d.y))));
            }
            // Tangent to each disk from the trap centre, turned by k·10⁻¹⁶ rad: grazing hits
            // and misses within a few ulps of tangency.
            for (m, c) in trap.vertices().iter().enumerate() {
                let d = c.sub(&centre);
                let dist = d.norm2().sqrt();
                let base = d.y.atan2(d.x) + (1.0 / dist).asin();
                for k in [-3.0, 0.0, 3.0] {
                    let ang = base + k * 1e-16 * (m + 1) as f64;
                    starts.push(lane(Flight::new(
                        centre.clone(),
                        Vec2::new(ang.cos(), ang.sin()),
                    )));
                }
            }
            // On an edge (σ = 0), leaving and entering.
            starts.push(lane(Flight::new(Vec2::new(a / 2.0, 0.0), unit(0.3, -1.0))));
            starts.push(lane(Flight::new(Vec2::new(a / 2.0, 0.0), unit(0.3, 1.0))));
            starts.truncate(BLOCK);
            let quotas = vec![3000; starts.len()];
            total += compare(path, w, &starts, &quotas);
        }
        eprintln!("{path}: {total} events of hard starts identical");
        assert!(total > 0, "{path}: no event compared");
        ran.push(path);
    }
    assert!(
        ran.contains(&SimdPath::Portable),
        "the portable path did not run"
    );
}

/// A report as JSON without what may differ between engines and thread counts: the metadata
/// (engine, threads) and the timings (with the precision plan, timed at this run's speed).
fn physics_json<T: serde::Serialize>(r: &T) -> serde_json::Value {
    let mut v = serde_json::to_value(r).unwrap();
    let m = v.as_object_mut().unwrap();
    for k in ["meta", "seconds", "collisions_per_second", "plan"] {
        m.remove(k);
    }
    v
}

/// `diffusion` and `hops` give byte-identical results (D, D_err, the check window, the mean free
/// path, τ, the MSD curve, the longest flight; every hop count and correlation) on the scalar
/// and SIMD engines and on 1 and 2 threads, at w = 0.02, 0.1 and 0.3. 20 batches: one full SIMD
/// block and one with 12 padding lanes.
#[test]
fn diffusion_and_hops_are_identical_on_every_engine() {
    use lorentz_gas::engine::Engine;
    use lorentz_gas::estimators::diffusion::{self, DiffusionConfig};
    use lorentz_gas::estimators::hops::{self, HopsConfig};
    for (w, collisions) in [(0.02, 4_000_000u64), (0.1, 2_000_000), (0.3, 1_000_000)] {
        let mut cfg = DiffusionConfig::new(w);
        cfg.collisions = collisions;
        cfg.batches = 20;
        let runs: Vec<serde_json::Value> = [
            (Engine::Scalar, 1),
            (Engine::Scalar, 2),
            (Engine::Simd, 1),
            (Engine::Simd, 2),
        ]
        .iter()
        .map(|&(e, t)| {
            physics_json(
                &diffusion::run(
                    &cfg,
                    &RunOptions {
                        engine: e,
                        threads: t,
                        ..RunOptions::default()
                    },
                )
                .unwrap(),
            )
        })
        .collect();
        for r in &runs[1..] {
            assert_eq!(r, &runs[0], "diffusion at w = {w}");
        }
        let hops: Vec<serde_json::Value> = [(Engine::Scalar, 2), (Engine::Simd, 1)]
            .iter()
            .map(|&(e, t)| {
                let cfg = HopsConfig {
                    table: Table::triangular_at(w),
                    collisions,
                    batches: 20,
                    order: 3,
                    seed: 5,
                    run: 0,
                };
                let opts = RunOptions {
                    engine: e,
                    threads: t,
                    ..RunOptions::default()
                };
                physics_json(&hops::run(&cfg, &opts).unwrap())
            })
            .collect();
        assert_eq!(hops[0], hops[1], "hops at w = {w}");
    }
}

/// The MSD's coarse grid (time origins every gcd(lags)·τ = 5τ) against origins every τ, on the
/// same trajectories: the batch error of D grows by about 1–2 % (`proofs-notes/msd-grid.md`),
/// and the two estimates of D differ by much less than that error.
#[test]
fn msd_grid_keeps_the_error_of_d() {
    use lorentz_gas::engine::drive;
    use lorentz_gas::estimators::diffusion::DiffusionConfig;
    use lorentz_gas::observers::msd::Msd;
    use lorentz_gas::scenes::triangular::geometry::Geometry;
    use lorentz_gas::statistics::{linear_fit, mean_se};
    let w = 0.1;
    let lat = TriangularLattice::new(w).unwrap();
    let tau = Geometry::new(w).unwrap().hop_time();
    let lags = DiffusionConfig::new(w).lags();
    let mut fine = vec![1];
    fine.extend(&lags);
    let slope = |m: &Msd, window: (usize, usize)| {
        let (mut x, mut y) = (Vec::new(), Vec::new());
        for (k, (&lag, v)) in m.lags().iter().zip(m.values(0)).enumerate() {
            let _ = k;
            if lag >= window.0 && lag <= window.1 {
                x.push(lag as f64 * tau);
                y.push(v);
            }
        }
        linear_fit(&x, &y).1 / 4.0
    };
    let (mut coarse_d, mut fine_d) = (Vec::new(), Vec::new());
    for b in 0..48u64 {
        let mut s = equilibrium_state(lat.trap(), &mut stream(77, b));
        let mut obs = (
            Msd::new(tau, &lags, lat.basis_f64(), 1),
            Msd::new(tau, &fine, lat.basis_f64(), 1),
        );
        drive(&lat, &mut s, 1_500_000, &mut obs, &|_| {}).unwrap();
        assert_eq!(obs.0.dt(), 5.0 * tau);
        assert_eq!(obs.1.dt(), tau);
        coarse_d.push(slope(&obs.0, (10, 40)));
        fine_d.push(slope(&obs.1, (10, 40)));
    }
    let (dc, ec) = mean_se(&coarse_d);
    let (df, ef) = mean_se(&fine_d);
    eprintln!(
        "coarse D = {dc} ± {ec}, fine D = {df} ± {ef}, error ratio {}",
        ec / ef
    );
    assert!((dc - df).abs() < 0.5 * ef, "{dc} vs {df} (± {ef})");
    assert!(ec / ef < 1.05, "error ratio {}", ec / ef);
}

/// A sweep point's runs packed into SIMD blocks give each run's bits of a run alone; with a
/// journal, an interrupted point (some batches finished, one line torn) resumes without redoing
/// the finished batches and ends with the same bits.
#[test]
fn packed_runs_equal_single_runs_and_resume_from_their_journal() {
    use lorentz_gas::engine::Engine;
    use lorentz_gas::estimators::diffusion::{self, DiffusionConfig, run_many};
    let cfgs: Vec<DiffusionConfig> = (0..3)
        .map(|r| {
            let mut c = DiffusionConfig::new(0.25);
            c.collisions = 300_000;
            c.batches = 6;
            c.run = 7 + r;
            c
        })
        .collect();
    let alone: Vec<_> = cfgs
        .iter()
        .map(|c| {
            physics_json(
                &diffusion::run(
                    c,
                    &RunOptions {
                        engine: Engine::Scalar,
                        threads: 1,
                        ..RunOptions::default()
                    },
                )
                .unwrap(),
            )
        })
        .collect();
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    std::fs::create_dir_all(&dir).unwrap();
    let journal = dir.join("point.partial");
    let journaled = RunOptions {
        threads: 2,
        resume: Some(journal.clone()),
        ..RunOptions::default()
    };
    let packed: Vec<_> = run_many(&cfgs, &journaled)
        .unwrap()
        .iter()
        .map(physics_json)
        .collect();
    let strip = |mut v: serde_json::Value| {
        let o = v.as_object_mut().unwrap();
        o.remove("resumed_batches");
        o.remove("resumed_collisions");
        v
    };
    for (a, p) in alone.iter().zip(&packed) {
        assert_eq!(strip(a.clone()), strip(p.clone()));
    }
    // Keep the header and 7 batches, tear the 8th line: 7 batches are reused.
    let text = std::fs::read_to_string(&journal).unwrap();
    let lines: Vec<&str> = text.lines().filter(|l| !l.is_empty()).collect();
    assert_eq!(lines.len(), 1 + 18);
    let mut cut = lines[..8].join("\n");
    cut.push('\n');
    cut.push_str(&lines[8][..lines[8].len() / 2]);
    std::fs::write(&journal, cut).unwrap();
    let done = std::sync::atomic::AtomicU64::new(0);
    let count = |n| {
        done.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
    };
    let resumed = run_many(
        &cfgs,
        &RunOptions {
            progress: &count,
            ..journaled.clone()
        },
    )
    .unwrap();
    let reused: u32 = resumed.iter().map(|r| r.resumed_batches).sum();
    assert_eq!(reused, 7);
    for (a, p) in alone.iter().zip(&resumed) {
        assert_eq!(strip(a.clone()), strip(physics_json(p)));
    }
    assert_eq!(done.into_inner(), 3 * 300_000);
    // A journal of other runs is refused.
    let mut other = cfgs.clone();
    other[0].seed = 99;
    assert!(run_many(&other, &journaled).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The MSD observer in the SIMD lanes against the scalar engine, lane by lane, bit for bit, on
/// every available path: at a grid finer than a flight (several samples in one flight, the
/// observer's rare path), with lanes that finish early (unequal quotas), in the dense layout
/// (largest lag 16 steps) and the sparse one (a lag of 40 steps).
#[test]
fn msd_lanes_equal_the_scalar_engine_at_a_fine_grid_on_every_available_path() {
    use lorentz_gas::engine::drive;
    use lorentz_gas::observers::msd::Msd;
    let w = 0.2;
    let lat = TriangularLattice::new(w).unwrap();
    let basis = lat.basis_f64();
    let starts: Vec<_> = (0..BLOCK)
        .map(|l| equilibrium_state(lat.trap(), &mut stream(808, l as u64)))
        .collect();
    let quotas: Vec<u64> = (0..BLOCK).map(|l| 4000 + 131 * l as u64).collect();
    for (tau, lags) in [(0.02, vec![1, 2, 5, 16]), (0.05, vec![3, 6, 40])] {
        let alone: Vec<Vec<f64>> = (0..BLOCK)
            .map(|l| {
                let mut m = Msd::new(tau, &lags, basis, 1);
                drive(&lat, &mut starts[l].clone(), quotas[l], &mut m, &|_| {}).unwrap();
                m.values(0)
            })
            .collect();
        for path in available_paths("msd_lanes_equal_the_scalar_engine") {
            let mut m = Msd::new(tau, &lags, basis, BLOCK);
            let mut states = starts.clone();
            run_block(path, lat.trap(), &mut states, &quotas, &mut m, &|_| {}).unwrap();
            for (l, want) in alone.iter().enumerate() {
                let got = m.values(l);
                let same = got
                    .iter()
                    .zip(want)
                    .all(|(a, b)| a.to_bits() == b.to_bits());
                assert!(same, "{path} tau {tau} lane {l}: {got:?} vs {want:?}");
            }
        }
    }
}

/// `bench --observer-costs` times each observer set on its own copy of the same starts, and
/// refuses a result whose crossings differ between sets: on both engines the five sets make the
/// same crossings, and the bare engine's cost over itself is 0. (Breaking it on purpose: the
/// hop set started from the next seed fails with "observing Hops changed the crossings".)
#[test]
fn observer_sets_make_the_same_crossings_on_both_engines() {
    use lorentz_gas::engine::Engine;
    use lorentz_gas::estimators::observer_costs::{self, ObserverCostsConfig, SETS};
    for engine in [Engine::Scalar, Engine::Simd] {
        let cfg = ObserverCostsConfig {
            collisions_per_thread: 160_000,
            repetitions: 2,
            ..ObserverCostsConfig::new(Table::triangular_at(0.2))
        };
        let r = observer_costs::run(
            &cfg,
            &RunOptions {
                engine,
                threads: 1,
                ..RunOptions::default()
            },
        )
        .unwrap_or_else(|e| panic!("{engine:?}: {e}"));
        let sets: Vec<_> = r.costs.iter().map(|c| c.observe).collect();
        assert_eq!(sets, SETS);
        assert_eq!(r.costs[0].over_bare, 0.0);
        assert!(
            r.costs.iter().all(|c| c.samples.len() == 2
                && c.ns_per_collision > 0.0
                && c.over_bare.is_finite())
        );
        assert!(r.crossings_per_collision > 0.0 && r.crossings_per_collision < 1.0);
    }
}

/// One trajectory driven in legs (`engine::parallel::in_legs`, how the scalar analyses look at a
/// stop flag mid-batch) ends where one drive of all its collisions ends, bit for bit, walking and
/// jumping. Broken on purpose (a leg that drops its last event, or skips an event between legs),
/// the states differ.
#[test]
fn a_trajectory_in_legs_has_the_bits_of_one_drive() {
    use lorentz_gas::engine::drive;
    use lorentz_gas::engine::long_flight::drive_jumps;
    use lorentz_gas::engine::observe::Nothing;
    use lorentz_gas::engine::parallel::in_legs;
    use lorentz_gas::scenes::Scene;
    use lorentz_gas::scenes::square::SquareScene;
    use lorentz_gas::scenes::triangular::TriangularScene;
    fn state_bits(s: &LatticeState<f64>) -> (i64, i64, bool, [u64; 4]) {
        let f = &s.flight;
        let p = [f.pos.x, f.pos.y, f.vel.x, f.vel.y].map(f64::to_bits);
        (s.cell.i, s.cell.j, s.cell.down, p)
    }
    let n = 100_003;
    let tri = TriangularScene::new(0.1).unwrap();
    let lat = tri.lattice::<f64>(()).unwrap();
    let start = tri.sample(&mut stream(5, 0));
    let (mut one, mut legs) = (start.clone(), start);
    drive(&lat, &mut one, n, &mut Nothing, &|_| {}).unwrap();
    in_legs(None, n, 7_777, |k| {
        drive(&lat, &mut legs, k, &mut Nothing, &|_| {})
    })
    .unwrap();
    assert_eq!(state_bits(&one), state_bits(&legs), "walking");
    let sq = SquareScene::new(1e-3).unwrap();
    let lat = sq.lattice::<f64>(()).unwrap();
    let flights = sq.long_flights().unwrap();
    let start = sq.sample(&mut stream(5, 1));
    let (mut one, mut legs) = (start.clone(), start);
    drive_jumps(&lat, &flights, &mut one, n, &mut Nothing, &|_| {}).unwrap();
    in_legs(None, n, 7_777, |k| {
        drive_jumps(&lat, &flights, &mut legs, k, &mut Nothing, &|_| {})
    })
    .unwrap();
    assert_eq!(state_bits(&one), state_bits(&legs), "jumping");
}
