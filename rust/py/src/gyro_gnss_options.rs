//! The gyro + GNSS filter's settings as one typed, frozen, keyword-only object
//! (`gnssatt._core.GyroGnssOptions`), so that `gyro_gnss_filter` takes named arrays and this object instead
//! of a long positional list. Values are checked by the core when the filter starts (`check_settings`,
//! which knows whether phases and fixes are present); here only their types and the baselines' shape.

use gnssatt_core::gyro_gnss::{FixSettings, GyroNoise, Sensitivity, Settings};
use gnssatt_core::lambda::gate::Gate;
use numpy::PyReadonlyArray2;
use pyo3::prelude::*;

use crate::convert::vectors;
use crate::guard::guard;

/// Settings of the gyro + GNSS filter (see `gnssatt.attitude.gyro_gnss.gyro_gnss_filter` for the meaning of each).
///
/// `arw` rad/s/sqrt(Hz), `rrw` rad/s^2/sqrt(Hz), `baselines` (m, 3) body frame m, `phase_sigma` cycles,
/// `slip_threshold` the chi-square NIS threshold (inf disables), `sensitivity`
/// `(misalignment_sigma_rad, baseline_sigma_m)`, `misalignment_sigma` rad, `max_failure_rate` the
/// fixed-failure-rate test below the success-rate gate (0 off, at most 0.1), as the observation engine's.
#[pyclass(frozen, module = "gnssatt._core")]
pub struct GyroGnssOptions {
    pub inner: Settings,
}

#[guard]
#[pymethods]
impl GyroGnssOptions {
    #[new]
    #[pyo3(signature = (
        *, arw, rrw, baselines, phase_sigma, fix_enabled, ratio_threshold, min_success_rate, slip_threshold,
        known_ambiguities, output_every, sensitivity = None, misalignment_sigma = None,
        max_failure_rate = 0.0
    ))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        arw: f64,
        rrw: f64,
        baselines: PyReadonlyArray2<'_, f64>,
        phase_sigma: f64,
        fix_enabled: bool,
        ratio_threshold: f64,
        min_success_rate: f64,
        slip_threshold: f64,
        known_ambiguities: bool,
        output_every: usize,
        sensitivity: Option<(f64, f64)>,
        misalignment_sigma: Option<f64>,
        max_failure_rate: f64,
    ) -> PyResult<GyroGnssOptions> {
        Ok(GyroGnssOptions {
            inner: Settings {
                noise: GyroNoise { arw, rrw },
                baselines: vectors(py, "baselines", &baselines)?,
                phase_sigma,
                fix: FixSettings {
                    enabled: fix_enabled,
                    gate: Gate {
                        min_success_rate,
                        ratio_threshold,
                        max_failure_rate,
                    },
                },
                slip_threshold,
                known_ambiguities,
                sensitivity: sensitivity.map(|(misalignment_sigma, baseline_sigma)| Sensitivity {
                    misalignment_sigma,
                    baseline_sigma,
                }),
                misalignment_sigma,
                output_every,
            },
        })
    }

    fn __repr__(&self) -> String {
        format!("GyroGnssOptions({:?})", self.inner)
    }
}
