//! Bindings of the observation engine (`gnssatt_core::gnss`): `gnss_run` processes a whole session in one
//! GIL-released call, `GnssEngine.process` the same engine a block of epochs at a time (state carried
//! between calls). Inputs are an [`ObservationArrays`] (the arrays of
//! `gnssatt.gnss.session_input.SessionInput`, converted and checked once) and a [`Navigation`]
//! (`gnss_nav_input.rs`: the navigation records converted once); results are a frozen
//! [`GnssSession`] of per-epoch numpy arrays (`gnss_session.rs`). Options come as one checked
//! [`GnssOptions`] (`gnss_options.rs`; `None`: the engine's defaults).

use gnssatt_core::gnss::observations::{Observations, ReceiverObservations, MAX_OBSERVATION_CELLS};
use gnssatt_core::gnss::options::EngineOptions;
use gnssatt_core::gnss::signal::{SatId, System, MAX_FREQUENCIES};
use gnssatt_core::gnss::solution::SessionSolution;
use gnssatt_core::gnss::{session, stream};
use gnssatt_core::Error;
use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray4};
use pyo3::prelude::*;

use crate::convert::{exact, shape_error};
use crate::errors::{invalid_input, IntoPyResult};
use crate::gnss_nav_input::Navigation;
use crate::gnss_options::{engine_options, GnssOptions};
use crate::gnss_session::{session_object, GnssSession};
use crate::guard::guard;
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
) -> PyResult<Observations> {
    let (ne, ns) = (a.time_gpst_ns.as_array().len(), sats.len());
    let nr = a.code_m.as_array().shape()[0];
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

/// Observations of every receiver on common epochs (`gnssatt._core.ObservationArrays`), converted into the
/// core's `Observations` and checked once, when made: the arrays of
/// `gnssatt.gnss.session_input.SessionInput` (`time_gpst_ns` (n_ep,) GPST ns; `sats` (n_sat,) ids;
/// `glonass_channel` (n_sat,), 99 where unknown; `code_m`, `phase_cycles`, `doppler_hz`, `snr_dbhz`, `lli`
/// (n_rx, n_ep, n_sat, 3); `approx_position_m` (n_rx, 3) ECEF m, NaN rows where unknown).
#[pyclass(frozen, module = "gnssatt._core")]
pub struct ObservationArrays {
    obs: Observations,
}

#[guard]
#[pymethods]
impl ObservationArrays {
    #[new]
    #[pyo3(signature = (
        *, time_gpst_ns, sats, glonass_channel, code_m, phase_cycles, doppler_hz, snr_dbhz, lli,
        approx_position_m
    ))]
    #[allow(clippy::too_many_arguments)]
    fn new<'py>(
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
    ) -> PyResult<ObservationArrays> {
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
        let obs = observations(py, &arrays, ids, ch)?;
        Ok(ObservationArrays { obs })
    }

    /// Number of receivers (the first is the base).
    #[getter]
    fn receivers(&self) -> usize {
        self.obs.receivers.len()
    }

    /// Number of epochs.
    #[getter]
    fn epochs(&self) -> usize {
        self.obs.time_gpst_ns.len()
    }

    /// The satellite ids, in the order of the arrays.
    #[getter]
    fn sats(&self) -> Vec<String> {
        self.obs.sats.iter().map(|s| s.to_string()).collect()
    }

    fn __repr__(&self) -> String {
        // the ids as Python shows a list of str
        let sats: Vec<String> = self.obs.sats.iter().map(|s| format!("'{s}'")).collect();
        format!(
            "ObservationArrays(receivers={}, epochs={}, sats=[{}])",
            self.obs.receivers.len(),
            self.obs.time_gpst_ns.len(),
            sats.join(", ")
        )
    }
}

/// Processes a whole session in one call (see `gnssatt.gnss.attitude.attitude_from_rinex` for the meaning of
/// every option); returns a [`GnssSession`].
#[guard]
#[pyfunction]
#[pyo3(signature = (observations, navigation, options = None))]
fn gnss_run<'py>(
    py: Python<'py>,
    observations: Bound<'py, ObservationArrays>,
    navigation: Bound<'py, Navigation>,
    options: Option<PyRef<'py, GnssOptions>>,
) -> PyResult<GnssSession> {
    let obs = &observations.get().obs;
    let n_rover = obs.receivers.len() - 1;
    let opts = engine_options(options.as_deref());
    let nav = &navigation.get().nav;
    let attitude = !opts.body_baselines_m.is_empty();
    let sol: SessionSolution = interruptible::run(py, || session::run(obs, nav, &opts))?;
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

#[guard]
#[pymethods]
impl GnssEngine {
    #[new]
    #[pyo3(signature = (
        sats, glonass_channel, n_receivers, navigation, options = None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn new<'py>(
        py: Python<'py>,
        sats: Vec<String>,
        glonass_channel: PyReadonlyArray1<'py, i64>,
        n_receivers: usize,
        navigation: Bound<'py, Navigation>,
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
        let nav = &navigation.get().nav;
        let attitude = !opts.body_baselines_m.is_empty();
        let (s, c) = (ids.clone(), ch.clone());
        let engine = interruptible::run(py, move || {
            stream::Engine::new(nav, opts, s, c, n_receivers)
        })?;
        Ok(GnssEngine {
            engine,
            sats: ids,
            glonass_channel: ch,
            n_receivers,
            attitude,
        })
    }

    /// Processes the next epochs (an [`ObservationArrays`] of the satellites, channels and receivers of the
    /// constructor, epochs after those already processed); returns their [`GnssSession`]
    /// (`double_differences` None, `warnings` those of the whole stream so far).
    fn process<'py>(
        &mut self,
        py: Python<'py>,
        observations: Bound<'py, ObservationArrays>,
    ) -> PyResult<GnssSession> {
        let obs = &observations.get().obs;
        if obs.sats != self.sats || obs.glonass_channel != self.glonass_channel {
            return Err(invalid_input(
                py,
                format!(
                    "expected observations of the constructor's satellites and GLONASS channels ({} \
                     satellites), got {} satellites or other channels",
                    self.sats.len(),
                    obs.sats.len()
                ),
            ));
        }
        if obs.receivers.len() != self.n_receivers {
            return Err(invalid_input(
                py,
                format!(
                    "expected observations of n_receivers = {} receivers, got {}",
                    self.n_receivers,
                    obs.receivers.len()
                ),
            ));
        }
        let engine = &mut self.engine;
        let epochs = interruptible::run(py, move || engine.process(obs))?;
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
    m.add_class::<Navigation>()?;
    m.add_class::<ObservationArrays>()?;
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
