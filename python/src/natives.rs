//! The compiled functions of the analyses: each takes one dict of its Python function's keyword
//! parameters and the progress callback (`_native.diffusion(params, progress)`), reads the dict
//! with its reader (every key, before any work; a key it does not read is refused) and runs the
//! work the reader returns. `_native.parameters(name)` names the keys each reads.

use pyo3::IntoPyObjectExt;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::params::{Params, Progress};

/// One compiled function per reader `name: reader`, `parameters` over all of them, and their
/// registration.
macro_rules! analyses {
    ($($name:ident: $read:path,)*) => {
        $(
            #[pyfunction]
            #[pyo3(signature = (params, progress))]
            fn $name<'py>(
                py: Python<'py>,
                params: &Bound<'py, PyDict>,
                progress: Progress<'py>,
            ) -> PyResult<Bound<'py, PyAny>> {
                Params::read(params, $read)?(py, progress)?.into_bound_py_any(py)
            }
        )*

        /// The keys the analysis `name` reads from its dict, in the order it reads them
        /// (`EventStream`: the constructor's).
        #[pyfunction]
        fn parameters(name: &str) -> PyResult<Vec<&'static str>> {
            match name {
                $(stringify!($name) => Params::keys($read),)*
                "constants" => Params::keys(crate::analyses::constants),
                "EventStream" => Params::keys(crate::events::EventStream::read),
                _ => Err(PyValueError::new_err(format!("no analysis named {name:?}"))),
            }
        }

        /// Registers the analyses and `parameters` in the module.
        pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
            $(m.add_function(wrap_pyfunction!(self::$name, m)?)?;)*
            m.add_function(wrap_pyfunction!(parameters, m)?)
        }
    };
}

analyses! {
    diffusion: crate::diffusion::read,
    hops: crate::analyses::hops,
    theory: crate::analyses::theory,
    lattice_walk: crate::analyses::lattice_walk,
    backscatter: crate::analyses::backscatter,
    sweep: crate::analyses::sweep,
    field_sweep: crate::field::sweep,
    driven_sweep: crate::field::driven_sweep,
    merge: crate::campaigns::merge,
    escape: crate::analyses::escape,
    superdiffusion: crate::analyses::superdiffusion,
    free_paths: crate::analyses::free_paths,
    report: crate::analyses::report,
    lyapunov: crate::verification::lyapunov,
    audit: crate::verification::audit,
    shadow: crate::verification::shadow,
    certify: crate::verification::certify,
    cycles: crate::cycles::cycles,
    lattice_cycles: crate::cycles::lattice_cycles,
    survival: crate::cycles::survival,
    trajectory: crate::verification::trajectory,
    section: crate::section::section,
    bench: crate::bench::bench,
    bench_long_flights: crate::bench::long_flights,
    figure: crate::figures::figure,
    reproduce: crate::figures::reproduce,
}
