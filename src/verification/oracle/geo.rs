//! The geometric context of a decoding (the cell at f64 and at the oracle's precision: free points, free arcs, edge–circle points) and the validation of a decoded start.

use super::*;

/// Geometric context of a decoding: the scene's cell at f64 and at [`ORACLE_BITS`].
pub(super) struct Geo {
    pub(super) c64: ConvexCell<f64>,
    pub(super) chp: ConvexCell<Float>,
}

impl Geo {
    pub(super) fn new<S: Scene>(scene: &S) -> Result<Self, String> {
        let k64 = scene.kernel::<f64>(()).map_err(|e| e.to_string())?;
        let khp = scene
            .kernel::<Float>(ORACLE_BITS)
            .map_err(|e| e.to_string())?;
        Ok(Geo {
            c64: k64.cell().clone(),
            chp: khp.cell().clone(),
        })
    }

    pub(super) fn n_disks(&self) -> usize {
        self.chp.disks.len()
    }

    /// Free at high precision, up to 2⁻¹⁰⁰: σₖ(p) ≥ −2⁻¹⁰⁰ for every edge and
    /// |p − c|² ≥ r²(1 − 2⁻¹⁰⁰) for every disk (points constructed on an edge or a tangent line).
    pub(super) fn free_hp(&self, p: &Vec2<Float>) -> bool {
        let tiny = HP_TINY_EXP.exp2();
        (0..self.chp.edges.len()).all(|k| self.chp.edge_distance(k, p).to_f64() >= -tiny)
            && self
                .chp
                .disks
                .iter()
                .all(|d| p.sub(&d.centre).norm2().to_f64() >= d.radius2().to_f64() * (1.0 - tiny))
    }

    /// A free point from two fractions: c₀ + u₁(c₁ − c₀) + u₂(c_last − c₀) over the corners
    /// (folded back onto the triangle c₀c₁c₂ when the cell is one; the whole cell when it is a
    /// parallelogram), then an additive-recurrence walk until free; the centroid or a free
    /// corner as the last resort.
    pub(super) fn free_point(&self, u1: f64, u2: f64) -> Vec2<f64> {
        let c = &self.c64.corners;
        let (o, p1, p2) = (&c[0], &c[1], &c[c.len() - 1]);
        let (e1, e2) = (p1.sub(o), p2.sub(o));
        for i in 0..256 {
            let (mut a, mut b) = (
                (u1 + i as f64 * 0.618_033_988_749_895).fract(),
                (u2 + i as f64 * 0.414_213_562_373_095).fract(),
            );
            if c.len() == 3 && a + b > 1.0 {
                a = 1.0 - a;
                b = 1.0 - b;
            }
            let p = Vec2::new(o.x + a * e1.x + b * e2.x, o.y + a * e1.y + b * e2.y);
            if self.c64.is_free(&p) {
                return p;
            }
        }
        let n = c.len() as f64;
        let centroid = Vec2::new(
            c.iter().map(|p| p.x).sum::<f64>() / n,
            c.iter().map(|p| p.y).sum::<f64>() / n,
        );
        std::iter::once(centroid.clone())
            .chain(c.iter().cloned())
            .find(|p| self.c64.is_free(p))
            .unwrap_or(centroid)
    }

    /// The range of s with A + s·u in the closed cell (at high precision), if not empty.
    pub(super) fn clip(&self, a: &Vec2<Float>, u: &Vec2<Float>) -> Option<(Float, Float)> {
        let (mut lo, mut hi): (Option<Float>, Option<Float>) = (None, None);
        for (k, e) in self.chp.edges.iter().enumerate() {
            let sigma = self.chp.edge_distance(k, a);
            let nu = e.normal.dot(u);
            // A direction within rounding of an edge's is parallel to it.
            if nu.to_f64().abs() < 1e-40 {
                if sigma.to_f64() < -1e-40 {
                    return None;
                }
                continue;
            }
            let s = -(sigma.clone()) / &nu;
            if nu.gt0() {
                lo = Some(match lo {
                    Some(l) if l >= s => l,
                    _ => s,
                });
            } else {
                hi = Some(match hi {
                    Some(h) if h <= s => h,
                    _ => s,
                });
            }
        }
        let (lo, hi) = (lo?, hi?);
        (lo <= hi).then_some((lo, hi))
    }

    /// A free point A + s·u of the line, s chosen from `frac` (then a walk, then the ends and
    /// the middle of the clipped range).
    pub(super) fn point_on_line(
        &self,
        a: &Vec2<Float>,
        u: &Vec2<Float>,
        frac: f64,
    ) -> Option<Vec2<Float>> {
        let (lo, hi) = self.clip(a, u)?;
        let len = hi - &lo;
        let tries = (0..64)
            .map(|i| (frac + i as f64 * 0.618_033_988_749_895).fract())
            .chain([0.0, 1.0, 0.5]);
        for f in tries {
            let s = lo.clone() + &(len.clone() * &hp(f));
            let p = a.along(&s, u);
            if self.free_hp(&p) {
                return Some(p);
            }
        }
        None
    }

    /// `true` if the point of disk `m`'s surface at angle `theta` is in the closed cell and
    /// outside the other disks (decided in `f64`, for the arc walk).
    pub(super) fn surface_free64(&self, m: usize, theta: f64) -> bool {
        let c = &self.c64;
        let (s, co) = theta.sin_cos();
        let (cm, r) = (&c.disks[m].centre, *c.disks[m].radius());
        let p = Vec2::new(cm.x + r * co, cm.y + r * s);
        (0..c.edges.len()).all(|k| c.edge_distance(k, &p) >= 0.0)
            && c.disks
                .iter()
                .enumerate()
                .all(|(j, d)| j == m || p.sub(&d.centre).norm2() >= *d.radius2())
    }

    /// The free arcs of disk `m`'s surface inside the cell, as angle intervals [lo, hi] (hi may
    /// exceed 2π): a walk over [`ARC_SAMPLES`] angles finds the runs of free samples, each end
    /// is then bisected to the last ulp. The whole circle is one arc [0, 2π].
    pub(super) fn free_arcs(&self, m: usize) -> Vec<(f64, f64)> {
        let step = std::f64::consts::TAU / ARC_SAMPLES as f64;
        let free: Vec<bool> = (0..ARC_SAMPLES)
            .map(|i| self.surface_free64(m, i as f64 * step))
            .collect();
        if free.iter().all(|&f| f) {
            return vec![(0.0, std::f64::consts::TAU)];
        }
        let Some(start) = free.iter().position(|&f| !f) else {
            return Vec::new();
        };
        // Bisects between a free angle and a non-free one, returning the free end.
        let refine = |mut inside: f64, mut outside: f64| {
            for _ in 0..ARC_REFINE_STEPS {
                let mid = 0.5 * (inside + outside);
                if mid == inside || mid == outside {
                    break;
                }
                if self.surface_free64(m, mid) {
                    inside = mid;
                } else {
                    outside = mid;
                }
            }
            inside
        };
        let mut arcs = Vec::new();
        let mut run: Option<usize> = None;
        for n in start + 1..=start + ARC_SAMPLES {
            let i = n % ARC_SAMPLES;
            match (free[i], run) {
                (true, None) => run = Some(n),
                (false, Some(first)) => {
                    let lo = refine(first as f64 * step, (first - 1) as f64 * step);
                    let hi = refine((n - 1) as f64 * step, n as f64 * step);
                    arcs.push((lo, hi));
                    run = None;
                }
                _ => {}
            }
        }
        arcs
    }

    /// The points where edge `k`'s line meets a disk's circle inside the closed cell, in
    /// counter-clockwise order along the edge.
    pub(super) fn edge_circle_points(&self, k: usize) -> Vec<Vec2<Float>> {
        let c = &self.chp;
        let e = &c.edges[k];
        let n = &e.normal;
        // Counter-clockwise direction along the edge: the interior (n) is on its left.
        let t = Vec2::new(n.y.clone(), -n.x.clone());
        let mut pts: Vec<(Float, Vec2<Float>)> = Vec::new();
        for disk in &c.disks {
            let d = &disk.centre;
            // Foot of the perpendicular from the centre, q = c + (o − n·c)n; half-chord √(r² − δ²).
            let delta = e.offset.clone() - &n.dot(d);
            let h2 = disk.radius2().clone() - &Real::square(&delta);
            if h2.is_sign_negative() {
                continue;
            }
            let q = d.along(&delta, n);
            let h = h2.sqrt();
            for s in [-h.clone(), h] {
                let p = q.along(&s, &t);
                let on_cell = (0..c.edges.len())
                    .all(|j| j == k || c.edge_distance(j, &p).to_f64() >= -HP_TINY_EXP.exp2());
                if on_cell {
                    pts.push((t.dot(&p), p));
                }
            }
        }
        pts.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal));
        pts.into_iter().map(|(_, p)| p).collect()
    }
}

/// Checks that a decoded state is valid in `cell` (see the module documentation).
pub(super) fn validate(cell: &ConvexCell<Float>, f: &Flight<f64>) -> Result<(), String> {
    let p = lift(&f.pos);
    let v = lift(&f.vel);
    let extent = cell.extent();
    for k in 0..cell.edges.len() {
        let s = cell.edge_distance(k, &p).to_f64();
        if s.is_nan() || s < -VALID_EDGE * extent {
            return Err(format!("decoded start outside edge {k}: sigma = {s:e}"));
        }
    }
    for (m, d) in cell.disks.iter().enumerate() {
        let r2 = d.radius2().to_f64();
        let e = ((p.sub(&d.centre).norm2() - d.radius2()) / d.radius2()).to_f64();
        if e.is_nan() || e < -VALID_DISK {
            return Err(format!(
                "decoded start inside disk {m}: (|p-c|^2 - r^2)/r^2 = {e:e} (r^2 = {r2:e})"
            ));
        }
    }
    let e = (v.norm2() - 1u32).to_f64();
    if e.abs().is_nan() || e.abs() > VALID_SPEED {
        return Err(format!("decoded speed off: |v|^2 - 1 = {e:e}"));
    }
    if f.excluded_edge.is_some() {
        return Err("decoded start with an excluded edge".into());
    }
    if let Some(m) = f.excluded_disk {
        let d = p.sub(&cell.disks[m as usize].centre);
        let beta = d.dot(&v).to_f64();
        // Excluding a disk is valid only if the flight leaves it, up to the rounding of v·n:
        // each component of v is within 4.5 ulps (≤ 4.5u) of the exact tangent direction.
        let tol = 16.0 * U * d.norm2().sqrt().to_f64();
        if beta < -tol {
            return Err(format!("excluded disk approached: v.n = {beta:e}"));
        }
    }
    Ok(())
}
