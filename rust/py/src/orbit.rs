//! Bindings of the Dzhepe Ali orbit models and orbit-determination filter (`gnssatt_core::orbit`). States
//! are `(x, y, z, vx, vy, vz)` in Earth-fixed axes, m and m/s; `gnssatt.orbit` / `gnssatt.orbit.determination`
//! hold the documented Python API.

use gnssatt_core::orbit::{
    propagate_with_stm, run_filter, CircularOrbit, Corrections, FilterConfig, FilterOutput, Fixes,
    GlonassModel, Ranges,
};
use nalgebra::Matrix6;
use numpy::ndarray::{Array1, Array2, Array3};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArray3, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3,
};
use pyo3::prelude::*;

use crate::convert::{exact, fixed, rows, rows3, square, values};
use crate::errors::{invalid_input, IntoPyResult};
use crate::guard::guard;
use crate::interruptible;
use crate::results::result_type;

/// The ICD model constants, passed as one dict (`gnssatt.orbit.GlonassModel._kwargs()`), SI units.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
struct ModelArgs {
    gm_m3_s2: f64,
    j2: f64,
    equatorial_radius_m: f64,
    omega_rad_s: f64,
    lunisolar_m_s2: [f64; 3],
}

impl From<ModelArgs> for GlonassModel {
    fn from(a: ModelArgs) -> Self {
        GlonassModel {
            gm_m3_s2: a.gm_m3_s2,
            j2: a.j2,
            equatorial_radius_m: a.equatorial_radius_m,
            omega_rad_s: a.omega_rad_s,
            lunisolar_m_s2: a.lunisolar_m_s2,
        }
    }
}

fn to_numpy6(m: &Matrix6<f64>) -> Array2<f64> {
    Array2::from_shape_fn((6, 6), |(i, j)| m[(i, j)])
}

result_type! {
    /// A propagated `state` (6,) and its state-transition matrix `stm` (6, 6) d state / d initial state.
    StateWithStm {
        state: Py<PyArray1<f64>>,
        stm: Py<PyArray2<f64>>,
    }
}

result_type! {
    /// Earth-fixed `position_m` (n, 3) and `velocity_m_s` (n, 3).
    OrbitStates {
        position_m: Py<PyArray2<f64>>,
        velocity_m_s: Py<PyArray2<f64>>,
    }
}

result_type! {
    /// The orbit filter's `states` (n, 6), `covariances` (n, 6, 6), and per epoch the normalised
    /// innovation squared `nis` (n,) with its degrees of freedom `dof` (n,) (0: no update).
    OrbitFilterRun {
        states: Py<PyArray2<f64>>,
        covariances: Py<PyArray3<f64>>,
        nis: Py<PyArray1<f64>>,
        dof: Py<PyArray1<u64>>,
    }
}

/// The state propagated over `duration_s` with its state-transition matrix.
#[guard]
#[pyfunction]
#[pyo3(signature = (state, duration_s, model, *, step_s))]
fn glonass_propagate(
    py: Python<'_>,
    state: PyReadonlyArray1<'_, f64>,
    duration_s: f64,
    model: ModelArgs,
    step_s: f64,
) -> PyResult<StateWithStm> {
    let s = fixed::<6>(py, "state", &state)?;
    let m = GlonassModel::from(model);
    let (x, phi) = interruptible::run(py, || propagate_with_stm(&m, &s, duration_s, step_s))?;
    Ok(StateWithStm {
        state: Array1::from_vec(x.to_vec()).into_pyarray(py).unbind(),
        stm: to_numpy6(&phi).into_pyarray(py).unbind(),
    })
}

/// ECEF positions and velocities of a circular orbit at times (n,).
#[guard]
#[pyfunction]
#[pyo3(signature = (elements, times_s, *, theta0_rad, omega_rad_s))]
fn circular_orbit_ecef(
    py: Python<'_>,
    elements: [f64; 5],
    times_s: PyReadonlyArray1<'_, f64>,
    theta0_rad: f64,
    omega_rad_s: f64,
) -> PyResult<OrbitStates> {
    let o = CircularOrbit {
        radius_m: elements[0],
        inclination_rad: elements[1],
        raan_rad: elements[2],
        arg_latitude0_rad: elements[3],
        gm_m3_s2: elements[4],
    };
    o.validate().into_py_result(py)?;
    if !(theta0_rad.is_finite() && omega_rad_s.is_finite()) {
        return Err(invalid_input(
            py,
            format!("expected finite theta0_rad and omega_rad_s, got {theta0_rad}, {omega_rad_s}"),
        ));
    }
    let t = values(py, "times_s", &times_s)?;
    let states: Vec<_> = t
        .iter()
        .map(|&ti| o.state_ecef(ti, theta0_rad, omega_rad_s))
        .collect();
    let n = states.len();
    Ok(OrbitStates {
        position_m: Array2::from_shape_fn((n, 3), |(i, j)| states[i].0[j])
            .into_pyarray(py)
            .unbind(),
        velocity_m_s: Array2::from_shape_fn((n, 3), |(i, j)| states[i].1[j])
            .into_pyarray(py)
            .unbind(),
    })
}

fn output(py: Python<'_>, out: FilterOutput) -> OrbitFilterRun {
    let n = out.states.len();
    OrbitFilterRun {
        states: Array2::from_shape_fn((n, 6), |(k, j)| out.states[k][j])
            .into_pyarray(py)
            .unbind(),
        covariances: Array3::from_shape_fn((n, 6, 6), |(k, i, j)| out.covariances[k][(i, j)])
            .into_pyarray(py)
            .unbind(),
        nis: Array1::from_vec(out.nis).into_pyarray(py).unbind(),
        dof: Array1::from_iter(out.dof.iter().map(|&d| d as u64))
            .into_pyarray(py)
            .unbind(),
    }
}

fn config(model: ModelArgs, accel_psd_m2_s3: f64, step_s: f64) -> FilterConfig {
    FilterConfig {
        model: model.into(),
        accel_psd_m2_s3,
        step_s,
    }
}

/// Loosely coupled run: fixes (n_t, 3) x2, their covariances (n_t, 6, 6) and validity (n_t,).
#[guard]
#[pyfunction]
#[pyo3(signature = (times_s, x0, p0, fix_position_m, fix_velocity_m_s, fix_covariance, fix_valid, *, model, accel_psd_m2_s3, step_s))]
#[allow(clippy::too_many_arguments)]
fn orbit_filter_loose(
    py: Python<'_>,
    times_s: PyReadonlyArray1<'_, f64>,
    x0: PyReadonlyArray1<'_, f64>,
    p0: PyReadonlyArray2<'_, f64>,
    fix_position_m: PyReadonlyArray2<'_, f64>,
    fix_velocity_m_s: PyReadonlyArray2<'_, f64>,
    fix_covariance: PyReadonlyArray3<'_, f64>,
    fix_valid: PyReadonlyArray1<'_, bool>,
    model: ModelArgs,
    accel_psd_m2_s3: f64,
    step_s: f64,
) -> PyResult<OrbitFilterRun> {
    let t = values(py, "times_s", &times_s)?;
    let n = t.len();
    let x0 = fixed::<6>(py, "x0", &x0)?;
    let p0 = square::<6>(py, "p0", &p0)?;
    // Epochs without a fix may hold NaN: the core checks the valid ones.
    let pos = rows::<3>(py, "fix_position_m", &fix_position_m, Some(n), true)?;
    let vel = rows::<3>(py, "fix_velocity_m_s", &fix_velocity_m_s, Some(n), true)?;
    let c = exact(py, "fix_covariance", &fix_covariance, &[n, 6, 6])?;
    let cov: Vec<Matrix6<f64>> = c
        .chunks_exact(36)
        .map(|k| Matrix6::from_fn(|i, j| k[6 * i + j]))
        .collect();
    let valid = exact(py, "fix_valid", &fix_valid, &[n])?;
    let cfg = config(model, accel_psd_m2_s3, step_s);
    let fixes = Fixes {
        position_m: &pos,
        velocity_m_s: &vel,
        covariance: &cov,
        valid: &valid,
    };
    let out = interruptible::run(py, || {
        run_filter(&cfg, &t, &x0, &p0, &Corrections::Loose(fixes))
    })?;
    Ok(output(py, out))
}

/// Tightly coupled run: satellite states (n_t, n_sat, 3) x2, pseudoranges, Doppler and tracking (n_t,
/// n_sat), wavelengths and systems (n_sat,), noise sigmas.
#[guard]
#[pyfunction]
#[pyo3(signature = (times_s, x0, p0, sat_position_m, sat_velocity_m_s, pseudorange_m, doppler_hz, visible, wavelength_m, system, *, code_sigma_m, doppler_sigma_hz, model, accel_psd_m2_s3, step_s))]
#[allow(clippy::too_many_arguments)]
fn orbit_filter_tight(
    py: Python<'_>,
    times_s: PyReadonlyArray1<'_, f64>,
    x0: PyReadonlyArray1<'_, f64>,
    p0: PyReadonlyArray2<'_, f64>,
    sat_position_m: PyReadonlyArray3<'_, f64>,
    sat_velocity_m_s: PyReadonlyArray3<'_, f64>,
    pseudorange_m: PyReadonlyArray2<'_, f64>,
    doppler_hz: PyReadonlyArray2<'_, f64>,
    visible: PyReadonlyArray2<'_, bool>,
    wavelength_m: PyReadonlyArray1<'_, f64>,
    system: PyReadonlyArray1<'_, u32>,
    code_sigma_m: f64,
    doppler_sigma_hz: f64,
    model: ModelArgs,
    accel_psd_m2_s3: f64,
    step_s: f64,
) -> PyResult<OrbitFilterRun> {
    let t = values(py, "times_s", &times_s)?;
    let n = t.len();
    let x0 = fixed::<6>(py, "x0", &x0)?;
    let p0 = square::<6>(py, "p0", &p0)?;
    let lam = values(py, "wavelength_m", &wavelength_m)?;
    let m = lam.len();
    let sys = exact(py, "system", &system, &[m])?;
    // Untracked satellites may hold NaN: the core checks the tracked ones.
    let pos = rows3::<3>(py, "sat_position_m", &sat_position_m, n, m, true)?;
    let vel = rows3::<3>(py, "sat_velocity_m_s", &sat_velocity_m_s, n, m, true)?;
    let pr = exact(py, "pseudorange_m", &pseudorange_m, &[n, m])?;
    let dop = exact(py, "doppler_hz", &doppler_hz, &[n, m])?;
    let vis = exact(py, "visible", &visible, &[n, m])?;
    let cfg = config(model, accel_psd_m2_s3, step_s);
    let ranges = Ranges {
        n_sat: m,
        sat_position_m: &pos,
        sat_velocity_m_s: &vel,
        pseudorange_m: &pr,
        doppler_hz: &dop,
        visible: &vis,
        wavelength_m: &lam,
        system: &sys,
        code_sigma_m,
        doppler_sigma_hz,
    };
    let out = interruptible::run(py, || {
        run_filter(&cfg, &t, &x0, &p0, &Corrections::Tight(ranges))
    })?;
    Ok(output(py, out))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(glonass_propagate, m)?)?;
    m.add_function(wrap_pyfunction!(circular_orbit_ecef, m)?)?;
    m.add_function(wrap_pyfunction!(orbit_filter_loose, m)?)?;
    m.add_function(wrap_pyfunction!(orbit_filter_tight, m)?)?;
    m.add_class::<StateWithStm>()?;
    m.add_class::<OrbitStates>()?;
    m.add_class::<OrbitFilterRun>()?;
    // The limits live in the core; Python reads them from here instead of restating them.
    m.add(
        "ORBIT_MAX_RK4_STEPS",
        gnssatt_core::orbit::glonass::MAX_RK4_STEPS,
    )?;
    m.add(
        "ORBIT_MIN_RADIUS_FRACTION",
        gnssatt_core::orbit::glonass::MIN_RADIUS_FRACTION,
    )?;
    Ok(())
}
