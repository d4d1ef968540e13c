//! Tables given as data in a magnetic field (`theory::magnetic` on many disks of any radii):
//! the exact pinned and skipping shares against phase points drawn from the invariant measure,
//! and the classification against the dynamics — a skipping orbit collides with one disk only,
//! a pinned one with none.

use lorentz_gas::kernel::flight::EventKind;
use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::lattice::LatticeState;
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::theory::magnetic::{FieldGeometry, Orbit};

use super::field::shares_agree;
use super::scene_diffusion::two_radius;
use super::tables::random_table;

/// Binomial 4σ bounds (`shares_agree`, n = 2·10⁵ per case): the shipped table where only
/// skipping orbits are localized (B = 3) and where both kinds are (B = 10), and four random
/// sheared tables of one to three disks in a field of ρ = 1/8 and 1/25.
#[test]
fn localized_shares_of_tables_agree_with_the_exact_ones() {
    let table = two_radius();
    let strong = FieldGeometry::new(table.disk_lattice().unwrap(), 10.0).unwrap();
    assert!(strong.pinned_fraction() > 0.01 && strong.skipping_fraction() > 0.01);
    shares_agree(&table, 3.0, 300);
    shares_agree(&table, 10.0, 301);
    let mut rng = stream(98, 0);
    let mut seed = 310;
    while seed < 314 {
        let Some((table, _)) = random_table(&mut rng) else {
            continue;
        };
        for b in [8.0, 25.0] {
            shares_agree(&table, b, seed);
        }
        seed += 1;
    }
}

/// The world centre of the disk `m` of the cell `s` is in.
fn disk_centre<S: Scene>(scene: &S, s: &LatticeState<f64>, m: u8) -> Vec2<f64> {
    let lat = scene.lattice::<f64>(()).unwrap();
    let c = &lat.cell().disks[m as usize].centre;
    let p = lat.world(s);
    // A table's cells are translates of one another: world = cell offset + position.
    Vec2::new(p.x - s.flight.pos.x + c.x, p.y - s.flight.pos.y + c.y)
}

/// 20 skipping and 20 pinned starts of the shipped table at B = 10, 3000 events each: every
/// collision of a skipping orbit is with one disk (one world centre), a pinned orbit never
/// collides.
#[test]
fn a_skipping_orbit_of_a_table_meets_one_disk_and_a_pinned_one_none() {
    let (table, b) = (two_radius(), 10.0);
    let lat = table.lattice::<f64>(()).unwrap();
    let geo = FieldGeometry::new(table.disk_lattice().unwrap(), b).unwrap();
    let (mut skipping, mut pinned, mut i) = (0, 0, 0);
    while skipping < 20 || pinned < 20 {
        let mut s = table.sample(&mut stream(320, i));
        i += 1;
        let p = lat.world(&s);
        let orbit = geo.classify(p.x, p.y, s.flight.vel.x, s.flight.vel.y);
        let mut centre: Option<Vec2<f64>> = None;
        match orbit {
            Orbit::Skipping if skipping < 20 => skipping += 1,
            Orbit::Pinned if pinned < 20 => pinned += 1,
            _ => continue,
        }
        for _ in 0..3000 {
            let Some(ev) = lat.next_event_in_field(&s, &b) else {
                assert_eq!(orbit, Orbit::Pinned, "start {i}: no next event");
                break;
            };
            lat.apply_in_field(&mut s, &ev);
            let EventKind::Collision(m) = ev.kind else {
                continue;
            };
            assert_eq!(orbit, Orbit::Skipping, "start {i}: a pinned orbit collided");
            let c = disk_centre(&table, &s, m);
            let first = centre.get_or_insert(c.clone());
            assert!(
                (c.x - first.x).abs() < 1e-9 && (c.y - first.y).abs() < 1e-9,
                "start {i}: a skipping orbit met a second disk, {first:?} then {c:?}"
            );
        }
    }
}
