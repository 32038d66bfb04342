//! Checked intake of numpy arrays, the one used by every binding: dtype float64 (pyo3 raises TypeError
//! otherwise), shape and finiteness checked here with expected-versus-actual messages naming the
//! parameter. numpy is row-major, nalgebra column-major: every conversion goes element by element through
//! explicit indices.

use nalgebra::{DMatrix, DVector, Matrix3, SMatrix, Vector3};
use numpy::ndarray::{Dimension, IntoDimension};
use numpy::{
    Element, PyArray2, PyArray3, PyReadonlyArray, PyReadonlyArray1, PyReadonlyArray2,
    PyReadonlyArray3, ToPyArray,
};
use pyo3::prelude::*;

use crate::errors::{invalid_input, invalid_type};

/// An option given by its name (`method`, `statistic`, `seq` ...) as text: an `InvalidTypeError` naming
/// the parameter for anything but a `str`. The binding that parses the name is the one place that checks
/// it (an unknown name is an `InvalidInputError` listing the options); the Python layer passes it on.
pub fn option_name(py: Python<'_>, name: &str, value: &Bound<'_, PyAny>) -> PyResult<String> {
    value.extract::<String>().map_err(|_| {
        invalid_type(
            py,
            format!(
                "expected {name} as the name of an option (a str), got {}",
                type_name(value)
            ),
        )
    })
}

/// The Python type name of `value`, for messages.
pub fn type_name(value: &Bound<'_, PyAny>) -> String {
    value
        .get_type()
        .name()
        .map_or_else(|_| "an object".to_string(), |n| n.to_string())
}

/// `expected {name} of shape {expected}, got {actual}`.
pub fn shape_error(py: Python<'_>, name: &str, expected: &str, actual: &[usize]) -> PyErr {
    invalid_input(
        py,
        format!("expected {name} of shape {expected}, got {actual:?}"),
    )
}

/// Refuses the first non-finite value, naming its index.
fn finite<D: Dimension>(
    py: Python<'_>,
    name: &str,
    a: &numpy::ndarray::ArrayView<'_, f64, D>,
) -> PyResult<()> {
    match a.indexed_iter().find(|(_, v)| !v.is_finite()) {
        Some((i, _)) => {
            let index: Vec<String> = i
                .into_dimension()
                .slice()
                .iter()
                .map(|k| k.to_string())
                .collect();
            Err(invalid_input(
                py,
                format!(
                    "{name} contains a non-finite value at [{}]",
                    index.join(", ")
                ),
            ))
        }
        None => Ok(()),
    }
}

/// A (N,) array of finite values.
pub fn fixed<const N: usize>(
    py: Python<'_>,
    name: &str,
    a: &PyReadonlyArray1<'_, f64>,
) -> PyResult<[f64; N]> {
    let v = a.as_array();
    if v.len() != N {
        return Err(shape_error(py, name, &format!("({N},)"), v.shape()));
    }
    finite(py, name, &v)?;
    Ok(std::array::from_fn(|i| v[i]))
}

/// An (N, N) array of finite values.
pub fn square<const N: usize>(
    py: Python<'_>,
    name: &str,
    a: &PyReadonlyArray2<'_, f64>,
) -> PyResult<SMatrix<f64, N, N>> {
    let v = a.as_array();
    if v.shape() != [N, N] {
        return Err(shape_error(py, name, &format!("({N}, {N})"), v.shape()));
    }
    finite(py, name, &v)?;
    Ok(SMatrix::from_fn(|i, j| v[[i, j]]))
}

/// An (n, N) array as n rows, `n` given or any; finite unless `masked` (values a mask marks unused may
/// be NaN: the core checks the used ones).
pub fn rows<const N: usize>(
    py: Python<'_>,
    name: &str,
    a: &PyReadonlyArray2<'_, f64>,
    n: Option<usize>,
    masked: bool,
) -> PyResult<Vec<[f64; N]>> {
    let v = a.as_array();
    if v.ncols() != N || n.is_some_and(|n| v.nrows() != n) {
        let rows = n.map_or("n".to_string(), |n| n.to_string());
        return Err(shape_error(py, name, &format!("({rows}, {N})"), v.shape()));
    }
    if !masked {
        finite(py, name, &v)?;
    }
    Ok(v.rows()
        .into_iter()
        .map(|r| std::array::from_fn(|j| r[j]))
        .collect())
}

/// An (n, m, N) array as `n * m` rows, epoch-major; finite unless `masked` (see [`rows`]).
pub fn rows3<const N: usize>(
    py: Python<'_>,
    name: &str,
    a: &PyReadonlyArray3<'_, f64>,
    n: usize,
    m: usize,
    masked: bool,
) -> PyResult<Vec<[f64; N]>> {
    let v = a.as_array();
    if v.shape() != [n, m, N] {
        return Err(shape_error(
            py,
            name,
            &format!("({n}, {m}, {N})"),
            v.shape(),
        ));
    }
    if !masked {
        finite(py, name, &v)?;
    }
    Ok((0..n * m)
        .map(|i| std::array::from_fn(|j| v[[i / m, i % m, j]]))
        .collect())
}

/// An array of exactly `shape`, flattened row-major, any element type (flags, integers; floats are
/// not checked for finiteness here: the caller's mask decides).
pub fn exact<T: Element + Copy, D: Dimension>(
    py: Python<'_>,
    name: &str,
    a: &PyReadonlyArray<'_, T, D>,
    shape: &[usize],
) -> PyResult<Vec<T>> {
    let v = a.as_array();
    if v.shape() != shape {
        let expected = format!(
            "({})",
            shape
                .iter()
                .map(|d| d.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
        return Err(shape_error(py, name, &expected, v.shape()));
    }
    Ok(v.iter().copied().collect())
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
    finite(py, name, &a)?;
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
    finite(py, name, &a)?;
    Ok(Matrix3::from_fn(|i, j| a[[i, j]]))
}

/// Any 2-D array as a dynamic matrix.
pub fn dmatrix(
    py: Python<'_>,
    name: &str,
    a: &PyReadonlyArray2<'_, f64>,
) -> PyResult<DMatrix<f64>> {
    let a = a.as_array();
    finite(py, name, &a)?;
    Ok(DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| a[[i, j]]))
}

/// A 1-D array as a dynamic vector.
pub fn dvector(
    py: Python<'_>,
    name: &str,
    a: &PyReadonlyArray1<'_, f64>,
) -> PyResult<DVector<f64>> {
    let a = a.as_array();
    finite(py, name, &a)?;
    Ok(DVector::from_iterator(a.len(), a.iter().copied()))
}

/// A matrix as a new (3, 3) numpy array.
pub fn to_numpy<'py>(py: Python<'py>, m: &Matrix3<f64>) -> Bound<'py, PyArray2<f64>> {
    numpy::ndarray::Array2::from_shape_fn((3, 3), |(i, j)| m[(i, j)]).to_pyarray(py)
}

/// A 1-D array as a vector of finite values.
pub fn values(py: Python<'_>, name: &str, a: &PyReadonlyArray1<'_, f64>) -> PyResult<Vec<f64>> {
    let a = a.as_array();
    finite(py, name, &a)?;
    Ok(a.to_vec())
}

/// `n` row-major 3x3 matrices as a new (n, 3, 3) numpy array.
pub fn matrices_to_numpy<'py>(
    py: Python<'py>,
    m: impl ExactSizeIterator<Item = Matrix3<f64>>,
) -> Bound<'py, PyArray3<f64>> {
    let m: Vec<Matrix3<f64>> = m.collect();
    numpy::ndarray::Array3::from_shape_fn((m.len(), 3, 3), |(k, i, j)| m[k][(i, j)]).to_pyarray(py)
}

/// `n` quaternions `[x, y, z, w]` as a new (n, 4) numpy array.
pub fn quats_to_numpy<'py>(py: Python<'py>, q: &[[f64; 4]]) -> Bound<'py, PyArray2<f64>> {
    numpy::ndarray::Array2::from_shape_fn((q.len(), 4), |(i, j)| q[i][j]).to_pyarray(py)
}
