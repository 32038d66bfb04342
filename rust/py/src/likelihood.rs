//! Binding of the Bunyaeva et al. maximum-likelihood grid search. The Python layer
//! (`gnssatt.attitude.likelihood`) broadcasts inputs to (epochs, m, M) phases, (epochs, M, 3) lines of sight
//! and (epochs, M) wavelengths.

use gnssatt_core::likelihood::{
    branch_and_bound, estimate, evaluate_grid, ml_attitude_series as core_attitude_series,
    ml_baseline_series as core_baseline_series, series_work, Epoch, Grid, MlEpoch, MlSolution,
    Model, Refine, Search, Statistic, MAX_SERIES_WORK,
};
use nalgebra::Vector3;
use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::prelude::*;

use crate::convert::{option_name, type_name, vectors};
use crate::errors::{invalid_input, invalid_type, IntoPyResult};
use crate::guard::guard;
use crate::interruptible;
use crate::results::result_type;

fn model(
    py: Python<'_>,
    phase_diffs: &PyReadonlyArray3<'_, f64>,
    los: &PyReadonlyArray3<'_, f64>,
    wavelengths: &PyReadonlyArray2<'_, f64>,
    baselines: &PyReadonlyArray2<'_, f64>,
    statistic: &Bound<'_, PyAny>,
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
    let stat = Statistic::parse(&option_name(py, "statistic", statistic)?).into_py_result(py)?;
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

result_type! {
    /// The grid search's estimate: `angles_rad` (3,) refined and `grid_angles_rad` (3,) of the best node
    /// (psi, theta, phi, GOST), the statistic's maximum `z_max`, the `cells_evaluated`, the lattice
    /// `step_rad` and the best node's `grid_index` (3,).
    MlEstimate {
        angles_rad: Py<PyArray1<f64>>,
        grid_angles_rad: Py<PyArray1<f64>>,
        z_max: f64,
        cells_evaluated: u64,
        step_rad: f64,
        grid_index: Py<PyArray1<usize>>,
    }
}

/// The public `refine` of `ml_attitude` / `ml_baseline`: `True` (Newton), `False` (none), `'parabolic'`
/// or `'newton'`; numpy booleans count as booleans.
fn refinement(py: Python<'_>, refine: &Bound<'_, PyAny>) -> PyResult<Refine> {
    const EXPECTED: &str = "expected refine True, False, 'parabolic' or 'newton'";
    if let Ok(name) = refine.extract::<String>() {
        return match name.as_str() {
            "parabolic" => Ok(Refine::Parabolic),
            "newton" => Ok(Refine::Newton),
            other => Err(invalid_input(py, format!("{EXPECTED}, got {other:?}"))),
        };
    }
    match refine.extract::<bool>() {
        Ok(true) => Ok(Refine::Newton),
        Ok(false) => Ok(Refine::None),
        Err(_) => Err(invalid_type(
            py,
            format!("{EXPECTED}, got {}", type_name(refine)),
        )),
    }
}

/// Grid search over the attitude angles (psi, theta, phi).
#[guard]
#[pyfunction]
#[pyo3(signature = (phase_diffs, los, wavelengths, baselines, *, statistic, step_rad, window_rad, search, refine, two_dimensional))]
#[allow(clippy::too_many_arguments)]
fn ml_search(
    py: Python<'_>,
    phase_diffs: PyReadonlyArray3<'_, f64>,
    los: PyReadonlyArray3<'_, f64>,
    wavelengths: PyReadonlyArray2<'_, f64>,
    baselines: PyReadonlyArray2<'_, f64>,
    statistic: &Bound<'_, PyAny>,
    step_rad: Option<f64>,
    window_rad: Option<[[f64; 2]; 3]>,
    search: &Bound<'_, PyAny>,
    refine: &Bound<'_, PyAny>,
    two_dimensional: bool,
) -> PyResult<MlEstimate> {
    let refine = refinement(py, refine)?;
    let search = match option_name(py, "search", search)?.as_str() {
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
    Ok(MlEstimate {
        angles_rad: est.angles_rad.to_vec().into_pyarray(py).unbind(),
        grid_angles_rad: est.grid_angles_rad.to_vec().into_pyarray(py).unbind(),
        z_max: est.grid_max.z as f64,
        cells_evaluated: est.grid_max.cells_evaluated,
        step_rad: est.step_rad,
        grid_index: est.grid_max.index.to_vec().into_pyarray(py).unbind(),
    })
}

result_type! {
    /// Branch-and-bound work counters: boxes bounded, leaf cells evaluated, the full grid's cells, and
    /// the rounds (targets tried).
    BnbStats {
        boxes_bounded: u64,
        leaf_cells: u64,
        grid_cells: u64,
        rounds: u32,
    }
}

/// The work of a branch-and-bound search next to the exhaustive grid's.
#[guard]
#[pyfunction]
#[pyo3(signature = (phase_diffs, los, wavelengths, baselines, *, statistic, step_rad, window_rad))]
#[allow(clippy::too_many_arguments)]
fn bnb_stats(
    py: Python<'_>,
    phase_diffs: PyReadonlyArray3<'_, f64>,
    los: PyReadonlyArray3<'_, f64>,
    wavelengths: PyReadonlyArray2<'_, f64>,
    baselines: PyReadonlyArray2<'_, f64>,
    statistic: &Bound<'_, PyAny>,
    step_rad: Option<f64>,
    window_rad: Option<[[f64; 2]; 3]>,
) -> PyResult<BnbStats> {
    let model = model(py, &phase_diffs, &los, &wavelengths, &baselines, statistic)?;
    let grid = grid(py, &model, step_rad, window_rad, false)?;
    let (_, s) = interruptible::run(py, || branch_and_bound(&model, &grid))?;
    Ok(BnbStats {
        boxes_bounded: s.boxes_bounded,
        leaf_cells: s.leaf_cells,
        grid_cells: grid.len() as u64,
        rounds: s.rounds,
    })
}

result_type! {
    /// The whole statistic `z` (n_theta, n_phi, n_psi) float32 and its axes `psi_rad`, `theta_rad`,
    /// `phi_rad`.
    LikelihoodGrid {
        z: Py<PyArray3<f32>>,
        psi_rad: Py<PyArray1<f64>>,
        theta_rad: Py<PyArray1<f64>>,
        phi_rad: Py<PyArray1<f64>>,
    }
}

/// The statistic on every node of the grid.
#[guard]
#[pyfunction]
#[pyo3(signature = (phase_diffs, los, wavelengths, baselines, *, statistic, step_rad, window_rad, two_dimensional))]
#[allow(clippy::too_many_arguments)]
fn likelihood_grid(
    py: Python<'_>,
    phase_diffs: PyReadonlyArray3<'_, f64>,
    los: PyReadonlyArray3<'_, f64>,
    wavelengths: PyReadonlyArray2<'_, f64>,
    baselines: PyReadonlyArray2<'_, f64>,
    statistic: &Bound<'_, PyAny>,
    step_rad: Option<f64>,
    window_rad: Option<[[f64; 2]; 3]>,
    two_dimensional: bool,
) -> PyResult<LikelihoodGrid> {
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
            .unbind()
    };
    Ok(LikelihoodGrid {
        z: z.into_pyarray(py).unbind(),
        psi_rad: axis(&g.psi),
        theta_rad: axis(&g.theta),
        phi_rad: axis(&g.phi),
    })
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

result_type! {
    /// Per-epoch ML solutions: `euler_gost_rad` (n, 3), `direction_rad` (n, 2) (compass azimuth and
    /// elevation of the first baseline), the statistic's maximum `z_max` (n,) and `solved` (n,).
    MlSeries {
        euler_gost_rad: Py<PyArray2<f64>>,
        direction_rad: Py<PyArray2<f64>>,
        z_max: Py<PyArray1<f64>>,
        solved: Py<PyArray1<bool>>,
    }
}

fn series_arrays(py: Python<'_>, sol: &[MlSolution]) -> MlSeries {
    let n = sol.len();
    let euler = Array2::from_shape_fn((n, 3), |(k, j)| sol[k].euler_gost_rad[j]);
    let direction = Array2::from_shape_fn((n, 2), |(k, j)| sol[k].direction_rad[j]);
    MlSeries {
        euler_gost_rad: euler.into_pyarray(py).unbind(),
        direction_rad: direction.into_pyarray(py).unbind(),
        z_max: sol
            .iter()
            .map(|x| x.value)
            .collect::<Vec<_>>()
            .into_pyarray(py)
            .unbind(),
        solved: sol
            .iter()
            .map(|x| x.solved)
            .collect::<Vec<_>>()
            .into_pyarray(py)
            .unbind(),
    }
}

/// Per-epoch ML attitude over a batch (GIL released, interruptible).
#[guard]
#[pyfunction]
#[pyo3(signature = (sd_phase, los, wavelengths, baselines, *, step_rad, window_rad))]
fn ml_attitude_series(
    py: Python<'_>,
    sd_phase: PyReadonlyArray3<'_, f64>,
    los: PyReadonlyArray3<'_, f64>,
    wavelengths: PyReadonlyArray2<'_, f64>,
    baselines: PyReadonlyArray2<'_, f64>,
    step_rad: Option<f64>,
    window_rad: Option<f64>,
) -> PyResult<MlSeries> {
    let b: Vec<[f64; 3]> = vectors(py, "baselines", &baselines)?
        .iter()
        .map(|v| [v.x, v.y, v.z])
        .collect();
    let epochs = series_epochs(py, &sd_phase, &los, &wavelengths, b.len())?;
    let sol = interruptible::run(py, || {
        core_attitude_series(&epochs, &b, step_rad, window_rad)
    })?;
    Ok(series_arrays(py, &sol))
}

/// Per-epoch ML direction of one baseline over a batch (GIL released, interruptible).
#[guard]
#[pyfunction]
#[pyo3(signature = (sd_phase, los, wavelengths, baseline_length_m, *, step_rad, window_rad))]
fn ml_baseline_series(
    py: Python<'_>,
    sd_phase: PyReadonlyArray3<'_, f64>,
    los: PyReadonlyArray3<'_, f64>,
    wavelengths: PyReadonlyArray2<'_, f64>,
    baseline_length_m: f64,
    step_rad: Option<f64>,
    window_rad: Option<f64>,
) -> PyResult<MlSeries> {
    let epochs = series_epochs(py, &sd_phase, &los, &wavelengths, 1)?;
    let sol = interruptible::run(py, || {
        core_baseline_series(&epochs, baseline_length_m, step_rad, window_rad)
    })?;
    Ok(series_arrays(py, &sol))
}

/// The work a series call of these shapes is charged (every epoch solved with all its signals), in the
/// kernel terms of `LIKELIHOOD_MAX_SERIES_WORK`: checked by the Python layer before it copies the measurements.
#[guard]
#[pyfunction]
#[pyo3(signature = (n_epochs, n_rover, n_sig, *, step_rad, wavelength_m, longest_baseline_m, window_rad, two_dimensional))]
#[allow(clippy::too_many_arguments)]
fn ml_series_work(
    n_epochs: usize,
    n_rover: usize,
    n_sig: usize,
    step_rad: Option<f64>,
    wavelength_m: f64,
    longest_baseline_m: f64,
    window_rad: Option<f64>,
    two_dimensional: bool,
) -> f64 {
    series_work(
        n_epochs,
        n_rover,
        n_sig,
        step_rad,
        wavelength_m,
        longest_baseline_m,
        window_rad,
        two_dimensional,
    )
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("LIKELIHOOD_MAX_SERIES_WORK", MAX_SERIES_WORK)?;
    m.add_function(wrap_pyfunction!(ml_series_work, m)?)?;
    m.add_function(wrap_pyfunction!(ml_attitude_series, m)?)?;
    m.add_function(wrap_pyfunction!(ml_baseline_series, m)?)?;
    m.add_function(wrap_pyfunction!(ml_search, m)?)?;
    m.add_function(wrap_pyfunction!(bnb_stats, m)?)?;
    m.add_function(wrap_pyfunction!(likelihood_grid, m)?)?;
    m.add_class::<MlEstimate>()?;
    m.add_class::<BnbStats>()?;
    m.add_class::<LikelihoodGrid>()?;
    m.add_class::<MlSeries>()?;
    Ok(())
}
