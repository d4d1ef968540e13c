//! The text `lorentz cycles --w W` prints (the triangular Lorentz gas by certified cycles):
//! the command line writes it to stdout, and Python's `str()` of the result is the same text.

use super::line;
use crate::verification::cycles::lattice::Stage;
use crate::verification::cycles::lattice::run::LatticeReport;

/// A number of the table, `—` where there is none.
fn num(x: f64, digits: usize) -> String {
    if x.is_finite() {
        format!("{x:.digits$}")
    } else {
        "—".into()
    }
}

/// The text of a lattice `cycles` result, line by line as the command line prints it.
pub fn lattice_cycles(r: &LatticeReport) -> String {
    let mut out = String::new();
    let c = &r.config;
    let radius = r.cycles.iter().map(|p| p.cycle.radius).fold(0.0, f64::max);
    let prime: usize = r.cycles.iter().map(|p| p.images.len()).sum();
    line!(
        out,
        "triangular Lorentz gas, w = {}: prime cycles of length 1 to {} over the 12 letters \
         (A-F nearest, a-f second neighbours): {} C6v classes certified ({} prime cycles; \
         Newton-Kantorovich at {} bits, largest certificate radius {:.1e}), {} classes not \
         certified ({} by the f64 screen, {} by the kernel, {} without convergence or \
         certificate)",
        c.w,
        c.max_length,
        r.cycles.len(),
        prime,
        c.bits,
        radius,
        r.refused.len(),
        r.refused
            .iter()
            .filter(|x| x.stage == Stage::Screen)
            .count(),
        r.refused
            .iter()
            .filter(|x| x.stage == Stage::Kernel)
            .count(),
        r.refused
            .iter()
            .filter(|x| matches!(x.stage, Stage::Newton | Stage::Certificate))
            .count(),
    );
    line!(
        out,
        "zeta function expanded to z^N: D_N = <n^2>/(4 <T>), 1/zeta(0,0) (-> 0: flux \
         conservation), <T>/<n> against the exact mean free time {:.9}",
        r.mean_free_time_exact
    );
    line!(
        out,
        "{:>2}  {:>9} {:>9}  {:>13}  {:>12}  {:>12}  {:>12}  {:>12}",
        "N",
        "certified",
        "refused",
        "1/zeta(0,0)",
        "<T>/<n>",
        "D_N",
        "D_N-D_(N-1)",
        "<T>"
    );
    for t in &r.table {
        line!(
            out,
            "{:>2}  {:>9} {:>9}  {:>13}  {:>12}  {:>12}  {:>12}  {:>12}",
            t.max_length,
            t.certified,
            t.refused,
            num(t.averages.zeta, 9),
            num(t.mean_free_time, 8),
            num(t.averages.diffusion, 8),
            num(t.change, 8),
            num(t.averages.mean_period, 8)
        );
    }
    if let (Some(m), Some(t)) = (&r.msd, r.table.last()) {
        line!(
            out,
            "D from the MSD ({:.3e} collisions) = {:.6} ± {:.6}; D_{} - D_MSD = {:+.6} = {:+.1} \
             standard errors",
            m.collisions as f64,
            m.D,
            m.D_err,
            t.max_length,
            t.averages.diffusion - m.D,
            m.difference_sigma
        );
    }
    out
}
