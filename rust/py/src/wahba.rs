//! Bindings of the vector-pair attitude solvers (TRIAD, Wahba) and of the magnetometer yaw of Ryzhkov and
//! Holembiovskyi. All take a leading epoch axis flattened by the Python layer and release the GIL around the
//! batch.

use gnssatt_core::magnetometer::yaw_batch;
use gnssatt_core::rotation::quaternion;
use gnssatt_core::wahba::{solve_batch, triad_batch, Method};
use numpy::{PyArray1, PyArray2, PyArray3, PyReadonlyArray1, PyReadonlyArray2, ToPyArray};
use pyo3::prelude::*;

use crate::convert::{matrices_to_numpy, option_name, quats_to_numpy, values, vectors};
use crate::errors::IntoPyResult;
use crate::guard::guard;
use crate::interruptible;
use crate::results::result_type;

type Arr1 = Py<PyArray1<f64>>;

result_type! {
    /// Wahba's problem per epoch: `quat_ref_from_body` (epochs, 4) scalar-last, `covariance_ref`
    /// (epochs, 3, 3) of the attitude in the reference frame, rad^2, `information_ratio` and `loss`
    /// (epochs,).
    WahbaBatch {
        quat_ref_from_body: Py<PyArray2<f64>>,
        covariance_ref: Py<PyArray3<f64>>,
        information_ratio: Arr1,
        loss: Arr1,
    }
}

result_type! {
    /// TRIAD per epoch: `quat_ref_from_body` (epochs, 4) scalar-last and the sines of the angle between
    /// the two vectors in the body and the reference frame, `sin_angle_body` / `sin_angle_ref` (epochs,).
    TriadBatch {
        quat_ref_from_body: Py<PyArray2<f64>>,
        sin_angle_body: Arr1,
        sin_angle_ref: Arr1,
    }
}

result_type! {
    /// Eq. (3) of Ryzhkov and Holembiovskyi per epoch: `yaw_rad`, `cos_pitch` (|cos pitch|) and the
    /// `horizontal_fraction` of the field, each (epochs,).
    YawBatch {
        yaw_rad: Arr1,
        cos_pitch: Arr1,
        horizontal_fraction: Arr1,
    }
}

/// Wahba's problem per epoch. `body`, `reference`: (epochs * pairs, 3); `weights`: (epochs * pairs,).
#[guard]
#[pyfunction]
fn wahba_batch(
    py: Python<'_>,
    body: PyReadonlyArray2<'_, f64>,
    reference: PyReadonlyArray2<'_, f64>,
    weights: PyReadonlyArray1<'_, f64>,
    pairs: usize,
    method: &Bound<'_, PyAny>,
) -> PyResult<WahbaBatch> {
    let method = Method::parse(&option_name(py, "method", method)?).into_py_result(py)?;
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
    Ok(WahbaBatch {
        quat_ref_from_body: quats_to_numpy(py, &quats).unbind(),
        covariance_ref: matrices_to_numpy(py, sols.iter().map(|s| s.covariance_ref)).unbind(),
        information_ratio: ratio.to_pyarray(py).unbind(),
        loss: loss.to_pyarray(py).unbind(),
    })
}

/// TRIAD per epoch; every argument (epochs, 3).
#[guard]
#[pyfunction]
#[pyo3(name = "triad_batch")]
fn triad_batch_py(
    py: Python<'_>,
    b1: PyReadonlyArray2<'_, f64>,
    b2: PyReadonlyArray2<'_, f64>,
    r1: PyReadonlyArray2<'_, f64>,
    r2: PyReadonlyArray2<'_, f64>,
) -> PyResult<TriadBatch> {
    let (b1, b2) = (vectors(py, "b1", &b1)?, vectors(py, "b2", &b2)?);
    let (r1, r2) = (vectors(py, "r1", &r1)?, vectors(py, "r2", &r2)?);
    let sols = interruptible::run(py, || triad_batch(&b1, &b2, &r1, &r2))?;
    let quats: Vec<_> = sols
        .iter()
        .map(|s| quaternion::from_dcm(&s.dcm_ref_from_body))
        .collect();
    let sb: Vec<f64> = sols.iter().map(|s| s.sin_angle_body).collect();
    let sr: Vec<f64> = sols.iter().map(|s| s.sin_angle_ref).collect();
    Ok(TriadBatch {
        quat_ref_from_body: quats_to_numpy(py, &quats).unbind(),
        sin_angle_body: sb.to_pyarray(py).unbind(),
        sin_angle_ref: sr.to_pyarray(py).unbind(),
    })
}

/// Eq. (3) of Ryzhkov and Holembiovskyi per epoch: b_body, b_orbital (epochs, 3); pitch_rad, roll_rad
/// (epochs,).
#[guard]
#[pyfunction]
#[pyo3(name = "yaw_batch")]
fn yaw_batch_py(
    py: Python<'_>,
    b_body: PyReadonlyArray2<'_, f64>,
    b_orbital: PyReadonlyArray2<'_, f64>,
    pitch_rad: PyReadonlyArray1<'_, f64>,
    roll_rad: PyReadonlyArray1<'_, f64>,
) -> PyResult<YawBatch> {
    let b = vectors(py, "b_body", &b_body)?;
    let o = vectors(py, "b_orbital", &b_orbital)?;
    let p = values(py, "pitch", &pitch_rad)?;
    let r = values(py, "roll", &roll_rad)?;
    let sols = interruptible::run(py, || yaw_batch(&b, &o, &p, &r))?;
    let yaw: Vec<f64> = sols.iter().map(|s| s.yaw_rad).collect();
    let cp: Vec<f64> = sols.iter().map(|s| s.cos_pitch).collect();
    let hf: Vec<f64> = sols.iter().map(|s| s.horizontal_fraction).collect();
    Ok(YawBatch {
        yaw_rad: yaw.to_pyarray(py).unbind(),
        cos_pitch: cp.to_pyarray(py).unbind(),
        horizontal_fraction: hf.to_pyarray(py).unbind(),
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(wahba_batch, m)?)?;
    m.add_function(wrap_pyfunction!(triad_batch_py, m)?)?;
    m.add_function(wrap_pyfunction!(yaw_batch_py, m)?)?;
    m.add_class::<WahbaBatch>()?;
    m.add_class::<TriadBatch>()?;
    m.add_class::<YawBatch>()?;
    Ok(())
}
