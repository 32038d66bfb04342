//! Bindings of the vector-pair attitude solvers (TRIAD, Wahba) and of the magnetometer yaw of seed 002.
//! All take a leading epoch axis flattened by the Python layer and release the GIL around the batch.

use gnssatt_core::magnetometer::yaw_batch;
use gnssatt_core::rotation::quaternion;
use gnssatt_core::wahba::{solve_batch, triad_batch, Method};
use numpy::{PyArray1, PyArray2, PyArray3, PyReadonlyArray1, PyReadonlyArray2, ToPyArray};
use pyo3::prelude::*;

use crate::convert::{matrices_to_numpy, quats_to_numpy, values, vectors};
use crate::errors::IntoPyResult;
use crate::interruptible;

type Arr1<'py> = Bound<'py, PyArray1<f64>>;
type Arr2<'py> = Bound<'py, PyArray2<f64>>;
type Arr3<'py> = Bound<'py, PyArray3<f64>>;

/// Wahba's problem per epoch. `body`, `reference`: (epochs * pairs, 3); `weights`: (epochs * pairs,).
/// Returns (quat_ref_from_body (epochs, 4), covariance_ref (epochs, 3, 3), information_ratio (epochs,),
/// loss (epochs,)).
#[pyfunction]
#[pyo3(signature = (body, reference, weights, pairs, method = "svd"))]
fn wahba_batch<'py>(
    py: Python<'py>,
    body: PyReadonlyArray2<'_, f64>,
    reference: PyReadonlyArray2<'_, f64>,
    weights: PyReadonlyArray1<'_, f64>,
    pairs: usize,
    method: &str,
) -> PyResult<(Arr2<'py>, Arr3<'py>, Arr1<'py>, Arr1<'py>)> {
    let method = Method::parse(method).into_py_result(py)?;
    let b = vectors(py, "body", &body)?;
    let r = vectors(py, "reference", &reference)?;
    let w = values(py, "weights", &weights)?;
    let sols = interruptible::run(py, || solve_batch(&b, &r, &w, pairs, method))?;
    let quats: Vec<_> = py.detach(|| {
        sols.iter()
            .map(|s| quaternion::from_dcm(&s.dcm_ref_from_body))
            .collect()
    });
    let ratio: Vec<f64> = sols.iter().map(|s| s.information_ratio).collect();
    let loss: Vec<f64> = sols.iter().map(|s| s.loss).collect();
    Ok((
        quats_to_numpy(py, &quats),
        matrices_to_numpy(py, sols.iter().map(|s| s.covariance_ref)),
        ratio.to_pyarray(py),
        loss.to_pyarray(py),
    ))
}

/// TRIAD per epoch; every argument (epochs, 3). Returns (quat_ref_from_body (epochs, 4),
/// sin_angle_body (epochs,), sin_angle_ref (epochs,)).
#[pyfunction]
#[pyo3(name = "triad_batch")]
fn triad_batch_py<'py>(
    py: Python<'py>,
    b1: PyReadonlyArray2<'_, f64>,
    b2: PyReadonlyArray2<'_, f64>,
    r1: PyReadonlyArray2<'_, f64>,
    r2: PyReadonlyArray2<'_, f64>,
) -> PyResult<(Arr2<'py>, Arr1<'py>, Arr1<'py>)> {
    let (b1, b2) = (vectors(py, "b1", &b1)?, vectors(py, "b2", &b2)?);
    let (r1, r2) = (vectors(py, "r1", &r1)?, vectors(py, "r2", &r2)?);
    let sols = interruptible::run(py, || triad_batch(&b1, &b2, &r1, &r2))?;
    let quats: Vec<_> = sols
        .iter()
        .map(|s| quaternion::from_dcm(&s.dcm_ref_from_body))
        .collect();
    let sb: Vec<f64> = sols.iter().map(|s| s.sin_angle_body).collect();
    let sr: Vec<f64> = sols.iter().map(|s| s.sin_angle_ref).collect();
    Ok((
        quats_to_numpy(py, &quats),
        sb.to_pyarray(py),
        sr.to_pyarray(py),
    ))
}

/// Eq. (3) of seed 002 per epoch: b_body, b_orbital (epochs, 3); pitch_rad, roll_rad (epochs,).
/// Returns (yaw_rad, |cos pitch|, horizontal fraction), each (epochs,).
#[pyfunction]
#[pyo3(name = "yaw_batch")]
fn yaw_batch_py<'py>(
    py: Python<'py>,
    b_body: PyReadonlyArray2<'_, f64>,
    b_orbital: PyReadonlyArray2<'_, f64>,
    pitch_rad: PyReadonlyArray1<'_, f64>,
    roll_rad: PyReadonlyArray1<'_, f64>,
) -> PyResult<(Arr1<'py>, Arr1<'py>, Arr1<'py>)> {
    let b = vectors(py, "b_body", &b_body)?;
    let o = vectors(py, "b_orbital", &b_orbital)?;
    let p = values(py, "pitch", &pitch_rad)?;
    let r = values(py, "roll", &roll_rad)?;
    let sols = interruptible::run(py, || yaw_batch(&b, &o, &p, &r))?;
    let yaw: Vec<f64> = sols.iter().map(|s| s.yaw_rad).collect();
    let cp: Vec<f64> = sols.iter().map(|s| s.cos_pitch).collect();
    let hf: Vec<f64> = sols.iter().map(|s| s.horizontal_fraction).collect();
    Ok((yaw.to_pyarray(py), cp.to_pyarray(py), hf.to_pyarray(py)))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(wahba_batch, m)?)?;
    m.add_function(wrap_pyfunction!(triad_batch_py, m)?)?;
    m.add_function(wrap_pyfunction!(yaw_batch_py, m)?)?;
    Ok(())
}
