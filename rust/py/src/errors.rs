//! Maps core errors onto the exception classes defined in Python by `gnssatt.errors`, so that the
//! hierarchy (and its `ValueError` base) lives in one place.

use gnssatt_core::Error;
use pyo3::prelude::*;

// The Python classes, imported once on first use and cached by pyo3. `gnssatt.errors` is part of the
// package that ships this module and imports nothing but the standard library, so the import cannot fail
// where `gnssatt._core` itself imported.
pyo3::import_exception!(gnssatt.errors, ConvergenceError);
pyo3::import_exception!(gnssatt.errors, DegenerateGeometryError);
pyo3::import_exception!(gnssatt.errors, InternalError); // a panic (`guard.rs`)
pyo3::import_exception!(gnssatt.errors, InvalidInputError);
pyo3::import_exception!(gnssatt.errors, InvalidTypeError);
pyo3::import_exception!(gnssatt.errors, WorkLimitError);
pyo3::import_exception!(gnssatt.errors, GnssattWarning);

/// Conversion of core results into Python results; the trait keeps pyo3 out of the core crate.
pub trait IntoPyResult<T> {
    fn into_py_result(self, py: Python<'_>) -> PyResult<T>;
}

impl<T> IntoPyResult<T> for Result<T, Error> {
    fn into_py_result(self, py: Python<'_>) -> PyResult<T> {
        self.map_err(|e| to_py_err(py, &e))
    }
}

pub fn to_py_err(_py: Python<'_>, e: &Error) -> PyErr {
    let message = e.to_string();
    match e {
        Error::DegenerateGeometry { .. } | Error::Degenerate { .. } => {
            DegenerateGeometryError::new_err(message)
        }
        Error::Convergence { .. } | Error::Numerical { .. } => ConvergenceError::new_err(message),
        Error::Shape { .. } | Error::NonFinite { .. } | Error::OutOfRange { .. } => {
            InvalidInputError::new_err(message)
        }
        Error::TooLarge { .. } => WorkLimitError::new_err(message),
        Error::Interrupted { .. } => pyo3::exceptions::PyKeyboardInterrupt::new_err(message),
    }
}

pub fn invalid_input(_py: Python<'_>, message: String) -> PyErr {
    InvalidInputError::new_err(message)
}

/// A value of the wrong kind (`InvalidTypeError`, also a `TypeError`).
pub fn invalid_type(_py: Python<'_>, message: String) -> PyErr {
    InvalidTypeError::new_err(message)
}

/// Issues each of `messages` as a `gnssatt.errors.GnssattWarning` (an error only where a warnings
/// filter turns warnings into errors).
pub fn warn_all(py: Python<'_>, messages: &[String]) -> PyResult<()> {
    if messages.is_empty() {
        return Ok(());
    }
    let category = py.get_type::<GnssattWarning>();
    for m in messages {
        let text = std::ffi::CString::new(m.replace('\0', " ")).unwrap_or_default();
        PyErr::warn(py, category.as_any(), &text, 1)?;
    }
    Ok(())
}
