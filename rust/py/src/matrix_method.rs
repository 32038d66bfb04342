//! Binding of the seed-000 matrix method.

use gnssatt_core::matrix_method::{solve, Method};
use numpy::{PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::convert::{dmatrix, to_numpy, vectors};
use crate::errors::{invalid_input, IntoPyResult};

/// Returns (dcm_ref_from_body, raw_body_from_ref, residual_rms_m).
#[pyfunction]
#[pyo3(signature = (baselines, los, range_diffs, method = "svd"))]
#[allow(clippy::type_complexity)]
fn matrix_attitude<'py>(
    py: Python<'py>,
    baselines: PyReadonlyArray2<'_, f64>,
    los: PyReadonlyArray2<'_, f64>,
    range_diffs: PyReadonlyArray2<'_, f64>,
    method: &str,
) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>, f64)> {
    let method = match method {
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
    Ok((
        to_numpy(py, &sol.dcm_ref_from_body),
        to_numpy(py, &sol.raw_body_from_ref),
        sol.residual_rms_m,
    ))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(matrix_attitude, m)?)?;
    Ok(())
}
