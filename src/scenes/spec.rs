//! Which table: one description of the crate's scenes, parsed once from the text a user typed
//! and resolved to the scene itself, for the command line, the Python package and the
//! configurations alike.
//!
//! The parameter is kept exactly as typed (`"1/10"`, `"0.1"`): an analysis at P bits rounds it
//! once at P bits, never through `f64`. The refusals are typed ([`Error::SceneParameter`]) so
//! that each front end names the parameter in its own terms (`--w` on the command line, `w=` in
//! Python).

use serde::{Deserialize, Serialize};

use super::square::SquareScene;
use super::table::PeriodicTable;
use super::table::spec::TableSpec;
use super::triangular::TriangularScene;
use crate::Error;
use crate::numbers::exact::ExactInput;

/// The crate's scenes, each with its one parameter exactly as typed.
///
/// # Examples
///
/// ```
/// use lorentz_gas::scenes::spec::{SceneChoice, SceneSpec};
/// let s = SceneSpec::parse("triangular", Some("1/10"), None).unwrap();
/// assert_eq!(s, SceneSpec::Triangular { w: "1/10".into() });
/// assert!(matches!(s.resolve().unwrap(), SceneChoice::Triangular(_)));
/// // A parameter of the other scene, or none, is refused naming what the scene takes.
/// assert!(SceneSpec::parse("square", Some("0.1"), None).is_err());
/// assert!(SceneSpec::parse("square", None, None).is_err());
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "scene", rename_all = "lowercase", deny_unknown_fields)]
pub enum SceneSpec {
    /// The paper's triangular lattice of unit disks at the gap `w` > 0 (finite horizon below
    /// w∞ = 4/√3 − 2; the scene-generic analyses run beyond it too).
    Triangular {
        /// The gap, as typed (a decimal or a fraction).
        w: String,
    },
    /// The square lattice of unit spacing with disks of radius 0 < `radius` < 1/2.
    Square {
        /// The radius, as typed.
        radius: String,
    },
    /// Any periodic table of disks given as data (a `--table` file, a Python dict), every
    /// number as written.
    Table(TableSpec),
}

/// A scene resolved from its [`SceneSpec`], for the scene-generic analyses (one monomorphic
/// copy of an analysis per scene).
#[derive(Debug, Clone)]
pub enum SceneChoice {
    /// The triangular lattice.
    Triangular(Box<TriangularScene>),
    /// The square lattice.
    Square(SquareScene),
    /// A table given as data.
    Table(Box<PeriodicTable>),
}

/// What a scene takes and what its parameter's range is, for the refusals.
fn parameter_of(scene: &str) -> Option<(&'static str, &'static str)> {
    match scene {
        "triangular" => Some((
            "w",
            "w > 0 (a finite horizon below w_inf = 4/sqrt(3) - 2 = 0.3094...)",
        )),
        "square" => Some(("radius", "0 < radius < 1/2")),
        _ => None,
    }
}

impl SceneSpec {
    /// The scenes' names.
    pub const NAMES: [&'static str; 2] = ["triangular", "square"];

    /// The scene `name` with its gap `w` or its `radius` as typed: exactly the parameter the
    /// scene takes, parsed exactly (a decimal or a fraction).
    ///
    /// # Errors
    /// An unknown scene, the other scene's parameter, a missing one ([`Error::SceneParameter`]),
    /// or a value that is not a number.
    pub fn parse(name: &str, w: Option<&str>, radius: Option<&str>) -> Result<Self, Error> {
        let Some((needs, range)) = parameter_of(name) else {
            return Err(Error::out_of_range(
                "scene",
                name,
                format!("use one of {}", Self::NAMES.join(", ")),
            ));
        };
        let scene = if name == "square" {
            "square"
        } else {
            "triangular"
        };
        let (given, other) = match scene {
            "square" => (radius, w.map(|_| "w")),
            _ => (w, radius.map(|_| "radius")),
        };
        if let Some(parameter) = other {
            return Err(Error::SceneParameter {
                scene,
                parameter,
                needs,
                range,
                missing: false,
            });
        }
        let Some(text) = given else {
            return Err(Error::SceneParameter {
                scene,
                parameter: needs,
                needs,
                range,
                missing: true,
            });
        };
        let text = ExactInput::parse(text).map_err(|e| e.named(needs))?.text;
        Ok(match scene {
            "square" => SceneSpec::Square { radius: text },
            _ => SceneSpec::Triangular { w: text },
        })
    }

    /// The scene's name.
    pub fn name(&self) -> &'static str {
        match self {
            SceneSpec::Triangular { .. } => "triangular",
            SceneSpec::Square { .. } => "square",
            SceneSpec::Table(_) => "table",
        }
    }

    /// The scene itself, its parameter checked and kept exact.
    ///
    /// # Errors
    /// A gap that is not finite or not positive, a radius outside (0, 1/2), a table that is not
    /// one ([`Error::Table`]).
    pub fn resolve(&self) -> Result<SceneChoice, Error> {
        match self {
            SceneSpec::Table(t) => Ok(SceneChoice::Table(Box::new(PeriodicTable::new(t)?))),
            SceneSpec::Square { radius } => {
                let r = (ExactInput::parse(radius).map_err(|e| e.named("radius"))?)
                    .rational("radius")?;
                Ok(SceneChoice::Square(SquareScene::exact(r)?))
            }
            SceneSpec::Triangular { w } => {
                let w = ExactInput::parse(w).map_err(|e| e.named("w"))?;
                if !w.value.is_finite() {
                    return Err(Error::NotFinite { what: "w" });
                }
                if w.value <= 0.0 {
                    return Err(Error::Trapped { w: w.value });
                }
                let scene = TriangularScene::exact(w.rational("w")?)?;
                Ok(SceneChoice::Triangular(Box::new(scene)))
            }
        }
    }
}

/// Runs `$body` with `$s` bound to the concrete scene of a `&`[`SceneChoice`] (one monomorphic
/// copy of `$body` per scene).
#[macro_export]
macro_rules! with_scene {
    ($choice:expr, |$s:ident| $body:expr) => {
        match $choice {
            $crate::scenes::spec::SceneChoice::Triangular($s) => {
                let $s: &$crate::scenes::triangular::TriangularScene = $s;
                $body
            }
            $crate::scenes::spec::SceneChoice::Square($s) => {
                let $s: &$crate::scenes::square::SquareScene = $s;
                $body
            }
            $crate::scenes::spec::SceneChoice::Table($s) => {
                let $s: &$crate::scenes::table::PeriodicTable = $s;
                $body
            }
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_scene_takes_its_parameter_exactly_and_refuses_the_other() {
        let s = SceneSpec::parse("square", None, Some(" 1/3 ")).unwrap();
        assert_eq!(s.name(), "square");
        assert_eq!(
            serde_json::to_string(&s).unwrap(),
            r#"{"scene":"square","radius":"1/3"}"#
        );
        let back: SceneSpec = serde_json::from_str(r#"{"scene":"triangular","w":"0.1"}"#).unwrap();
        assert_eq!(back, SceneSpec::Triangular { w: "0.1".into() });
        assert!(serde_json::from_str::<SceneSpec>(r#"{"scene":"square","w":"0.1"}"#).is_err());
        for (name, w, r, missing, parameter) in [
            ("square", Some("0.1"), None, false, "w"),
            ("square", None, None, true, "radius"),
            ("triangular", None, Some("0.2"), false, "radius"),
            ("triangular", None, None, true, "w"),
        ] {
            match SceneSpec::parse(name, w, r) {
                Err(Error::SceneParameter {
                    parameter: p,
                    missing: m,
                    ..
                }) => assert_eq!((p, m), (parameter, missing), "{name}"),
                other => panic!("{name}: {other:?}"),
            }
        }
        assert!(SceneSpec::parse("hexagonal", Some("0.1"), None).is_err());
        let nan = SceneSpec::parse("triangular", Some("nan"), None).unwrap();
        assert!(matches!(nan.resolve(), Err(Error::NotFinite { what: "w" })));
        let zero = SceneSpec::parse("triangular", Some("0"), None).unwrap();
        assert!(matches!(zero.resolve(), Err(Error::Trapped { .. })));
        let wide = SceneSpec::parse("square", None, Some("1/2")).unwrap();
        assert!(wide.resolve().is_err());
    }

    /// The scene of `w = "1/10"` or `"0.1"` at 256 bits has w = 1/10 rounded once at 256 bits,
    /// not the double nearest 0.1 (which differs from 1/10 by 5.6e-18); the same for the radius.
    #[test]
    fn scenes_keep_the_exact_gap_and_radius() {
        use crate::scenes::Scene;
        use rug::{Float, Rational};
        let tenth = Float::with_val(256, Rational::from((1, 10)));
        for typed in ["0.1", "1/10"] {
            let spec = SceneSpec::parse("triangular", Some(typed), None).unwrap();
            let Ok(SceneChoice::Triangular(s)) = spec.resolve() else {
                panic!("a triangular scene")
            };
            let w = s.kernel::<Float>(256).unwrap().w;
            assert_eq!(w, tenth, "w = {typed}");
            assert_ne!(w, Float::with_val(256, 0.1f64), "w = {typed}");
            // f64 runs use the double nearest 0.1.
            assert_eq!(s.kernel::<f64>(()).unwrap().w, 0.1);
        }
        let spec = SceneSpec::parse("square", None, Some("1/3")).unwrap();
        let Ok(SceneChoice::Square(s)) = spec.resolve() else {
            panic!("a square scene")
        };
        let third = Float::with_val(256, Rational::from((1, 3)));
        assert_eq!(*s.kernel::<Float>(256).unwrap().disks[0].radius(), third);
    }
}
