//! The SIMD engine reproduces the scalar kernel bit for bit, lane by lane, event by event, on
//! every instruction path this machine has (AVX-512, AVX2, portable), and the production
//! observables have the same bits on every engine and thread count.

use lorentz_gas::engine::{run_block, SimdPath, BLOCK};
use lorentz_gas::kernel::trap::Trap;
use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::kernel::{Event, Flight};
use lorentz_gas::observables::{EventLanes, Observer};
use lorentz_gas::sampling::stream;
use lorentz_gas::scenes::lattice::{CellIndex, LatticeState, TriangularLattice};
use lorentz_gas::scenes::triangular::equilibrium_state;

/// Every event of every lane, as bits.
struct Record {
    events: Vec<Vec<[u64; 9]>>,
}

fn bits(s: &LatticeState<f64>, e: &Event<f64>) -> [u64; 9] {
    let f = &s.flight;
    let code = match e.kind {
        lorentz_gas::kernel::EventKind::Collision(m) => m as u64,
        lorentz_gas::kernel::EventKind::Crossing(k) => 3 + k as u64,
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
    fn observe<V: lorentz_gas::lanes::Lanes>(&mut self, steps: &[EventLanes<L>]) {
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
fn compare(path: SimdPath, w: f64, starts: &[LatticeState<f64>], quotas: &[u64]) -> usize {
    let lat = TriangularLattice::new(w).unwrap();
    let mut rec = Record {
        events: vec![Vec::new(); BLOCK],
    };
    let mut states = starts.to_vec();
    run_block(path, lat.trap(), &mut states, quotas, &mut rec, &|_| {}).unwrap();
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
                "{path} w={w} lane {l} event {k}"
            );
            if let lorentz_gas::kernel::EventKind::Collision(_) = ev.kind {
                c += 1;
            }
            lat.apply(&mut s, &ev);
            k += 1;
        }
        assert_eq!(rec.events[l].len(), k, "{path} lane {l}: extra events");
        assert_eq!(states[l], s, "{path} lane {l}: final state");
        n += k;
    }
    n
}

const GAPS: [f64; 7] = [0.001, 0.02, 0.05, 0.1, 0.15, 0.25, 0.3];

#[test]
fn every_lane_reproduces_the_scalar_kernel_on_every_path() {
    for path in SimdPath::ALL.into_iter().filter(|p| p.available()) {
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
    }
}

/// The hard cases of `tests/hard_cases.rs` and near-grazing starts, one per lane: the gap
/// widths w = 10⁻⁶, w₀ and just below w∞; the exact periodic orbit along a gap edge (starting
/// on a disk's surface); rays aimed at the corners where a gap meets a disk; flights that graze a
/// disk within a few ulps of tangency from either side; starts exactly on an edge.
#[test]
fn hard_cases_and_grazing_starts_are_reproduced_on_every_path() {
    use lorentz_gas::geometry::Geometry;
    let w_inf = Geometry::<f64>::w_inf(());
    let w0 = Geometry::<f64>::w_0(());
    for path in SimdPath::ALL.into_iter().filter(|p| p.available()) {
        let mut total = 0;
        for w in [1e-6, 0.01, w0, 0.1, w_inf - 1e-9] {
            let trap = Trap::new(w).unwrap();
            let (a, h) = (trap.a, trap.h);
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
            for (m, c) in trap.vertices.iter().enumerate() {
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
    }
}
