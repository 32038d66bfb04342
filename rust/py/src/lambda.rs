//! Bindings of LAMBDA integer ambiguity resolution (`gnssatt_core::lambda`). The GIL is released around
//! every decorrelation and search; the fixed-failure-rate simulation runs on rayon's global pool.

use gnssatt_core::lambda::batch::{is_short, BATCH_MAX_SEARCH_WORK, BATCH_MAX_WORK};
use gnssatt_core::lambda::validation::{
    fixed_failure_rate_threshold, partial_fix, ratio_test, RatioThreshold,
};
use gnssatt_core::lambda::{bootstrap_success_rate, ils, ils_batch, reduce};
use std::borrow::Cow;

use nalgebra::{DMatrix, DVector};
use numpy::ndarray::{Array1, Array2, Array3, ArrayView, Dimension, ShapeError};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArray3, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3,
};
use pyo3::prelude::*;

use crate::convert::{dmatrix, dvector};
use crate::errors::{invalid_input, IntoPyResult};
use crate::guard::guard;
use crate::interruptible;
use crate::results::result_type;

/// Default fixed ratio threshold when neither `threshold` nor `failure_rate` is given.
const DEFAULT_RATIO_THRESHOLD: f64 = 3.0;

fn to_numpy2<T: numpy::Element + Copy>(py: Python<'_>, m: &DMatrix<T>) -> Py<PyArray2<T>> {
    Array2::from_shape_fn(m.shape(), |(i, j)| m[(i, j)])
        .into_pyarray(py)
        .unbind()
}

fn to_numpy1<T: numpy::Element + Copy>(
    py: Python<'_>,
    v: impl IntoIterator<Item = T>,
) -> Py<PyArray1<T>> {
    Array1::from_iter(v).into_pyarray(py).unbind()
}

/// The float ambiguities (n,) and their covariance (n, n) of one problem, converted and checked once.
fn problem(
    py: Python<'_>,
    float_ambiguities: &PyReadonlyArray1<'_, f64>,
    covariance: &PyReadonlyArray2<'_, f64>,
) -> PyResult<(DVector<f64>, DMatrix<f64>)> {
    Ok((
        dvector(py, "float_ambiguities", float_ambiguities)?,
        dmatrix(py, "covariance", covariance)?,
    ))
}

/// The elements of `a` in row-major order: borrowed when C-contiguous (what the wrapper passes), else
/// copied once.
fn row_major<'a, D: Dimension>(a: &'a ArrayView<'_, f64, D>) -> Cow<'a, [f64]> {
    a.as_slice()
        .map_or_else(|| Cow::Owned(a.iter().copied().collect()), Cow::Borrowed)
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

result_type! {
    /// The `candidates` best integer vectors: `fixed` (m, n) int64 (row k the k-th best), their
    /// `squared_norms` (m,) in the metric of the covariance, and the search-tree `nodes_visited`.
    IlsSolution {
        fixed: Py<PyArray2<i64>>,
        squared_norms: Py<PyArray1<f64>>,
        nodes_visited: u64,
    }
}

/// The `candidates` best integer vectors of `float_ambiguities` (n,) in the metric of `covariance` (n, n).
#[guard]
#[pyfunction]
#[pyo3(signature = (float_ambiguities, covariance, candidates = 2))]
fn lambda_ils(
    py: Python<'_>,
    float_ambiguities: PyReadonlyArray1<'_, f64>,
    covariance: PyReadonlyArray2<'_, f64>,
    candidates: usize,
) -> PyResult<IlsSolution> {
    let (a, q) = problem(py, &float_ambiguities, &covariance)?;
    let sol = py.detach(|| ils(&a, &q, candidates)).into_py_result(py)?;
    Ok(IlsSolution {
        fixed: to_numpy2(py, &sol.fixed.transpose()),
        squared_norms: to_numpy1(py, sol.squared_norms),
        nodes_visited: sol.nodes_visited,
    })
}

result_type! {
    /// The `candidates` best integer vectors of each of k problems: `fixed` (k, m, n) int64 (row
    /// `[p, c]` the c-th best of problem p), `squared_norms` (k, m), and `nodes_visited` (k,) uint64.
    IlsBatch {
        fixed: Py<PyArray3<i64>>,
        squared_norms: Py<PyArray2<f64>>,
        nodes_visited: Py<PyArray1<u64>>,
    }
}

/// The `candidates` best integer vectors of each row of `float_ambiguities` (k, n), with `covariance`
/// (1, n, n) shared by every row or (k, n, n) one per row; in parallel, interruptible (Ctrl-C), except a
/// short batch (`batch::is_short`), solved on the calling thread.
#[guard]
#[pyfunction]
#[pyo3(signature = (float_ambiguities, covariance, candidates = 2))]
fn lambda_ils_batch(
    py: Python<'_>,
    float_ambiguities: PyReadonlyArray2<'_, f64>,
    covariance: PyReadonlyArray3<'_, f64>,
    candidates: usize,
) -> PyResult<IlsBatch> {
    let a = float_ambiguities.as_array();
    let q = covariance.as_array();
    let (k, n) = a.dim();
    let qs = q.dim();
    if qs.1 != n || qs.2 != n || (qs.0 != 1 && qs.0 != k) {
        return Err(invalid_input(
            py,
            format!(
                "expected covariance of shape ({n}, {n}) or ({k}, {n}, {n}) to match float_ambiguities \
                 of shape ({k}, {n}), got {qs:?}"
            ),
        ));
    }
    let (a_flat, q_flat) = (row_major(&a), row_major(&q));
    let m = candidates;
    // A short batch (well under a millisecond of decorrelation) runs on the calling thread like
    // `lambda_ils`: the worker thread and the pool would cost more than the work.
    let sol = if is_short(k, n) {
        py.detach(|| ils_batch(&a_flat, &q_flat, n, m))
            .into_py_result(py)?
    } else {
        interruptible::run(py, || ils_batch(&a_flat, &q_flat, n, m))?
    };
    let unexpected =
        |e: ShapeError| invalid_input(py, format!("batch result of unexpected size: {e}"));
    let fixed = Array3::from_shape_vec((k, m, n), sol.fixed).map_err(unexpected)?;
    let norms = Array2::from_shape_vec((k, m), sol.squared_norms).map_err(unexpected)?;
    Ok(IlsBatch {
        fixed: fixed.into_pyarray(py).unbind(),
        squared_norms: norms.into_pyarray(py).unbind(),
        nodes_visited: to_numpy1(py, sol.nodes_visited),
    })
}

result_type! {
    /// The decorrelation of a covariance Q: `z` (n, n) int64 and the factors `l` (n, n), `d` (n,) with
    /// `Z^T Q Z = L^T diag(D) L`.
    Decorrelation {
        z: Py<PyArray2<i64>>,
        l: Py<PyArray2<f64>>,
        d: Py<PyArray1<f64>>,
    }
}

/// The LAMBDA decorrelation of `covariance` (n, n).
#[guard]
#[pyfunction]
fn lambda_decorrelate(
    py: Python<'_>,
    covariance: PyReadonlyArray2<'_, f64>,
) -> PyResult<Decorrelation> {
    let q = dmatrix(py, "covariance", &covariance)?;
    let r = py.detach(|| reduce(&q)).into_py_result(py)?;
    Ok(Decorrelation {
        z: to_numpy2(py, &r.z),
        l: to_numpy2(py, &r.factor.l),
        d: to_numpy1(py, r.factor.d.iter().copied()),
    })
}

/// Bootstrapped success rate of the decorrelated ambiguities.
#[guard]
#[pyfunction]
fn lambda_bootstrap_success_rate(
    py: Python<'_>,
    covariance: PyReadonlyArray2<'_, f64>,
) -> PyResult<f64> {
    let q = dmatrix(py, "covariance", &covariance)?;
    py.detach(|| bootstrap_success_rate(&q)).into_py_result(py)
}

/// Fixed-failure-rate ratio threshold by seeded simulation.
#[guard]
#[pyfunction]
fn lambda_ffrt_threshold(
    py: Python<'_>,
    covariance: PyReadonlyArray2<'_, f64>,
    failure_rate: f64,
    samples: usize,
    seed: u64,
) -> PyResult<f64> {
    let q = dmatrix(py, "covariance", &covariance)?;
    py.detach(|| {
        crate::pool::install(|| fixed_failure_rate_threshold(&q, failure_rate, samples, seed))
    })
    .into_py_result(py)
}

result_type! {
    /// The ratio test of the two best candidates: `accepted`, the `ratio` second / best squared norm,
    /// the `threshold` used, the best candidate `fixed` (n,) int64 and both `squared_norms` (2,).
    RatioTest {
        accepted: bool,
        ratio: f64,
        threshold: f64,
        fixed: Py<PyArray1<i64>>,
        squared_norms: Py<PyArray1<f64>>,
    }
}

/// The ratio test at a fixed `threshold` or at the threshold of a simulated `failure_rate`.
#[guard]
#[pyfunction]
#[pyo3(signature = (float_ambiguities, covariance, *, threshold, failure_rate, samples, seed))]
fn lambda_ratio_test(
    py: Python<'_>,
    float_ambiguities: PyReadonlyArray1<'_, f64>,
    covariance: PyReadonlyArray2<'_, f64>,
    threshold: Option<f64>,
    failure_rate: Option<f64>,
    samples: usize,
    seed: u64,
) -> PyResult<RatioTest> {
    let t = threshold_of(py, threshold, failure_rate, samples, seed)?;
    let (a, q) = problem(py, &float_ambiguities, &covariance)?;
    let r = py.detach(|| ratio_test(&a, &q, t)).into_py_result(py)?;
    Ok(RatioTest {
        accepted: r.accepted,
        ratio: r.ratio,
        threshold: r.threshold,
        fixed: to_numpy1(py, r.fixed.iter().copied()),
        squared_norms: to_numpy1(py, r.squared_norms),
    })
}

result_type! {
    /// Partial ambiguity resolution: `fixed_count` k decorrelated combinations fixed, their
    /// `combinations` (n, k) int64 and integer `values` (k,) int64, the ratio test's `ratio` and
    /// `threshold`, the bootstrapped `success_rate` of the fixed subset, and the float `ambiguities` (n,)
    /// and `covariance` (n, n) conditioned on the fixed combinations.
    PartialFix {
        fixed_count: usize,
        combinations: Py<PyArray2<i64>>,
        values: Py<PyArray1<i64>>,
        ratio: f64,
        threshold: f64,
        success_rate: f64,
        ambiguities: Py<PyArray1<f64>>,
        covariance: Py<PyArray2<f64>>,
    }
}

/// The largest subset of decorrelated ambiguities with a bootstrapped success rate of at least
/// `min_success_rate` that passes the ratio test.
#[guard]
#[pyfunction]
#[pyo3(signature = (float_ambiguities, covariance, *, threshold, failure_rate, samples, seed, min_success_rate))]
#[allow(clippy::too_many_arguments)]
fn lambda_partial_fix(
    py: Python<'_>,
    float_ambiguities: PyReadonlyArray1<'_, f64>,
    covariance: PyReadonlyArray2<'_, f64>,
    threshold: Option<f64>,
    failure_rate: Option<f64>,
    samples: usize,
    seed: u64,
    min_success_rate: f64,
) -> PyResult<PartialFix> {
    let t = threshold_of(py, threshold, failure_rate, samples, seed)?;
    let (a, q) = problem(py, &float_ambiguities, &covariance)?;
    let r = py
        .detach(|| partial_fix(&a, &q, t, min_success_rate))
        .into_py_result(py)?;
    Ok(PartialFix {
        fixed_count: r.fixed_count,
        combinations: to_numpy2(py, &r.combinations),
        values: to_numpy1(py, r.values.iter().copied()),
        ratio: r.ratio,
        threshold: r.threshold,
        success_rate: r.success_rate,
        ambiguities: to_numpy1(py, r.ambiguities.iter().copied()),
        covariance: to_numpy2(py, &r.covariance),
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(lambda_ils, m)?)?;
    m.add_function(wrap_pyfunction!(lambda_ils_batch, m)?)?;
    m.add_function(wrap_pyfunction!(lambda_decorrelate, m)?)?;
    m.add_function(wrap_pyfunction!(lambda_bootstrap_success_rate, m)?)?;
    m.add_function(wrap_pyfunction!(lambda_ffrt_threshold, m)?)?;
    m.add_function(wrap_pyfunction!(lambda_ratio_test, m)?)?;
    m.add_function(wrap_pyfunction!(lambda_partial_fix, m)?)?;
    m.add_class::<IlsSolution>()?;
    m.add_class::<IlsBatch>()?;
    m.add_class::<Decorrelation>()?;
    m.add_class::<RatioTest>()?;
    m.add_class::<PartialFix>()?;
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
        "LAMBDA_NODES_PER_AMBIGUITY",
        gnssatt_core::lambda::NODES_PER_AMBIGUITY,
    )?;
    m.add("LAMBDA_BATCH_MAX_WORK", BATCH_MAX_WORK)?;
    m.add("LAMBDA_BATCH_MAX_SEARCH_WORK", BATCH_MAX_SEARCH_WORK)?;
    m.add(
        "LAMBDA_MAX_ABS_AMBIGUITY",
        gnssatt_core::lambda::MAX_ABS_AMBIGUITY,
    )?;
    Ok(())
}
