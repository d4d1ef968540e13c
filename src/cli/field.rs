//! `lorentz diffusion --field B`: the diffusion tensor in a magnetic field.

use lorentz_gas::estimators::field::FieldReport;
use lorentz_gas::statistics::comparison;

/// The text of a field result, and on stderr a warning when the diffusing part's mean free
/// time is far from Kac's.
pub fn print(r: &FieldReport) {
    print!("{}", lorentz_gas::report::text::field::field(r));
    if r.point.all_localized {
        return;
    }
    let n = r.point.batch_D_xx.len();
    let kac = comparison::of(
        r.point.mean_free_time - r.point.mean_free_time_exact,
        r.point.mean_free_time_err,
        comparison::batch_dof(n),
    );
    if !kac.agrees() {
        eprintln!(
            "warning: the diffusing part's mean free time is {:.1} standard errors from Kac's: \
             what is neither pinned nor skipping is not one ergodic component here (regular \
             islands of orbits that stay near their start), and {n} batches do not sample the \
             components in proportion; use more --batches",
            kac.z.abs()
        );
    }
}
