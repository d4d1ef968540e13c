//! Arcs whose cyclotron circle is nearly concentric with a disk and tangent to it within the
//! rounding (`proofs-notes/magnetic-arcs.md`, "the tangency band"): the contact, where there is
//! one, lies on the disk; where there is none, the orbit enters the disk by no more than the
//! rounding. The twenty-first libFuzzer campaign found a contact 10⁻⁹ off the disk there.

use lorentz_gas::kernel::arc::Arc;
use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::verification::error_model::UNIT_ROUNDOFF;
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus as Gen;
use rug::Float;

fn hi(x: f64) -> Float {
    Float::with_val(256, x)
}

/// What the contact of one band configuration did, in units of u times its scale.
struct Outcome {
    /// Some(distance of the contact from the disk) or None for no contact.
    off_disk: Option<f64>,
    /// The depth r + D − ρ by which the orbit of the f64 state enters the disk.
    depth: f64,
}

/// The particle at angle `b` on the cyclotron circle of radius ρ about o = D(cos a, sin a), the
/// disk of radius `r` at the origin; `None` if the f64 particle is not outside the disk.
fn band_case(r: f64, rho: f64, dist: f64, a: f64, b: f64, sign: f64) -> Option<Outcome> {
    let u = UNIT_ROUNDOFF;
    let w = sign / rho;
    let o = (dist * a.cos(), dist * a.sin());
    let d = Vec2::new(o.0 + rho * b.cos(), o.1 + rho * b.sin());
    let v = Vec2::new(-w * (d.y - o.1), w * (d.x - o.0));
    if d.norm2() <= r * r {
        return None;
    }
    let scale = r + rho + d.norm2().sqrt();
    // The orbit of the f64 state: centre p + Jv/ω, radius |v|/|ω|.
    let (ox, oy) = (hi(d.x) - hi(v.y) / hi(w), hi(d.y) + hi(v.x) / hi(w));
    let big_d = Float::with_val(256, &ox * &ox + &oy * &oy).sqrt();
    let speed = Float::with_val(256, hi(v.x) * hi(v.x) + hi(v.y) * hi(v.y)).sqrt();
    let rho_exact = speed / hi(w).abs();
    let depth = (hi(r) + big_d - rho_exact).to_f64() / (u * scale);
    let c = Arc::new(&v, &w).contact(d.x, d.y, &r, &(r * r), false);
    let off_disk = c.map(|c| {
        let (yx, yy) = (hi(d.x) + hi(c.chord.x), hi(d.y) + hi(c.chord.y));
        let y = Float::with_val(256, &yx * &yx + &yy * &yy).sqrt();
        (y - r).to_f64().abs() / (u * scale)
    });
    Some(Outcome { off_disk, depth })
}

/// Both orientations (the disk inside the cyclotron circle, ρ > r, and the circle inside the
/// disk, ρ < r), centres 10⁻¹⁵ρ to 0.3ρ apart, tangent to within ±64uρ: every contact is on the
/// disk to 64u of the scale r + ρ + |d|, and every miss leaves the orbit at most 64u deep.
#[test]
fn nearly_concentric_circles_tangent_within_rounding_meet_on_the_disk_or_miss_it() {
    let mut rng = Gen::seed_from_u64(2101);
    let (mut worst_on, mut worst_miss, mut hits, mut misses) = (0.0f64, 0.0f64, 0, 0);
    for n in 0..40_000 {
        let r: f64 = [1.0, 0.3, 0.5, 2.5][n % 4];
        let dist = r * 10f64.powf(rng.random_range(-15.0..-0.5f64));
        let tang = rng.random_range(-64.0..64.0f64) * UNIT_ROUNDOFF * r;
        // Internal tangency: |ρ − r| = D, the disk inside (ρ = r + D) or outside (ρ = r − D).
        let rho = if n % 2 == 0 {
            r + dist + tang
        } else {
            r - dist + tang
        };
        if rho <= 0.0 || dist >= 0.4 * rho {
            continue;
        }
        // Half of the particles near the tangency point (at angle a + π on the cyclotron circle
        // when the disk is inside it, at a when outside), where a particle off a disk that
        // contains its circle can only be.
        let a = rng.random_range(0.0..6.3f64);
        let at = if n % 2 == 0 {
            a + std::f64::consts::PI
        } else {
            a
        };
        let near = 10f64.powf(rng.random_range(-16.0..-1.0f64)) * rng.random_range(-1.0..1.0f64);
        let b = if (n / 4) % 2 == 0 {
            at + near
        } else {
            rng.random_range(0.0..6.3f64)
        };
        let sign = if (n / 8) % 2 == 0 { 1.0 } else { -1.0 };
        let Some(out) = band_case(r, rho, dist, a, b, sign) else {
            continue;
        };
        match out.off_disk {
            Some(e) => {
                hits += 1;
                worst_on = worst_on.max(e);
            }
            None => {
                misses += 1;
                worst_miss = worst_miss.max(out.depth);
            }
        }
    }
    println!(
        "hits {hits} (worst {worst_on:.2} u off the disk), misses {misses} (worst {worst_miss:.2} u deep)"
    );
    assert!(hits > 1000 && misses > 1000, "{hits} {misses}");
    assert!(
        worst_on < 64.0,
        "a contact {worst_on} u(r + ρ + |d|) off the disk"
    );
    assert!(
        worst_miss < 64.0,
        "a miss whose orbit is {worst_miss} u(r + ρ + |d|) deep"
    );
}
