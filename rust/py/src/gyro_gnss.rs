//! Bindings of the gyro + multi-antenna GNSS attitude filter (`gnssatt_core::gyro_gnss`). The whole filter
//! runs with the GIL released; the Python wrapper `gnssatt.gyro_gnss` builds the arguments.

use gnssatt_core::gyro_gnss::kinematics::propagate;
use gnssatt_core::gyro_gnss::{
    run, AttitudeFix, FilterRun, FixSettings, GyroNoise, Initial, PhaseEpoch, PhaseObs,
    Sensitivity, Settings,
};
use nalgebra::{Matrix3, Matrix6, Vector3};
use numpy::ndarray::{Array1, Array2, Array3};
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{exact, fixed, quats_to_numpy, rows, square, values, vectors};
use crate::errors::invalid_input;
use crate::interruptible;

/// Attitude (n, 4) at the time stamps `t` from `q0` and the body rates held over each interval.
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

fn to_dict<'py>(py: Python<'py>, run: FilterRun) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let n = run.t.len();
    let mat6 =
        |m: &[Matrix6<f64>]| Array3::from_shape_fn((m.len(), 6, 6), |(k, i, j)| m[k][(i, j)]);
    d.set_item("t", Array1::from(run.t).into_pyarray(py))?;
    d.set_item("quaternion", quats_to_numpy(py, &run.quaternion))?;
    d.set_item(
        "drift",
        Array2::from_shape_fn((n, 3), |(k, i)| run.drift[k][i]).into_pyarray(py),
    )?;
    d.set_item("covariance", mat6(&run.covariance).into_pyarray(py))?;
    d.set_item(
        "true_covariance",
        mat6(&run.true_covariance).into_pyarray(py),
    )?;
    d.set_item(
        "misalignment",
        Array2::from_shape_fn((n, 3), |(k, i)| run.misalignment[k][i]).into_pyarray(py),
    )?;
    d.set_item(
        "misalignment_covariance",
        Array3::from_shape_fn((n, 3, 3), |(k, i, j)| {
            run.misalignment_covariance[k][(i, j)]
        })
        .into_pyarray(py),
    )?;
    d.set_item("n_float", Array1::from(run.n_float).into_pyarray(py))?;
    d.set_item("n_fixed", Array1::from(run.n_fixed).into_pyarray(py))?;
    let fixes: Vec<_> = run
        .fixes
        .into_iter()
        .map(|f| (f.t, f.accepted, f.ratio, f.success_rate, f.values))
        .collect();
    d.set_item("fixes", fixes)?;
    let slips: Vec<_> = run
        .slips
        .into_iter()
        .map(|s| (s.t, s.track, s.nis))
        .collect();
    d.set_item("slips", slips)?;
    let nis: Vec<_> = run.nis.into_iter().map(|s| (s.t, s.nis, s.dof)).collect();
    d.set_item("nis", nis)?;
    Ok(d)
}

/// Runs the filter; returns a dict (see `gnssatt.gyro_gnss.gyro_gnss_filter`).
#[pyfunction]
#[pyo3(signature = (
    gyro_t, gyro_rates, q0, drift0, p0, arw, rrw, baselines, phase_sigma, fix_enabled,
    ratio_threshold, min_success_rate, slip_threshold, known_ambiguities, sensitivity, misalignment_sigma,
    output_every,
    fix_t, fix_q, fix_cov, epoch_t, phase_epoch, phase_track, phase_los, phase_wavelength, phase
))]
#[allow(clippy::too_many_arguments)]
fn gyro_gnss_filter<'py>(
    py: Python<'py>,
    gyro_t: PyReadonlyArray1<'_, f64>,
    gyro_rates: PyReadonlyArray2<'_, f64>,
    q0: PyReadonlyArray1<'_, f64>,
    drift0: PyReadonlyArray1<'_, f64>,
    p0: PyReadonlyArray2<'_, f64>,
    arw: f64,
    rrw: f64,
    baselines: PyReadonlyArray2<'_, f64>,
    phase_sigma: f64,
    fix_enabled: bool,
    ratio_threshold: f64,
    min_success_rate: f64,
    slip_threshold: f64,
    known_ambiguities: bool,
    sensitivity: Option<(f64, f64)>,
    misalignment_sigma: Option<f64>,
    output_every: usize,
    fix_t: PyReadonlyArray1<'_, f64>,
    fix_q: PyReadonlyArray2<'_, f64>,
    fix_cov: PyReadonlyArray3<'_, f64>,
    epoch_t: PyReadonlyArray1<'_, f64>,
    phase_epoch: PyReadonlyArray1<'_, i64>,
    phase_track: PyReadonlyArray1<'_, i64>,
    phase_los: PyReadonlyArray2<'_, f64>,
    phase_wavelength: PyReadonlyArray1<'_, f64>,
    phase: PyReadonlyArray2<'_, f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let gyro_t = values(py, "gyro_t", &gyro_t)?;
    let gyro_rates = vectors(py, "gyro_rates", &gyro_rates)?;
    let drift0 = fixed::<3>(py, "drift0", &drift0)?;
    let p0 = square::<6>(py, "p0", &p0)?;
    let baselines = vectors(py, "baselines", &baselines)?;
    let settings = Settings {
        noise: GyroNoise { arw, rrw },
        phase_sigma,
        fix: FixSettings {
            enabled: fix_enabled,
            ratio_threshold,
            min_success_rate,
        },
        slip_threshold,
        known_ambiguities,
        sensitivity: sensitivity.map(|(misalignment_sigma, baseline_sigma)| Sensitivity {
            misalignment_sigma,
            baseline_sigma,
        }),
        misalignment_sigma,
        output_every,
        baselines,
    };
    let initial = Initial {
        quaternion: fixed::<4>(py, "q0", &q0)?,
        drift: Vector3::new(drift0[0], drift0[1], drift0[2]),
        covariance: p0,
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
        run(&settings, &initial, &gyro_t, &gyro_rates, &fixes, &epochs)
    })?;
    to_dict(py, result)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(gyro_propagate, m)?)?;
    m.add_function(wrap_pyfunction!(gyro_gnss_filter, m)?)?;
    Ok(())
}
