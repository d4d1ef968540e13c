//! Named regression tests of the arc kernel (flights in a magnetic field) from the libFuzzer
//! campaigns and the statistical sweeps of `fuzz_oracle`: each degenerate state that once
//! failed, replayed through the oracle (`proofs-notes/fuzzing.md`).

use lorentz_gas::verification::oracle::arc_kernel;

/// The fourth libFuzzer campaign: triangular w = 0.329, B = 1 (cyclotron radius = r), a
/// particle near a disk whose cyclotron circle nearly coincides with it (M = 2.3·10⁻⁹). The
/// radical-line contact missed the disk by u/M (2.3·10⁻⁸ inside it), and the particle, hugging
/// the disk along its arc, was still 1.2·10⁻⁸ inside it after the next crossing. Such contacts
/// are now found in the disk's frame, on the circle to a few u
/// (`fuzz/artifacts/arc_kernel/crash-4b92…`).
#[test]
fn regression_arc_on_a_disk_whose_cyclotron_circle_nearly_coincides_with_it() {
    let data: [u8; 22] = [
        254, 249, 252, 0, 0, 0, 255, 122, 6, 250, 0, 0, 1, 221, 255, 4, 0, 3, 0, 255, 225, 0,
    ];
    let rep = arc_kernel(&data).unwrap_or_else(|e| panic!("{e}"));
    assert!(rep.events >= 1, "{rep:?}");
}

/// The fifth libFuzzer campaign: triangular w = 1.2·10⁻¹⁰, B = 244 (cyclotron radius 0.004), a
/// particle in the cusp where two disks nearly touch, moving along disk 1 with the arc turning
/// into it: every return is a hop shorter than an ulp, and the position, rounded after each,
/// drifts into the disk by about u per hop (257u after 255 hops). A return is found from the
/// position by identity (the other intersection, −2β/M), so along k consecutive returns the
/// post-event bound is k + 1 times one event's; the drift is the pseudo-orbit's, not a wrong
/// contact (`fuzz/artifacts/arc_kernel/crash-2afd…`, `proofs-notes/magnetic-arcs.md`).
#[test]
fn regression_arc_sub_ulp_hops_along_a_disk_in_a_cusp_drift_one_event_bound_per_hop() {
    let data: [u8; 45] = [
        0, 64, 83, 126, 2, 131, 2, 19, 2, 17, 26, 26, 235, 26, 26, 126, 235, 25, 60, 235, 235, 86,
        255, 0, 0, 0, 0, 0, 0, 41, 0, 0, 0, 0, 0, 0, 232, 232, 45, 232, 232, 232, 229, 232, 232,
    ];
    let rep = arc_kernel(&data).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((rep.events, rep.collisions), (256, 256), "{rep:?}");
}

/// The sixth libFuzzer campaign: triangular w = 2.9·10⁻¹¹, B = 3.8·10⁻⁶, a particle at the cusp
/// of two nearly touching disks, on disk 0 and on edge 1 (σ = 10⁻¹⁶), leaving across the edge.
/// The crossing is 10⁻¹⁶ ahead and disk 2 is 6·10⁻¹¹ ahead, both chords along v; rounding put
/// the crossing's on the turning side and the collision's just behind v, and an order that ranked
/// "just behind" before "turning" took the collision, leaving the particle 5·10⁻¹¹ beyond the
/// edge. Chords within π/4 of v are now ordered by length whichever side they rounded to
/// (`fuzz/artifacts/arc_kernel/crash-e847…`).
#[test]
fn regression_arc_cusp_crossing_and_collision_along_v_are_ordered_by_length() {
    let data: [u8; 60] = [
        63, 255, 255, 0, 0, 66, 214, 0, 0, 0, 2, 2, 3, 34, 83, 66, 0, 214, 0, 229, 255, 255, 255,
        255, 255, 127, 0, 250, 64, 64, 1, 1, 247, 2, 83, 2, 47, 2, 2, 2, 3, 2, 83, 83, 247, 2, 83,
        2, 83, 2, 47, 2, 2, 2, 3, 2, 83, 83, 2, 2,
    ];
    let rep = arc_kernel(&data).unwrap_or_else(|e| panic!("{e}"));
    assert!(rep.crossings >= 1, "{rep:?}");
}

/// The seventh libFuzzer campaign: triangular w = 0.308, B = 1.40 (ρ = 0.715), a particle on
/// disk 0 at (1, 0) moving along it (v = (−2·10⁻¹⁶, 1)) with its cyclotron circle inside the
/// disk, tangent there: it meets the disk now. The disk frame (M = 0.16 < V²/4) computed r − a
/// below its rounding, found "no cut", and the particle flew along the circle through the disk
/// and 0.34 into the next one. Where the disk frame finds no cut, the radical line decides
/// (`fuzz/artifacts/arc_kernel/crash-ace8…`).
#[test]
fn regression_arc_tangent_on_a_disk_with_the_cyclotron_circle_inside_it_collides_now() {
    let data: [u8; 28] = [
        255, 171, 0, 129, 0, 0, 0, 231, 0, 0, 2, 104, 1, 0, 254, 254, 254, 254, 254, 0, 235, 254,
        254, 0, 0, 0, 225, 102,
    ];
    let rep = arc_kernel(&data).unwrap_or_else(|e| panic!("{e}"));
    assert!(rep.collisions >= 1, "{rep:?}");
}

/// The eighth libFuzzer campaign: triangular w = 0.070, B = 1 (ρ = r), a particle on disk 2
/// moving along it whose cyclotron centre is the disk's centre to rounding: its cyclotron circle
/// is the disk. β rounded to a few u made it a return, and the disk frame, from an m of rounding
/// size, put the contact at a random point of the disk with the speed 2 % off. Coincident circles
/// are now the creeping slide: no event (`fuzz/artifacts/arc_kernel/crash-f67d…`).
#[test]
fn regression_arc_cyclotron_circle_that_is_the_disk_slides_without_an_event() {
    let data: [u8; 35] = [
        255, 255, 0, 127, 0, 255, 0, 0, 0, 255, 225, 102, 7, 0, 0, 0, 0, 58, 53, 53, 53, 50, 182,
        129, 253, 172, 253, 20, 20, 16, 172, 253, 20, 20, 0,
    ];
    let rep = arc_kernel(&data).unwrap_or_else(|e| panic!("{e}"));
    assert!(rep.events >= 1, "{rep:?}");
}

/// The ninth libFuzzer campaign: triangular w = 0.064, B = 1 (ρ = r), a particle at the surface
/// of disk 1 (not on it by identity) whose cyclotron circle is the disk to rounding: β of a few u
/// made it a return, and the disk frame gave a random contact with the speed 150 % off. Circles
/// concentric to rounding now do not cut: the particle slides (`fuzz/artifacts/arc_kernel/crash-47af…`).
#[test]
fn regression_arc_surface_start_on_a_coincident_cyclotron_circle_does_not_collide() {
    let data: [u8; 34] = [
        255, 255, 127, 0, 0, 0, 0, 2, 0, 0, 225, 102, 7, 0, 0, 53, 0, 53, 53, 16, 53, 53, 50, 182,
        129, 253, 172, 45, 37, 20, 20, 16, 20, 0,
    ];
    arc_kernel(&data).unwrap_or_else(|e| panic!("{e}"));
}

/// The tenth libFuzzer campaign: triangular w = 0.064, B = −1.21 (ρ = 0.83 < r), a particle an
/// ulp outside disk 1 and tangent to it, its cyclotron circle internally tangent to the disk:
/// the product discriminant's factor Vr + q − ωγ/2 ≈ 10⁻¹⁶ rounded to ≤ 0, no contact was
/// found, and the particle crossed an edge 3·10⁻⁵ deep inside the disk. Off the circle with
/// K < 0, β² − γK > 0 exactly, and the kernel now takes that sum there: a collision 3·10⁻⁸ ahead.
#[test]
fn regression_arc_tangent_start_on_an_internally_tangent_cyclotron_circle_collides() {
    let data: [u8; 35] = [
        2, 0, 127, 0, 0, 0, 0, 0, 0, 2, 225, 102, 7, 0, 0, 53, 0, 53, 53, 16, 53, 53, 0, 50, 4, 0,
        0, 0, 52, 253, 20, 20, 16, 20, 53,
    ];
    arc_kernel(&data).unwrap_or_else(|e| panic!("{e}"));
}

/// The eleventh libFuzzer campaign: triangular w = 0.308, B = 1 (ρ = r), a particle an ulp off
/// disk 0 moving into it at 5·10⁻⁵ rad, its cyclotron centre 5·10⁻⁵ from the disk's: the disk
/// frame's entry, 2·10⁻¹² ahead, came out 4·10⁻¹⁴ behind v (its direction along the disk carries
/// u/√M), was ordered at the half-turn after an edge crossing, and the particle flew 4·10⁻⁵ into
/// the disk. Within its own rounding of the particle, moving in, the entry is now.
#[test]
fn regression_arc_disk_frame_entry_within_its_rounding_of_the_particle_is_now() {
    let data: [u8; 29] = [
        255, 255, 127, 0, 0, 64, 0, 0, 0, 2, 225, 102, 7, 0, 0, 255, 255, 254, 182, 48, 51, 255,
        34, 49, 16, 0, 0, 20, 0,
    ];
    let rep = arc_kernel(&data).unwrap_or_else(|e| panic!("{e}"));
    assert!(rep.collisions >= 1, "{rep:?}");
}

/// The fifteenth libFuzzer campaign: a particle an ulp off a disk (w = 0.064), moving into it at
/// 4.8·10⁻⁵ rad on a cyclotron circle nearly internally tangent to it (B = −1.434, ρ = 0.70,
/// cyclotron centre 0.30 from the disk's). The disk frame's entry, 1.2·10⁻¹² ahead (at 300 bits),
/// came out 1.3·10⁻¹² behind v in `f64` — its error across the disk, a few u, moves it along the
/// arc by 1/sin α — and was ordered after an edge crossing; the particle flew into the disk
/// (`fuzz/artifacts/arc_kernel/crash-cb9d…`). Within E, which now carries that factor, the
/// entry is now: a collision with disk 0 at once.
#[test]
fn regression_arc_entry_at_a_small_crossing_angle_within_its_rounding_is_now() {
    let data: [u8; 30] = [
        255, 255, 0, 127, 0, 255, 0, 0, 0, 245, 255, 102, 7, 0, 0, 0, 0, 53, 30, 0, 53, 0, 0, 0,
        30, 255, 255, 255, 20, 111,
    ];
    let rep = arc_kernel(&data).unwrap_or_else(|e| panic!("{e}"));
    assert!(rep.events >= 1, "{rep:?}");
    use lorentz_gas::kernel::arc::Arc;
    use lorentz_gas::kernel::vec2::Vec2;
    let (p, v, b) = (
        (0.9924793053751814f64, 0.12241253368016532f64),
        Vec2::new(0.12236495788464784f64, -0.992485172222683),
        -1.43359375f64,
    );
    let c = Arc::new(&v, &b)
        .contact(p.0, p.1, &1.0, &1.0, false)
        .unwrap();
    assert_eq!((c.chord.x, c.chord.y), (0.0, 0.0), "{c:?}");
}

/// The seventeenth libFuzzer campaign: square r = 0.49999999813735485 (disks 3.7·10⁻⁹ apart),
/// B = 2 (ρ = 1/2), a particle on a cell edge 1.9·10⁻⁹ off disk 0 whose cyclotron centre is
/// 1.9·10⁻⁹ from the disk's: the disk lies inside the cyclotron circle, 3.6·10⁻¹² from tangency
/// (checked at 300 bits). The disk frame found rs² = −10⁻³, far beyond its rounding, and left the
/// decision to the radical line, whose discriminant (true value −1.4·10⁻²⁰) rounded to
/// +5.6·10⁻¹⁷ and whose 1/M = 7·10¹⁶ put a contact 0.16 off the disk, the speed 98 % off
/// (`fuzz/artifacts/arc_kernel/crash-2f8c…`). A miss beyond the rounding of rs² is a miss.
#[test]
fn regression_arc_disk_inside_a_nearly_concentric_cyclotron_circle_is_missed() {
    let data: [u8; 35] = [
        2, 3, 1, 0, 255, 238, 30, 153, 248, 255, 1, 191, 1, 255, 127, 64, 8, 249, 0, 0, 36, 251,
        64, 0, 0, 0, 64, 0, 0, 129, 45, 1, 93, 21, 0,
    ];
    let rep = arc_kernel(&data).unwrap_or_else(|e| panic!("{e}"));
    assert!(rep.events >= 8, "{rep:?}");
    use lorentz_gas::kernel::arc::Arc;
    use lorentz_gas::kernel::vec2::Vec2;
    let r = 0.49999999813735485f64;
    let v = Vec2::new(0.9999999999999992f64, 3.161013628627529e-8);
    let c = Arc::new(&v, &2.0).contact(1.3946061083736083e-8, -0.5, &r, &(r * r), false);
    assert_eq!(c, None);
}

/// The eighteenth libFuzzer campaign (on the fix of the seventeenth): triangular w = 0.064,
/// B = 1.195 (ρ = 0.837), a particle on disk 0 by identity after 230 events, its position drifted
/// 1.1·10⁻¹⁴ inside the disk by its returns (within the error model), moving along it (β a
/// rounding, 2.9·10⁻⁹) with its cyclotron circle internally tangent — by the drift, inside the
/// disk by 1.1·10⁻¹⁴. The disk frame's rs² = −1.150·10⁻¹³ just beyond its rounding
/// E = 1.146·10⁻¹³ made it a miss, and the particle circled through the disk, 0.18 deep in the
/// next. A particle on the circle keeps its return: the miss applies off the circle only
/// (`fuzz/artifacts/arc_kernel/crash-9241…`).
#[test]
fn regression_arc_return_on_a_disk_is_kept_when_drift_puts_the_cyclotron_circle_inside() {
    let data: [u8; 41] = [
        255, 48, 127, 0, 0, 0, 0, 0, 0, 2, 225, 102, 7, 0, 0, 1, 64, 53, 49, 0, 51, 53, 83, 202, 0,
        0, 0, 235, 172, 253, 20, 20, 20, 235, 22, 153, 153, 73, 213, 20, 50,
    ];
    let rep = arc_kernel(&data).unwrap_or_else(|e| panic!("{e}"));
    assert!(rep.events >= 231, "{rep:?}");
}

/// The twenty-first libFuzzer campaign: square lattice, r = 0.4999999999997726 (the disks
/// 4.5·10⁻¹³ apart), B = 2 (ρ = 1/2): a particle 1.8·10⁻¹⁶ off disk 0, moving along it, its
/// cyclotron circle 2.3·10⁻¹³ from concentric with the disk and tangent to it within 1.6u — the
/// disk inside the circle. The disk frame left the tangency to the radical line, whose 1/M
/// (M = 2·10⁻²⁵) placed the contact 10⁻⁹ off the disk: the speed after it was off by 9.4·10⁷u.
/// Now the disk inside the cyclotron circle is missed, its orbit entering it by less than the
/// rounding (`fuzz/artifacts/arc_kernel/crash-eea82b92…`).
#[test]
fn regression_arc_disk_inside_a_concentric_cyclotron_circle_tangent_within_rounding_is_missed() {
    let data: [u8; 49] = [
        255, 255, 134, 255, 1, 163, 0, 0, 122, 25, 134, 255, 1, 163, 0, 0, 122, 25, 1, 170, 170,
        170, 170, 170, 170, 170, 255, 255, 255, 255, 255, 255, 1, 170, 170, 170, 170, 170, 170,
        170, 255, 255, 255, 255, 255, 255, 40, 185, 0,
    ];
    let rep = arc_kernel(&data).unwrap_or_else(|e| panic!("{e}"));
    assert!(rep.events >= 1, "{rep:?}");
    use lorentz_gas::kernel::arc::Arc;
    use lorentz_gas::kernel::vec2::Vec2;
    let r = 0.4999999999997726f64;
    let v = Vec2::new(0.8660254037844387f64, -0.5000000000000002);
    let c = Arc::new(&v, &2.0).contact(
        -0.2499999999998866,
        -0.43301270189202246,
        &r,
        &(r * r),
        false,
    );
    assert_eq!(c, None);
}
