//! Binding of the Belokonov et al. rotational dynamics. The Python layer (`gnssatt.attitude.visibility`)
//! packs the model parameters; `params` rows are `(psi, alpha, phi, wx, wy, wz)` (rad, rad/s), axes come back
//! in the library's orbital frame (x along-track, y orbit normal, z radial).

use gnssatt_core::dynamics::{
    axis_cost_batch, propagate, propagate_axes_batch, Aerodynamics, State, TumbleModel,
};
use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::convert::{fixed, rows, values};
use crate::errors::IntoPyResult;
use crate::guard::guard;
use crate::interruptible;

/// Calls of at most this many RK4 steps (all rows together; about 60 ms of one core) run on the calling
/// thread, the interpreter released: [`interruptible::run`] starts a thread per call and waits for it in
/// slices, which costs more than the work for the one-state calls of a local search (a Nelder-Mead or
/// L-BFGS-B step, some 0.1 ms of work) and, on a loaded machine, a scheduler wake-up per call. Ctrl-C is
/// then handled when the call returns, within the same 60 ms.
const DIRECT_RK4_STEPS: f64 = 1e6;

/// Runs `work` directly when its `steps` (RK4 steps, all rows) are few, else interruptibly.
fn run_core<T: Send>(
    py: Python<'_>,
    steps: f64,
    work: impl FnOnce() -> gnssatt_core::Result<T> + Send,
) -> PyResult<T> {
    if steps <= DIRECT_RK4_STEPS {
        py.detach(|| crate::pool::install(work)).into_py_result(py)
    } else {
        interruptible::run(py, work)
    }
}

/// RK4 steps of `rows` trajectories to the last of `t` in steps of `step_s` (an upper bound of the core's
/// count, which the core checks; non-finite for invalid input, which then takes the interruptible path
/// and fails there).
fn rk4_steps(rows: usize, t: &[f64], step_s: f64) -> f64 {
    let end = t.last().copied().unwrap_or(0.0);
    rows as f64 * ((end / step_s).ceil() + 1.0)
}

/// The model parameters, passed as one dict (`gnssatt.attitude.dynamics.TumbleModel._kwargs()`), SI units.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
struct ModelArgs {
    inertia_kg_m2: [f64; 3],
    orbital_rate_rad_s: f64,
    gravity_gradient: bool,
    density_kg_m3: f64,
    drag_coefficient: f64,
    area_m2: f64,
    cp_offset_m: [f64; 3],
    speed_m_s: f64,
}

impl From<ModelArgs> for TumbleModel {
    fn from(a: ModelArgs) -> Self {
        TumbleModel {
            inertia_kg_m2: a.inertia_kg_m2,
            orbital_rate_rad_s: a.orbital_rate_rad_s,
            gravity_gradient: a.gravity_gradient,
            aero: Aerodynamics {
                density_kg_m3: a.density_kg_m3,
                drag_coefficient: a.drag_coefficient,
                area_m2: a.area_m2,
                cp_offset_m: a.cp_offset_m,
                speed_m_s: a.speed_m_s,
            },
        }
    }
}

/// Antenna axes (n, m, 3) of n initial states at m times.
#[guard]
#[pyfunction]
#[pyo3(signature = (params, times_s, model, *, step_s))]
fn tumble_axes<'py>(
    py: Python<'py>,
    params: PyReadonlyArray2<'_, f64>,
    times_s: PyReadonlyArray1<'_, f64>,
    model: ModelArgs,
    step_s: f64,
) -> PyResult<Bound<'py, PyArray3<f64>>> {
    let m = TumbleModel::from(model);
    let b = rows::<6>(py, "params", &params, None, false)?;
    let t = values(py, "t", &times_s)?;
    let axes = run_core(py, rk4_steps(b.len(), &t, step_s), || {
        propagate_axes_batch(&m, &b, &t, step_s)
    })?;
    let out = Array3::from_shape_fn((b.len(), t.len(), 3), |(i, k, j)| axes[i][k][j]);
    Ok(out.into_pyarray(py))
}

/// Objective (1) for each of n parameter rows against measured axes (m, 3).
#[guard]
#[pyfunction]
#[pyo3(signature = (params, times_s, measured, model, *, step_s))]
fn tumble_cost<'py>(
    py: Python<'py>,
    params: PyReadonlyArray2<'_, f64>,
    times_s: PyReadonlyArray1<'_, f64>,
    measured: PyReadonlyArray2<'_, f64>,
    model: ModelArgs,
    step_s: f64,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let m = TumbleModel::from(model);
    let b = rows::<6>(py, "params", &params, None, false)?;
    let t = values(py, "t", &times_s)?;
    let meas = rows::<3>(py, "measured_axes", &measured, None, false)?;
    let cost = run_core(py, rk4_steps(b.len(), &t, step_s), || {
        axis_cost_batch(&m, &b, &t, &meas, step_s)
    })?;
    Ok(cost.into_pyarray(py))
}

/// Full states (m, 7) of one initial state: scalar-last quaternion of `dcm_orb0_from_body` (the paper's
/// orbital axes X0 radial, Y0 along-track, Z0 normal) and the absolute angular velocity (body, rad/s).
#[guard]
#[pyfunction]
#[pyo3(signature = (param, times_s, model, *, step_s))]
fn tumble_states<'py>(
    py: Python<'py>,
    param: PyReadonlyArray1<'_, f64>,
    times_s: PyReadonlyArray1<'_, f64>,
    model: ModelArgs,
    step_s: f64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let m = TumbleModel::from(model);
    let b = fixed::<6>(py, "params", &param)?;
    let s0 = State::from_angles([b[0], b[1], b[2]], [b[3], b[4], b[5]]);
    let t = values(py, "t", &times_s)?;
    let states = run_core(py, rk4_steps(1, &t, step_s), || {
        propagate(&m, s0, &t, step_s)
    })?;
    let out = Array2::from_shape_fn((t.len(), 7), |(k, j)| {
        let s = &states[k];
        match j {
            0..=2 => s.q[j + 1],
            3 => s.q[0],
            _ => s.omega[j - 4],
        }
    });
    Ok(out.into_pyarray(py))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(tumble_axes, m)?)?;
    m.add_function(wrap_pyfunction!(tumble_cost, m)?)?;
    m.add_function(wrap_pyfunction!(tumble_states, m)?)?;
    // The limits live in the core; Python reads them from here instead of restating them.
    m.add(
        "DYNAMICS_MAX_RK4_STEPS",
        gnssatt_core::dynamics::MAX_RK4_STEPS,
    )?;
    m.add(
        "DYNAMICS_MAX_ROTATION_PER_STEP_RAD",
        gnssatt_core::dynamics::MAX_ROTATION_PER_STEP_RAD,
    )?;
    Ok(())
}
