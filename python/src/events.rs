//! `events`: the consecutive events of one trajectory as numpy columns, for a user's own
//! observables (free paths, velocity autocorrelations, Poincaré sections).

use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::{PyMemoryError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use lorentz_gas::Error;
use lorentz_gas::engine::long_flight::Flights;
use lorentz_gas::estimators::field::FieldWalk;
use lorentz_gas::kernel::flight::EventKind;
use lorentz_gas::numbers::exact::parse_exact;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::lattice::{LatticeState, Unwrapped};
use lorentz_gas::scenes::long_flight::LongFlights;
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::spec::SceneChoice;
use lorentz_gas::scenes::square::SquareScene;
use lorentz_gas::scenes::table::PeriodicTable;
use lorentz_gas::scenes::triangular::TriangularScene;

use crate::inputs::count_u64;
use crate::params::Params;
use crate::scenes::Where;
use crate::watch::{Ctl, compute};
use lorentz_gas::with_scene;

/// Bytes per event: the columns here (5 `f64`, 2 `i64`, 4 `u8`) and the structured array the
/// Python package builds from them (the same, padded, with the kind as a name of up to 9
/// characters).
pub const BYTES_PER_EVENT: u64 = 60 + 100;

/// Most events of one call: 2³² (about 500 GiB of events; memory refuses far fewer).
pub const MAX_EVENTS: u64 = 1 << 32;

/// Events between two looks at the stop flag and two progress reports.
const CHUNK: u64 = 1 << 16;

/// The columns of the events.
#[derive(Default)]
struct Columns {
    t: Vec<f64>,
    x: Vec<f64>,
    y: Vec<f64>,
    vx: Vec<f64>,
    vy: Vec<f64>,
    kind: Vec<u8>,
    collision: Vec<u8>,
    obstacle: Vec<u8>,
    down: Vec<u8>,
    i: Vec<i64>,
    j: Vec<i64>,
}

/// The `kind` codes: the start of the trajectory, a collision with a disk, an edge crossing, and
/// a long flight's landing (Python names them `"start"`, `"collision"`, `"crossing"`, `"jump"`).
const START: u8 = 0;
const COLLISION: u8 = 1;
const CROSSING: u8 = 2;
const JUMP: u8 = 3;
/// The obstacle label of the start row (no obstacle).
const NO_OBSTACLE: u8 = 255;

impl Columns {
    /// One event: time `t`, world position `p` after it, the state after it and its kind
    /// (`None`: the start).
    fn push(&mut self, t: f64, p: [f64; 2], s: &LatticeState<f64>, kind: Option<EventKind>) {
        let (code, label) = match kind {
            None => (START, NO_OBSTACLE),
            Some(EventKind::Collision(d)) => (COLLISION, d),
            Some(EventKind::Crossing(e)) => (CROSSING, e),
        };
        self.push_coded(t, p, s, code, label);
    }

    /// One event of kind `code` at obstacle `label` (time `t`, position `p`, state `s` after it).
    fn push_coded(&mut self, t: f64, p: [f64; 2], s: &LatticeState<f64>, code: u8, label: u8) {
        let sg = s.cell.sign();
        self.t.push(t);
        self.x.push(p[0]);
        self.y.push(p[1]);
        self.vx.push(sg * s.flight.vel.x);
        self.vy.push(sg * s.flight.vel.y);
        self.kind.push(code);
        self.collision.push(u8::from(code == COLLISION));
        self.obstacle.push(label);
        self.down.push(u8::from(s.cell.down));
        self.i.push(s.cell.i);
        self.j.push(s.cell.j);
    }

    fn with_capacity(n: usize) -> Self {
        Columns {
            t: Vec::with_capacity(n),
            x: Vec::with_capacity(n),
            y: Vec::with_capacity(n),
            vx: Vec::with_capacity(n),
            vy: Vec::with_capacity(n),
            kind: Vec::with_capacity(n),
            collision: Vec::with_capacity(n),
            obstacle: Vec::with_capacity(n),
            down: Vec::with_capacity(n),
            i: Vec::with_capacity(n),
            j: Vec::with_capacity(n),
        }
    }
}

/// The memory the machine has available now (`MemAvailable` of /proc/meminfo), if known.
fn available_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Refuses `n` events beyond [`MAX_EVENTS`] or beyond 80 % of the available memory.
fn check_memory(n: u64) -> PyResult<()> {
    if n == 0 || n > MAX_EVENTS {
        return Err(PyValueError::new_err(format!(
            "n = {n} is out of range: use 1 to {MAX_EVENTS} events"
        )));
    }
    let need = n.saturating_mul(BYTES_PER_EVENT);
    if let Some(avail) = available_bytes()
        && need as f64 > 0.8 * avail as f64
    {
        return Err(PyMemoryError::new_err(format!(
            "n = {n} events need {:.2} GiB ({BYTES_PER_EVENT} bytes each), more than 80 % of \
                 the {:.2} GiB available: ask for at most {} events, and continue a Trajectory in chunks",
            need as f64 / 2f64.powi(30),
            avail as f64 / 2f64.powi(30),
            (0.8 * avail as f64 / BYTES_PER_EVENT as f64) as u64
        )));
    }
    Ok(())
}

/// `n` events, each appended by `event` (given the time so far, it returns the flight time to
/// the event), in chunks between looks at the stop flag and progress reports; the time starts at
/// `t0` (the time of the previous call's last event: one running sum, so chunks have the bits of
/// one call) and its final value is returned.
fn collect(
    n: u64,
    t0: f64,
    ctl: &Ctl<'_>,
    mut event: impl FnMut(&mut Columns, f64) -> Result<f64, Error>,
) -> Result<(Columns, f64), Error> {
    let mut c = Columns::with_capacity(n as usize);
    let mut t = t0;
    let mut k = 0u64;
    while k < n {
        ctl.stop.check()?;
        let end = (k + CHUNK).min(n);
        for _ in k..end {
            let dt = event(&mut c, t)?;
            t += dt;
        }
        (ctl.progress)(end - k);
        k = end;
    }
    Ok((c, t))
}

/// The next `n` events of the trajectory at `s` (time `t0` so far) of `scene`, on the scalar
/// `f64` engine, with the long flights `flights` jumped (`None`: the cell walk, every crossing an
/// event); the time at the last.
///
/// A jump is the engine's ([`lorentz_gas::engine::long_flight::drive_jumps`]): at the crossing of
/// the trigger edge the search finds the landing, and the row is the landing (kind `jump`, the
/// entered edge as its obstacle, the flight time from the pre-jump position); the crossings it
/// skips are not rows. Where the search walks, the crossing is an ordinary row.
fn advance<S: Scene>(
    scene: &S,
    flights: Option<&LongFlights>,
    s: &mut LatticeState<f64>,
    t0: f64,
    n: u64,
    ctl: &Ctl<'_>,
) -> Result<(Columns, f64), Error> {
    let lat = scene.lattice::<f64>(())?;
    let basis = lat.basis_f64();
    let origin = Unwrapped::default();
    collect(n, t0, ctl, |c, t| {
        let ev = lat
            .next_event(s)
            .ok_or_else(|| Error::Failed("trajectory lost its next event".into()))?;
        if let Some(f) = flights
            && let Some(landing) = f.landing_at(s, ev.kind)?
        {
            s.cell = landing.cell;
            s.flight = landing.flight;
            let p = lat.unwrapped(s, 0.0).displacement_from(&origin, &basis);
            let entered = s.flight.excluded_edge.unwrap_or(NO_OBSTACLE);
            c.push_coded(t + landing.time, p, s, JUMP, entered);
            return Ok(landing.time);
        }
        lat.apply(s, &ev);
        let p = lat.unwrapped(s, 0.0).displacement_from(&origin, &basis);
        c.push(t + ev.time, p, s, Some(ev.kind));
        Ok(ev.time)
    })
}

/// The next `n` events of the field walk `walk` (time `t0` so far), on the `f64` arc kernel.
fn advance_in_field<S: Scene>(
    walk: &mut FieldWalk<S>,
    t0: f64,
    n: u64,
    ctl: &Ctl<'_>,
) -> Result<(Columns, f64), Error> {
    let lat = walk.lattice().clone();
    let basis = lat.basis_f64();
    let origin = Unwrapped::default();
    collect(n, t0, ctl, |c, t| {
        let ev = walk.step()?;
        let s = walk.state();
        let p = lat.unwrapped(s, 0.0).displacement_from(&origin, &basis);
        c.push(t + ev.time, p, s, Some(ev.kind));
        Ok(ev.time)
    })
}

/// A walk in a field on either lattice.
enum AnyFieldWalk {
    Triangular(Box<FieldWalk<TriangularScene>>),
    Square(FieldWalk<SquareScene>),
    Table(Box<FieldWalk<PeriodicTable>>),
}

impl AnyFieldWalk {
    fn state(&self) -> &LatticeState<f64> {
        match self {
            AnyFieldWalk::Triangular(w) => w.state(),
            AnyFieldWalk::Square(w) => w.state(),
            AnyFieldWalk::Table(w) => w.state(),
        }
    }

    /// The next `n` events (time `t0` so far).
    fn advance(&mut self, t0: f64, n: u64, ctl: &Ctl<'_>) -> Result<(Columns, f64), Error> {
        match self {
            AnyFieldWalk::Triangular(w) => advance_in_field(w, t0, n, ctl),
            AnyFieldWalk::Square(w) => advance_in_field(w, t0, n, ctl),
            AnyFieldWalk::Table(w) => advance_in_field(w, t0, n, ctl),
        }
    }
}

/// The walk of a nonzero field (`None` for no field or exactly 0: the events without a field,
/// with their own bits).
fn field_walk(
    choice: &SceneChoice,
    field: Option<&str>,
    seed: u64,
    batch: u32,
) -> PyResult<Option<AnyFieldWalk>> {
    let Some(b) = field else {
        return Ok(None);
    };
    let exact =
        parse_exact(b).map_err(|e| PyValueError::new_err(format!("field = {}: {e}", b.trim())))?;
    if exact == 0 {
        return Ok(None);
    }
    let batch = u64::from(batch);
    match choice {
        SceneChoice::Triangular(s) => FieldWalk::start(s.as_ref(), b, seed, batch)
            .map(|w| AnyFieldWalk::Triangular(Box::new(w))),
        SceneChoice::Square(s) => FieldWalk::start(s, b, seed, batch).map(AnyFieldWalk::Square),
        SceneChoice::Table(s) => {
            FieldWalk::start(s.as_ref(), b, seed, batch).map(|w| AnyFieldWalk::Table(Box::new(w)))
        }
    }
    .map(Some)
    .map_err(crate::py_err)
}

/// One trajectory's events, continued call after call: the trajectory of batch `batch` of
/// `diffusion` (or of the field run) with seed `seed`, its state kept between calls, so events
/// in chunks are the events of one call, bit for bit.
#[pyclass(module = "lorentz_gas._native", name = "EventStream")]
pub struct EventStream {
    choice: SceneChoice,
    /// The long flights jumped (`None`: the walk, or a field).
    flights: Option<LongFlights>,
    state: LatticeState<f64>,
    walk: Option<AnyFieldWalk>,
    /// The time of the last event so far (0 at the start).
    t: f64,
}

impl EventStream {
    /// `EventStream(params)`: the trajectory of batch `batch` of `diffusion(seed=seed)` (or of
    /// the run in `field`), its long flights as `flights` asks.
    pub fn read(p: &Params<'_, '_>) -> PyResult<impl FnOnce() -> PyResult<Self> + use<>> {
        let place = Where::read(p)?;
        let seed = p.count_u64("seed")?;
        let batch = p.count_u32("batch")?;
        let field = p.opt_text("field")?;
        let flights = p.text("flights")?;
        Ok(move || {
            let choice = place.resolve()?;
            let walk = field_walk(&choice, field.as_deref(), seed, batch)?;
            let flights = long_flights(&choice, &flights, walk.is_some())?;
            let state = match &walk {
                Some(walk) => walk.state().clone(),
                None => {
                    let mut s =
                        with_scene!(&choice, |sc| sc.sample(&mut stream(seed, batch as u64)));
                    s.flight.normalise_speed();
                    s
                }
            };
            Ok(EventStream {
                choice,
                flights,
                state,
                walk,
                t: 0.0,
            })
        })
    }

    fn state(&self) -> &LatticeState<f64> {
        self.walk.as_ref().map_or(&self.state, AnyFieldWalk::state)
    }

    /// The columns as numpy arrays.
    fn dict<'py>(py: Python<'py>, c: Columns) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let f = |v: Vec<f64>| -> Bound<'py, PyArray1<f64>> { v.into_pyarray(py) };
        d.set_item("t", f(c.t))?;
        d.set_item("x", f(c.x))?;
        d.set_item("y", f(c.y))?;
        d.set_item("vx", f(c.vx))?;
        d.set_item("vy", f(c.vy))?;
        d.set_item("kind", c.kind.into_pyarray(py))?;
        d.set_item("collision", c.collision.into_pyarray(py))?;
        d.set_item("obstacle", c.obstacle.into_pyarray(py))?;
        d.set_item("down", c.down.into_pyarray(py))?;
        d.set_item("i", c.i.into_pyarray(py))?;
        d.set_item("j", c.j.into_pyarray(py))?;
        Ok(d)
    }
}

#[pymethods]
impl EventStream {
    #[new]
    #[pyo3(signature = (params))]
    fn new(params: &Bound<'_, PyDict>) -> PyResult<Self> {
        Params::read(params, Self::read)?()
    }

    /// The start of the trajectory as one row (time 0, kind start).
    fn start<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = self.state();
        let p = with_scene!(&self.choice, |sc| {
            let lat = sc.lattice::<f64>(()).map_err(crate::py_err)?;
            lat.unwrapped(s, 0.0)
                .displacement_from(&Unwrapped::default(), &lat.basis_f64())
        });
        let mut c = Columns::with_capacity(1);
        c.push(0.0, p, s, None);
        Self::dict(py, c)
    }

    /// The next `n` events.
    #[pyo3(signature = (n, progress))]
    fn next<'py>(
        &mut self,
        py: Python<'py>,
        n: &str,
        progress: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let n = count_u64("n", n)?;
        check_memory(n)?;
        let t0 = self.t;
        let (choice, state, walk) = (&self.choice, &mut self.state, &mut self.walk);
        let flights = self.flights.as_ref();
        let (c, end) = compute(py, progress, |ctl| match walk {
            Some(walk) => walk.advance(t0, n, ctl),
            None => with_scene!(choice, |s| advance(s, flights, state, t0, n, ctl)),
        })?;
        self.t = end;
        Self::dict(py, c)
    }

    /// The time of the last event so far.
    #[getter]
    fn time(&self) -> f64 {
        self.t
    }

    /// How the flights cross the lattice: `"jump"` or `"walk"` (the engine `flights` chose).
    #[getter]
    fn flights(&self) -> &'static str {
        if self.flights.is_some() {
            "jump"
        } else {
            "walk"
        }
    }
}

/// The long flights of the choice `flights` (`auto`, `walk`, `jump`) in `choice`: `None` for the
/// walk. A field's arcs walk: `jump` is refused there, `auto` walks.
fn long_flights(
    choice: &SceneChoice,
    flights: &str,
    in_field: bool,
) -> PyResult<Option<LongFlights>> {
    let flights: Flights = flights.parse().map_err(crate::py_err)?;
    if in_field {
        return match flights {
            Flights::Jump => Err(PyValueError::new_err(
                "flights = jump: arcs in a field cross the lattice cell by cell; use walk or auto",
            )),
            _ => Ok(None),
        };
    }
    with_scene!(choice, |s| flights.of(s)).map_err(crate::py_err)
}

/// Registers `EventStream` in the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<EventStream>()?;
    m.add("BYTES_PER_EVENT", BYTES_PER_EVENT)?;
    Ok(())
}
