//! The grid of a field sweep as the command line and Python give it: the scene's parameter (a
//! gap, an exact range of gaps, or the square lattice's radius) and the fields, as exact texts
//! ([`super::field::FieldGrid`] holds them).

use rug::{Integer, Rational};

use crate::Error;
use crate::numbers::exact::parse_exact;

/// The points of a field sweep's grid as exact texts: the triangular scene's gaps, or the square
/// scene's radius, and the fields.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SweepGrid {
    /// The gaps (empty with a radius).
    pub gaps: Vec<String>,
    /// The square lattice's radius.
    pub radius: Option<String>,
    /// The fields.
    pub fields: Vec<String>,
}

/// The grid of a field sweep as the command line and Python give it: one gap `w` (a sweep over
/// the field) or the exact grid `w_from` … `w_to` in `steps` points (a sweep over w); one `field`
/// or a list `fields`. Returns (gaps, fields) as exact texts.
///
/// # Errors
/// Neither or both of `w` and the range, neither or both of `field` and `fields`, or an end of
/// the range that is not exact.
pub fn grid_of(
    w: Option<&str>,
    range: (Option<&str>, Option<&str>, u32),
    field: Option<&str>,
    fields: &[String],
) -> Result<(Vec<String>, Vec<String>), Error> {
    let gaps = match (w, range) {
        (Some(w), (None, None, _)) => vec![w.trim().to_string()],
        (None, (Some(from), Some(to), steps)) => exact_grid(from, to, steps)?,
        (Some(w), _) => {
            return Err(Error::parameter(
                "w",
                w,
                "a sweep in a field takes either one gap (a sweep over the field) or the ends \
                 of a range of gaps (a sweep over w), not both",
            ));
        }
        (None, _) => {
            return Err(Error::SceneParameter {
                scene: "triangular",
                parameter: "w",
                needs: "w",
                range: "one gap (a sweep over the field), or the ends of a range of gaps (a \
                        sweep over w)",
                missing: true,
            });
        }
    };
    Ok((gaps, fields_of(field, fields)?))
}

/// The grid of a field sweep on the scene `scene` (`"triangular"` or `"square"`): the triangular
/// scene's gaps as [`grid_of`] gives them, or the square scene's one `radius` (a sweep over the
/// field), and the fields, as exact texts.
///
/// # Errors
/// An unknown scene, a parameter of the other scene, a square scene without its radius, or what
/// [`grid_of`] refuses.
pub fn scene_grid(
    scene: &str,
    (w, radius): (Option<&str>, Option<&str>),
    range: (Option<&str>, Option<&str>, u32),
    field: Option<&str>,
    fields: &[String],
) -> Result<SweepGrid, Error> {
    match scene {
        "square" => {
            let given = [("w", w), ("w_from", range.0), ("w_to", range.1)];
            if let Some((parameter, _)) = given.iter().find(|(_, v)| v.is_some()) {
                return Err(square_parameter(parameter, false));
            }
            let Some(r) = radius else {
                return Err(square_parameter("radius", true));
            };
            Ok(SweepGrid {
                gaps: Vec::new(),
                radius: Some(r.trim().to_string()),
                fields: fields_of(field, fields)?,
            })
        }
        "triangular" => {
            if radius.is_some() {
                return Err(Error::SceneParameter {
                    scene: "triangular",
                    parameter: "radius",
                    needs: "w",
                    range: "or the ends of a range of gaps; the radius is the square scene's",
                    missing: false,
                });
            }
            let (gaps, fields) = grid_of(w, range, field, fields)?;
            Ok(SweepGrid {
                gaps,
                radius: None,
                fields,
            })
        }
        "table" => {
            let given = [
                ("w", w),
                ("radius", radius),
                ("w_from", range.0),
                ("w_to", range.1),
            ];
            if let Some((parameter, _)) = given.iter().find(|(_, v)| v.is_some()) {
                return Err(Error::SceneParameter {
                    scene: "table",
                    parameter,
                    needs: "fields",
                    range: "a table given as data sweeps its field; the gaps and radius are the \
                            shipped scenes'",
                    missing: false,
                });
            }
            Ok(SweepGrid {
                gaps: Vec::new(),
                radius: None,
                fields: fields_of(field, fields)?,
            })
        }
        other => Err(Error::out_of_range(
            "scene",
            other,
            "use triangular, square or table",
        )),
    }
}

/// The square scene's refusal of `parameter` (the triangular scene's), or of its missing radius.
fn square_parameter(parameter: &'static str, missing: bool) -> Error {
    Error::SceneParameter {
        scene: "square",
        parameter,
        needs: "radius",
        range: "0 < radius < 1/2; the square scene sweeps the field at its radius",
        missing,
    }
}

/// The fields of a sweep: one `field` (a sweep over w) or the list `fields`, as exact texts.
///
/// # Errors
/// Neither or both.
pub fn fields_of(field: Option<&str>, fields: &[String]) -> Result<Vec<String>, Error> {
    match (field, fields.is_empty()) {
        (Some(b), true) => Ok(vec![b.trim().to_string()]),
        (None, false) => Ok(fields.iter().map(|b| b.trim().to_string()).collect()),
        (Some(b), false) => Err(Error::parameter(
            "field",
            b,
            "give either one field (a sweep over w) or a list of fields (a sweep over the \
             field), not both",
        )),
        (None, true) => Err(Error::missing(
            "fields",
            "give either one field (a sweep over w) or a list of fields (a sweep over the field)",
        )),
    }
}

/// The exact points `from + (to − from)·k/(steps − 1)`, k = 0 … steps − 1, as exact texts: a
/// terminating decimal where there is one, else a fraction `p/q` (both parse back to the same
/// rational).
///
/// # Examples
///
/// ```
/// use lorentz_gas::estimators::sweep::field_grid::exact_grid;
/// assert_eq!(exact_grid("0.1", "0.2", 3).unwrap(), ["0.1", "0.15", "0.2"]);
/// assert_eq!(exact_grid("0", "1", 4).unwrap(), ["0", "1/3", "2/3", "1"]);
/// ```
///
/// # Errors
/// Fewer than 2 steps, an end that is not an exact decimal or fraction, or equal ends.
pub fn exact_grid(from: &str, to: &str, steps: u32) -> Result<Vec<String>, Error> {
    if steps < 2 {
        return Err(Error::out_of_range("steps", steps, "use at least 2 points"));
    }
    let a = parse_exact(from).map_err(|e| e.named("w_from"))?;
    let b = parse_exact(to).map_err(|e| e.named("w_to"))?;
    if a == b {
        return Err(Error::parameter(
            "w_to",
            to,
            "the same gap as w_from: a range of gaps needs two different ends",
        ));
    }
    let span = Rational::from(&b - &a);
    Ok((0..steps)
        .map(|k| exact_text(&(a.clone() + span.clone() * Rational::from((k, steps - 1)))))
        .collect())
}

/// A rational as a terminating decimal if it is one (denominator 2ᵃ5ᵇ), else as `p/q`.
fn exact_text(x: &Rational) -> String {
    let mut den = x.denom().clone();
    let (mut twos, mut fives) = (0u32, 0u32);
    while den.is_divisible_u(2) {
        den /= 2;
        twos += 1;
    }
    while den.is_divisible_u(5) {
        den /= 5;
        fives += 1;
    }
    if den != 1 {
        return x.to_string();
    }
    let places = twos.max(fives);
    let scaled = (x.numer() * Integer::from(Integer::u_pow_u(10, places))) / x.denom().clone();
    let digits = scaled.clone().abs().to_string();
    let sign = if scaled < 0 { "-" } else { "" };
    if places == 0 {
        return format!("{sign}{digits}");
    }
    let p = places as usize;
    let padded = format!("{digits:0>width$}", width = p + 1);
    let (int, frac) = padded.split_at(padded.len() - p);
    format!("{sign}{int}.{frac}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_grid_texts_parse_back_to_the_grid() {
        let g = exact_grid("-0.25", "1/3", 5).unwrap();
        assert_eq!(g, ["-0.25", "-5/48", "1/24", "0.1875", "1/3"]);
        let f = exact_grid("0.1", "0.3", 21).unwrap();
        assert_eq!(f[1], "0.11");
        assert_eq!(exact_grid("0.001", "0.002", 2).unwrap(), ["0.001", "0.002"]);
        assert!(exact_grid("0.1", "0.2", 1).is_err());
    }
}
