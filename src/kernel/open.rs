//! The kernel of an open table: finitely many disks, no lattice, no cell edges. A flight ends on
//! the first disk its ray enters, or nowhere: then the particle has escaped (a straight line
//! that meets no disk of a finite table never meets one again, so it leaves the convex hull of
//! the disks for good).
//!
//! The contact is the cancellation-free root of [`super::ray_disk`] (each disk with its own
//! radius, r² rounded once); the disk just left is excluded by identity, never by a tolerance,
//! and the particle is never nudged. Generic over `f64` and `rug::Float`.

use super::cell::Disk;
use super::flight::Flight;
use super::ray_disk::ray_circle_centred;
use super::vec2::Vec2;
use crate::numbers::real::Real;

/// The disks of an open table at one working precision.
#[derive(Debug, Clone, PartialEq)]
pub struct OpenDisks<T> {
    /// The disks, labelled by their index (at most 255).
    pub disks: Vec<Disk<T>>,
}

impl<T: Real> OpenDisks<T> {
    /// The table of `disks` (labels 0 … n − 1, n ≤ 255).
    pub fn new(disks: Vec<Disk<T>>) -> Self {
        debug_assert!(disks.len() <= 255);
        OpenDisks { disks }
    }

    /// The first disk the flight's ray enters and the time to it, skipping the disk it left
    /// (`flight.excluded_disk`); `None` if it meets none: escaped. Ties go to the lower label.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::kernel::{cell::Disk, flight::Flight, open::OpenDisks, vec2::Vec2};
    /// let d = |x: f64| Disk::new(Vec2::new(x, 0.0), 1.0);
    /// let table = OpenDisks::new(vec![d(0.0), d(6.0)]);
    /// // Leaving disk 0 at (1, 0) eastwards: disk 1 at t = 4.
    /// let mut f = Flight::new(Vec2::new(1.0, 0.0), Vec2::new(1.0, 0.0));
    /// f.excluded_disk = Some(0);
    /// assert_eq!(table.next_collision(&f), Some((1, 4.0)));
    /// f.vel = Vec2::new(0.0, 1.0);
    /// assert_eq!(table.next_collision(&f), None);
    /// ```
    pub fn next_collision(&self, flight: &Flight<T>) -> Option<(u8, T)> {
        let vv = flight.vel.norm2();
        let mut best: Option<(u8, T)> = None;
        for (k, disk) in self.disks.iter().enumerate() {
            let k = k as u8;
            if flight.excluded_disk == Some(k) {
                continue;
            }
            let d = flight.pos.sub(&disk.centre);
            let Some(t) = ray_circle_centred(d.x, d.y, &flight.vel, &vv, disk.radius2()) else {
                continue;
            };
            if best.as_ref().is_none_or(|(_, b)| t < *b) {
                best = Some((k, t));
            }
        }
        best
    }

    /// Flies `flight` for `time` to disk `k` and reflects it there: the new position is
    /// p + t v, the velocity the specular reflection, and disk `k` is excluded from the next
    /// flight.
    pub fn collide(&self, flight: &mut Flight<T>, k: u8, time: &T) {
        let x: Vec2<T> = flight.pos.along(time, &flight.vel);
        self.disks[k as usize].reflect(&mut flight.vel, &x);
        flight.pos = x;
        flight.excluded_disk = Some(k);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rug::Float;

    /// The same flights in f64 and in MPFR at 53 bits give the same bits (the kernel is one
    /// generic code), and the disk just left is never hit again.
    #[test]
    fn f64_and_mpfr_53_agree_bit_for_bit() {
        let c = [(0.0, 0.0), (6.0, 0.0), (3.0, 3.0 * 3f64.sqrt())];
        let f = OpenDisks::new(
            c.iter()
                .map(|&(x, y)| Disk::new(Vec2::new(x, y), 1.0))
                .collect(),
        );
        let m = OpenDisks::new(
            c.iter()
                .map(|&(x, y)| Disk::new(Vec2::from_f64(53, x, y), Float::with_val(53, 1)))
                .collect(),
        );
        let (a, b) = (0.3f64, 0.05f64);
        let mut ff = Flight::new(Vec2::new(a.cos(), a.sin()), Vec2::new(b.cos(), b.sin()));
        ff.excluded_disk = Some(0);
        let mut fm = Flight::convert_from_f64(53, &ff);
        for _ in 0..3 {
            let (Some((k, t)), Some((km, tm))) = (f.next_collision(&ff), m.next_collision(&fm))
            else {
                break;
            };
            assert_eq!((k, t), (km, tm.to_f64()));
            assert_ne!(Some(k), ff.excluded_disk);
            f.collide(&mut ff, k, &t);
            m.collide(&mut fm, km, &tm);
            assert_eq!(ff, fm.to_f64());
        }
    }
}
