//! The observation engine's per-epoch results as one frozen object of numpy arrays (`GnssSession`), made
//! from the core's epoch solutions by `gnss_run` and `GnssEngine.process` (`gnss`).

use gnssatt_core::gnss::options::Method;
use gnssatt_core::gnss::signal::MAX_FREQUENCIES;
use gnssatt_core::gnss::solution::{EpochSolution, N_SYSTEMS};
use numpy::ndarray::{Array1, Array2, Array3, Array4};
use numpy::IntoPyArray;
use pyo3::prelude::*;

fn method_name(m: Method) -> &'static str {
    match m {
        Method::Ml => "ml",
        Method::Lambda => "lambda",
        Method::Auto => "auto",
    }
}

/// Per-epoch results of the engine as numpy arrays (NaN where an epoch was not solved).
///
/// Shapes: `n` epochs, `m` rovers (antennas after the first), `k` angles (2 in baseline mode: azimuth,
/// elevation; 3 in attitude mode: heading, pitch, roll).
#[pyclass(frozen, module = "gnssatt._core")]
pub struct GnssSession {
    /// "baseline" or "attitude".
    #[pyo3(get)]
    mode: &'static str,
    /// (n,) int64 epoch labels, GPST ns since 1980-01-06.
    #[pyo3(get)]
    time_gpst_ns: Py<PyAny>,
    /// (n,) str "lambda" or "ml".
    #[pyo3(get)]
    method: Vec<&'static str>,
    /// (n,) bool.
    #[pyo3(get)]
    solved: Py<PyAny>,
    #[pyo3(get)]
    fixed: Py<PyAny>,
    /// (n,) str "fixed" (validated at the epoch), "held" (fixed through integers held from earlier
    /// epochs) or "float" (not every ambiguity fixed; unsolved epochs too).
    #[pyo3(get)]
    fix_state: Vec<&'static str>,
    /// (n,) int64.
    #[pyo3(get)]
    fixed_ambiguities: Py<PyAny>,
    #[pyo3(get)]
    ambiguities: Py<PyAny>,
    /// (n,) float64 (NaN where nothing was fixed, or for ml).
    #[pyo3(get)]
    ratio: Py<PyAny>,
    #[pyo3(get)]
    success_rate: Py<PyAny>,
    /// (n, k) degrees and their one-sigma.
    #[pyo3(get)]
    angles_deg: Py<PyAny>,
    #[pyo3(get)]
    angle_sigmas_deg: Py<PyAny>,
    /// (n, m, 3) ENU at the reference antenna, m; (n, m, 3, 3) covariance, m^2.
    #[pyo3(get)]
    baselines_enu_m: Py<PyAny>,
    #[pyo3(get)]
    baseline_covariance_enu_m2: Py<PyAny>,
    /// (n, 3, 3) body -> ENU rotation matrices in attitude mode, None in baseline mode.
    #[pyo3(get)]
    rotation_enu_from_body: Option<Py<PyAny>>,
    /// (n, 5) int64 satellites per system, order G R E C J.
    #[pyo3(get)]
    satellites_per_system: Py<PyAny>,
    /// (n,) uint8: bit s set when frequency slot s contributed double differences.
    #[pyo3(get)]
    frequency_slots_used: Py<PyAny>,
    /// (n, 3) reference-antenna position used, ECEF m.
    #[pyo3(get)]
    base_position_m: Py<PyAny>,
    /// (5, 3) uint64 double differences formed per system and slot over the session; None from
    /// `GnssEngine.process`, which returns epochs only.
    #[pyo3(get)]
    double_differences: Option<Py<PyAny>>,
    #[pyo3(get)]
    warnings: Vec<String>,
    /// Per rover, the code sigma scale estimated from the residuals so far (NaN where not estimated:
    /// static mode, or too few residuals).
    #[pyo3(get)]
    code_sigma_scale: Vec<f64>,
}

pub fn session_object(
    py: Python<'_>,
    epochs: &[EpochSolution],
    n_rover: usize,
    attitude: bool,
    double_differences: Option<&[[u64; MAX_FREQUENCIES]; N_SYSTEMS]>,
    warnings: Vec<String>,
    code_sigma_scale: Vec<f64>,
) -> GnssSession {
    let n = epochs.len();
    let k = if attitude { 3 } else { 2 };
    let any = |b: Bound<'_, PyAny>| b.unbind();
    let col = |f: &dyn Fn(&EpochSolution) -> f64| {
        any(Array1::from_iter(epochs.iter().map(f))
            .into_pyarray(py)
            .into_any())
    };
    let get = |v: &[f64], j: usize| v.get(j).copied().unwrap_or(f64::NAN);
    let per_angle = |f: &dyn Fn(&EpochSolution) -> &Vec<f64>| {
        any(
            Array2::from_shape_fn((n, k), |(i, j)| get(f(&epochs[i]), j))
                .into_pyarray(py)
                .into_any(),
        )
    };
    let baselines = Array3::from_shape_fn((n, n_rover, 3), |(i, r, j)| {
        epochs[i].baselines_enu_m.get(r).map_or(f64::NAN, |b| b[j])
    });
    let covariance = Array4::from_shape_fn((n, n_rover, 3, 3), |(i, r, a, b)| {
        epochs[i]
            .baseline_covariance_enu_m2
            .get(r)
            .map_or(f64::NAN, |c| c[3 * a + b])
    });
    let rotation = attitude.then(|| {
        any(Array3::from_shape_fn((n, 3, 3), |(i, a, b)| {
            epochs[i]
                .rotation_enu_from_body
                .map_or(f64::NAN, |m| m[3 * a + b])
        })
        .into_pyarray(py)
        .into_any())
    });
    GnssSession {
        mode: if attitude { "attitude" } else { "baseline" },
        time_gpst_ns: any(Array1::from_iter(epochs.iter().map(|e| e.time_gpst_ns))
            .into_pyarray(py)
            .into_any()),
        method: epochs.iter().map(|e| method_name(e.method)).collect(),
        solved: any(Array1::from_iter(epochs.iter().map(|e| e.solved))
            .into_pyarray(py)
            .into_any()),
        fixed: any(Array1::from_iter(epochs.iter().map(|e| e.fixed))
            .into_pyarray(py)
            .into_any()),
        fix_state: epochs.iter().map(|e| e.fix_state.name()).collect(),
        fixed_ambiguities: any(Array1::from_iter(
            epochs
                .iter()
                .map(|e| i64::try_from(e.fixed_ambiguities).unwrap_or(i64::MAX)),
        )
        .into_pyarray(py)
        .into_any()),
        ambiguities: any(Array1::from_iter(
            epochs
                .iter()
                .map(|e| i64::try_from(e.ambiguities).unwrap_or(i64::MAX)),
        )
        .into_pyarray(py)
        .into_any()),
        ratio: col(&|e| e.ratio),
        success_rate: col(&|e| e.success_rate),
        angles_deg: per_angle(&|e| &e.angles_deg),
        angle_sigmas_deg: per_angle(&|e| &e.angle_sigmas_deg),
        baselines_enu_m: any(baselines.into_pyarray(py).into_any()),
        baseline_covariance_enu_m2: any(covariance.into_pyarray(py).into_any()),
        rotation_enu_from_body: rotation,
        satellites_per_system: any(Array2::from_shape_fn((n, N_SYSTEMS), |(i, s)| {
            i64::from(epochs[i].satellites_per_system[s])
        })
        .into_pyarray(py)
        .into_any()),
        frequency_slots_used: any(
            Array1::from_iter(epochs.iter().map(|e| e.frequency_slots_used))
                .into_pyarray(py)
                .into_any(),
        ),
        base_position_m: any(
            Array2::from_shape_fn((n, 3), |(i, j)| epochs[i].base_position_m[j])
                .into_pyarray(py)
                .into_any(),
        ),
        double_differences: double_differences.map(|dd| {
            any(
                Array2::from_shape_fn((N_SYSTEMS, MAX_FREQUENCIES), |(s, f)| dd[s][f])
                    .into_pyarray(py)
                    .into_any(),
            )
        }),
        warnings,
        code_sigma_scale,
    }
}
