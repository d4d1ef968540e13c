//! The hard cases: w → 0, w just below w∞, w = w₀ exactly, flights along a gap edge and through
//! the corner where a gap meets a disk, and very long runs (the 10⁹-collision one is `--ignored`).

use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::kernel::{flight::EventKind, flight::Flight, trap::Trap};
use lorentz_gas::scenes::lattice::{LatticeState, TriangularLattice};
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::triangular::equilibrium_state;
use lorentz_gas::scenes::triangular::geometry::Geometry;
use lorentz_gas::statistics::{CompensatedSum, mean_se, normal_sigma_equivalent_t};
use lorentz_gas::verification::error_model::{ENERGY_BAND_U, ONE_EVENT_U, UNIT_ROUNDOFF};
use lorentz_gas::verification::replay::check_event;
use rug::Float;

/// What [`free_path`] measured over its trajectories.
struct FreePaths {
    /// Mean free path (mean of the trajectories' means).
    mean: f64,
    /// Its standard error: (mean − exact)/SE is Student-t with b − 1 dof; see
    /// [`santalo_within_four_sigma`].
    se: f64,
    /// Trap crossings in all.
    hops: u64,
    /// The longest free flight, from one collision to the next (crossings between them summed),
    /// over every trajectory.
    longest: f64,
    /// Crossings within that longest flight.
    longest_crossings: u64,
}

/// Mean free path over `b` independent trajectories of `n` collisions, and the longest flight.
fn free_path(w: f64, n: u64, b: u64, seed: u64) -> FreePaths {
    let lat = TriangularLattice::new(w).unwrap();
    let mut ls = Vec::new();
    let (mut hops, mut longest, mut longest_crossings) = (0, 0.0f64, 0);
    for k in 0..b {
        let mut s = equilibrium_state(lat.trap(), &mut stream(seed, k));
        let mut t = CompensatedSum::default();
        let mut c = 0;
        // The flight in progress (None before the first collision: the start is not one) and
        // the crossings within it.
        let (mut flight, mut crossings): (Option<f64>, u64) = (None, 0);
        while c < n {
            let ev = lat.step(&mut s).unwrap();
            t.add(ev.time);
            if let Some(f) = flight.as_mut() {
                *f += ev.time;
            }
            match ev.kind {
                EventKind::Collision(_) => {
                    c += 1;
                    if let Some(f) = flight
                        && f > longest
                    {
                        (longest, longest_crossings) = (f, crossings);
                    }
                    (flight, crossings) = (Some(0.0), 0);
                }
                EventKind::Crossing(_) => {
                    hops += 1;
                    crossings += 1;
                }
            }
        }
        ls.push(t.value() / n as f64);
    }
    let (mean, se) = mean_se(&ls);
    FreePaths {
        mean,
        se,
        hops,
        longest,
        longest_crossings,
    }
}

/// Santaló's ⟨ℓ⟩ within "4σ" of a mean over `b` batches: the Student-t quantile with b − 1 dof at
/// the normal's two-sided 4σ tail probability 6.3·10⁻⁵ (16 batches: 5.48; 4 batches would allow
/// 32.6, which is why these runs use 16 shorter trajectories rather than 4 or 8 long ones).
fn santalo_within_four_sigma(w: f64, m: f64, se: f64, b: u64) {
    let exact = Geometry::new(w).unwrap().mean_free_path();
    let k = normal_sigma_equivalent_t(b as f64 - 1.0, 4.0);
    super::physics::within(m, se, exact, k, &format!("w = {w}"));
}

/// w = 10⁻⁶: a gap of a millionth, about 10⁶ collisions per hop. Santaló still holds within 4σ,
/// and the number of hops is Poisson with mean N·3w/π (within 4√mean + 1).
#[test]
fn tiny_gap_w_1e_minus_6() {
    let w = 1e-6;
    let FreePaths { mean, se, hops, .. } = free_path(w, 625_000, 16, 41);
    let g = Geometry::new(w).unwrap();
    santalo_within_four_sigma(w, mean, se, 16);
    let expect = 1e7 / g.collisions_per_hop();
    assert!(
        (hops as f64 - expect).abs() <= 4.0 * expect.sqrt() + 1.0,
        "{hops} hops vs {expect}"
    );
}

/// w = w∞ − 10⁻⁹: corridors almost open, very long flights; Santaló within 4σ and every flight
/// within the proven bound ℓ_max = 12a (`Geometry::max_free_path_bound`,
/// `proofs-notes/max-free-path.md`). A flight is summed in f64 from its events' times (each with
/// a relative error of a few u, `proofs-notes/error-model.md`), so it may exceed its exact length
/// by (crossings + 1)·[`ONE_EVENT_U`]·u·ℓ at most — far below anything the bound could hide.
#[test]
fn just_below_the_horizon_threshold() {
    let w = Geometry::<f64>::w_inf(()) - 1e-9;
    let fp = free_path(w, 500_000, 16, 42);
    santalo_within_four_sigma(w, fp.mean, fp.se, 16);
    let bound = Geometry::new(w).unwrap().max_free_path_bound().unwrap();
    let rounding = (fp.longest_crossings + 1) as f64 * ONE_EVENT_U * UNIT_ROUNDOFF * fp.longest;
    assert!(
        fp.longest <= bound + rounding,
        "w = {w}: a free flight of {} ({} crossings) beyond the proven bound {bound}",
        fp.longest,
        fp.longest_crossings
    );
    eprintln!(
        "w = w_inf - 1e-9: longest of 8e6 flights {:.3} ({} crossings), bound 12a = {bound:.3}",
        fp.longest, fp.longest_crossings
    );
}

/// w = w₀ exactly (the double nearest 2/√3 − 1): collisionless crossings have measure zero there
/// (the only candidates graze P₀ within rounding), so none occur; Santaló holds.
#[test]
fn exactly_at_w0() {
    let w = Geometry::<f64>::w_0(());
    assert_eq!(super::physics::collisionless_crossings(w, 43), 0);
    let fp = free_path(w, 500_000, 16, 44);
    santalo_within_four_sigma(w, fp.mean, fp.se, 16);
}

/// A flight along the edge line y = 0 between disks P₀ and P₁ (through the gap, along its length):
/// it bounces head-on between the two disks for ever, exactly on the line, never crossing.
#[test]
fn flight_along_a_gap_edge_is_an_exact_periodic_orbit() {
    let trap = Trap::new(0.1).unwrap();
    let mut f = Flight::new(Vec2::new(1.0, 0.0), Vec2::new(1.0, 0.0));
    f.excluded_disk = Some(0);
    for k in 0..10_000 {
        let ev = trap.next_event(&f).unwrap();
        let expect = if k % 2 == 0 { 1 } else { 0 };
        assert_eq!(ev.kind, EventKind::Collision(expect), "event {k}");
        assert!(
            (ev.time - (trap.a() - 2.0)).abs() <= 4.0 * f64::EPSILON,
            "flight {k}: {}",
            ev.time
        );
        trap.apply(&mut f, &ev);
        assert_eq!(f.pos.y, 0.0);
        assert_eq!(f.vel.y, 0.0);
        assert_eq!(f.vel.x.abs(), 1.0);
    }
}

/// Rays aimed at the corner where a gap meets a disk (the point at distance 1 from P₀ on each of
/// its edges), from many directions: the kernel's choice (collision or crossing) and its outcome
/// are within the error model, judged by the MPFR replay (a tie there is legitimately ambiguous).
#[test]
fn rays_through_the_gap_disk_corners_are_within_the_model() {
    for &w in &[0.01, 0.1, 0.3] {
        let t64 = Trap::new(w).unwrap();
        let tr = Trap::new(Float::with_val(256, w)).unwrap();
        let c = t64.a() / 2.0;
        let corners = [
            Vec2::new(1.0, 0.0),
            Vec2::new(0.5, 3f64.sqrt() / 2.0),
            Vec2::new(t64.a() - 1.0, 0.0),
        ];
        for corner in corners {
            for k in 0..200 {
                // From points on a small circle around the trap centre towards the corner.
                let ang = k as f64 * 0.0314159;
                let p = Vec2::new(c + 0.1 * ang.cos(), t64.h() / 3.0 + 0.1 * ang.sin());
                let d = corner.sub(&p);
                let n = d.norm2().sqrt();
                let f = Flight::new(p, Vec2::new(d.x / n, d.y / n));
                let chk = check_event(&t64, &tr, &f).unwrap();
                assert!(chk.in_model, "w={w} corner {corner:?} k={k}: {chk:?}");
            }
        }
    }
}

/// 10⁷ f64 collisions (the 10⁹ version is `--ignored`): |v|² − 1 within 128u throughout, and the
/// unwrapped displacement equals the compensated sum of the flight vectors within the random walk
/// of per-event roundings (6·√E·4u·a).
#[test]
fn long_run_speed_and_exact_unwrapped_displacement() {
    long_run(10_000_000);
}

/// The 10⁹-collision version (about a minute single-threaded): `cargo test --release -- --ignored`.
#[test]
#[ignore]
fn billion_collision_run_speed_and_exact_unwrapped_displacement() {
    long_run(1_000_000_000);
}

fn long_run(n: u64) {
    let u = UNIT_ROUNDOFF;
    let lat = TriangularLattice::new(0.1).unwrap();
    let basis = lat.basis_f64();
    let a = basis.a;
    let mut s: LatticeState<f64> = equilibrium_state(lat.trap(), &mut stream(45, 0));
    s.flight.normalise_speed();
    let start = lat.unwrapped(&s, 0.0);
    let (mut sx, mut sy) = (CompensatedSum::default(), CompensatedSum::default());
    let (mut c, mut events, mut worst) = (0u64, 0u64, 0.0f64);
    while c < n {
        let sg = s.cell.sign();
        let (vx, vy) = (sg * s.flight.vel.x, sg * s.flight.vel.y);
        let ev = lat.step(&mut s).unwrap();
        sx.add(ev.time * vx);
        sy.add(ev.time * vy);
        events += 1;
        if let EventKind::Collision(_) = ev.kind {
            c += 1;
            worst = worst.max((s.flight.vel.norm2() - 1.0).abs());
        }
    }
    assert!(worst <= ENERGY_BAND_U * u, "|v|^2 - 1 reached {worst:e}");
    let d = lat.unwrapped(&s, 0.0).displacement_from(&start, &basis);
    let err = ((d[0] - sx.value()).powi(2) + (d[1] - sy.value()).powi(2)).sqrt();
    let bound = 6.0 * (events as f64).sqrt() * 4.0 * u * a;
    assert!(
        err <= bound,
        "displacement {d:?} vs sum ({}, {}): {err:e} > {bound:e}",
        sx.value(),
        sy.value()
    );
    eprintln!(
        "{n} collisions: worst ||v|^2-1| = {:.1}u, displacement {:.1} matches the summed flights to {err:e} (bound {bound:e})",
        worst / u,
        (d[0] * d[0] + d[1] * d[1]).sqrt()
    );
}
