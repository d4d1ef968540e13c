//! Open tables: finitely many disjoint disks and no lattice. A trajectory whose ray meets no
//! disk leaves the convex hull of the disks and has escaped ([`crate::kernel::open`]).
//!
//! Two forms, every number exact as typed: the three-disk repeller (disks of radius a at the
//! corners (0, 0), (R, 0), (R/2, R√3/2) of the equilateral triangle of side R; R and a rounded
//! once at the working precision, √3 too), and any disks given as data (a JSON or Python list
//! of centres and radii, each number a decimal or a fraction as written).
//!
//! ```json
//! {"name": "four disks", "disks": [{"centre": ["0", "0"], "radius": "1"},
//!                                 {"centre": ["6", "0"], "radius": "1/2"}]}
//! ```

use rug::Rational;
use serde::{Deserialize, Serialize};

use super::table::spec::{DiskSpec, Number};
use crate::Error;
use crate::kernel::cell::Disk;
use crate::kernel::open::OpenDisks;
use crate::kernel::vec2::Vec2;
use crate::numbers::exact::nearest_f64;
use crate::numbers::real::Real;

/// Most disks of an open table given as data (labels are bytes; the escape kernel tries every
/// disk at each flight).
pub const MAX_OPEN_DISKS: usize = 64;

/// The three-disk repeller's side R and radius a, as typed.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RepellerSpec {
    /// Distance R between the centres, R > 2a.
    pub side: Number,
    /// Disk radius a > 0.
    pub radius: Number,
}

/// An open table as written: the three-disk repeller, or disks given as data (exactly one of
/// the two).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OpenSpec {
    /// A name for labels and reports.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The three-disk repeller.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub repeller: Option<RepellerSpec>,
    /// Disks given as data: centres and radii.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub disks: Vec<DiskSpec>,
}

impl OpenSpec {
    /// The three-disk repeller of side `side` = R and radius `radius` = a, as typed.
    ///
    /// # Errors
    /// Text that is not an exact decimal or fraction (naming `side` or `radius`).
    pub fn repeller(side: &str, radius: &str) -> Result<Self, Error> {
        let number = |what: &'static str, text: &str| {
            Number::new(text).map_err(|why| Error::parameter(what, text.trim(), why))
        };
        Ok(OpenSpec {
            name: None,
            repeller: Some(RepellerSpec {
                side: number("side", side)?,
                radius: number("radius", radius)?,
            }),
            disks: Vec::new(),
        })
    }

    /// The open table written in JSON (`{"name": …, "disks": [{"centre": [x, y], "radius":
    /// r}, …]}`, numbers quoted or integers; or `{"repeller": {"side": R, "radius": a}}`),
    /// repeated keys refused; validated.
    ///
    /// # Errors
    /// Text that is not such a table, or a table that [`Self::validate`] refuses.
    pub fn from_json(text: &str) -> Result<Self, Error> {
        let refuse = |e: serde_json::Error| Error::Invalid(format!("open table: {e}"));
        let value = crate::engine::json::parse_unique(text.as_bytes()).map_err(refuse)?;
        let spec: OpenSpec = serde_json::from_value(value).map_err(refuse)?;
        spec.validate()?;
        Ok(spec)
    }

    /// The name for messages: the given one, or `three-disk repeller R = …, a = …`, or
    /// `open table of N disks`.
    pub fn title(&self) -> String {
        match (&self.name, &self.repeller) {
            (Some(n), _) => n.clone(),
            (None, Some(r)) => format!("three-disk repeller R = {}, a = {}", r.side, r.radius),
            (None, None) => format!("open table of {} disks", self.disks.len()),
        }
    }

    /// The disks exactly: (centre x, centre y, radius) as rationals, except that the repeller's
    /// third centre has the irrational height R√3/2, given here as `None` (see [`Self::at`]).
    fn exact(&self) -> Vec<(Rational, Option<Rational>, Rational)> {
        match &self.repeller {
            Some(r) => {
                let (side, a) = (r.side.value(), r.radius.value());
                let half = Rational::from(&side / 2u32);
                vec![
                    (Rational::new(), Some(Rational::new()), a.clone()),
                    (side, Some(Rational::new()), a.clone()),
                    (half, None, a),
                ]
            }
            None => (self.disks.iter())
                .map(|d| {
                    (
                        d.centre[0].value(),
                        Some(d.centre[1].value()),
                        d.radius.value(),
                    )
                })
                .collect(),
        }
    }

    /// Checks the table exactly: one of the two forms; radii > 0; 2 to [`MAX_OPEN_DISKS`] disks;
    /// no two disks touching (the repeller: R > 2a, decided exactly).
    ///
    /// # Errors
    /// [`Error::OutOfRange`] naming the parameter and its valid range.
    pub fn validate(&self) -> Result<(), Error> {
        if let Some(r) = &self.repeller {
            if !self.disks.is_empty() {
                return Err(Error::Invalid(
                    "an open table is either the repeller or disks given as data, not both".into(),
                ));
            }
            let (side, a) = (r.side.value(), r.radius.value());
            if a <= 0 {
                return Err(Error::out_of_range(
                    "radius",
                    &r.radius,
                    "use a radius a > 0",
                ));
            }
            if side <= Rational::from(&a * 2u32) {
                return Err(Error::out_of_range(
                    "side",
                    &r.side,
                    format!(
                        "use a side R > 2a = {} (disjoint disks)",
                        nearest_f64(&(a * 2u32))
                    ),
                ));
            }
            return Ok(());
        }
        let n = self.disks.len();
        if !(2..=MAX_OPEN_DISKS).contains(&n) {
            return Err(Error::out_of_range(
                "disks",
                n,
                format!("use 2 to {MAX_OPEN_DISKS} disks (or the repeller)"),
            ));
        }
        let exact = self.exact();
        for (i, (x, y, r)) in exact.iter().enumerate() {
            if *r <= 0 {
                return Err(Error::out_of_range(
                    "radius",
                    &self.disks[i].radius,
                    "use radii > 0",
                ));
            }
            let y = y.as_ref().expect("data disks are rational");
            for (j, (x2, y2, r2)) in exact[..i].iter().enumerate() {
                let y2 = y2.as_ref().expect("data disks are rational");
                let d2 = Rational::from(x - x2).square() + Rational::from(y - y2).square();
                if d2 <= Rational::from(r + r2).square() {
                    return Err(Error::out_of_range(
                        "disks",
                        format!("{j} and {i}"),
                        "use disjoint disks: each distance between centres above the sum of \
                         the two radii",
                    ));
                }
            }
        }
        Ok(())
    }

    /// The disks at the working precision `ctx`: each centre and radius rounded once (the
    /// repeller's third centre (R/2, √3·R/2) from R rounded once and √3 rounded once, as the
    /// cycles compute it).
    pub fn at<T: Real>(&self, ctx: T::Ctx) -> OpenDisks<T> {
        let disks = (self.exact().iter())
            .map(|(x, y, r)| {
                let cx = T::from_rational(ctx, x);
                let cy = match y {
                    Some(y) => T::from_rational(ctx, y),
                    None => {
                        let side = T::from_rational(ctx, &self.repeller_side());
                        (T::sqrt3(ctx) * &side).scale(0.5)
                    }
                };
                Disk::new(Vec2::new(cx, cy), T::from_rational(ctx, r))
            })
            .collect();
        OpenDisks::new(disks)
    }

    /// The repeller's R (zero for a table of data disks, which never asks).
    fn repeller_side(&self) -> Rational {
        self.repeller
            .as_ref()
            .map_or_else(Rational::new, |r| r.side.value())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_repeller_and_data_disks_are_exact_and_checked() {
        let r = OpenSpec::repeller("6", "1").unwrap();
        r.validate().unwrap();
        let d = r.at::<f64>(());
        assert_eq!(d.disks[2].centre, Vec2::new(3.0, 3.0 * 3f64.sqrt()));
        assert!(OpenSpec::repeller("2", "1").unwrap().validate().is_err());
        assert!(OpenSpec::repeller("6", "0").unwrap().validate().is_err());
        assert!(OpenSpec::repeller("6", "x").is_err());
        let ok = r#"{"disks": [{"centre": ["0", "0"], "radius": "1"},
                               {"centre": ["21/10", 0], "radius": "1/10"}]}"#;
        let t = OpenSpec::from_json(ok).unwrap();
        assert_eq!(t.at::<f64>(()).disks[1].centre.x, 2.1);
        let touching = ok.replace("21/10", "11/10");
        assert!(OpenSpec::from_json(&touching).is_err());
        let float = ok.replace("\"21/10\"", "2.1");
        assert!(OpenSpec::from_json(&float).is_err());
        let one = r#"{"disks": [{"centre": ["0", "0"], "radius": "1"}]}"#;
        assert!(OpenSpec::from_json(one).is_err());
    }
}
