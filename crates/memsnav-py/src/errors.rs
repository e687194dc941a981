//! Core errors → Python exceptions: `ValueError` for bad arguments, the
//! `MemsnavError` family for estimation failures.

use memsnav_core::Error;
use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    memsnav,
    MemsnavError,
    pyo3::exceptions::PyException,
    "Base class of memsnav's estimation failures."
);
pyo3::create_exception!(
    memsnav,
    UnobservableError,
    MemsnavError,
    "The data cannot determine a parameter (rank-deficient or badly conditioned problem)."
);
pyo3::create_exception!(
    memsnav,
    DivergenceError,
    MemsnavError,
    "A filter diverged: its covariance stopped being positive definite or its state became non-finite."
);
pyo3::create_exception!(
    memsnav,
    ParseError,
    PyValueError,
    "A data file could not be read; the message names the file and the line."
);

/// Converts a core error into the matching Python exception.
pub fn to_py(error: Error) -> PyErr {
    let message = error.to_string();
    match error {
        Error::InvalidArgument { .. } => PyValueError::new_err(message),
        Error::Unobservable { .. } => UnobservableError::new_err(message),
        Error::Divergence { .. } => DivergenceError::new_err(message),
        Error::Parse { .. } | Error::ParseBinary { .. } => ParseError::new_err(message),
        Error::Io { .. } => PyOSError::new_err(message),
        Error::Interrupted => PyKeyboardInterrupt::new_err(message),
    }
}

/// Runs the body of a Python entry point (the `#[catch_panics]` attribute
/// puts every one through here): a Rust panic, which would otherwise reach
/// Python as pyo3's `PanicException` (not an `Exception`), becomes a
/// `MemsnavError` carrying the panic message. A panic is a memsnav bug; the
/// message says so.
pub fn catch_panics<T>(body: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(body))
        .unwrap_or_else(|payload| Err(panic_error(payload.as_ref())))
}

/// The `MemsnavError` of a caught panic (its payload: a message or not).
pub fn panic_error(payload: &(dyn std::any::Any + Send)) -> PyErr {
    let what = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "no message".to_string());
    MemsnavError::new_err(format!(
        "internal error (a bug in memsnav, please report it with the input): {what}"
    ))
}

/// `Result<T, core::Error>` → `PyResult<T>`.
pub trait IntoPyResult<T> {
    fn py(self) -> PyResult<T>;
}

impl<T> IntoPyResult<T> for memsnav_core::Result<T> {
    fn py(self) -> PyResult<T> {
        self.map_err(to_py)
    }
}

/// Test hook: panics with `message`, so the tests can show that a panic
/// reaches Python as a `MemsnavError` (no public function is known to
/// panic).
#[memsnav_py_macros::catch_panics]
#[pyfunction]
fn _panic_for_test(message: &str) -> PyResult<()> {
    panic!("{message}")
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_function(wrap_pyfunction!(_panic_for_test, m)?)?;
    m.add("MemsnavError", py.get_type::<MemsnavError>())?;
    m.add("UnobservableError", py.get_type::<UnobservableError>())?;
    m.add("DivergenceError", py.get_type::<DivergenceError>())?;
    m.add("ParseError", py.get_type::<ParseError>())?;
    Ok(())
}
