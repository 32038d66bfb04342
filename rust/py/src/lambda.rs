//! Bindings of LAMBDA integer ambiguity resolution (`gnssatt_core::lambda`). The GIL is released around
//! every decorrelation and search; the fixed-failure-rate simulation runs on rayon's global pool.

use gnssatt_core::lambda::validation::{
    fixed_failure_rate_threshold, partial_fix, ratio_test, RatioThreshold,
};
use gnssatt_core::lambda::{bootstrap_success_rate, ils, reduce};
use nalgebra::DMatrix;
use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::convert::{dmatrix, dvector};
use crate::errors::{invalid_input, IntoPyResult};

/// Default fixed ratio threshold when neither `threshold` nor `failure_rate` is given.
const DEFAULT_RATIO_THRESHOLD: f64 = 3.0;

fn to_numpy2<'py, T: numpy::Element + Copy>(
    py: Python<'py>,
    m: &DMatrix<T>,
) -> Bound<'py, PyArray2<T>> {
    Array2::from_shape_fn(m.shape(), |(i, j)| m[(i, j)]).into_pyarray(py)
}

fn to_numpy1<'py, T: numpy::Element + Copy>(
    py: Python<'py>,
    v: impl IntoIterator<Item = T>,
) -> Bound<'py, PyArray1<T>> {
    Array1::from_iter(v).into_pyarray(py)
}

fn threshold_of(
    py: Python<'_>,
    threshold: Option<f64>,
    failure_rate: Option<f64>,
    samples: usize,
    seed: u64,
) -> PyResult<RatioThreshold> {
    match (threshold, failure_rate) {
        (Some(_), Some(_)) => Err(invalid_input(
            py,
            "expected either threshold or failure_rate, got both".into(),
        )),
        (_, Some(failure_rate)) => Ok(RatioThreshold::FixedFailureRate {
            failure_rate,
            samples,
            seed,
        }),
        (t, None) => Ok(RatioThreshold::Fixed(t.unwrap_or(DEFAULT_RATIO_THRESHOLD))),
    }
}

/// Returns (fixed (m, n) int64, squared_norms (m,), nodes_visited).
#[pyfunction]
#[pyo3(signature = (float_ambiguities, covariance, candidates = 2))]
#[allow(clippy::type_complexity)]
fn lambda_ils<'py>(
    py: Python<'py>,
    float_ambiguities: PyReadonlyArray1<'_, f64>,
    covariance: PyReadonlyArray2<'_, f64>,
    candidates: usize,
) -> PyResult<(Bound<'py, PyArray2<i64>>, Bound<'py, PyArray1<f64>>, u64)> {
    let a = dvector(py, "float_ambiguities", &float_ambiguities)?;
    let q = dmatrix(py, "covariance", &covariance)?;
    let sol = py.detach(|| ils(&a, &q, candidates)).into_py_result(py)?;
    Ok((
        to_numpy2(py, &sol.fixed.transpose()),
        to_numpy1(py, sol.squared_norms),
        sol.nodes_visited,
    ))
}

/// Returns (Z (n, n) int64, L (n, n), D (n,)) with Z^T Q Z = L^T diag(D) L.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn lambda_decorrelate<'py>(
    py: Python<'py>,
    covariance: PyReadonlyArray2<'_, f64>,
) -> PyResult<(
    Bound<'py, PyArray2<i64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
)> {
    let q = dmatrix(py, "covariance", &covariance)?;
    let r = py.detach(|| reduce(&q)).into_py_result(py)?;
    Ok((
        to_numpy2(py, &r.z),
        to_numpy2(py, &r.factor.l),
        to_numpy1(py, r.factor.d.iter().copied()),
    ))
}

/// Bootstrapped success rate of the decorrelated ambiguities.
#[pyfunction]
fn lambda_bootstrap_success_rate(
    py: Python<'_>,
    covariance: PyReadonlyArray2<'_, f64>,
) -> PyResult<f64> {
    let q = dmatrix(py, "covariance", &covariance)?;
    py.detach(|| bootstrap_success_rate(&q)).into_py_result(py)
}

/// Fixed-failure-rate ratio threshold by seeded simulation.
#[pyfunction]
fn lambda_ffrt_threshold(
    py: Python<'_>,
    covariance: PyReadonlyArray2<'_, f64>,
    failure_rate: f64,
    samples: usize,
    seed: u64,
) -> PyResult<f64> {
    let q = dmatrix(py, "covariance", &covariance)?;
    py.detach(|| fixed_failure_rate_threshold(&q, failure_rate, samples, seed))
        .into_py_result(py)
}

/// Returns (accepted, ratio, threshold, fixed (n,) int64, squared_norms (2,)).
#[pyfunction]
#[pyo3(signature = (float_ambiguities, covariance, threshold, failure_rate, samples, seed))]
#[allow(clippy::type_complexity)]
fn lambda_ratio_test<'py>(
    py: Python<'py>,
    float_ambiguities: PyReadonlyArray1<'_, f64>,
    covariance: PyReadonlyArray2<'_, f64>,
    threshold: Option<f64>,
    failure_rate: Option<f64>,
    samples: usize,
    seed: u64,
) -> PyResult<(
    bool,
    f64,
    f64,
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<f64>>,
)> {
    let t = threshold_of(py, threshold, failure_rate, samples, seed)?;
    let a = dvector(py, "float_ambiguities", &float_ambiguities)?;
    let q = dmatrix(py, "covariance", &covariance)?;
    let r = py.detach(|| ratio_test(&a, &q, t)).into_py_result(py)?;
    Ok((
        r.accepted,
        r.ratio,
        r.threshold,
        to_numpy1(py, r.fixed.iter().copied()),
        to_numpy1(py, r.squared_norms),
    ))
}

type PartialFixTuple<'py> = (
    usize,
    Bound<'py, PyArray2<i64>>,
    Bound<'py, PyArray1<i64>>,
    f64,
    f64,
    f64,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
);

/// Returns (fixed_count, combinations (n, k) int64, values (k,) int64, ratio, threshold, success_rate,
/// ambiguities (n,), covariance (n, n)).
#[pyfunction]
#[pyo3(signature = (float_ambiguities, covariance, threshold, failure_rate, samples, seed, min_success_rate))]
#[allow(clippy::too_many_arguments)]
fn lambda_partial_fix<'py>(
    py: Python<'py>,
    float_ambiguities: PyReadonlyArray1<'_, f64>,
    covariance: PyReadonlyArray2<'_, f64>,
    threshold: Option<f64>,
    failure_rate: Option<f64>,
    samples: usize,
    seed: u64,
    min_success_rate: f64,
) -> PyResult<PartialFixTuple<'py>> {
    let t = threshold_of(py, threshold, failure_rate, samples, seed)?;
    let a = dvector(py, "float_ambiguities", &float_ambiguities)?;
    let q = dmatrix(py, "covariance", &covariance)?;
    let r = py
        .detach(|| partial_fix(&a, &q, t, min_success_rate))
        .into_py_result(py)?;
    Ok((
        r.fixed_count,
        to_numpy2(py, &r.combinations),
        to_numpy1(py, r.values.iter().copied()),
        r.ratio,
        r.threshold,
        r.success_rate,
        to_numpy1(py, r.ambiguities.iter().copied()),
        to_numpy2(py, &r.covariance),
    ))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(lambda_ils, m)?)?;
    m.add_function(wrap_pyfunction!(lambda_decorrelate, m)?)?;
    m.add_function(wrap_pyfunction!(lambda_bootstrap_success_rate, m)?)?;
    m.add_function(wrap_pyfunction!(lambda_ffrt_threshold, m)?)?;
    m.add_function(wrap_pyfunction!(lambda_ratio_test, m)?)?;
    m.add_function(wrap_pyfunction!(lambda_partial_fix, m)?)?;
    // The limits live in the core; Python reads them from here instead of restating them.
    m.add(
        "LAMBDA_MAX_CANDIDATES",
        gnssatt_core::lambda::MAX_CANDIDATES,
    )?;
    m.add(
        "LAMBDA_MAX_SAMPLES",
        gnssatt_core::lambda::validation::MAX_SAMPLES,
    )?;
    m.add(
        "LAMBDA_MAX_DIMENSION",
        gnssatt_core::lambda::ldl::MAX_DIMENSION,
    )?;
    m.add("LAMBDA_MAX_NODES", gnssatt_core::lambda::DEFAULT_MAX_NODES)?;
    m.add(
        "LAMBDA_MAX_ABS_AMBIGUITY",
        gnssatt_core::lambda::MAX_ABS_AMBIGUITY,
    )?;
    Ok(())
}
