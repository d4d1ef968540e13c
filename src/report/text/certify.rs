//! The text `lorentz certify` prints (a segment certified to its digits): the command line
//! writes it to stdout, and Python's `str()` of the result is the same text.

use super::line;
use crate::verification::certify::Certificate;

/// The text of a `certify` result as the command line prints it (the seed of the start is the
/// one in its `meta`).
pub fn certify(c: &Certificate) -> String {
    let mut out = String::new();
    line!(
        out,
        "{}: {} collisions from the seed-{} start certified to {:.1} digits (runs at {} and {} bits agree; tried {:?});\nthe f64 orbit from the same start stays within 1e-3 of it for {} collisions",
        c.scene,
        c.collisions,
        c.meta.seed.unwrap_or_default(),
        c.digits_agreed,
        c.bits,
        2 * c.bits,
        c.tried,
        c.f64_faithful_collisions
    );
    out
}
