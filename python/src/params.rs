//! The parameters of an analysis as Python passes them: one dict of the Python function's
//! keyword parameters (values as the text, numbers and `None` its wrapper normalises them to),
//! read by key. Each analysis reads its dict in one function (`read`), every key before any
//! work; the key it did not read is refused ("unknown parameter"), a key it reads that is not
//! there too ("missing parameter"), so that the Python wrapper and the reader cannot drift
//! apart silently. The same function, run on no dict, names the keys it reads
//! (`_native.parameters(name)`, compared with the Python signatures by a test).

use std::cell::RefCell;
use std::path::PathBuf;
use std::time::Duration;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use lorentz_gas::engine::Engine;
use lorentz_gas::engine::long_flight::Flights;
use lorentz_gas::engine::options::MAX_CHECKPOINT_EVERY;
use lorentz_gas::numbers::precision::Precision;

use crate::inputs;

/// The progress callback of a computation (`None`: none).
pub type Progress<'py> = Option<Bound<'py, PyAny>>;

/// The work of an analysis whose parameters are read: run with the GIL's token and the progress
/// callback.
pub type Work<R> = Box<dyn for<'py> FnOnce(Python<'py>, Progress<'py>) -> PyResult<R>>;

/// `f` as [`Work`].
pub fn work<R>(
    f: impl for<'py> FnOnce(Python<'py>, Progress<'py>) -> PyResult<R> + 'static,
) -> Work<R> {
    Box::new(f)
}

/// The dict of one call (or none: describing), and the keys read so far.
pub struct Params<'a, 'py> {
    dict: Option<&'a Bound<'py, PyDict>>,
    read: RefCell<Vec<&'static str>>,
}

impl<'a, 'py> Params<'a, 'py> {
    /// `read` of `dict`; then any key of `dict` that `read` did not take is refused.
    pub fn read<T>(
        dict: &'a Bound<'py, PyDict>,
        read: impl FnOnce(&Self) -> PyResult<T>,
    ) -> PyResult<T> {
        let p = Params {
            dict: Some(dict),
            read: RefCell::default(),
        };
        let t = read(&p)?;
        p.refuse_unread(dict)?;
        Ok(t)
    }

    /// The keys `read` takes, in the order it takes them (each value a placeholder, the work it
    /// returns not done).
    pub fn keys<T>(read: impl FnOnce(&Self) -> PyResult<T>) -> PyResult<Vec<&'static str>> {
        let p = Params {
            dict: None,
            read: RefCell::default(),
        };
        read(&p)?;
        let mut keys = p.read.into_inner();
        let mut seen = std::collections::HashSet::new();
        keys.retain(|k| seen.insert(*k));
        Ok(keys)
    }

    fn refuse_unread(&self, dict: &Bound<'py, PyDict>) -> PyResult<()> {
        let read = self.read.borrow();
        let mut unknown = Vec::new();
        for key in dict.keys() {
            let name: String = key.str()?.extract()?;
            if !read.contains(&name.as_str()) {
                unknown.push(format!("`{name}`"));
            }
        }
        match unknown.len() {
            0 => Ok(()),
            1 => Err(PyValueError::new_err(format!(
                "unknown parameter {}",
                unknown[0]
            ))),
            _ => Err(PyValueError::new_err(format!(
                "unknown parameters {}",
                unknown.join(", ")
            ))),
        }
    }

    /// The value of `key` as `T` (`None` while describing).
    fn value<T: FromPyObjectOwned<'py>>(&self, key: &'static str) -> PyResult<Option<T>> {
        self.read.borrow_mut().push(key);
        let Some(dict) = self.dict else {
            return Ok(None);
        };
        let v = dict
            .get_item(key)?
            .ok_or_else(|| PyValueError::new_err(format!("missing parameter `{key}`")))?;
        v.extract::<T>().map(Some).map_err(|e| {
            let e: PyErr = e.into();
            PyValueError::new_err(format!("{key}={}: {e}", repr(&v)))
        })
    }

    /// The text of `key` parsed by `parse` (`placeholder` while describing: a reader does no
    /// work but parsing one value at a time, so that it runs on placeholders too).
    pub fn parsed<T>(
        &self,
        key: &'static str,
        placeholder: T,
        parse: impl FnOnce(&str) -> PyResult<T>,
    ) -> PyResult<T> {
        match self.value::<String>(key)? {
            Some(text) => parse(&text),
            None => Ok(placeholder),
        }
    }

    /// The text of `key`, if given (not `None`), parsed by `parse`.
    fn opt_parsed<T>(
        &self,
        key: &'static str,
        parse: impl FnOnce(&str) -> PyResult<T>,
    ) -> PyResult<Option<T>> {
        self.value::<Option<String>>(key)?
            .flatten()
            .map(|t| parse(&t))
            .transpose()
    }

    /// Text (an exact number as typed, a name).
    pub fn text(&self, key: &'static str) -> PyResult<String> {
        Ok(self.value(key)?.unwrap_or_default())
    }

    /// Text or `None`.
    pub fn opt_text(&self, key: &'static str) -> PyResult<Option<String>> {
        Ok(self.value(key)?.flatten())
    }

    /// Texts (exact numbers as typed).
    pub fn texts(&self, key: &'static str) -> PyResult<Vec<String>> {
        Ok(self.value(key)?.unwrap_or_default())
    }

    /// A number.
    pub fn number(&self, key: &'static str) -> PyResult<f64> {
        Ok(self.value(key)?.unwrap_or_default())
    }

    /// A number or `None`.
    pub fn opt_number(&self, key: &'static str) -> PyResult<Option<f64>> {
        Ok(self.value(key)?.flatten())
    }

    /// Numbers or `None`.
    pub fn opt_numbers(&self, key: &'static str) -> PyResult<Option<Vec<f64>>> {
        Ok(self.value(key)?.flatten())
    }

    /// Two numbers (a window).
    pub fn pair(&self, key: &'static str) -> PyResult<(f64, f64)> {
        Ok(self.value(key)?.unwrap_or_default())
    }

    /// Two numbers or `None`.
    pub fn opt_pair(&self, key: &'static str) -> PyResult<Option<[f64; 2]>> {
        Ok(self.value(key)?.flatten())
    }

    /// Two texts (a point or a direction, exact).
    pub fn text_pair(&self, key: &'static str) -> PyResult<(String, String)> {
        Ok(self.value(key)?.unwrap_or_default())
    }

    /// True or false.
    pub fn flag(&self, key: &'static str) -> PyResult<bool> {
        Ok(self.value(key)?.unwrap_or_default())
    }

    /// A path.
    pub fn path(&self, key: &'static str) -> PyResult<PathBuf> {
        Ok(self.value(key)?.unwrap_or_default())
    }

    /// A path or `None`.
    pub fn opt_path(&self, key: &'static str) -> PyResult<Option<PathBuf>> {
        Ok(self.value(key)?.flatten())
    }

    /// A count (`2e9`, `2_000_000_000`), as the command line parses it.
    pub fn count_u64(&self, key: &'static str) -> PyResult<u64> {
        self.parsed(key, 0, |t| inputs::count_u64(key, t))
    }

    /// A count or `None`.
    pub fn opt_count_u64(&self, key: &'static str) -> PyResult<Option<u64>> {
        self.opt_parsed(key, |t| inputs::count_u64(key, t))
    }

    /// A count that fits in 32 bits.
    pub fn count_u32(&self, key: &'static str) -> PyResult<u32> {
        self.parsed(key, 0, |t| inputs::count_u32(key, t))
    }

    /// A count that indexes memory.
    pub fn count_usize(&self, key: &'static str) -> PyResult<usize> {
        self.parsed(key, 0, |t| inputs::count_usize(key, t))
    }

    /// `threads`: worker threads, `None` every core this process may use.
    pub fn threads(&self) -> PyResult<usize> {
        inputs::threads(self.opt_text("threads")?.as_deref())
    }

    /// `engine`: `auto`, `scalar` or `simd`.
    pub fn engine(&self) -> PyResult<Engine> {
        self.parsed("engine", Engine::Auto, inputs::engine)
    }

    /// `flights`: `auto`, `walk` or `jump`.
    pub fn flights(&self) -> PyResult<Flights> {
        self.parsed("flights", Flights::default(), inputs::flights)
    }

    /// `precision`: `f64` or a number of MPFR bits.
    pub fn precision(&self) -> PyResult<Precision> {
        self.parsed("precision", Precision::F64, inputs::precision)
    }

    /// `checkpoint_every`: seconds between saves, 0 to a day.
    pub fn checkpoint_every(&self) -> PyResult<Duration> {
        let seconds = self.number("checkpoint_every")?;
        let max = MAX_CHECKPOINT_EVERY.as_secs_f64();
        if !(0.0..=max).contains(&seconds) {
            return Err(PyValueError::new_err(format!(
                "checkpoint_every = {seconds} s is out of range: use 0 to {max} s"
            )));
        }
        Ok(Duration::from_secs_f64(seconds))
    }
}

/// `repr(v)`, for a message.
fn repr(v: &Bound<'_, PyAny>) -> String {
    v.repr()
        .and_then(|r| r.extract::<String>())
        .unwrap_or_else(|_| "?".into())
}
