//! How the particle moves between collisions: straight lines, arcs of a magnetic field, or the
//! flights of a Gaussian-thermostatted electric field — each parameter exactly as typed, one
//! variant of a table's description ([`super::spec::Table`]).

use serde::{Deserialize, Serialize};

use crate::Error;

/// How the particle moves between collisions.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Motion {
    /// Straight lines at speed 1.
    #[default]
    Straight,
    /// Arcs of a uniform magnetic field B perpendicular to the plane, B exactly as typed (a
    /// decimal or a fraction): the velocity turns at the angular velocity B, counter-clockwise
    /// for B > 0, on a cyclotron circle of radius 1/|B|.
    Field(String),
    /// A Gaussian-thermostatted electric field E in the plane (ṙ = v, v̇ = E − (E·v)v: the
    /// speed stays 1), its signed strength and its angle from the x axis in degrees, each exactly
    /// as typed (`proofs-notes/thermostat-flight.md`). Taken by the diffusion run (the current
    /// J(E), [`crate::estimators::current`]); the other analyses that hold a table refuse it
    /// ([`super::spec::Table::motion_taken_by`]). The Lyapunov pair, one trajectory and the
    /// bench take the field through their own configurations
    /// ([`crate::verification::lyapunov::LyapunovConfig::motion`],
    /// [`crate::estimators::trajectory::TrajectoryInput::electric`]).
    Thermostat {
        /// The signed strength (a decimal or a fraction); −E is the field turned by 180°.
        field: String,
        /// The angle of E from the x axis, in degrees (a decimal or a fraction).
        angle: String,
    },
}

impl Motion {
    /// The motion in the field B as typed: a field, or straight lines where B is exactly zero
    /// (text that is not a number stays a field, for validation to refuse naming it).
    pub fn in_field(b: &str) -> Motion {
        if crate::numbers::exact::parse_exact(b).is_ok_and(|q| q == 0) {
            Motion::Straight
        } else {
            Motion::Field(b.trim().to_string())
        }
    }

    /// The thermostatted field of strength `field` along `angle` (degrees), each as typed: straight
    /// lines where the strength is exactly zero, so that E = 0 keeps today's bits (text that is
    /// not a number stays a field, for validation to refuse naming it).
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::scenes::spec::Motion;
    /// assert_eq!(Motion::thermostat("0/3", "30"), Motion::Straight);
    /// let m = Motion::thermostat(" 3/10 ", "90");
    /// let th = m.thermostat_at::<f64>(()).unwrap().unwrap();
    /// assert_eq!((th.strength, th.dir.x, th.dir.y), (0.3, 0.0, 1.0));
    /// ```
    pub fn thermostat(field: &str, angle: &str) -> Motion {
        if crate::numbers::exact::parse_exact(field).is_ok_and(|q| q == 0) {
            Motion::Straight
        } else {
            Motion::Thermostat {
                field: field.trim().to_string(),
                angle: angle.trim().to_string(),
            }
        }
    }

    /// The thermostat's strength and angle as a configuration records them (`electric`,
    /// `electric_angle`): both `None` for another motion (a zero strength is straight lines).
    pub fn thermostat_texts(self) -> (Option<String>, Option<String>) {
        match self {
            Motion::Thermostat { field, angle } => (Some(field), Some(angle)),
            _ => (None, None),
        }
    }

    /// The field as typed, `None` for straight lines and for the thermostat.
    pub fn field(&self) -> Option<&str> {
        match self {
            Motion::Field(b) => Some(b),
            Motion::Straight | Motion::Thermostat { .. } => None,
        }
    }

    /// The thermostatted field at the working precision `ctx`, each input parsed exactly and
    /// rounded once there; `None` for another motion.
    ///
    /// # Errors
    /// A strength or an angle that is not an exact decimal or fraction.
    pub fn thermostat_at<T: crate::numbers::real::Real>(
        &self,
        ctx: T::Ctx,
    ) -> Result<Option<crate::kernel::thermostat::Thermostat<T>>, Error> {
        use crate::numbers::exact::parse_exact;
        let Motion::Thermostat { field, angle } = self else {
            return Ok(None);
        };
        let e = parse_exact(field).map_err(|e| e.named("electric"))?;
        let a = parse_exact(angle).map_err(|e| e.named("electric_angle"))?;
        Ok(crate::kernel::thermostat::Thermostat::exact(&e, &a, ctx))
    }
}

/// A motion's parameters exactly as a configuration gives them: the keys `field`, `electric` and
/// `electric_angle` that the configurations of the shadow audit, true shadowing and the Lyapunov
/// measurement flatten into their JSON (all absent: straight flights; a table's record has the
/// same keys, [`super::spec::Table`]). [`MotionInput::resolve`] checks its shape, once for all of
/// them; each analysis checks the ranges it takes.
///
/// # Examples
///
/// ```
/// use lorentz_gas::scenes::motion::{Motion, MotionInput};
/// let m = MotionInput::default().with_electric("-3/10", "90");
/// assert_eq!(m.resolve().unwrap(), Motion::thermostat("-3/10", "90"));
/// let json = serde_json::to_string(&m).unwrap();
/// assert_eq!(json, r#"{"electric":"-3/10","electric_angle":"90"}"#);
/// let both = MotionInput { field: Some("1".into()), ..m };
/// assert!(both.resolve().unwrap_err().to_string().contains("give one motion"));
/// ```
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct MotionInput {
    /// A uniform magnetic field B perpendicular to the plane, exactly as typed (a decimal or a
    /// fraction; absent or 0: no field): the flights are arcs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub field: Option<String>,
    /// A Gaussian-thermostatted electric field E, its signed strength exactly as typed (a decimal
    /// or a fraction; absent or 0: no field): the flights are the thermostat's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub electric: Option<String>,
    /// With `electric`: the angle of E from the x axis in degrees, exactly as typed (absent: 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub electric_angle: Option<String>,
}

impl MotionInput {
    /// The same input with the magnetic field B as typed (none where B is exactly zero,
    /// [`Motion::in_field`]); the electric field stays as it was.
    pub fn with_field(self, b: &str) -> Self {
        MotionInput {
            field: Motion::in_field(b).field().map(str::to_string),
            ..self
        }
    }

    /// The same input with the thermostatted field of strength `e` along `angle` degrees, each as
    /// typed (none where E is exactly zero, [`Motion::thermostat`]); the magnetic field stays as it
    /// was.
    pub fn with_electric(self, e: &str, angle: &str) -> Self {
        let (electric, electric_angle) = Motion::thermostat(e, angle).thermostat_texts();
        MotionInput {
            electric,
            electric_angle,
            ..self
        }
    }

    /// The motion: straight lines, a magnetic field's arcs or the thermostat's flights (a zero
    /// field of either kind is straight lines).
    ///
    /// # Errors
    /// Both a magnetic and an electric field, or an angle without the electric field.
    pub fn resolve(&self) -> Result<Motion, Error> {
        match (&self.field, &self.electric, &self.electric_angle) {
            (Some(_), Some(e), _) => Err(Error::parameter(
                "electric",
                e,
                "both a magnetic field and an electric one: give one motion",
            )),
            (_, None, Some(a)) => Err(Error::parameter(
                "electric_angle",
                a,
                "electric_angle without electric: give the field's strength too",
            )),
            (b, None, None) => Ok(b.as_deref().map_or(Motion::Straight, Motion::in_field)),
            (None, Some(e), a) => Ok(Motion::thermostat(e, a.as_deref().unwrap_or("0"))),
        }
    }
}
