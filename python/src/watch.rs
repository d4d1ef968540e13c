//! Running a computation for Python: on a worker thread with the GIL released, while the
//! calling thread looks every 100 ms for Ctrl-C (Python's pending signals) and feeds the
//! progress callback. Ctrl-C requests the run's [`StopFlag`]; the run ends within one segment
//! (about 0.1 s) and the `KeyboardInterrupt` is raised once every worker has joined, so no
//! thread outlives the call.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

use lorentz_gas::Error;
use lorentz_gas::engine::options::StopFlag;

use crate::py_err;

/// How often the calling thread looks at Python's signals and reports progress.
const POLL: Duration = Duration::from_millis(100);

/// What a computation receives: the stop flag to pass in its `RunOptions`, the progress sink,
/// and `restart(total)`, which starts the progress again over `total` units (a run's second
/// stage: the run its pilot planned), so that a bar's rate and time estimate are that stage's.
pub struct Ctl<'a> {
    pub stop: &'a StopFlag,
    pub progress: &'a (dyn Fn(u64) + Sync),
    pub restart: &'a (dyn Fn(u64) + Sync),
}

/// A restart of the progress not yet passed to Python: the new total, and the units done when
/// it was asked for (those before it belong to the stage that ended).
type Restart = std::sync::Mutex<Option<(u64, u64)>>;

/// Runs `f` on a worker thread with the GIL released, stopping it on Ctrl-C and calling
/// `progress(n)` (a Python callable, with the GIL) with the units done since the last call.
pub fn compute<R: Send>(
    py: Python<'_>,
    progress: Option<Bound<'_, PyAny>>,
    f: impl FnOnce(&Ctl<'_>) -> Result<R, Error> + Send,
) -> PyResult<R> {
    let stop = StopFlag::default();
    let done = AtomicU64::new(0);
    let sink = |n: u64| {
        done.fetch_add(n, Ordering::Relaxed);
    };
    let restarted: Restart = std::sync::Mutex::new(None);
    let restart = |total: u64| {
        if let Ok(mut r) = restarted.lock() {
            *r = Some((total, done.load(Ordering::Relaxed)));
        }
    };
    let callback: Option<Py<PyAny>> = progress.map(Bound::unbind);
    let (result, raised) = py.detach(|| {
        std::thread::scope(|s| {
            let (tx, rx) = mpsc::channel::<()>();
            let (stop_ref, sink_ref, restart_ref) = (&stop, &sink, &restart);
            let worker = s.spawn(move || {
                let ctl = Ctl {
                    stop: stop_ref,
                    progress: sink_ref,
                    restart: restart_ref,
                };
                let r = f(&ctl);
                let _ = tx.send(());
                r
            });
            let mut raised: Option<PyErr> = None;
            let mut reported = 0u64;
            loop {
                let finished =
                    !matches!(rx.recv_timeout(POLL), Err(mpsc::RecvTimeoutError::Timeout));
                Python::attach(|py| {
                    if raised.is_none()
                        && let Err(e) = py.check_signals()
                    {
                        stop.request();
                        raised = Some(e);
                    }
                    let pending = restarted.lock().ok().and_then(|mut r| r.take());
                    if let (Some(cb), None) = (&callback, &raised) {
                        let fed = feed(py, cb, &done, &mut reported, pending);
                        if let Err(e) = fed {
                            stop.request();
                            raised = Some(e);
                        }
                    }
                });
                if finished {
                    break;
                }
            }
            let result = worker
                .join()
                .unwrap_or_else(|_| Err(Error::Failed("the computation panicked".into())));
            (result, raised)
        })
    });
    if let Some(e) = raised {
        return Err(e);
    }
    result.map_err(py_err)
}

/// Passes the units done since the last call to the callback `cb` (a restart first closes the
/// stage it ends, then calls `cb.restart(total)` where the callback has that method).
fn feed(
    py: Python<'_>,
    cb: &Py<PyAny>,
    done: &AtomicU64,
    reported: &mut u64,
    restart: Option<(u64, u64)>,
) -> PyResult<()> {
    if let Some((total, at)) = restart {
        if at > *reported {
            cb.call1(py, (at - *reported,))?;
        }
        *reported = at;
        if cb.bind(py).hasattr("restart")? {
            cb.call_method1(py, "restart", (total,))?;
        }
    }
    let now = done.load(Ordering::Relaxed);
    if now > *reported {
        cb.call1(py, (now - *reported,))?;
        *reported = now;
    }
    Ok(())
}

/// A result as the command line's JSON (the same serializer, so the same digits).
pub fn json<T: serde::Serialize>(r: &T) -> PyResult<String> {
    serde_json::to_string_pretty(r)
        .map_err(|e| PyRuntimeError::new_err(format!("cannot encode the result as JSON: {e}")))
}
