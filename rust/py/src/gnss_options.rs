//! The observation engine's options as one typed, frozen object (`gnssatt._core.GnssOptions`), checked when
//! it is made: `gnss_run` and `GnssEngine` take it instead of repeating a dozen keyword arguments. Every
//! option left `None` takes the engine's default (`EngineOptions::default`, the one place the defaults
//! live); errors name the CLI option (`--min-success-rate`, ...).

use gnssatt_core::gnss::options::{EngineOptions, Method, Motion};
use gnssatt_core::gnss::rtk::filter::Dynamics;
use gnssatt_core::gnss::signal::System;
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::convert::{fixed, rows};
use crate::errors::{invalid_input, IntoPyResult};
use crate::guard::guard;

/// Options of the observation engine (see `gnssatt.gnss.attitude.attitude_from_rinex` for the meaning of each).
#[pyclass(frozen, module = "gnssatt._core")]
pub struct GnssOptions {
    inner: EngineOptions,
}

#[guard]
#[pymethods]
impl GnssOptions {
    #[new]
    #[pyo3(signature = (
        *, systems = None, frequencies = None, elevation_mask_deg = None, base_position_m = None,
        motion = None, method = None, continuity = None, min_success_rate = None, ratio_threshold = None,
        max_failure_rate = None, body_baselines_m = None, step_deg = None, window_deg = None,
        baseline_lengths_m = None, filter = None, rigid = None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn new<'py>(
        py: Python<'py>,
        systems: Option<String>,
        frequencies: Option<usize>,
        elevation_mask_deg: Option<f64>,
        base_position_m: Option<PyReadonlyArray1<'py, f64>>,
        motion: Option<String>,
        method: Option<String>,
        continuity: Option<bool>,
        min_success_rate: Option<f64>,
        ratio_threshold: Option<f64>,
        max_failure_rate: Option<f64>,
        body_baselines_m: Option<PyReadonlyArray2<'py, f64>>,
        step_deg: Option<f64>,
        window_deg: Option<f64>,
        baseline_lengths_m: Option<Vec<f64>>,
        filter: Option<String>,
        rigid: Option<bool>,
    ) -> PyResult<GnssOptions> {
        let mut o = EngineOptions::default();
        if let Some(s) = systems {
            let mut systems = Vec::new();
            for c in s.chars() {
                match System::from_letter(c) {
                    Some(sys) if !systems.contains(&sys) => systems.push(sys),
                    Some(_) => {}
                    None => {
                        return Err(invalid_input(
                            py,
                            format!("expected systems as letters among GRECJ, got {s:?}"),
                        ))
                    }
                }
            }
            o.systems = systems;
        }
        if let Some(f) = frequencies {
            o.frequencies = f;
        }
        if let Some(m) = elevation_mask_deg {
            o.elevation_mask_rad = m.to_radians();
        }
        if let Some(p) = base_position_m {
            o.base_position_m = Some(fixed::<3>(py, "base_position_m", &p)?);
        }
        if let Some(m) = motion {
            o.motion = match m.as_str() {
                "static" => Motion::Static,
                "moving" => Motion::Moving,
                _ => {
                    return Err(invalid_input(
                        py,
                        format!("expected motion 'static' or 'moving', got {m:?}"),
                    ))
                }
            };
        }
        if let Some(m) = method {
            o.method = match m.as_str() {
                "auto" => Method::Auto,
                "ml" => Method::Ml,
                "lambda" => Method::Lambda,
                _ => {
                    return Err(invalid_input(
                        py,
                        format!("expected method 'auto', 'ml' or 'lambda', got {m:?}"),
                    ))
                }
            };
        }
        if let Some(c) = continuity {
            o.continuity = c;
        }
        if let Some(f) = filter {
            o.filter = Some(match f.as_str() {
                "static" => Dynamics::Static,
                "kinematic" => Dynamics::KINEMATIC,
                "velocity" => Dynamics::VELOCITY,
                _ => {
                    return Err(invalid_input(
                        py,
                        format!(
                            "--filter: expected 'static', 'kinematic' or 'velocity', got {f:?}"
                        ),
                    ))
                }
            });
        }
        if let Some(p) = min_success_rate {
            o.min_success_rate = p;
        }
        if let Some(r) = ratio_threshold {
            o.ratio_threshold = r;
        }
        if let Some(p) = max_failure_rate {
            o.max_failure_rate = p;
        }
        if let Some(b) = body_baselines_m {
            o.body_baselines_m = rows::<3>(py, "body_baselines_m", &b, None, false)?;
        }
        if let Some(l) = baseline_lengths_m {
            o.baseline_lengths_m = l;
        }
        if let Some(r) = rigid {
            o.rigid = r;
        }
        o.ml_step_rad = step_deg.map(f64::to_radians);
        o.ml_window_rad = window_deg.map(f64::to_radians);
        o.validate().into_py_result(py)?;
        Ok(GnssOptions { inner: o })
    }

    fn __repr__(&self) -> String {
        format!("GnssOptions({:?})", self.inner)
    }
}

/// The engine options of `options` (the defaults for `None`).
pub fn engine_options(options: Option<&GnssOptions>) -> EngineOptions {
    options.map_or_else(EngineOptions::default, |o| o.inner.clone())
}
