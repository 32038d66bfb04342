//! Bindings of the gyro + multi-antenna GNSS attitude filter (`gnssatt_core::gyro_gnss`). The whole filter
//! runs with the GIL released; the Python wrapper `gnssatt.attitude.gyro_gnss` builds the arguments (settings in a
//! `GyroGnssOptions`) and reads the typed `GyroGnssRun` back by attribute.

use gnssatt_core::gyro_gnss::kinematics::propagate;
use gnssatt_core::gyro_gnss::{run, AttitudeFix, FilterRun, Initial, PhaseEpoch, PhaseObs};
use nalgebra::{Matrix3, Matrix6, Vector3};
use numpy::ndarray::{Array1, Array2, Array3};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArray3, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3,
};
use pyo3::prelude::*;

use crate::convert::{exact, fixed, quats_to_numpy, rows, square, values, vectors};
use crate::errors::invalid_input;
use crate::guard::guard;
use crate::gyro_gnss_options::GyroGnssOptions;
use crate::interruptible;
use crate::results::result_type;

/// Attitude (n, 4) at the time stamps `t` from `q0` and the body rates held over each interval.
#[guard]
#[pyfunction]
fn gyro_propagate<'py>(
    py: Python<'py>,
    q0: PyReadonlyArray1<'_, f64>,
    t: PyReadonlyArray1<'_, f64>,
    rates: PyReadonlyArray2<'_, f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let q0 = fixed::<4>(py, "q0", &q0)?;
    let t = values(py, "t", &t)?;
    let rates = vectors(py, "rates", &rates)?;
    let q = interruptible::run(py, || propagate(q0, &t, &rates))?;
    Ok(quats_to_numpy(py, &q))
}

#[allow(clippy::too_many_arguments)]
fn phase_epochs(
    py: Python<'_>,
    m: usize,
    epoch_t: Vec<f64>,
    epoch: &PyReadonlyArray1<'_, i64>,
    track: &PyReadonlyArray1<'_, i64>,
    los: &PyReadonlyArray2<'_, f64>,
    wavelength: &PyReadonlyArray1<'_, f64>,
    phase: &PyReadonlyArray2<'_, f64>,
) -> PyResult<Vec<PhaseEpoch>> {
    let epoch = epoch.as_array();
    let track = track.as_array();
    let los = vectors(py, "phase_los", los)?;
    let wavelength = values(py, "phase_wavelength", wavelength)?;
    let phase = phase.as_array();
    let rows = epoch.len();
    if track.len() != rows || los.len() != rows || wavelength.len() != rows || phase.nrows() != rows
    {
        return Err(invalid_input(
            py,
            format!(
                "expected phase_epoch, phase_track, phase_los, phase_wavelength and phase rows of equal \
                 length, got {rows}, {}, {}, {} and {}",
                track.len(),
                los.len(),
                wavelength.len(),
                phase.nrows()
            ),
        ));
    }
    if phase.ncols() != m {
        return Err(invalid_input(
            py,
            format!(
                "expected phase of shape (n_rows, {m}) (one column per baseline), got {:?}",
                phase.shape()
            ),
        ));
    }
    let mut out: Vec<PhaseEpoch> = epoch_t
        .iter()
        .map(|&t| PhaseEpoch { t, obs: Vec::new() })
        .collect();
    let mut last = 0;
    for r in 0..rows {
        let e = epoch[r];
        if e < last || e as usize >= out.len() {
            return Err(invalid_input(
                py,
                format!(
                    "expected phase_epoch non-decreasing in [0, {}), got {e} at row {r}",
                    out.len()
                ),
            ));
        }
        last = e;
        out[e as usize].obs.push(PhaseObs {
            track: track[r],
            los: los[r],
            wavelength: wavelength[r],
            phase: phase.row(r).to_vec(),
        });
    }
    Ok(out)
}

result_type! {
    /// One LAMBDA attempt of the filter: `values` are `(track, baseline, integer)` of the best candidate.
    GyroGnssFix {
        t: f64,
        accepted: bool,
        ratio: f64,
        success_rate: f64,
        values: Vec<(i64, usize, i64)>,
    }
}

result_type! {
    /// The filter's output at the recorded gyro times: `t` (n,) s, `quaternion` (n, 4) scalar-last body ->
    /// reference, `drift` (n, 3) rad/s, `covariance` and `true_covariance` (n, 6, 6) of `[dtheta, ddrift]`,
    /// `misalignment` (n, 3) rad and its covariance (n, 3, 3), `n_float` / `n_fixed` (n,) ambiguities held,
    /// `fixes` the LAMBDA attempts, `slips` (k, 3) rows `(t, track, NIS)`, `nis` (u, 3) rows `(t, NIS, dof)`.
    GyroGnssRun {
        t: Py<PyArray1<f64>>,
        quaternion: Py<PyArray2<f64>>,
        drift: Py<PyArray2<f64>>,
        covariance: Py<PyArray3<f64>>,
        true_covariance: Py<PyArray3<f64>>,
        misalignment: Py<PyArray2<f64>>,
        misalignment_covariance: Py<PyArray3<f64>>,
        n_float: Py<PyArray1<usize>>,
        n_fixed: Py<PyArray1<usize>>,
        fixes: Vec<Py<GyroGnssFix>>,
        slips: Py<PyArray2<f64>>,
        nis: Py<PyArray2<f64>>,
    }
}

fn typed(py: Python<'_>, run: FilterRun) -> PyResult<GyroGnssRun> {
    let n = run.t.len();
    let mat6 = |m: &[Matrix6<f64>]| {
        Array3::from_shape_fn((m.len(), 6, 6), |(k, i, j)| m[k][(i, j)])
            .into_pyarray(py)
            .unbind()
    };
    let rows3 = |v: &[Vector3<f64>]| {
        Array2::from_shape_fn((v.len(), 3), |(k, i)| v[k][i])
            .into_pyarray(py)
            .unbind()
    };
    let fixes = run
        .fixes
        .into_iter()
        .map(|f| {
            Py::new(
                py,
                GyroGnssFix {
                    t: f.t,
                    accepted: f.accepted,
                    ratio: f.ratio,
                    success_rate: f.success_rate,
                    values: f.values,
                },
            )
        })
        .collect::<PyResult<Vec<_>>>()?;
    // track ids and degrees of freedom are small integers, exact in f64
    let slips = Array2::from_shape_fn((run.slips.len(), 3), |(k, j)| {
        let s = &run.slips[k];
        [s.t, s.track as f64, s.nis][j]
    });
    let nis = Array2::from_shape_fn((run.nis.len(), 3), |(k, j)| {
        let s = &run.nis[k];
        [s.t, s.nis, s.dof as f64][j]
    });
    Ok(GyroGnssRun {
        t: Array1::from(run.t).into_pyarray(py).unbind(),
        quaternion: quats_to_numpy(py, &run.quaternion).unbind(),
        drift: rows3(&run.drift),
        covariance: mat6(&run.covariance),
        true_covariance: mat6(&run.true_covariance),
        misalignment: rows3(&run.misalignment),
        misalignment_covariance: Array3::from_shape_fn((n, 3, 3), |(k, i, j)| {
            run.misalignment_covariance[k][(i, j)]
        })
        .into_pyarray(py)
        .unbind(),
        n_float: Array1::from(run.n_float).into_pyarray(py).unbind(),
        n_fixed: Array1::from(run.n_fixed).into_pyarray(py).unbind(),
        fixes,
        slips: slips.into_pyarray(py).unbind(),
        nis: nis.into_pyarray(py).unbind(),
    })
}

/// Runs the filter from the initial state `q0` (4,), `drift0` (3,), `p0` (6, 6) over the gyro record, with
/// attitude fixes `fix_*` and phase rows `phase_*` (empty arrays for none); see
/// `gnssatt.attitude.gyro_gnss.gyro_gnss_filter`.
#[guard]
#[pyfunction]
#[pyo3(signature = (
    gyro_t, gyro_rates, *, q0, drift0, p0, options, fix_t, fix_q, fix_cov, epoch_t, phase_epoch, phase_track,
    phase_los, phase_wavelength, phase
))]
#[allow(clippy::too_many_arguments)]
fn gyro_gnss_filter(
    py: Python<'_>,
    gyro_t: PyReadonlyArray1<'_, f64>,
    gyro_rates: PyReadonlyArray2<'_, f64>,
    q0: PyReadonlyArray1<'_, f64>,
    drift0: PyReadonlyArray1<'_, f64>,
    p0: PyReadonlyArray2<'_, f64>,
    options: &GyroGnssOptions,
    fix_t: PyReadonlyArray1<'_, f64>,
    fix_q: PyReadonlyArray2<'_, f64>,
    fix_cov: PyReadonlyArray3<'_, f64>,
    epoch_t: PyReadonlyArray1<'_, f64>,
    phase_epoch: PyReadonlyArray1<'_, i64>,
    phase_track: PyReadonlyArray1<'_, i64>,
    phase_los: PyReadonlyArray2<'_, f64>,
    phase_wavelength: PyReadonlyArray1<'_, f64>,
    phase: PyReadonlyArray2<'_, f64>,
) -> PyResult<GyroGnssRun> {
    let gyro_t = values(py, "gyro_t", &gyro_t)?;
    let gyro_rates = vectors(py, "gyro_rates", &gyro_rates)?;
    let drift0 = fixed::<3>(py, "drift0", &drift0)?;
    let settings = &options.inner;
    let initial = Initial {
        quaternion: fixed::<4>(py, "q0", &q0)?,
        drift: Vector3::new(drift0[0], drift0[1], drift0[2]),
        covariance: square::<6>(py, "p0", &p0)?,
    };
    let fix_t = values(py, "fix_t", &fix_t)?;
    let fix_q = rows::<4>(py, "fix_q", &fix_q, Some(fix_t.len()), false)?;
    let fix_cov = exact(py, "fix_cov", &fix_cov, &[fix_t.len(), 3, 3])?;
    let fixes: Vec<AttitudeFix> = (0..fix_t.len())
        .map(|k| AttitudeFix {
            t: fix_t[k],
            quaternion: fix_q[k],
            covariance: Matrix3::from_fn(|i, j| fix_cov[9 * k + 3 * i + j]),
        })
        .collect();
    let epochs = phase_epochs(
        py,
        settings.baselines.len(),
        values(py, "epoch_t", &epoch_t)?,
        &phase_epoch,
        &phase_track,
        &phase_los,
        &phase_wavelength,
        &phase,
    )?;
    let result = interruptible::run(py, || {
        run(settings, &initial, &gyro_t, &gyro_rates, &fixes, &epochs)
    })?;
    typed(py, result)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(gyro_propagate, m)?)?;
    m.add_function(wrap_pyfunction!(gyro_gnss_filter, m)?)?;
    m.add_class::<GyroGnssOptions>()?;
    m.add_class::<GyroGnssRun>()?;
    m.add_class::<GyroGnssFix>()?;
    Ok(())
}
