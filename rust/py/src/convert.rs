//! Checked intake of numpy arrays: dtype float64 (pyo3 raises TypeError otherwise), shape and finiteness
//! checked here with expected-versus-actual messages. numpy is row-major, nalgebra column-major: every
//! conversion goes element by element through explicit indices.

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use numpy::ndarray::ArrayView2;
use numpy::{PyArray2, PyArray3, PyReadonlyArray1, PyReadonlyArray2, ToPyArray};
use pyo3::prelude::*;

use crate::errors::invalid_input;

fn check_finite(py: Python<'_>, name: &str, a: &ArrayView2<'_, f64>) -> PyResult<()> {
    if let Some(((i, j), _)) = a.indexed_iter().find(|(_, v)| !v.is_finite()) {
        return Err(invalid_input(
            py,
            format!("{name} contains a non-finite value at [{i}, {j}]"),
        ));
    }
    Ok(())
}

/// An (n, 3) array as n vectors.
pub fn vectors(
    py: Python<'_>,
    name: &str,
    a: &PyReadonlyArray2<'_, f64>,
) -> PyResult<Vec<Vector3<f64>>> {
    let a = a.as_array();
    if a.ncols() != 3 {
        return Err(invalid_input(
            py,
            format!("expected {name} of shape (n, 3), got {:?}", a.shape()),
        ));
    }
    check_finite(py, name, &a)?;
    Ok(a.rows()
        .into_iter()
        .map(|r| Vector3::new(r[0], r[1], r[2]))
        .collect())
}

/// A (3, 3) array as a matrix.
pub fn matrix3(
    py: Python<'_>,
    name: &str,
    a: &PyReadonlyArray2<'_, f64>,
) -> PyResult<Matrix3<f64>> {
    let a = a.as_array();
    if a.shape() != [3, 3] {
        return Err(invalid_input(
            py,
            format!("expected {name} of shape (3, 3), got {:?}", a.shape()),
        ));
    }
    check_finite(py, name, &a)?;
    Ok(Matrix3::from_fn(|i, j| a[[i, j]]))
}

/// Any 2-D array as a dynamic matrix.
pub fn dmatrix(
    py: Python<'_>,
    name: &str,
    a: &PyReadonlyArray2<'_, f64>,
) -> PyResult<DMatrix<f64>> {
    let a = a.as_array();
    check_finite(py, name, &a)?;
    Ok(DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| a[[i, j]]))
}

/// A 1-D array as a dynamic vector.
pub fn dvector(
    py: Python<'_>,
    name: &str,
    a: &PyReadonlyArray1<'_, f64>,
) -> PyResult<DVector<f64>> {
    let a = a.as_array();
    if let Some((i, _)) = a.indexed_iter().find(|(_, v)| !v.is_finite()) {
        return Err(invalid_input(
            py,
            format!("{name} contains a non-finite value at [{i}]"),
        ));
    }
    Ok(DVector::from_iterator(a.len(), a.iter().copied()))
}

/// A matrix as a new (3, 3) numpy array.
pub fn to_numpy<'py>(py: Python<'py>, m: &Matrix3<f64>) -> Bound<'py, PyArray2<f64>> {
    numpy::ndarray::Array2::from_shape_fn((3, 3), |(i, j)| m[(i, j)]).to_pyarray(py)
}

/// A 1-D array as a vector of finite values.
pub fn values(py: Python<'_>, name: &str, a: &PyReadonlyArray1<'_, f64>) -> PyResult<Vec<f64>> {
    let a = a.as_array();
    if let Some((i, _)) = a.indexed_iter().find(|(_, v)| !v.is_finite()) {
        return Err(invalid_input(
            py,
            format!("{name} contains a non-finite value at [{i}]"),
        ));
    }
    Ok(a.to_vec())
}

/// `n` row-major 3x3 matrices as a new (n, 3, 3) numpy array.
pub fn matrices_to_numpy<'py>(
    py: Python<'py>,
    m: impl ExactSizeIterator<Item = Matrix3<f64>>,
) -> Bound<'py, PyArray3<f64>> {
    let n = m.len();
    let mut flat = Vec::with_capacity(9 * n);
    for m in m {
        for i in 0..3 {
            for j in 0..3 {
                flat.push(m[(i, j)]);
            }
        }
    }
    numpy::ndarray::Array3::from_shape_vec((n, 3, 3), flat)
        .expect("length is 9 n")
        .to_pyarray(py)
}

/// `n` quaternions `[x, y, z, w]` as a new (n, 4) numpy array.
pub fn quats_to_numpy<'py>(py: Python<'py>, q: &[[f64; 4]]) -> Bound<'py, PyArray2<f64>> {
    numpy::ndarray::Array2::from_shape_fn((q.len(), 4), |(i, j)| q[i][j]).to_pyarray(py)
}
