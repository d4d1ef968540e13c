use super::*;
use crate::engine::drive;
use crate::scenes::lattice::{TriangularLattice, Unwrapped};
use crate::scenes::sampling::stream;
use crate::scenes::triangular::equilibrium_state;

/// Keeps every event of one trajectory.
struct Record(Vec<EventLanes<1>>);

impl Observer<1> for Record {
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<1>]) {
        self.0
            .extend(steps.iter().filter(|e| e.is_live(0)).cloned());
    }
}

/// The position and velocity at absolute time `at` of a recorded trajectory (flight start
/// times summed in order: the reference, not the observer's countdown).
fn at(events: &[EventLanes<1>], starts: &[f64], at: f64) -> (Unwrapped, [f64; 2]) {
    let k = starts.partition_point(|&s| s <= at) - 1;
    let e = &events[k];
    let sg = e.cell[2][0];
    (
        e.unwrapped(0, at - starts[k]),
        [sg * e.vel[0][0], sg * e.vel[1][0]],
    )
}

/// Against a direct computation from the recorded events (origins at n·spacing, ends at
/// n·spacing + t found by absolute time): the same MSD, VACF per component and Green–Kubo
/// values to the rounding of absolute times (1e-9 relative); at t = 0 the MSD is exactly 0 and
/// the two components of the VACF add up to 1 (speed 1). Broken on purpose (each end taken at
/// ρ + spacing/2 instead of ρ), the MSD at t = 0 is no longer 0 and the comparison fails.
#[test]
fn the_values_are_those_of_a_direct_computation() {
    let lat = TriangularLattice::new(0.2).unwrap();
    let basis = lat.basis_f64();
    let ell = 0.5;
    let times = vec![0.0, 0.3, 0.5, 1.0, 1.7, 4.0, 9.25];
    let grid = TimesGrid::new(times.clone(), ell);
    let mut obs = MsdAtTimes::new(grid.clone(), basis, 1);
    let mut rec = Record(Vec::new());
    let start = equilibrium_state(lat.trap(), &mut stream(4, 1));
    drive(&lat, &mut start.clone(), 3000, &mut obs, &|_| {}).unwrap();
    drive(&lat, &mut start.clone(), 3000, &mut rec, &|_| {}).unwrap();
    let mut starts = vec![0.0];
    for e in &rec.0 {
        starts.push(starts.last().unwrap() + e.time[0]);
    }
    let end = *starts.last().unwrap();
    let v = obs.values(0);
    assert_eq!(v.msd[0], 0.0);
    assert!((v.vacf_x[0] + v.vacf_y[0] - 1.0).abs() < 1e-14, "{v:?}");
    for (k, &t) in times.iter().enumerate() {
        let (mut s, mut n) = ([0.0; 4], 0u64);
        let mut origin = 0.0;
        while origin + t <= end * (1.0 - 1e-12) {
            let (p0, v0) = at(&rec.0, &starts, origin);
            let (p1, v1) = at(&rec.0, &starts, origin + t);
            let d = p1.displacement_from(&p0, &basis);
            s[0] += d[0] * d[0] + d[1] * d[1];
            s[1] += v0[0] * d[0] + v0[1] * d[1];
            s[2] += v0[0] * v1[0];
            s[3] += v0[1] * v1[1];
            n += 1;
            origin += ell;
        }
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * (1.0 + b.abs());
        let n = n as f64;
        assert!(
            close(v.msd[k], s[0] / n),
            "t = {t}: {} {}",
            v.msd[k],
            s[0] / n
        );
        assert!(close(v.green_kubo[k], 0.5 * s[1] / n), "t = {t}");
        assert!(close(v.vacf_x[k], s[2] / n), "t = {t}");
        assert!(close(v.vacf_y[k], s[3] / n), "t = {t}");
    }
}

/// A lane saved in the middle of a run and put back goes on to the bits of the run never
/// stopped; a state of another grid is refused.
#[test]
fn a_saved_lane_resumes_to_the_bits_of_the_run_never_stopped() {
    let lat = TriangularLattice::new(0.15).unwrap();
    let basis = lat.basis_f64();
    let grid = TimesGrid::new(vec![0.0, 0.1, 2.0, 30.0], 0.4);
    let start = equilibrium_state(lat.trap(), &mut stream(9, 1));
    let mut whole = MsdAtTimes::new(grid.clone(), basis, 1);
    drive(&lat, &mut start.clone(), 20_000, &mut whole, &|_| {}).unwrap();
    let mut s = start.clone();
    let mut a = MsdAtTimes::new(grid.clone(), basis, 1);
    drive(&lat, &mut s, 7_000, &mut a, &|_| {}).unwrap();
    let state = a.lane_state(0);
    let json = serde_json::to_string(&state).unwrap();
    let mut b = MsdAtTimes::new(grid, basis, 1);
    b.set_lane_state(0, &serde_json::from_str(&json).unwrap())
        .unwrap();
    drive(&lat, &mut s, 13_000, &mut b, &|_| {}).unwrap();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let (x, y) = (b.values(0), whole.values(0));
    assert_eq!(bits(&x.msd), bits(&y.msd));
    assert_eq!(bits(&x.vacf_x), bits(&y.vacf_x));
    assert_eq!(bits(&x.green_kubo), bits(&y.green_kubo));
    let other = TimesGrid::new(vec![0.0, 100.0], 0.4);
    assert!(
        MsdAtTimes::new(other, basis, 1)
            .set_lane_state(0, &state)
            .is_err()
    );
}

/// Times that are whole spacings have no rest; the ring holds q_max + 1 origins; a long grid
/// spaces its origins out to at most [`MAX_ORIGINS`].
#[test]
fn the_grid_splits_times_into_spacings_and_rests() {
    let g = TimesGrid::new(vec![0.0, 0.25, 1.0, 2.5], 0.5);
    assert_eq!(g.spacing(), 0.5);
    assert_eq!(g.split, vec![(0, 0.0), (0, 0.25), (2, 0.0), (5, 0.0)]);
    assert_eq!(g.order, vec![0, 2, 3, 1]);
    assert_eq!(g.ring(), 6);
    let long = TimesGrid::new(vec![0.0, 1e9], 0.5);
    assert_eq!(long.spacing(), 1e9 / MAX_ORIGINS as f64);
    assert!(long.ring() <= MAX_ORIGINS + 1);
}
