//! Which table: one description of the crate's scenes, parsed once from the text a user typed
//! and resolved to the scene itself, for the command line, the Python package and the
//! configurations alike.
//!
//! The parameter is kept exactly as typed (`"1/10"`, `"0.1"`): an analysis at P bits rounds it
//! once at P bits, never through `f64`. The refusals are typed ([`Error::SceneParameter`]) so
//! that each front end names the parameter in its own terms (`--w` on the command line, `w=` in
//! Python).

use serde::{Deserialize, Serialize};

use super::open::OpenSpec;
use super::square::SquareScene;
use super::table::PeriodicTable;
use super::table::spec::TableSpec;
use super::triangular::TriangularScene;
use crate::Error;
use crate::numbers::exact::ExactInput;

pub use super::motion::Motion;

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
    /// An open table: finitely many disks and no lattice (the three-disk repeller, or disks
    /// given as data), whose trajectories escape. Only the escape analysis takes it; every
    /// analysis of a lattice refuses it ([`Error::Lacks`] a lattice, from [`Self::resolve`]).
    Open(OpenSpec),
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
            SceneSpec::Open(_) => "open",
        }
    }

    /// The scene itself, its parameter checked and kept exact.
    ///
    /// # Errors
    /// A gap that is not finite or not positive, a radius outside (0, 1/2), a table that is not
    /// one ([`Error::Table`]), an open table (no lattice: [`Error::Lacks`]).
    pub fn resolve(&self) -> Result<SceneChoice, Error> {
        match self {
            SceneSpec::Open(t) => Err(Error::Lacks {
                scene: t.title(),
                capability: crate::Capability::Lattice,
                analysis: "lattice",
            }),
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

/// The fields the transport analyses take: 10⁻³ ≤ |B| ≤ 10³ (cyclotron radii from 10⁻³ to 10³;
/// the kernel itself is tested from 10⁻⁶ to 10⁶).
pub const FIELD_RANGE: (f64, f64) = (1e-3, 1e3);

/// The field B of `text` as the nearest double, checked: nonzero and within [`FIELD_RANGE`].
///
/// # Errors
/// A field that is not an exact decimal or fraction, zero (the straight-line run: leave the
/// field out), or outside [`FIELD_RANGE`].
pub fn field_value(text: &str) -> Result<f64, Error> {
    use crate::numbers::exact::{nearest_f64, parse_exact};
    let b = nearest_f64(&parse_exact(text).map_err(|e| e.named("field"))?);
    if b == 0.0 {
        return Err(Error::out_of_range(
            "field",
            shown(text),
            format!(
                "use {:e} <= |field| <= {:e} (field = 0 is the zero-field run: leave the \
                 field out)",
                FIELD_RANGE.0, FIELD_RANGE.1
            ),
        ));
    }
    field_within(b, text, FIELD_RANGE)?;
    Ok(b)
}

/// Refuses the field `b` (typed as `text`) unless `lo ≤ |b| ≤ hi`. The bounds are decimals
/// and `b` is the double nearest the exact field, so a field typed as a bound (`1e-3`, `1/1000`)
/// is the bound and accepted: one rule for every analysis and its range.
///
/// # Errors
/// [`Error::OutOfRange`] naming the range, with the field as typed (shortened).
pub fn field_within(b: f64, text: &str, (lo, hi): (f64, f64)) -> Result<(), Error> {
    if (lo..=hi).contains(&b.abs()) {
        return Ok(());
    }
    Err(Error::out_of_range(
        "field",
        shown(text),
        format!("use {lo:e} <= |field| <= {hi:e}"),
    ))
}

/// A value as typed, for a message: trimmed, and shortened beyond 32 characters.
fn shown(text: &str) -> String {
    let t = text.trim();
    match t.char_indices().nth(32) {
        Some((at, _)) => format!("{}…", &t[..at]),
        None => t.to_string(),
    }
}

/// What is simulated: the geometry (which table, its parameters exactly as typed) and the motion.
/// Every analysis's configuration holds one; what only some tables have is asked of it
/// ([`Error::Lacks`]).
///
/// In a configuration's JSON the table is flattened into the record in the form each kind of
/// result has always had, so that files written before the table existed read as they were: the
/// triangular gas without a field as `w` (the double) and `w_exact` (as typed), everything else as
/// `scene` (a [`SceneSpec`]) with `field` for a field.
///
/// # Examples
///
/// ```
/// use lorentz_gas::scenes::spec::{Motion, SceneSpec, Table};
/// let t = Table::triangular("1/10").unwrap();
/// assert_eq!(t.gap_for("hops").unwrap(), 0.1);
/// assert_eq!(serde_json::to_string(&t).unwrap(), r#"{"w":0.1,"w_exact":"1/10"}"#);
/// let f = Table { scene: SceneSpec::Square { radius: "1/4".into() }, motion: Motion::Field("1".into()) };
/// assert_eq!(
///     serde_json::to_string(&f).unwrap(),
///     r#"{"scene":{"scene":"square","radius":"1/4"},"field":"1"}"#
/// );
/// // A record of before: the double alone is the gap.
/// let old: Table = serde_json::from_str(r#"{"w":0.1}"#).unwrap();
/// assert_eq!(old.gap_for("hops").unwrap(), 0.1);
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "TableRecord", into = "TableRecord")]
pub struct Table {
    /// The geometry.
    pub scene: SceneSpec,
    /// The motion.
    pub motion: Motion,
}

/// The keys a table has in a configuration's JSON.
#[derive(Serialize, Deserialize)]
struct TableRecord {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    w: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    w_exact: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    scene: Option<SceneSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    field: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    electric: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    electric_angle: Option<String>,
}

impl From<Table> for TableRecord {
    fn from(t: Table) -> Self {
        let (field, electric, electric_angle) = match t.motion {
            Motion::Straight => (None, None, None),
            Motion::Field(b) => (Some(b), None, None),
            Motion::Thermostat { field, angle } => (None, Some(field), Some(angle)),
        };
        match t.scene {
            SceneSpec::Triangular { w } if field.is_none() && electric.is_none() => TableRecord {
                w: Some(ExactInput::parse(&w).map_or(f64::NAN, |x| x.value)),
                w_exact: Some(w),
                scene: None,
                field,
                electric,
                electric_angle,
            },
            scene => TableRecord {
                w: None,
                w_exact: None,
                scene: Some(scene),
                field,
                electric,
                electric_angle,
            },
        }
    }
}

impl TryFrom<TableRecord> for Table {
    type Error = Error;
    fn try_from(r: TableRecord) -> Result<Self, Error> {
        let motion = match (r.field, r.electric, r.electric_angle) {
            (Some(_), Some(_), _) => {
                return Err(Error::Invalid(
                    "both a magnetic `field` and an `electric` one: give one motion".into(),
                ));
            }
            (_, None, Some(_)) => {
                return Err(Error::Invalid(
                    "`electric_angle` without `electric`: give the field's strength".into(),
                ));
            }
            (b, None, None) => b.map_or(Motion::Straight, Motion::Field),
            (None, Some(e), angle) => Motion::thermostat(&e, angle.as_deref().unwrap_or("0")),
        };
        let scene = match (r.w, r.scene) {
            (Some(w), None) => {
                if motion != Motion::Straight {
                    return Err(Error::Invalid(
                        "a gap w with a field: a field's table is given as `scene`".into(),
                    ));
                }
                crate::numbers::exact::check_exact(("w", "w_exact"), w, r.w_exact.as_deref())?;
                match r.w_exact {
                    Some(text) => SceneSpec::Triangular { w: text },
                    None => Table::triangular_at(w).scene,
                }
            }
            (None, Some(scene)) if r.w_exact.is_none() => scene,
            (None, None) => {
                return Err(Error::Invalid(
                    "no table: give `w` (the triangular gas's gap) or `scene`".into(),
                ));
            }
            _ => {
                return Err(Error::Invalid(
                    "both a gap `w` and a `scene`: give one table".into(),
                ));
            }
        };
        Ok(Table { scene, motion })
    }
}

impl Table {
    /// The triangular gas at the gap `w` as typed (a decimal or a fraction), without a field.
    ///
    /// # Errors
    /// Text that is not an exact number (or `nan`, `inf`, which validation refuses later).
    pub fn triangular(w: &str) -> Result<Table, Error> {
        let text = ExactInput::parse(w).map_err(|e| e.named("w"))?.text;
        Ok(Table {
            scene: SceneSpec::Triangular { w: text },
            motion: Motion::Straight,
        })
    }

    /// The triangular gas at the gap that is exactly the double `w` (runs at any precision start
    /// from that binary number), without a field.
    pub fn triangular_at(w: f64) -> Table {
        let text = crate::numbers::exact::exact_text_of(w).unwrap_or_else(|| format!("{w:?}"));
        Table {
            scene: SceneSpec::Triangular { w: text },
            motion: Motion::Straight,
        }
    }

    /// The same geometry in the field B (as typed); `"0"` is the table without a field.
    pub fn in_field(&self, b: &str) -> Table {
        Table {
            scene: self.scene.clone(),
            motion: Motion::in_field(b),
        }
    }

    /// The triangular gap as typed, `None` on another scene.
    pub fn gap_text(&self) -> Option<&str> {
        match &self.scene {
            SceneSpec::Triangular { w } => Some(w),
            _ => None,
        }
    }

    /// The triangular gap as the nearest double (what `f64` runs use), for `analysis`, which
    /// runs on the triangular gas only.
    ///
    /// # Errors
    /// Another scene ([`Error::Lacks`] trap symbols), or a gap that is not a number.
    pub fn gap_for(&self, analysis: &'static str) -> Result<f64, Error> {
        let Some(w) = self.gap_text() else {
            return Err(self.lacks(crate::Capability::TrapSymbols, analysis));
        };
        Ok(ExactInput::parse(w).map_err(|e| e.named("w"))?.value)
    }

    /// The field B as the nearest double, checked ([`field_value`]); `None` without a field.
    ///
    /// # Errors
    /// As [`field_value`].
    pub fn field_value(&self) -> Result<Option<f64>, Error> {
        self.field().map(field_value).transpose()
    }

    /// The field B as typed, `None` without a field.
    pub fn field(&self) -> Option<&str> {
        self.motion.field()
    }

    /// Refuses a motion `analysis` does not take yet: the thermostatted field is taken by the
    /// diffusion run (whose validation does not call this) and by no other analysis so far, and
    /// [`Self::field`] is `None` for it, so an analysis that did not ask would fly straight
    /// lines. Every other configuration holding a table calls this in its validation.
    ///
    /// # Errors
    /// [`Error::Invalid`] for [`Motion::Thermostat`], naming the analysis.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::estimators::hops::HopsConfig;
    /// use lorentz_gas::scenes::spec::{Motion, Table};
    /// let mut cfg = HopsConfig::new(Table::triangular("1/10").unwrap());
    /// assert!(cfg.validate().is_ok());
    /// cfg.table.motion = Motion::thermostat("3/10", "0");
    /// let e = cfg.validate().unwrap_err().to_string();
    /// assert!(e.contains("hops does not take the thermostatted electric field"), "{e}");
    /// // A zero field is the straight-line table.
    /// cfg.table.motion = Motion::thermostat("0", "30");
    /// assert!(cfg.validate().is_ok());
    /// ```
    pub fn motion_taken_by(&self, analysis: &'static str) -> Result<(), Error> {
        match self.motion {
            Motion::Thermostat { .. } => Err(Error::Invalid(format!(
                "{analysis} does not take the thermostatted electric field yet: leave it out"
            ))),
            _ => Ok(()),
        }
    }

    /// The refusal of `analysis` on this table, which lacks `capability`.
    pub fn lacks(&self, capability: crate::Capability, analysis: &'static str) -> Error {
        Error::Lacks {
            scene: self.title(),
            capability,
            analysis,
        }
    }

    /// The table's name for messages: the scene's, or a table's own title.
    pub fn title(&self) -> String {
        match &self.scene {
            SceneSpec::Table(t) => t.title().to_string(),
            SceneSpec::Open(t) => t.title(),
            s => s.name().to_string(),
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

    /// E = 0 is the straight motion itself (today's bits); a thermostat is written with its
    /// inputs as typed and refused on reading until the analyses take it; its field is exact.
    #[test]
    fn a_thermostat_is_straight_at_zero_field_and_exact_otherwise() {
        assert_eq!(Motion::thermostat("0.000", "45"), Motion::Straight);
        assert_eq!(Motion::thermostat("-0", "1/3"), Motion::Straight);
        let m = Motion::thermostat("1/3", "-90");
        assert_eq!(m.field(), None);
        let th = m.thermostat_at::<rug::Float>(256).unwrap().unwrap();
        assert_eq!(
            th.strength,
            rug::Float::with_val(256, rug::Rational::from((1, 3)))
        );
        assert_eq!((th.dir.x.to_f64(), th.dir.y.to_f64()), (0.0, -1.0));
        assert!(
            Motion::thermostat("x", "0")
                .thermostat_at::<f64>(())
                .is_err()
        );
        let t = Table {
            scene: SceneSpec::Triangular { w: "0.1".into() },
            motion: m,
        };
        let json = serde_json::to_string(&t).unwrap();
        assert_eq!(
            json,
            r#"{"scene":{"scene":"triangular","w":"0.1"},"electric":"1/3","electric_angle":"-90"}"#
        );
        assert_eq!(serde_json::from_str::<Table>(&json).unwrap(), t);
        for bad in [
            r#"{"scene":{"scene":"square","radius":"1/4"},"field":"1","electric":"1"}"#,
            r#"{"scene":{"scene":"square","radius":"1/4"},"electric_angle":"30"}"#,
        ] {
            assert!(serde_json::from_str::<Table>(bad).is_err(), "{bad}");
        }
        // A zero field read is the straight table.
        let zero = r#"{"scene":{"scene":"square","radius":"1/4"},"electric":"0/7"}"#;
        let read: Table = serde_json::from_str(zero).unwrap();
        assert_eq!(read.motion, Motion::Straight);
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
