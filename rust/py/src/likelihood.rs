//! Binding of the seed-001 maximum-likelihood grid search. The Python layer (`gnssatt.likelihood`)
//! broadcasts inputs to (epochs, m, M) phases, (epochs, M, 3) lines of sight and (epochs, M) wavelengths.

use gnssatt_core::likelihood::{
    branch_and_bound, estimate, evaluate_grid, ml_attitude_series as core_attitude_series,
    ml_baseline_series as core_baseline_series, Epoch, Grid, MlEpoch, MlSolution, Model, Refine,
    Search, Statistic,
};
use nalgebra::Vector3;
use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::prelude::*;

use crate::convert::vectors;
use crate::errors::{invalid_input, IntoPyResult};
use crate::interruptible;

fn model(
    py: Python<'_>,
    phase_diffs: &PyReadonlyArray3<'_, f64>,
    los: &PyReadonlyArray3<'_, f64>,
    wavelengths: &PyReadonlyArray2<'_, f64>,
    baselines: &PyReadonlyArray2<'_, f64>,
    statistic: &str,
) -> PyResult<Model> {
    let b = vectors(py, "baselines", baselines)?;
    let (p, s, w) = (
        phase_diffs.as_array(),
        los.as_array(),
        wavelengths.as_array(),
    );
    let (ne, nb, m) = p.dim();
    if s.dim() != (ne, m, 3) || w.dim() != (ne, m) || nb != b.len() {
        return Err(invalid_input(
            py,
            format!(
                "inconsistent shapes: phase_diffs {:?} (epochs, m, M), los {:?} (epochs, M, 3), \
                 wavelength {:?} (epochs, M), baselines ({}, 3)",
                p.shape(),
                s.shape(),
                w.shape(),
                b.len()
            ),
        ));
    }
    let epochs: Vec<Epoch> = (0..ne)
        .map(|e| Epoch {
            phase_diffs: (0..nb)
                .map(|i| (0..m).map(|k| p[[e, i, k]]).collect())
                .collect(),
            los_enu: (0..m)
                .map(|k| Vector3::new(s[[e, k, 0]], s[[e, k, 1]], s[[e, k, 2]]))
                .collect(),
            wavelengths: (0..m).map(|k| w[[e, k]]).collect(),
        })
        .collect();
    let stat = Statistic::parse(statistic).into_py_result(py)?;
    Model::new(&b, &epochs, stat).into_py_result(py)
}

fn grid(
    py: Python<'_>,
    model: &Model,
    step_rad: Option<f64>,
    window_rad: Option<[[f64; 2]; 3]>,
    two_dimensional: bool,
) -> PyResult<Grid> {
    let step = step_rad.unwrap_or_else(|| model.default_step());
    match (window_rad, two_dimensional) {
        (Some(w), false) => Grid::window(step, w.map(|r| (r[0], r[1]))),
        (None, false) => Grid::full(step),
        (Some(w), true) => {
            Grid::two_dimensional_window(step, [(w[0][0], w[0][1]), (w[1][0], w[1][1])])
        }
        (None, true) => Grid::two_dimensional(step),
    }
    .into_py_result(py)
}

/// Grid search. Returns (angles_rad, grid_angles_rad, z_max, cells_evaluated, step_rad, grid_index).
#[pyfunction]
#[pyo3(signature = (phase_diffs, los, wavelengths, baselines, statistic, step_rad, window_rad, search, refine, two_dimensional))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
fn ml_search(
    py: Python<'_>,
    phase_diffs: PyReadonlyArray3<'_, f64>,
    los: PyReadonlyArray3<'_, f64>,
    wavelengths: PyReadonlyArray2<'_, f64>,
    baselines: PyReadonlyArray2<'_, f64>,
    statistic: &str,
    step_rad: Option<f64>,
    window_rad: Option<[[f64; 2]; 3]>,
    search: &str,
    refine: &str,
    two_dimensional: bool,
) -> PyResult<([f64; 3], [f64; 3], f64, u64, f64, [usize; 3])> {
    let refine = match refine {
        "none" => Refine::None,
        "parabolic" => Refine::Parabolic,
        "newton" => Refine::Newton,
        other => {
            return Err(invalid_input(
                py,
                format!("expected refine 'none', 'parabolic' or 'newton', got {other:?}"),
            ))
        }
    };
    let search = match search {
        "exhaustive" => Search::Exhaustive,
        "branch_and_bound" => Search::BranchAndBound,
        "auto" => Search::Auto,
        other => {
            return Err(invalid_input(
                py,
                format!(
                    "expected search 'auto', 'exhaustive' or 'branch_and_bound', got {other:?}"
                ),
            ))
        }
    };
    let model = model(py, &phase_diffs, &los, &wavelengths, &baselines, statistic)?;
    let grid = grid(py, &model, step_rad, window_rad, two_dimensional)?;
    let est = interruptible::run(py, || estimate(&model, &grid, search, refine))?;
    Ok((
        est.angles_rad,
        est.grid_angles_rad,
        est.grid_max.z as f64,
        est.grid_max.cells_evaluated,
        est.step_rad,
        est.grid_max.index,
    ))
}

/// Branch-and-bound work counters: (boxes_bounded, leaf_cells, grid_cells).
#[pyfunction]
#[pyo3(signature = (phase_diffs, los, wavelengths, baselines, statistic, step_rad, window_rad))]
#[allow(clippy::too_many_arguments)]
fn bnb_stats(
    py: Python<'_>,
    phase_diffs: PyReadonlyArray3<'_, f64>,
    los: PyReadonlyArray3<'_, f64>,
    wavelengths: PyReadonlyArray2<'_, f64>,
    baselines: PyReadonlyArray2<'_, f64>,
    statistic: &str,
    step_rad: Option<f64>,
    window_rad: Option<[[f64; 2]; 3]>,
) -> PyResult<(u64, u64, u64)> {
    let model = model(py, &phase_diffs, &los, &wavelengths, &baselines, statistic)?;
    let grid = grid(py, &model, step_rad, window_rad, false)?;
    let (_, s) = interruptible::run(py, || branch_and_bound(&model, &grid))?;
    Ok((s.boxes_bounded, s.leaf_cells, grid.len() as u64))
}

/// The whole Z array (float32, shape (n_theta, n_phi, n_psi)) and the axes (radians) psi, theta, phi.
#[pyfunction]
#[pyo3(signature = (phase_diffs, los, wavelengths, baselines, statistic, step_rad, window_rad, two_dimensional))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
fn likelihood_grid<'py>(
    py: Python<'py>,
    phase_diffs: PyReadonlyArray3<'_, f64>,
    los: PyReadonlyArray3<'_, f64>,
    wavelengths: PyReadonlyArray2<'_, f64>,
    baselines: PyReadonlyArray2<'_, f64>,
    statistic: &str,
    step_rad: Option<f64>,
    window_rad: Option<[[f64; 2]; 3]>,
    two_dimensional: bool,
) -> PyResult<(
    Bound<'py, PyArray3<f32>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
)> {
    let model = model(py, &phase_diffs, &los, &wavelengths, &baselines, statistic)?;
    let g = grid(py, &model, step_rad, window_rad, two_dimensional)?;
    let z = interruptible::run(py, || evaluate_grid(&model, &g))?;
    let z = Array3::from_shape_vec((g.theta.len, g.phi.len, g.psi.len), z)
        .map_err(|e| invalid_input(py, e.to_string()))?;
    let axis = |a: &gnssatt_core::likelihood::Axis| {
        (0..a.len as i64)
            .map(|j| a.angle(j))
            .collect::<Vec<_>>()
            .into_pyarray(py)
    };
    Ok((
        z.into_pyarray(py),
        axis(&g.psi),
        axis(&g.theta),
        axis(&g.phi),
    ))
}

/// Per-epoch inputs of the series calls: sd_phase (n_ep, n_rover, n_sig) with NaN for absent signals,
/// los (n_ep, n_sig, 3) ENU, wavelengths (n_ep, n_sig); `n_rover` checked against `rovers`.
fn series_epochs(
    py: Python<'_>,
    sd_phase: &PyReadonlyArray3<'_, f64>,
    los: &PyReadonlyArray3<'_, f64>,
    wavelengths: &PyReadonlyArray2<'_, f64>,
    rovers: usize,
) -> PyResult<Vec<MlEpoch>> {
    let (p, s, w) = (sd_phase.as_array(), los.as_array(), wavelengths.as_array());
    let (ne, nr, m) = p.dim();
    if s.dim() != (ne, m, 3) || w.dim() != (ne, m) || nr != rovers {
        return Err(invalid_input(
            py,
            format!(
                "inconsistent shapes: sd_phase {:?} (epochs, n_rover, n_sig), los {:?} (epochs, n_sig, \
                 3), wavelength {:?} (epochs, n_sig), {rovers} rover baselines",
                p.shape(),
                s.shape(),
                w.shape(),
            ),
        ));
    }
    Ok((0..ne)
        .map(|e| MlEpoch {
            sd_phase_rad: p
                .slice(numpy::ndarray::s![e, .., ..])
                .iter()
                .copied()
                .collect(),
            los_enu: (0..m)
                .map(|k| [s[[e, k, 0]], s[[e, k, 1]], s[[e, k, 2]]])
                .collect(),
            wavelength_m: (0..m).map(|k| w[[e, k]]).collect(),
        })
        .collect())
}

/// (euler_rad (n, 3), direction_rad (n, 2), value (n,), solved (n,)).
type SeriesArrays<'py> = (
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<bool>>,
);

fn series_arrays<'py>(py: Python<'py>, sol: &[MlSolution]) -> PyResult<SeriesArrays<'py>> {
    let n = sol.len();
    let euler = Array2::from_shape_fn((n, 3), |(k, j)| sol[k].euler_gost_rad[j]);
    let direction = Array2::from_shape_fn((n, 2), |(k, j)| sol[k].direction_rad[j]);
    Ok((
        euler.into_pyarray(py),
        direction.into_pyarray(py),
        sol.iter()
            .map(|x| x.value)
            .collect::<Vec<_>>()
            .into_pyarray(py),
        sol.iter()
            .map(|x| x.solved)
            .collect::<Vec<_>>()
            .into_pyarray(py),
    ))
}

/// Per-epoch ML attitude over a batch (GIL released, interruptible).
#[pyfunction]
#[pyo3(signature = (sd_phase, los, wavelengths, baselines, step_rad, window_rad))]
fn ml_attitude_series<'py>(
    py: Python<'py>,
    sd_phase: PyReadonlyArray3<'_, f64>,
    los: PyReadonlyArray3<'_, f64>,
    wavelengths: PyReadonlyArray2<'_, f64>,
    baselines: PyReadonlyArray2<'_, f64>,
    step_rad: Option<f64>,
    window_rad: Option<f64>,
) -> PyResult<SeriesArrays<'py>> {
    let b: Vec<[f64; 3]> = vectors(py, "baselines", &baselines)?
        .iter()
        .map(|v| [v.x, v.y, v.z])
        .collect();
    let epochs = series_epochs(py, &sd_phase, &los, &wavelengths, b.len())?;
    let sol = interruptible::run(py, || {
        core_attitude_series(&epochs, &b, step_rad, window_rad)
    })?;
    series_arrays(py, &sol)
}

/// Per-epoch ML direction of one baseline over a batch (GIL released, interruptible).
#[pyfunction]
#[pyo3(signature = (sd_phase, los, wavelengths, baseline_length_m, step_rad, window_rad))]
fn ml_baseline_series<'py>(
    py: Python<'py>,
    sd_phase: PyReadonlyArray3<'_, f64>,
    los: PyReadonlyArray3<'_, f64>,
    wavelengths: PyReadonlyArray2<'_, f64>,
    baseline_length_m: f64,
    step_rad: Option<f64>,
    window_rad: Option<f64>,
) -> PyResult<SeriesArrays<'py>> {
    let epochs = series_epochs(py, &sd_phase, &los, &wavelengths, 1)?;
    let sol = interruptible::run(py, || {
        core_baseline_series(&epochs, baseline_length_m, step_rad, window_rad)
    })?;
    series_arrays(py, &sol)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(ml_attitude_series, m)?)?;
    m.add_function(wrap_pyfunction!(ml_baseline_series, m)?)?;
    m.add_function(wrap_pyfunction!(ml_search, m)?)?;
    m.add_function(wrap_pyfunction!(bnb_stats, m)?)?;
    m.add_function(wrap_pyfunction!(likelihood_grid, m)?)?;
    Ok(())
}
