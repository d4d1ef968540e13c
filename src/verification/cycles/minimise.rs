//! Starting guesses by length minimisation in `f64`: a periodic orbit of a dispersing billiard
//! is a critical point (for convex scatterers a local minimum) of the length
//! L(s) = Σ_k |X_{k+1} − X_k| of the closed polygon through the contact points
//! X_k = c_k + r(cos s_k, sin s_k), X_n = X₀ + the winding (`proofs-notes/lattice-cycles.md`).

use super::neighbours;

/// Most damped Newton steps on the gradient of the length.
const MAX_STEPS: usize = 60;
/// Converged when every component of the gradient is below this.
const TOLERANCE: f64 = 1e-13;

/// The polygon's unit edge vectors u_k (from X_k to X_{k+1}) and lengths ℓ_k.
fn edges(c: &[[f64; 2]], shift: [f64; 2], r: f64, s: &[f64]) -> Vec<([f64; 2], f64)> {
    let n = c.len();
    (0..n)
        .map(|k| {
            let next = neighbours(c, shift, k).1;
            let s1 = s[(k + 1) % n];
            let x = next[0] + r * s1.cos() - c[k][0] - r * s[k].cos();
            let y = next[1] + r * s1.sin() - c[k][1] - r * s[k].sin();
            let l = x.hypot(y);
            ([x / l, y / l], l)
        })
        .collect()
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// t·(I − u uᵀ)t′/ℓ: the derivative of u·t along t′ divided by the edge's length.
fn projected(t: [f64; 2], (u, l): ([f64; 2], f64), t2: [f64; 2]) -> f64 {
    (dot(t, t2) - dot(t, u) * dot(u, t2)) / l
}

/// The gradient g_k = r t_k·(u_{k−1} − u_k) of the length and its Hessian (dense, n × n).
fn gradient_hessian(
    c: &[[f64; 2]],
    shift: [f64; 2],
    r: f64,
    s: &[f64],
) -> (Vec<f64>, Vec<Vec<f64>>) {
    let n = c.len();
    let e = edges(c, shift, r, s);
    let t: Vec<[f64; 2]> = s.iter().map(|x| [-r * x.sin(), r * x.cos()]).collect();
    let nrm: Vec<[f64; 2]> = s.iter().map(|x| [r * x.cos(), r * x.sin()]).collect();
    let mut g = vec![0.0; n];
    let mut h = vec![vec![0.0; n]; n];
    for k in 0..n {
        let prev = (k + n - 1) % n;
        let (up, u) = (e[prev].0, e[k].0);
        let d = [up[0] - u[0], up[1] - u[1]];
        g[k] = dot(t[k], d);
        h[k][k] += -dot(nrm[k], d) + projected(t[k], e[prev], t[k]) + projected(t[k], e[k], t[k]);
        h[k][(k + 1) % n] -= projected(t[k], e[k], t[(k + 1) % n]);
        h[k][prev] -= projected(t[k], e[prev], t[prev]);
    }
    (g, h)
}

/// Solves (h + μI)x = −g by Gaussian elimination with partial pivoting; `None` if singular.
fn solve(h: &[Vec<f64>], g: &[f64], mu: f64) -> Option<Vec<f64>> {
    let n = g.len();
    let mut a: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            let mut row = h[i].clone();
            row[i] += mu;
            row.push(-g[i]);
            row
        })
        .collect();
    for col in 0..n {
        let piv = (col..n).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        a.swap(col, piv);
        if a[col][col].abs() < 1e-300 {
            return None;
        }
        let pivot = a[col].clone();
        for row in a.iter_mut().skip(col + 1) {
            let f = row[col] / pivot[col];
            for (x, p) in row.iter_mut().zip(&pivot).skip(col) {
                *x -= f * p;
            }
        }
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let rest: f64 = (i + 1..n).map(|j| a[i][j] * x[j]).sum();
        x[i] = (a[i][n] - rest) / a[i][i];
    }
    Some(x)
}

fn length(c: &[[f64; 2]], shift: [f64; 2], r: f64, s: &[f64]) -> f64 {
    edges(c, shift, r, s).iter().map(|e| e.1).sum()
}

/// The contact angles of the shortest closed polygon through the disks of centres `c` (radius
/// `r`, closing with `shift`) near the angles `s`: Levenberg–Marquardt-damped Newton on the
/// gradient of the length. `None` if it does not converge.
pub(crate) fn shortest_polygon(
    c: &[[f64; 2]],
    shift: [f64; 2],
    r: f64,
    mut s: Vec<f64>,
) -> Option<Vec<f64>> {
    let mut mu = 0.0;
    let mut len = length(c, shift, r, &s);
    for _ in 0..MAX_STEPS {
        let (g, h) = gradient_hessian(c, shift, r, &s);
        if g.iter().all(|x| x.abs() < TOLERANCE) {
            return Some(s);
        }
        let step = solve(&h, &g, mu);
        let trial: Option<Vec<f64>> = step.map(|d| s.iter().zip(&d).map(|(a, b)| a + b).collect());
        match trial {
            Some(t) if length(c, shift, r, &t) <= len + 1e-15 * len.max(1.0) => {
                len = length(c, shift, r, &t);
                s = t;
                mu *= 0.25;
            }
            _ => mu = (mu * 4.0).max(1e-3),
        }
        if !len.is_finite() || mu > 1e12 {
            return None;
        }
    }
    None
}

/// The unit edges of the polygon with contact angles `s`, as [`shortest_polygon`] measures it.
pub(crate) fn polygon_edges(
    c: &[[f64; 2]],
    shift: [f64; 2],
    r: f64,
    s: &[f64],
) -> Vec<([f64; 2], f64)> {
    edges(c, shift, r, s)
}
