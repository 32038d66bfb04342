//! The panic boundary: `#[guard]` (crate `gnssatt-py-guard`) runs the body of every `#[pyfunction]` and
//! `#[pymethods]` method through [`call`]. The core is written not to panic on any input; a defect that
//! still panics reaches Python as `gnssatt.errors.InternalError` (a `GnssattError`, so an ordinary
//! `Exception`) rather than pyo3's `PanicException`, a `BaseException` that `except Exception` misses and
//! that kills Monte Carlo workers. A panic on an interruptible worker thread is resumed on the calling
//! thread (`interruptible::run`) and caught here like any other.

use std::any::Any;
use std::panic::{catch_unwind, AssertUnwindSafe};

use pyo3::prelude::*;

use crate::errors::InternalError;

pub use gnssatt_py_guard::guard;

/// Runs `work`, the body of the entry point `name`; a panic becomes `InternalError` naming `name` and
/// the panic's message.
pub fn call<T>(name: &str, work: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    // Unwind safety: after a panic nothing the body touched is used again; its error is raised instead.
    catch_unwind(AssertUnwindSafe(work)).unwrap_or_else(|payload| {
        Err(InternalError::new_err(format!(
            "{name}: Rust core defect ({}); please report it with its input",
            message(payload.as_ref())
        )))
    })
}

/// The text a `panic!` carries (a `&str` or a `String`), else a placeholder.
fn message(payload: &(dyn Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "panic".to_string()
    }
}

/// The test hook of the boundary (`tests/test_panic_guard.py`): panics with `message`, on the calling
/// thread or, with `in_worker`, on an interruptible worker thread, as a defect of the core would.
#[guard]
#[pyfunction]
#[pyo3(signature = (message, *, in_worker = false))]
fn _panic_for_tests(py: Python<'_>, message: String, in_worker: bool) -> PyResult<()> {
    if in_worker {
        crate::interruptible::run(py, || -> gnssatt_core::Result<()> { panic!("{message}") })
    } else {
        panic!("{message}")
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(_panic_for_tests, m)?)
}
