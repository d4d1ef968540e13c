//! The table's exact validation, images, closed forms and kernel.

use rug::Rational;

use super::spec::TableSpec;
use super::{PeriodicTable, TableError};
use crate::Error;

/// The table error of a refusal.
fn refusal(r: Result<PeriodicTable, Error>) -> TableError {
    match r {
        Err(Error::Table(e)) => *e,
        other => panic!("not a table refusal: {other:?}"),
    }
}
use crate::scenes::Scene;

/// A table on the lattice e1 = (1, 0), e2 = (`b`, `h`) with `disks` (centre x, y, radius).
fn table(b: &str, h: &str, disks: &[(&str, &str, &str)]) -> Result<PeriodicTable, Error> {
    let mut text = format!("[lattice]\ne1 = [\"1\", \"0\"]\ne2 = [\"{b}\", \"{h}\"]\n");
    for (x, y, r) in disks {
        text += &format!("[[disks]]\ncentre = [\"{x}\", \"{y}\"]\nradius = \"{r}\"\n");
    }
    PeriodicTable::new(&TableSpec::from_toml(&text)?)
}

fn two_radii(rm: &str) -> Result<PeriodicTable, Error> {
    table("0", "1", &[("0", "0", "2/5"), ("1/2", "1/2", rm)])
}

#[test]
fn the_two_radius_square_has_five_images_and_santalos_closed_forms() {
    let t = two_radii("1/5").unwrap();
    // The corner disk reaches the cell at its four corners, the centre disk once.
    assert_eq!(t.images.len(), 5);
    assert!(t.finite_horizon() && t.corridor().is_none());
    let pi = std::f64::consts::PI;
    let free = 1.0 - pi * (0.16 + 0.04);
    assert!((t.mean_free_path() - pi * free / (2.0 * pi * 0.6)).abs() < 1e-15);
    // Each edge is free between its two corner disks: L = 4(1 − 4/5).
    let tau = t.crossing_time().unwrap();
    assert!((tau - pi * free / 0.8).abs() < 1e-14, "{tau}");
}

#[test]
fn an_open_corridor_is_named() {
    let t = two_radii("1/20").unwrap();
    let c = t.corridor().unwrap();
    assert_eq!(c.direction, [1, 0]);
    assert!((c.width - 0.05).abs() < 1e-15);
    let e = crate::estimators::diffusion::require_finite_horizon(&t).unwrap_err();
    assert!(matches!(e, Error::OpenCorridor { .. }), "{e}");
    assert!(e.to_string().contains("1 e1 + 0 e2"), "{e}");
}

#[test]
fn overlapping_and_touching_disks_are_refused_naming_both() {
    // |(1/2, 1/2)| = √2/2 = 0.7071 against 2/5 + r: overlap above r = 0.3071, touching never
    // exactly (irrational), so 0.31 overlaps and 0.30 does not.
    assert!(two_radii("0.30").is_ok());
    match refusal(two_radii("0.31")) {
        TableError::Overlap { first, second, .. } => assert_eq!((first, second), (1, 2)),
        other => panic!("{other:?}"),
    }
    // Touching exactly: radii 1/4 + 1/4 at distance 1/2 along x.
    let touch = table("0", "1", &[("0", "0", "1/4"), ("1/2", "0", "1/4")]);
    assert!(matches!(refusal(touch), TableError::Overlap { .. }));
    // A disk touching its own image: radius 1/2 on the unit lattice.
    match refusal(table("0", "1", &[("0", "0", "1/2")])) {
        TableError::Overlap {
            first,
            second,
            shift,
            ..
        } => {
            assert_eq!((first, second), (1, 1));
            assert_ne!(shift, [0, 0]);
        }
        other => panic!("{other:?}"),
    }
    let msg = two_radii("0.31").unwrap_err().to_string();
    assert!(
        msg.contains("disk 1 (centre (0, 0), radius 2/5)") && msg.contains("disk 2"),
        "{msg}"
    );
    assert!(!msg.contains('\n'));
}

#[test]
fn bad_bases_and_radii_are_refused() {
    let basis = |b: &str, h: &str| refusal(table(b, h, &[("0", "0", "1/10")]));
    assert!(matches!(basis("0", "0"), TableError::Basis { .. }));
    assert!(matches!(basis("1/2", "-1"), TableError::Basis { .. }));
    let slanted = TableSpec::from_toml(
        "[lattice]\ne1 = [\"1\", \"1/3\"]\ne2 = [\"0\", \"1\"]\n[[disks]]\ncentre = [0, 0]\nradius = \"1/10\"\n",
    )
    .unwrap();
    let slanted = refusal(PeriodicTable::new(&slanted));
    assert!(matches!(slanted, TableError::Basis { .. }));
    let zero = refusal(table("0", "1", &[("0", "0", "0")]));
    assert!(
        matches!(zero, TableError::Radius { disk: 1, .. }),
        "{zero:?}"
    );
    let none = refusal(table("0", "1", &[]));
    assert!(
        matches!(none, TableError::DiskCount { count: 0 }),
        "{none:?}"
    );
}

/// Centres anywhere in the plane are reduced into the cell exactly: the same table written with
/// shifted centres has the same images.
#[test]
fn centres_are_reduced_into_the_cell_exactly() {
    let a = two_radii("1/5").unwrap();
    let b = table("0", "1", &[("-3", "7", "2/5"), ("5/2", "-1/2", "1/5")]).unwrap();
    assert_eq!(a.images, b.images);
    assert_eq!(a.disks, b.disks);
    // Centres beyond any machine integer reduce exactly too (no index is converted on the way).
    let c = table(
        "0",
        "1",
        &[
            ("1000000000000000000000000000000", "-1e40", "2/5"),
            ("1000000000000000000000000000000.5", "0.5", "1/5"),
        ],
    )
    .unwrap();
    assert_eq!(a.images, c.images);
}

/// A sheared lattice (e2 = (1/3, 1)) with one disk: the kernel's cell holds every image that
/// reaches it, every sampled start is free, and each edge maps the images it carries onto the
/// neighbour's (a disk that leaves through one edge is the same disk entering the other).
#[test]
fn a_sheared_cell_carries_its_images_across_its_edges() {
    let t = table("1/3", "1", &[("1/2", "1/2", "2/5"), ("0", "0", "1/10")]).unwrap();
    let cell = t.kernel::<f64>(()).unwrap();
    assert_eq!(cell.disks.len(), t.images.len());
    let mut rng = <rand_xoshiro::Xoshiro256PlusPlus as rand::SeedableRng>::seed_from_u64(5);
    for _ in 0..1000 {
        let s = t.sample(&mut rng);
        assert!(cell.is_free(&s.flight.pos));
    }
    for e in &cell.edges {
        let back = &cell.edges[e.entered as usize];
        for (k, after) in e.disks_after.iter().enumerate() {
            if let Some(l) = after {
                assert_eq!(back.disks_after[*l as usize], Some(k as u8));
            }
        }
    }
    // Opposite edges carry the same number of images.
    let carried = |k: usize| cell.edges[k].disks_after.iter().flatten().count();
    assert_eq!(carried(0), carried(2));
    assert_eq!(carried(1), carried(3));
}

#[test]
fn a_point_is_located_in_its_cell_exactly() {
    let t = table("1/3", "1", &[("1/2", "1/2", "1/10")]).unwrap();
    let (cell, p) = t
        .locate::<f64>((), &Rational::from((7, 3)), &Rational::from((-1, 2)))
        .unwrap();
    // v = y/h = −1/2 in row j = −1; u = x − b·v = 7/3 + 1/6 = 5/2 in column i = 2; the offset
    // (7/3 − 2 − 1/3·(−1), 1/2) = (2/3, 1/2), rounded once.
    assert_eq!((cell.i, cell.j), (2, -1));
    assert_eq!((p.x, p.y), (2.0 / 3.0, 0.5));
    // A point whose column differs from the one its row's corner gives: (0.95, 0.9) on
    // e2 = (1/3, 1) has u = 0.95 − 0.3 = 0.65 (cell (0, 0)); x − b·⌊v⌋ = 0.95 would say the same,
    // but (1.05, 0.9) has u = 0.75, in cell (0, 0), where x − b·⌊v⌋ = 1.05 says column 1.
    let (cell, p) = t
        .locate::<f64>((), &Rational::from((21, 20)), &Rational::from((9, 10)))
        .unwrap();
    assert_eq!((cell.i, cell.j), (0, 0));
    assert_eq!((p.x, p.y), (1.05, 0.9));
}

/// Hostile numbers are refused before any enumeration (the test would hang otherwise): a radius of 10⁹ on the unit lattice,
/// a cell 10⁻⁹ high, a shear of 10⁹ (the same lattice as no shear: accepted, reduced).
#[test]
fn hostile_scales_are_refused_or_reduced_at_once() {
    assert!(matches!(
        refusal(table("0", "1", &[("0", "0", "1e9")])),
        TableError::Images { .. }
    ));
    assert!(matches!(
        refusal(table("0", "1e-9", &[("0", "0", "1/4")])),
        TableError::Images { .. }
    ));
    let sheared = table("1000000000", "1", &[("0", "0", "1/4")]).unwrap();
    let plain = table("0", "1", &[("0", "0", "1/4")]).unwrap();
    assert_eq!(sheared.images, plain.images);
    assert_eq!(sheared.corridor(), plain.corridor());
}

/// The quarter-turn symmetry, exactly: the shipped table, a pinwheel of four equal disks about
/// the cell's centre, and the same written with a sheared e₂ have it; a disk moved off its
/// place, unequal radii in the pinwheel and a rectangular lattice do not.
#[test]
fn a_quarter_turn_is_found_exactly_and_only_where_it_is() {
    let pinwheel = |r4: &str| {
        table(
            "0",
            "1",
            &[
                ("1/4", "1/2", "1/10"),
                ("1/2", "1/4", "1/10"),
                ("3/4", "1/2", "1/10"),
                ("1/2", "3/4", r4),
            ],
        )
        .unwrap()
    };
    assert!(two_radii("1/5").unwrap().isotropic());
    assert!(pinwheel("1/10").isotropic());
    assert!(!pinwheel("1/11").isotropic());
    assert!(table("1", "1", &[("0", "0", "1/4")]).unwrap().isotropic());
    assert!(
        !table("0", "1", &[("0", "0", "2/5"), ("1/2", "2/5", "1/5")])
            .unwrap()
            .isotropic()
    );
    assert!(!table("0", "2", &[("0", "0", "1/4")]).unwrap().isotropic());
}
