//! One orbit of a Poincaré section: its start, its flight on the `f64` scalar kernel (arcs in a
//! field, straight flights without), the Birkhoff coordinates of its first collisions and the
//! largest distance from its start that it reached.

use crate::Error;
use crate::engine::options::StopFlag;
use crate::kernel::flight::EventKind;
use crate::observers::excursion::Reach;
use crate::scenes::Scene;
use crate::scenes::lattice::{Lattice, LatticeState};
use crate::scenes::magnetic::DiskLattice;
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::theory::magnetic::{FieldGeometry, Orbit};

/// Collisions between two looks at the progress and the stop flag.
const LOOK_EVERY: u64 = 1 << 15;

/// The Birkhoff coordinates (θ, p) of a collision: θ the polar angle of the contact point about
/// the disk's centre, in [−π, π), from the outward `normal` (any length > 0) in world
/// coordinates; p = sin α, α the angle of the outgoing `velocity` (unit speed) to the normal,
/// counted counter-clockwise: p = n̂ × v, the velocity's component along the counter-clockwise
/// tangent. The cross product is invariant under the point reflection of a down cell, so either
/// frame gives p. p is clamped to [−1, 1] against the rounding of a grazing collision (|v| = 1
/// and |n̂| = 1 each to a few ulps).
pub fn birkhoff(normal: [f64; 2], velocity: [f64; 2]) -> (f64, f64) {
    let theta = normal[1].atan2(normal[0]);
    let theta = if theta >= std::f64::consts::PI {
        -std::f64::consts::PI
    } else {
        theta
    };
    let n = normal[0].hypot(normal[1]);
    let p = (normal[0] * velocity[1] - normal[1] * velocity[0]) / n;
    (theta, p.clamp(-1.0, 1.0))
}

/// The label of each disk of a scene's cell kernel as a disk of its [`DiskLattice`] (the index of
/// the lattice's disk it is an image of), in an up cell and in a down one.
#[derive(Debug, Clone)]
pub(super) struct DiskLabels {
    up: Vec<u32>,
    down: Vec<u32>,
}

impl DiskLabels {
    /// The labels of the disks of `lattice`'s cell in the array `disks` (`None`: the kernel's own
    /// indices).
    pub(super) fn new<K: crate::kernel::cell::CellKernel<f64>>(
        lattice: &Lattice<f64, K>,
        disks: Option<&DiskLattice>,
    ) -> Self {
        let centres: Vec<[f64; 2]> = (lattice.cell().disks.iter())
            .map(|d| [d.centre.x, d.centre.y])
            .collect();
        let label = |m: usize, sign: f64| -> u32 {
            let own = m as u32;
            let Some(dl) = disks else { return own };
            let c = [sign * centres[m][0], sign * centres[m][1]];
            (dl.disks.iter().position(|d| {
                let (dx, dy) = (c[0] - d.centre[0], c[1] - d.centre[1]);
                let j = dy / dl.h;
                let i = dx / dl.a - dl.beta * j;
                (i - i.round()).abs() < 1e-6 && (j - j.round()).abs() < 1e-6
            }))
            .map_or(own, |k| k as u32)
        };
        DiskLabels {
            up: (0..centres.len()).map(|m| label(m, 1.0)).collect(),
            down: (0..centres.len()).map(|m| label(m, -1.0)).collect(),
        }
    }

    fn of(&self, m: u8, down: bool) -> u32 {
        let l = if down { &self.down } else { &self.up };
        l.get(m as usize).copied().unwrap_or(u32::from(m))
    }
}

/// Where and how the orbits run.
pub(super) struct Setup<'a, S: Scene> {
    pub scene: &'a S,
    pub lattice: &'a Lattice<f64, S::Kernel<f64>>,
    /// The field's exact geometry, and B; `None` without a field.
    pub field: Option<(&'a FieldGeometry, f64)>,
    pub labels: &'a DiskLabels,
    /// The cells come in two orientations ([`two_orientations`]).
    pub two_orientations: bool,
    /// Collisions recorded per orbit.
    pub collisions: u64,
    /// Collisions flown per orbit to classify it (in a field).
    pub classify: u64,
    pub seed: u64,
    pub stop: Option<&'a StopFlag>,
    pub progress: &'a (dyn Fn(u64) + Sync),
}

/// What one orbit gave.
#[derive(Debug, Clone, Default)]
pub(super) struct Flown {
    pub theta: Vec<f64>,
    pub p: Vec<f64>,
    pub disk: Vec<u32>,
    /// Pinned, skipping or diffusing by its cyclotron circle (diffusing without a field).
    pub orbit: Option<Orbit>,
    pub reach: Reach,
    /// Collisions flown.
    pub collisions: u64,
}

/// The start of orbit `index`: drawn from the invariant measure on its own stream, its speed
/// normalised. Where the scene's cells come in two orientations (the triangular lattice's up
/// and down traps, each the other's point reflection) the sample of the cell (0, 0) is put in
/// either with probability ½ (a further bit of the stream), so that the starts cover the whole
/// period and not only its up traps: a regular island in a down trap is the point reflection of
/// one in an up trap, its Birkhoff points θ + π.
pub(super) fn start<S: Scene>(
    scene: &S,
    two_orientations: bool,
    seed: u64,
    index: u64,
) -> LatticeState<f64> {
    let mut rng = StreamKey::new(seed, Purpose::Section, index).rng();
    let mut s = scene.sample(&mut rng);
    if two_orientations {
        s.cell.down = rand::RngCore::next_u64(&mut rng) >> 63 == 1;
    }
    s.flight.normalise_speed();
    s
}

/// Whether the cells of `lattice` come in two orientations (some edge maps by a point
/// reflection).
pub(super) fn two_orientations<K: crate::kernel::cell::CellKernel<f64>>(
    lattice: &Lattice<f64, K>,
) -> bool {
    lattice.cell().edges.iter().any(|e| e.flips())
}

/// The class by geometry of the orbit through `s` (diffusing without a field).
fn orbit_of<S: Scene>(su: &Setup<'_, S>, s: &LatticeState<f64>) -> Orbit {
    let Some((geometry, _)) = su.field else {
        return Orbit::Diffusing;
    };
    geometry.classify_state(su.lattice, s)
}

/// Flies orbit `index`: none of a pinned orbit (its reach is its circle's diameter 2ρ), the
/// recorded collisions of a skipping one (its class is exact), the classification's of a
/// diffusing one in a field, the recorded ones without a field.
pub(super) fn fly<S: Scene>(su: &Setup<'_, S>, index: u64) -> Result<Flown, Error> {
    let mut s = start(su.scene, su.two_orientations, su.seed, index);
    let orbit = orbit_of(su, &s);
    let mut out = Flown {
        orbit: Some(orbit),
        ..Flown::default()
    };
    let budget = match (orbit, su.field) {
        (Orbit::Pinned, Some((g, _))) => {
            out.reach.push(2.0 * g.cyclotron_radius(), 0.0);
            return Ok(out);
        }
        (Orbit::Diffusing, Some(_)) => su.classify,
        _ => su.collisions,
    };
    let n = su.collisions.min(budget) as usize;
    (out.theta, out.p, out.disk) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    let (origin, basis) = (su.lattice.unwrapped(&s, 0.0), su.lattice.basis_f64());
    while out.collisions < budget {
        let kind = match su.field {
            Some((_, b)) => su.lattice.step_in_field(&mut s, &b)?.kind,
            None => su.lattice.step(&mut s)?.kind,
        };
        let r = (su.lattice.unwrapped(&s, 0.0)).displacement_from(&origin, &basis);
        out.reach.push(r[0], r[1]);
        if let EventKind::Collision(m) = kind {
            if out.collisions < su.collisions {
                record(su, &s, m, &mut out);
            }
            out.collisions += 1;
            if out.collisions.is_multiple_of(LOOK_EVERY) {
                (su.progress)(LOOK_EVERY);
                if let Some(stop) = su.stop {
                    stop.check()?;
                }
            }
        }
    }
    (su.progress)(out.collisions % LOOK_EVERY);
    Ok(out)
}

/// Records the collision with disk `m` of the cell that `s` (just reflected) is in.
fn record<S: Scene>(su: &Setup<'_, S>, s: &LatticeState<f64>, m: u8, out: &mut Flown) {
    let c = &su.lattice.cell().disks[m as usize].centre;
    let sg = s.cell.sign();
    let normal = [sg * (s.flight.pos.x - c.x), sg * (s.flight.pos.y - c.y)];
    let v = [sg * s.flight.vel.x, sg * s.flight.vel.y];
    let (theta, p) = birkhoff(normal, v);
    out.theta.push(theta);
    out.p.push(p);
    out.disk.push(su.labels.of(m, s.cell.down));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn birkhoff_coordinates_of_simple_collisions() {
        // The contact point on the right of the disk, leaving along the normal: θ = 0, p = 0.
        assert_eq!(birkhoff([1.0, 0.0], [1.0, 0.0]), (0.0, 0.0));
        // Leaving along the counter-clockwise tangent: p = 1; clockwise: p = −1.
        assert_eq!(birkhoff([2.0, 0.0], [0.0, 1.0]).1, 1.0);
        assert_eq!(birkhoff([0.0, 1.0], [1.0, 0.0]).1, -1.0);
        // The left of the disk is −π, never π.
        assert_eq!(birkhoff([-1.0, 0.0], [-1.0, 0.0]).0, -std::f64::consts::PI);
        assert_eq!(birkhoff([-1.0, -0.0], [-1.0, 0.0]).0, -std::f64::consts::PI);
        // A point reflection of both vectors (a down cell's frame) keeps p.
        let (a, b) = ([0.6, 0.8], [0.28, 0.96]);
        assert_eq!(birkhoff(a, b).1, birkhoff([-a[0], -a[1]], [-b[0], -b[1]]).1);
    }
}
