//! Maps core errors onto the exception classes defined in Python by `gnssatt.errors`, so that the
//! hierarchy (and its `ValueError` base) lives in one place.

use gnssatt_core::Error;
use pyo3::prelude::*;
use pyo3::types::PyType;

/// Conversion of core results into Python results; the trait keeps pyo3 out of the core crate.
pub trait IntoPyResult<T> {
    fn into_py_result(self, py: Python<'_>) -> PyResult<T>;
}

impl<T> IntoPyResult<T> for Result<T, Error> {
    fn into_py_result(self, py: Python<'_>) -> PyResult<T> {
        self.map_err(|e| to_py_err(py, &e))
    }
}

pub fn to_py_err(py: Python<'_>, e: &Error) -> PyErr {
    let class = match e {
        Error::DegenerateGeometry { .. } | Error::Degenerate { .. } => "DegenerateGeometryError",
        Error::Convergence { .. } | Error::Numerical { .. } => "ConvergenceError",
        Error::Shape { .. } | Error::NonFinite { .. } | Error::OutOfRange { .. } => {
            "InvalidInputError"
        }
        Error::TooLarge { .. } => "WorkLimitError",
        Error::Interrupted { .. } => {
            return pyo3::exceptions::PyKeyboardInterrupt::new_err(e.to_string())
        }
    };
    match exception_class(py, class) {
        Ok(cls) => PyErr::from_type(cls, e.to_string()),
        Err(err) => err,
    }
}

pub fn invalid_input(py: Python<'_>, message: String) -> PyErr {
    match exception_class(py, "InvalidInputError") {
        Ok(cls) => PyErr::from_type(cls, message),
        Err(err) => err,
    }
}

fn exception_class<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyType>> {
    Ok(py
        .import("gnssatt.errors")?
        .getattr(name)?
        .cast_into::<PyType>()?)
}

/// `gnssatt.errors.InternalError` (a defect of the core, e.g. a panic caught outside the module's guard).
pub fn internal_error(py: Python<'_>, message: String) -> PyErr {
    match exception_class(py, "InternalError") {
        Ok(cls) => PyErr::from_type(cls, message),
        Err(err) => err,
    }
}

/// Issues each of `messages` as a `gnssatt.errors.GnssattWarning` (an error only where a warnings
/// filter turns warnings into errors).
pub fn warn_all(py: Python<'_>, messages: &[String]) -> PyResult<()> {
    if messages.is_empty() {
        return Ok(());
    }
    let category = exception_class(py, "GnssattWarning")?;
    for m in messages {
        let text = std::ffi::CString::new(m.replace('\0', " ")).unwrap_or_default();
        PyErr::warn(py, &category, &text, 1)?;
    }
    Ok(())
}
