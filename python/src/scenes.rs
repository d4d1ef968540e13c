//! A scene from its name and its parameter (`w` for the triangular scene, `radius` for the
//! square one), with the command line's checks and messages.

use pyo3::exceptions::PyValueError;
use pyo3::PyResult;

use lorentz_gas::scenes::square::SquareScene;
use lorentz_gas::scenes::triangular::TriangularScene;
use lorentz_gas::Error;

use crate::inputs::exact;
use crate::py_err;

/// A resolved scene, for the library's scene-generic analyses (see [`with_scene`]).
pub enum SceneChoice {
    Triangular(Box<TriangularScene>),
    Square(SquareScene),
}

/// The scene `name` with its gap `w` or its radius (exact text), each checked.
pub fn resolve(name: &str, w: Option<&str>, radius: Option<&str>) -> PyResult<SceneChoice> {
    let refuse = |p: &str, scene: &str| {
        Err(PyValueError::new_err(format!(
            "{p} does not apply to the {scene} scene: use w with scene='triangular', radius with scene='square'"
        )))
    };
    match name {
        "square" => {
            if w.is_some() {
                return refuse("w", "square");
            }
            let r = radius.ok_or_else(|| {
                PyValueError::new_err("the square scene needs radius: 0 < radius < 1/2")
            })?;
            let r = exact("radius", r)?;
            SquareScene::exact(r.rational("radius").map_err(py_err)?)
                .map(SceneChoice::Square)
                .map_err(py_err)
        }
        "triangular" => {
            if radius.is_some() {
                return refuse("radius", "triangular");
            }
            let w = w.ok_or_else(|| {
                PyValueError::new_err(
                    "the triangular scene needs w: w > 0 (a finite horizon below w_inf = 4/sqrt(3) - 2 = 0.3094...)",
                )
            })?;
            let w = exact("w", w)?;
            // Any w > 0 (beyond w_inf the horizon is infinite: audits, Lyapunov exponents and
            // events run there; diffusion refuses it itself).
            if !w.value.is_finite() {
                return Err(py_err(Error::NotFinite { what: "w" }));
            }
            if w.value <= 0.0 {
                return Err(py_err(Error::Trapped { w: w.value }));
            }
            TriangularScene::exact(w.rational("w").map_err(py_err)?)
                .map(|s| SceneChoice::Triangular(Box::new(s)))
                .map_err(py_err)
        }
        _ => Err(PyValueError::new_err(format!(
            "scene '{name}' is not one of 'triangular', 'square'"
        ))),
    }
}

/// Runs `$body` with `$s` bound to the concrete scene of `$choice` (one copy per scene).
macro_rules! with_scene {
    ($choice:expr, |$s:ident| $body:expr) => {
        match $choice {
            $crate::scenes::SceneChoice::Triangular($s) => {
                let $s: &lorentz_gas::scenes::triangular::TriangularScene = &$s;
                $body
            }
            $crate::scenes::SceneChoice::Square($s) => $body,
        }
    };
}
pub(crate) use with_scene;
