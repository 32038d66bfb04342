//! Rotation utilities: Euler sequences and quaternions of the core, for round-trip checks and users who
//! want the papers' sequences without scipy's naming.

use gnssatt_core::error::ensure_finite;
use gnssatt_core::rotation::{euler::EulerSeq, quaternion};
use numpy::{PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::convert::{matrix3, option_name, to_numpy};
use crate::errors::IntoPyResult;
use crate::guard::guard;

/// Active body -> reference matrix of intrinsic Euler angles (radians).
#[guard]
#[pyfunction]
fn euler_to_dcm<'py>(
    py: Python<'py>,
    seq: &Bound<'py, PyAny>,
    angles_rad: [f64; 3],
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let seq = EulerSeq::parse(&option_name(py, "seq", seq)?).into_py_result(py)?;
    ensure_finite("angles_rad", &angles_rad).into_py_result(py)?;
    Ok(to_numpy(py, &seq.to_dcm(angles_rad)))
}

/// Intrinsic Euler angles (radians) of a rotation matrix.
#[guard]
#[pyfunction]
fn dcm_to_euler(
    py: Python<'_>,
    seq: &Bound<'_, PyAny>,
    dcm: PyReadonlyArray2<'_, f64>,
) -> PyResult<[f64; 3]> {
    let seq = EulerSeq::parse(&option_name(py, "seq", seq)?).into_py_result(py)?;
    let m = matrix3(py, "dcm", &dcm)?;
    gnssatt_core::rotation::check_rotation("dcm", &m, 1e-6).into_py_result(py)?;
    Ok(seq.from_dcm(&m))
}

/// Rotation matrix of a scalar-last quaternion [x, y, z, w].
#[guard]
#[pyfunction]
fn quat_to_dcm<'py>(py: Python<'py>, quat: [f64; 4]) -> PyResult<Bound<'py, PyArray2<f64>>> {
    Ok(to_numpy(py, &quaternion::to_dcm(quat).into_py_result(py)?))
}

/// Scalar-last quaternion [x, y, z, w] (w >= 0) of a rotation matrix.
#[guard]
#[pyfunction]
fn dcm_to_quat(py: Python<'_>, dcm: PyReadonlyArray2<'_, f64>) -> PyResult<[f64; 4]> {
    let m = matrix3(py, "dcm", &dcm)?;
    gnssatt_core::rotation::check_rotation("dcm", &m, 1e-6).into_py_result(py)?;
    Ok(quaternion::from_dcm(&m))
}

/// The proper rotation nearest to a 3x3 matrix (Frobenius norm).
#[guard]
#[pyfunction]
fn nearest_rotation<'py>(
    py: Python<'py>,
    matrix: PyReadonlyArray2<'_, f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let m = matrix3(py, "matrix", &matrix)?;
    Ok(to_numpy(
        py,
        &gnssatt_core::rotation::nearest_rotation(&m).into_py_result(py)?,
    ))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(euler_to_dcm, m)?)?;
    m.add_function(wrap_pyfunction!(dcm_to_euler, m)?)?;
    m.add_function(wrap_pyfunction!(quat_to_dcm, m)?)?;
    m.add_function(wrap_pyfunction!(dcm_to_quat, m)?)?;
    m.add_function(wrap_pyfunction!(nearest_rotation, m)?)?;
    Ok(())
}
