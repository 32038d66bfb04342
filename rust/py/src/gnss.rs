//! Bindings of the observation engine (`gnssatt_core::gnss`): `gnss_run` processes a whole session in one
//! GIL-released call, `GnssEngine.process` the same engine a block of epochs at a time (state carried
//! between calls). Inputs are the arrays of `gnssatt.rinex.session_input.SessionInput` and `NavInput`
//! (navigation dictionaries converted by `gnss_nav::nav_from_py`); results are a frozen [`GnssSession`]
//! of per-epoch numpy arrays. Options come as one checked [`GnssOptions`] (`gnss_options.rs`; `None`: the
//! engine's defaults).

use std::panic::{catch_unwind, AssertUnwindSafe};

use gnssatt_core::gnss::navdata::NavData;
use gnssatt_core::gnss::observations::{Observations, ReceiverObservations, MAX_OBSERVATION_CELLS};
use gnssatt_core::gnss::options::{EngineOptions, Method};
use gnssatt_core::gnss::signal::{SatId, System, MAX_FREQUENCIES};
use gnssatt_core::gnss::solution::{EpochSolution, SessionSolution, N_SYSTEMS};
use gnssatt_core::gnss::{session, stream};
use gnssatt_core::Error;
use numpy::ndarray::{Array1, Array2, Array3, Array4};
use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray4};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{exact, shape_error};
use crate::errors::{internal_error, invalid_input, IntoPyResult};
use crate::gnss_nav::nav_from_py;
use crate::gnss_options::{engine_options, GnssOptions};
use crate::interruptible;

/// `glonass_channel` value of a satellite whose channel is unknown (or that is not GLONASS).
const NO_CHANNEL: i64 = 99;

/// The arrays of one block of epochs of every receiver (`SessionInput` less the satellite list).
struct EpochArrays<'py> {
    time_gpst_ns: PyReadonlyArray1<'py, i64>,
    code_m: PyReadonlyArray4<'py, f64>,
    phase_cycles: PyReadonlyArray4<'py, f64>,
    doppler_hz: PyReadonlyArray4<'py, f64>,
    snr_dbhz: PyReadonlyArray4<'py, f64>,
    lli: PyReadonlyArray4<'py, u8>,
    approx_position_m: PyReadonlyArray2<'py, f64>,
}

fn sat_ids(py: Python<'_>, sats: &[String]) -> PyResult<Vec<SatId>> {
    sats.iter()
        .enumerate()
        .map(|(i, s)| {
            let mut chars = s.chars();
            let system = chars.next().and_then(System::from_letter);
            let prn = chars.as_str().parse::<u8>().ok().filter(|&p| p > 0);
            match (system, prn) {
                (Some(system), Some(prn)) => Ok(SatId { system, prn }),
                _ => Err(invalid_input(
                    py,
                    format!(
                        "expected sats[{i}] as a system letter among GRECJ and a number 1..255 such \
                         as 'G03', got {s:?}"
                    ),
                )),
            }
        })
        .collect()
}

fn channels(
    py: Python<'_>,
    sats: &[SatId],
    glonass_channel: &PyReadonlyArray1<'_, i64>,
) -> PyResult<Vec<Option<i8>>> {
    let ch = exact(py, "glonass_channel", glonass_channel, &[sats.len()])?;
    sats.iter()
        .zip(ch)
        .enumerate()
        .map(|(i, (sat, k))| match (sat.system, k) {
            (System::Glonass, -7..=6) => Ok(i8::try_from(k).ok()),
            (System::Glonass, NO_CHANNEL) => Ok(None),
            (System::Glonass, _) => Err(invalid_input(
                py,
                format!(
                    "expected glonass_channel[{i}] ({sat}) in -7..6, or {NO_CHANNEL} where unknown, \
                     got {k}"
                ),
            )),
            // Other systems are CDMA: a channel given for them is ignored.
            _ => Ok(None),
        })
        .collect()
}

/// A (n_rx, n_ep, n_sat, 3) array of exactly `shape`, one row-major vector per receiver.
fn per_receiver<T: numpy::Element + Copy>(
    py: Python<'_>,
    name: &str,
    a: &PyReadonlyArray4<'_, T>,
    shape: &[usize; 4],
) -> PyResult<Vec<Vec<T>>> {
    let v = a.as_array();
    if v.shape() != shape {
        let expected = format!("({}, {}, {}, {})", shape[0], shape[1], shape[2], shape[3]);
        return Err(shape_error(py, name, &expected, v.shape()));
    }
    Ok(v.outer_iter()
        .map(|r| r.iter().copied().collect())
        .collect())
}

fn observations(
    py: Python<'_>,
    a: &EpochArrays<'_>,
    sats: Vec<SatId>,
    glonass_channel: Vec<Option<i8>>,
    n_receivers: Option<usize>,
) -> PyResult<Observations> {
    let (ne, ns) = (a.time_gpst_ns.as_array().len(), sats.len());
    let nr = n_receivers.unwrap_or(a.code_m.as_array().shape()[0]);
    // The documented limit before any copy: the arrays are already in memory once, in numpy.
    let cells = ne.saturating_mul(ns).saturating_mul(nr);
    if cells > MAX_OBSERVATION_CELLS {
        return Err(Error::too_large(
            "observations",
            cells as f64,
            MAX_OBSERVATION_CELLS as f64,
            "epochs x satellites x receivers",
        ))
        .into_py_result(py);
    }
    let shape = [nr, ne, ns, MAX_FREQUENCIES];
    let mut code = per_receiver(py, "code_m", &a.code_m, &shape)?;
    let mut phase = per_receiver(py, "phase_cycles", &a.phase_cycles, &shape)?;
    let mut doppler = per_receiver(py, "doppler_hz", &a.doppler_hz, &shape)?;
    let mut snr = per_receiver(py, "snr_dbhz", &a.snr_dbhz, &shape)?;
    let mut lli = per_receiver(py, "lli", &a.lli, &shape)?;
    let approx = exact(py, "approx_position_m", &a.approx_position_m, &[nr, 3])?;
    let mut receivers = Vec::with_capacity(nr);
    for r in (0..nr).rev() {
        let p = [approx[3 * r], approx[3 * r + 1], approx[3 * r + 2]];
        // NaN rows (the reader's "none") and the zeros of a header without a position mean "unknown".
        let approx_position_m = if p.iter().all(|x| x.is_finite()) && p != [0.0; 3] {
            Some(p)
        } else if p.iter().all(|x| x.is_nan()) || p == [0.0; 3] {
            None
        } else {
            return Err(invalid_input(
                py,
                format!(
                    "expected approx_position_m[{r}] finite, or all NaN where unknown, got {p:?}"
                ),
            ));
        };
        // popped from the back: each receiver's arrays move without a second copy
        receivers.push(ReceiverObservations {
            code_m: code.pop().unwrap_or_default(),
            phase_cycles: phase.pop().unwrap_or_default(),
            doppler_hz: doppler.pop().unwrap_or_default(),
            snr_dbhz: snr.pop().unwrap_or_default(),
            lli: lli.pop().unwrap_or_default(),
            approx_position_m,
        });
    }
    receivers.reverse();
    let time_gpst_ns = a.time_gpst_ns.as_array().to_vec();
    let obs = Observations {
        time_gpst_ns,
        sats,
        glonass_channel,
        receivers,
    };
    obs.validate().into_py_result(py)?;
    Ok(obs)
}

/// Runs `work` (a core call) without the GIL, interruptibly; a panic of the core (a defect) becomes
/// `gnssatt.errors.InternalError` here, since class methods are not reached by the module's panic guard.
fn guarded_run<T: Send>(
    py: Python<'_>,
    what: &str,
    work: impl FnOnce() -> gnssatt_core::Result<T> + Send,
) -> PyResult<T> {
    let caught = interruptible::run(py, || Ok(catch_unwind(AssertUnwindSafe(work))))?;
    match caught {
        Ok(result) => result.into_py_result(py),
        Err(_) => Err(internal_error(
            py,
            format!("{what}: Rust core defect (panic); please report it with its input"),
        )),
    }
}

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

fn session_object(
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

/// Processes a whole session in one call (see `gnssatt.rinex.attitude_from_rinex` for the meaning of
/// every option); returns a [`GnssSession`].
#[pyfunction]
#[pyo3(signature = (
    time_gpst_ns, sats, glonass_channel, code_m, phase_cycles, doppler_hz, snr_dbhz, lli,
    approx_position_m, kepler, glonass, klobuchar, leap_seconds, options = None
))]
#[allow(clippy::too_many_arguments)]
fn gnss_run<'py>(
    py: Python<'py>,
    time_gpst_ns: PyReadonlyArray1<'py, i64>,
    sats: Vec<String>,
    glonass_channel: PyReadonlyArray1<'py, i64>,
    code_m: PyReadonlyArray4<'py, f64>,
    phase_cycles: PyReadonlyArray4<'py, f64>,
    doppler_hz: PyReadonlyArray4<'py, f64>,
    snr_dbhz: PyReadonlyArray4<'py, f64>,
    lli: PyReadonlyArray4<'py, u8>,
    approx_position_m: PyReadonlyArray2<'py, f64>,
    kepler: Bound<'py, PyDict>,
    glonass: Bound<'py, PyDict>,
    klobuchar: Option<PyReadonlyArray1<'py, f64>>,
    leap_seconds: Option<i32>,
    options: Option<PyRef<'py, GnssOptions>>,
) -> PyResult<GnssSession> {
    let ids = sat_ids(py, &sats)?;
    let ch = channels(py, &ids, &glonass_channel)?;
    let arrays = EpochArrays {
        time_gpst_ns,
        code_m,
        phase_cycles,
        doppler_hz,
        snr_dbhz,
        lli,
        approx_position_m,
    };
    let obs = observations(py, &arrays, ids, ch, None)?;
    let n_rover = obs.receivers.len() - 1;
    let opts = engine_options(options.as_deref());
    let nav: NavData = nav_from_py(&kepler, &glonass, klobuchar, leap_seconds)?;
    let attitude = !opts.body_baselines_m.is_empty();
    let sol: SessionSolution = guarded_run(py, "gnss_run", || session::run(&obs, &nav, &opts))?;
    Ok(session_object(
        py,
        &sol.epochs,
        n_rover,
        attitude,
        Some(&sol.double_differences),
        sol.warnings,
        sol.code_sigma_scale,
    ))
}

/// The engine fed a block of epochs at a time, for streaming use: ambiguities held, slip detection and
/// the previous solution carried between calls to `process`.
#[pyclass(module = "gnssatt._core")]
pub struct GnssEngine {
    engine: stream::Engine,
    sats: Vec<SatId>,
    glonass_channel: Vec<Option<i8>>,
    n_receivers: usize,
    attitude: bool,
}

#[pymethods]
impl GnssEngine {
    #[new]
    #[pyo3(signature = (
        sats, glonass_channel, n_receivers, kepler, glonass, klobuchar, leap_seconds, options = None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn new<'py>(
        py: Python<'py>,
        sats: Vec<String>,
        glonass_channel: PyReadonlyArray1<'py, i64>,
        n_receivers: usize,
        kepler: Bound<'py, PyDict>,
        glonass: Bound<'py, PyDict>,
        klobuchar: Option<PyReadonlyArray1<'py, f64>>,
        leap_seconds: Option<i32>,
        options: Option<PyRef<'py, GnssOptions>>,
    ) -> PyResult<GnssEngine> {
        if n_receivers < 2 {
            return Err(invalid_input(
                py,
                format!("expected n_receivers >= 2, got {n_receivers}"),
            ));
        }
        let ids = sat_ids(py, &sats)?;
        let ch = channels(py, &ids, &glonass_channel)?;
        let opts = engine_options(options.as_deref());
        let nav = nav_from_py(&kepler, &glonass, klobuchar, leap_seconds)?;
        let attitude = !opts.body_baselines_m.is_empty();
        let (s, c) = (ids.clone(), ch.clone());
        let engine = guarded_run(py, "GnssEngine", move || {
            stream::Engine::new(&nav, opts, s, c, n_receivers)
        })?;
        Ok(GnssEngine {
            engine,
            sats: ids,
            glonass_channel: ch,
            n_receivers,
            attitude,
        })
    }

    /// Processes the next epochs (arrays as `gnss_run`'s, the satellites and receivers of the
    /// constructor, epochs after those already processed); returns their [`GnssSession`]
    /// (`double_differences` None, `warnings` those of the whole stream so far).
    #[allow(clippy::too_many_arguments)]
    fn process<'py>(
        &mut self,
        py: Python<'py>,
        time_gpst_ns: PyReadonlyArray1<'py, i64>,
        code_m: PyReadonlyArray4<'py, f64>,
        phase_cycles: PyReadonlyArray4<'py, f64>,
        doppler_hz: PyReadonlyArray4<'py, f64>,
        snr_dbhz: PyReadonlyArray4<'py, f64>,
        lli: PyReadonlyArray4<'py, u8>,
        approx_position_m: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<GnssSession> {
        let arrays = EpochArrays {
            time_gpst_ns,
            code_m,
            phase_cycles,
            doppler_hz,
            snr_dbhz,
            lli,
            approx_position_m,
        };
        let obs = observations(
            py,
            &arrays,
            self.sats.clone(),
            self.glonass_channel.clone(),
            Some(self.n_receivers),
        )?;
        let engine = &mut self.engine;
        let epochs = guarded_run(py, "GnssEngine.process", move || engine.process(&obs))?;
        Ok(session_object(
            py,
            &epochs,
            self.n_receivers - 1,
            self.attitude,
            None,
            self.engine.warnings().to_vec(),
            self.engine.code_sigma_scale(),
        ))
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(gnss_run, m)?)?;
    m.add_class::<GnssOptions>()?;
    m.add_class::<GnssSession>()?;
    m.add_class::<GnssEngine>()?;
    // The engine's defaults, read by the Python API and the CLI instead of restating them.
    let d = EngineOptions::default();
    m.add("GNSS_DEFAULT_MIN_SUCCESS_RATE", d.min_success_rate)?;
    m.add("GNSS_DEFAULT_RATIO_THRESHOLD", d.ratio_threshold)?;
    m.add("GNSS_DEFAULT_MAX_FAILURE_RATE", d.max_failure_rate)?;
    m.add(
        "GNSS_DEFAULT_ELEVATION_MASK_DEG",
        d.elevation_mask_rad.to_degrees(),
    )?;
    m.add("GNSS_MAX_FREQUENCIES", MAX_FREQUENCIES)?;
    Ok(())
}
