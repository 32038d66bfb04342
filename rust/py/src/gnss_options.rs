//! The observation engine's options as one typed, frozen object (`gnssatt._core.GnssOptions`), checked when
//! it is made: `gnss_run` and `GnssEngine` take it instead of repeating a dozen keyword arguments. Every
//! option left `None` takes the engine's default (`EngineOptions::default`, the one place the defaults
//! live); errors name the CLI option (`--min-success-rate`, ...). The names `motion`, `method` and `filter`
//! accept are the tables below, exported as `GNSS_MOTIONS`, `GNSS_METHODS` and `GNSS_FILTERS` so that the
//! CLI's choices are these, not a copy.

use gnssatt_core::gnss::options::{EngineOptions, Method, Motion};
use gnssatt_core::gnss::rtk::filter::Dynamics;
use gnssatt_core::gnss::signal::System;
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::convert::{fixed, rows};
use crate::errors::{invalid_input, IntoPyResult};
use crate::guard::guard;

/// `motion`: each name and what it selects.
const MOTIONS: [(&str, Motion); 2] = [("static", Motion::Static), ("moving", Motion::Moving)];
/// `method`: each name and what it selects.
const METHODS: [(&str, Method); 3] = [
    ("auto", Method::Auto),
    ("ml", Method::Ml),
    ("lambda", Method::Lambda),
];
/// `filter`: each name and the process model it selects.
const FILTERS: [(&str, Dynamics); 3] = [
    ("static", Dynamics::Static),
    ("kinematic", Dynamics::KINEMATIC),
    ("velocity", Dynamics::VELOCITY),
];

/// The value `table` names `got`, or an error "`expected` 'a', 'b' or 'c', got ...".
fn named<T: Copy>(py: Python<'_>, table: &[(&str, T)], expected: &str, got: &str) -> PyResult<T> {
    if let Some((_, value)) = table.iter().find(|(name, _)| *name == got) {
        return Ok(*value);
    }
    let quoted: Vec<String> = table.iter().map(|(name, _)| format!("'{name}'")).collect();
    let (last, rest) = quoted
        .split_last()
        .expect("a table names at least one value");
    let names = if rest.is_empty() {
        last.clone()
    } else {
        format!("{} or {last}", rest.join(", "))
    };
    Err(invalid_input(
        py,
        format!("{expected} {names}, got {got:?}"),
    ))
}

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
            o.motion = named(py, &MOTIONS, "expected motion", &m)?;
        }
        if let Some(m) = method {
            o.method = named(py, &METHODS, "expected method", &m)?;
        }
        if let Some(c) = continuity {
            o.continuity = c;
        }
        if let Some(f) = filter {
            o.filter = Some(named(py, &FILTERS, "--filter: expected", &f)?);
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

/// The names of `table`, as a tuple.
fn names<'py, T>(py: Python<'py>, table: &[(&str, T)]) -> PyResult<Bound<'py, PyTuple>> {
    PyTuple::new(py, table.iter().map(|(name, _)| *name))
}

/// `GNSS_MOTIONS`, `GNSS_METHODS`, `GNSS_FILTERS`: the names `GnssOptions` accepts, in the order of its
/// messages, for the CLI's choices and the Python API's checks.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("GNSS_MOTIONS", names(py, &MOTIONS)?)?;
    m.add("GNSS_METHODS", names(py, &METHODS)?)?;
    m.add("GNSS_FILTERS", names(py, &FILTERS)?)?;
    Ok(())
}
