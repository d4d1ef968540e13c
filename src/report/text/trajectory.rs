//! The text `lorentz trajectory` prints (one trajectory to certified digits): the command line
//! writes it to stdout, and Python's `str()` of the result is the same text.

use super::line;
use crate::estimators::trajectory::TrajectoryReport;

/// The text of a `trajectory` result at the time `time` as typed, line by line as the command
/// line prints it.
pub fn trajectory(r: &TrajectoryReport, time: &str) -> String {
    let mut out = String::new();
    line!(
        out,
        "{}{}, t = {time}: {} collisions, {} crossings",
        r.scene,
        match (&r.motion.electric, &r.motion.electric_angle) {
            (Some(e), Some(a)) => format!(" under the thermostatted field E = {e} at {a}°"),
            _ => String::new(),
        },
        r.collisions,
        r.crossings
    );
    line!(out, "x        = {}", r.x);
    line!(out, "y        = {}", r.y);
    line!(out, "distance = {}", r.distance);
    line!(
        out,
        "{} digits certified (runs at {} and {} bits agree to {:.1} digits and go through the same events; tried {:?})",
        r.certified_digits,
        r.precision_bits,
        2 * r.precision_bits,
        r.digits_agreed,
        r.tried
    );
    out
}
