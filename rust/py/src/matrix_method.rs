//! Binding of the Ryzhkov-Oliinyk matrix method.

use gnssatt_core::matrix_method::{solve, Method};
use numpy::{PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::convert::{dmatrix, option_name, to_numpy, vectors};
use crate::errors::{invalid_input, IntoPyResult};
use crate::guard::guard;
use crate::results::result_type;

result_type! {
    /// The matrix method's attitude: `dcm_ref_from_body` (3, 3) a rotation, `raw_body_from_ref` (3, 3)
    /// the unconstrained least-squares matrix it was made from, and the `residual_rms_m` of the range
    /// differences, m.
    MatrixAttitude {
        dcm_ref_from_body: Py<PyArray2<f64>>,
        raw_body_from_ref: Py<PyArray2<f64>>,
        residual_rms_m: f64,
    }
}

/// Attitude from baselines (m, 3) body, lines of sight (n, 3) reference and range differences (m, n), m.
#[guard]
#[pyfunction]
fn matrix_attitude(
    py: Python<'_>,
    baselines: PyReadonlyArray2<'_, f64>,
    los: PyReadonlyArray2<'_, f64>,
    range_diffs: PyReadonlyArray2<'_, f64>,
    method: &Bound<'_, PyAny>,
) -> PyResult<MatrixAttitude> {
    let method = match option_name(py, "method", method)?.as_str() {
        "svd" => Method::Svd,
        "ml" => Method::MaxLikelihood,
        "closed_form" => Method::ClosedForm,
        "paper" => Method::Paper,
        other => {
            return Err(invalid_input(
                py,
                format!("expected method 'svd', 'ml', 'closed_form' or 'paper', got {other:?}"),
            ))
        }
    };
    let b = vectors(py, "baselines", &baselines)?;
    let s = vectors(py, "los", &los)?;
    let r = dmatrix(py, "range_diffs", &range_diffs)?;
    let sol = solve(&b, &s, &r, method).into_py_result(py)?;
    Ok(MatrixAttitude {
        dcm_ref_from_body: to_numpy(py, &sol.dcm_ref_from_body).unbind(),
        raw_body_from_ref: to_numpy(py, &sol.raw_body_from_ref).unbind(),
        residual_rms_m: sol.residual_rms_m,
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(matrix_attitude, m)?)?;
    m.add_class::<MatrixAttitude>()?;
    Ok(())
}
