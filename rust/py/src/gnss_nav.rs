//! Evaluations of the broadcast ephemerides (at a time, or at transmission for a reception), of the
//! Klobuchar ionosphere (the simulator's) and of single-point positioning (test-facing), on navigation data
//! read by `gnss_nav_input`.

use gnssatt_core::gnss::atmosphere::klobuchar_delay_m;
use gnssatt_core::gnss::ephemeris::Ephemerides;
use gnssatt_core::gnss::geometry::satellite_geometry;
use gnssatt_core::gnss::observations::{Observations, ReceiverObservations};
use gnssatt_core::gnss::options::EngineOptions;
use gnssatt_core::gnss::signal::{System, MAX_FREQUENCIES};
use gnssatt_core::gnss::spp::{single_points, SppSolution};
use nalgebra::Vector3;
use numpy::ndarray::{Array1, Array2};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3,
};
use pyo3::prelude::*;

use gnssatt_core::Error;

use crate::convert::{exact, fixed, rows, values};
use crate::errors::{invalid_input, warn_all, IntoPyResult};
use crate::gnss_nav_input::{sat_from_str, Navigation};
use crate::guard::guard;
use crate::interruptible;
use crate::results::result_type;

/// Most evaluations (satellite, instant) of one call of [`gnss_transmit_states`] or
/// [`gnss_klobuchar_delay`]: a GLONASS state costs up to 30 Runge-Kutta steps, about 10 us, so the
/// limit is a minute or two of work.
pub const MAX_EVALUATIONS: usize = 10_000_000;
/// Largest receiver distance from the Earth's centre accepted, m (beyond the Moon).
pub const MAX_RECEIVER_RADIUS_M: f64 = 1e9;
/// Largest receiver clock offset accepted, s (receivers steer their clocks to within a millisecond).
pub const MAX_RECEIVER_CLOCK_S: f64 = 1.0;
/// Carrier frequencies accepted by [`gnss_klobuchar_delay`], Hz.
pub const FREQUENCY_RANGE_HZ: (f64, f64) = (1e6, 1e11);

/// The documented limit on `n` evaluations, checked before any copy.
fn evaluations(py: Python<'_>, n: usize) -> PyResult<()> {
    if n > MAX_EVALUATIONS {
        return Err(Error::too_large(
            "sats",
            n as f64,
            MAX_EVALUATIONS as f64,
            "evaluations",
        ))
        .into_py_result(py);
    }
    Ok(())
}

/// `name` (finite, checked by the caller) with every value in `[lo, hi]`.
fn within(py: Python<'_>, name: &str, v: &[f64], lo: f64, hi: f64, unit: &str) -> PyResult<()> {
    match v.iter().position(|x| !(lo..=hi).contains(x)) {
        Some(i) => Err(invalid_input(
            py,
            format!(
                "expected {name} in [{lo}, {hi}] {unit}, got {} at [{i}]",
                v[i]
            ),
        )),
        None => Ok(()),
    }
}

result_type! {
    /// Broadcast states of `gnss_satellite_states`, one row per evaluation: `position_m` (n, 3) ECEF m
    /// (frame of the instant), `clock_s` (n,) s (relativistic term included, no group delay) and `valid`
    /// (n,); NaN where not valid.
    SatelliteStates {
        position_m: Py<PyArray2<f64>>,
        clock_s: Py<PyArray1<f64>>,
        valid: Py<PyArray1<bool>>,
    }
}

/// Broadcast positions (n, 3) ECEF m (frame of the transmit instant), clocks (n,) s (relativistic term
/// included, no group delay) and validity (n,) of `sats[i]` at GPST `t_gpst_ns[i] + offset_s[i]`, as
/// [`SatelliteStates`]; NaN where not valid (no healthy record within its validity interval).
#[guard]
#[pyfunction]
#[pyo3(signature = (navigation, sats, t_gpst_ns, *, offset_s=None))]
fn gnss_satellite_states<'py>(
    py: Python<'py>,
    navigation: &Bound<'py, Navigation>,
    sats: Vec<String>,
    t_gpst_ns: PyReadonlyArray1<'py, i64>,
    offset_s: Option<PyReadonlyArray1<'py, f64>>,
) -> PyResult<SatelliteStates> {
    let nav = &navigation.get().nav;
    let n = sats.len();
    let ids = sats
        .iter()
        .map(|s| sat_from_str(py, "sats", s))
        .collect::<PyResult<Vec<_>>>()?;
    let t = exact(py, "t_gpst_ns", &t_gpst_ns, &[n])?;
    let off = match offset_s {
        Some(o) => exact(py, "offset_s", &o, &[n])?,
        None => vec![0.0; n],
    };
    let (states, skipped) = interruptible::run(py, || {
        let eph = Ephemerides::new(nav)?;
        let states = (0..n)
            .map(|i| eph.state(ids[i], t[i], off[i]))
            .collect::<Vec<_>>();
        Ok((states, eph.skip_warnings()))
    })?;
    warn_all(py, &skipped)?;
    let pos = Array2::from_shape_fn((n, 3), |(i, j)| {
        states[i].map_or(f64::NAN, |s| s.position_m[j])
    });
    let clk = Array1::from_shape_fn(n, |i| states[i].map_or(f64::NAN, |s| s.clock_s));
    let ok = Array1::from_shape_fn(n, |i| states[i].is_some());
    Ok(SatelliteStates {
        position_m: pos.into_pyarray(py).unbind(),
        clock_s: clk.into_pyarray(py).unbind(),
        valid: ok.into_pyarray(py).unbind(),
    })
}

result_type! {
    /// Single-point solutions of `gnss_single_point`, one row per epoch: `position_m` (n_ep, 3) ECEF m,
    /// `clock_s` (n_ep, 5) receiver clock per system G R E C J, s (NaN where not estimated), `satellites`
    /// (n_ep,) used, `residual_rms_m` (n_ep,) m, `pdop` (n_ep,) and `satellites_per_system` (n_ep, 5);
    /// NaN rows (and 0 satellites) where no solution.
    SinglePoints {
        position_m: Py<PyArray2<f64>>,
        clock_s: Py<PyArray2<f64>>,
        satellites: Py<PyArray1<i64>>,
        residual_rms_m: Py<PyArray1<f64>>,
        pdop: Py<PyArray1<f64>>,
        satellites_per_system: Py<PyArray2<i64>>,
    }
}

/// Single-point solutions of one receiver at every epoch (`gnssatt.position_from_rinex`; the core's
/// `single_points`: epochs independent, each started from `approx_position_m` or the Earth's centre,
/// in parallel): code `code_m` (n_ep, n_sat, 3) m, NaN where absent; `glonass_channel` (n_sat,), 99
/// where none. Returns [`SinglePoints`]; rows of epochs without a solution are NaN (and 0 satellites).
/// Navigation records the engine cannot use are skipped with a `GnssattWarning` naming them.
#[guard]
#[pyfunction]
#[pyo3(signature = (navigation, time_gpst_ns, sats, glonass_channel, code_m, *,
                    approx_position_m=None, systems="GRECJ", frequencies=1, elevation_mask_deg=10.0))]
#[allow(clippy::too_many_arguments)]
fn gnss_single_point<'py>(
    py: Python<'py>,
    navigation: &Bound<'py, Navigation>,
    time_gpst_ns: PyReadonlyArray1<'py, i64>,
    sats: Vec<String>,
    glonass_channel: PyReadonlyArray1<'py, i64>,
    code_m: PyReadonlyArray3<'py, f64>,
    approx_position_m: Option<PyReadonlyArray1<'py, f64>>,
    systems: &str,
    frequencies: usize,
    elevation_mask_deg: f64,
) -> PyResult<SinglePoints> {
    let nav = &navigation.get().nav;
    let ids = sats
        .iter()
        .map(|s| sat_from_str(py, "sats", s))
        .collect::<PyResult<Vec<_>>>()?;
    let ns = ids.len();
    let time = time_gpst_ns.as_array().to_vec();
    let ne = time.len();
    let channel = exact(py, "glonass_channel", &glonass_channel, &[ns])?
        .into_iter()
        .map(|k| i8::try_from(k).ok().filter(|k| (-7..=6).contains(k)))
        .collect();
    let code = exact(py, "code_m", &code_m, &[ne, ns, MAX_FREQUENCIES])?;
    let approx = approx_position_m
        .map(|a| fixed::<3>(py, "approx_position_m", &a))
        .transpose()?;
    let mut opts = EngineOptions {
        frequencies,
        elevation_mask_rad: elevation_mask_deg.to_radians(),
        ..EngineOptions::default()
    };
    opts.systems = systems.chars().filter_map(System::from_letter).collect();
    let len = code.len();
    let receiver = ReceiverObservations {
        code_m: code,
        phase_cycles: vec![f64::NAN; len],
        doppler_hz: vec![f64::NAN; len],
        snr_dbhz: vec![f64::NAN; len],
        lli: vec![0; len],
        approx_position_m: approx,
    };
    let obs = Observations {
        time_gpst_ns: time,
        sats: ids,
        glonass_channel: channel,
        receivers: vec![receiver.clone(), receiver],
    };
    let (solutions, skipped) = interruptible::run(py, || {
        obs.validate()?;
        let eph = Ephemerides::new(nav)?;
        Ok((
            single_points(&obs, 0, &eph, nav, &opts)?,
            eph.skip_warnings(),
        ))
    })?;
    warn_all(py, &skipped)?;
    Ok(single_points_rows(py, &solutions, ne))
}

/// The `ne` rows of [`SinglePoints`], one per epoch of `solutions`: NaN (and 0 satellites) where an
/// epoch has no solution.
fn single_points_rows(
    py: Python<'_>,
    solutions: &[Option<SppSolution>],
    ne: usize,
) -> SinglePoints {
    let pos = Array2::from_shape_fn((ne, 3), |(i, j)| {
        solutions[i].as_ref().map_or(f64::NAN, |s| s.position_m[j])
    });
    let clk = Array2::from_shape_fn((ne, 5), |(i, j)| {
        solutions[i].as_ref().map_or(f64::NAN, |s| s.clock_s[j])
    });
    let n = Array1::from_shape_fn(ne, |i| {
        solutions[i].as_ref().map_or(0, |s| s.satellites as i64)
    });
    let rms = Array1::from_shape_fn(ne, |i| {
        solutions[i].as_ref().map_or(f64::NAN, |s| s.residual_rms_m)
    });
    let pdop = Array1::from_shape_fn(ne, |i| solutions[i].as_ref().map_or(f64::NAN, |s| s.pdop));
    let per_system = Array2::from_shape_fn((ne, 5), |(i, j)| {
        solutions[i]
            .as_ref()
            .map_or(0, |s| s.satellites_per_system[j] as i64)
    });
    SinglePoints {
        position_m: pos.into_pyarray(py).unbind(),
        clock_s: clk.into_pyarray(py).unbind(),
        satellites: n.into_pyarray(py).unbind(),
        residual_rms_m: rms.into_pyarray(py).unbind(),
        pdop: pdop.into_pyarray(py).unbind(),
        satellites_per_system: per_system.into_pyarray(py).unbind(),
    }
}

result_type! {
    /// Satellites as received, from `gnss_transmit_states`, one row per evaluation: `position_m` (n, 3) at
    /// transmission in the ECEF frame of reception, m; `clock_s` (n,) satellite clock at transmission, s;
    /// `elevation_rad`, `azimuth_rad` (n,) at the receiver (azimuth clockwise from North); `valid` (n,);
    /// NaN where not valid.
    TransmitStates {
        position_m: Py<PyArray2<f64>>,
        clock_s: Py<PyArray1<f64>>,
        elevation_rad: Py<PyArray1<f64>>,
        azimuth_rad: Py<PyArray1<f64>>,
        valid: Py<PyArray1<bool>>,
    }
}

/// Satellite `sats[i]` as received at GPST label `t_rx_gpst_ns[i]` by a receiver at `receiver_m[i]`
/// (ECEF, m) whose clock reads `receiver_clock_s[i]` ahead (true reception = label - clock): light time
/// iterated from the receiver, Earth rotation during it (the core's `satellite_geometry`). Returns, as
/// [`TransmitStates`], the transmit-time position in the ECEF frame of reception (n, 3) m, the satellite
/// clock at transmission (n,) s (relativistic term included, no group delay), elevation and azimuth
/// (clockwise from North) at the receiver's geodetic position (n,) rad, and validity (n,); NaN where not
/// valid (no usable record).
#[guard]
#[pyfunction]
#[pyo3(signature = (navigation, sats, t_rx_gpst_ns, receiver_m, receiver_clock_s))]
fn gnss_transmit_states<'py>(
    py: Python<'py>,
    navigation: &Bound<'py, Navigation>,
    sats: Vec<String>,
    t_rx_gpst_ns: PyReadonlyArray1<'py, i64>,
    receiver_m: PyReadonlyArray2<'py, f64>,
    receiver_clock_s: PyReadonlyArray1<'py, f64>,
) -> PyResult<TransmitStates> {
    let n = sats.len();
    evaluations(py, n)?;
    let nav = &navigation.get().nav;
    let ids = sats
        .iter()
        .map(|s| sat_from_str(py, "sats", s))
        .collect::<PyResult<Vec<_>>>()?;
    let t = exact(py, "t_rx_gpst_ns", &t_rx_gpst_ns, &[n])?;
    let rx = rows::<3>(py, "receiver_m", &receiver_m, Some(n), false)?;
    if let Some(i) = rx
        .iter()
        .position(|p| Vector3::from(*p).norm() > MAX_RECEIVER_RADIUS_M)
    {
        return Err(invalid_input(
            py,
            format!(
                "expected |receiver_m| <= {MAX_RECEIVER_RADIUS_M} m, got {:?} at [{i}]",
                rx[i]
            ),
        ));
    }
    let clock = values(py, "receiver_clock_s", &receiver_clock_s)?;
    if clock.len() != n {
        return Err(crate::convert::shape_error(
            py,
            "receiver_clock_s",
            &format!("({n},)"),
            &[clock.len()],
        ));
    }
    within(
        py,
        "receiver_clock_s",
        &clock,
        -MAX_RECEIVER_CLOCK_S,
        MAX_RECEIVER_CLOCK_S,
        "s",
    )?;
    let (geometry, skipped) = interruptible::run(py, || {
        let eph = Ephemerides::new(nav)?;
        let mut out = Vec::with_capacity(n);
        for i in 0..n {
            gnssatt_core::interrupt::check_every(i, "transmit states")?;
            out.push(satellite_geometry(
                &eph,
                ids[i],
                t[i],
                clock[i],
                &Vector3::from(rx[i]),
            ));
        }
        Ok((out, eph.skip_warnings()))
    })?;
    warn_all(py, &skipped)?;
    let pos = Array2::from_shape_fn((n, 3), |(i, j)| {
        geometry[i].map_or(f64::NAN, |g| g.position_m[j])
    });
    let per = |f: fn(&gnssatt_core::gnss::geometry::SatGeometry) -> f64| {
        Array1::from_shape_fn(n, |i| geometry[i].as_ref().map_or(f64::NAN, f))
    };
    let clk = per(|g| g.clock_s);
    let el = per(|g| g.elevation_rad);
    let az = per(|g| g.azimuth_rad);
    let ok = Array1::from_shape_fn(n, |i| geometry[i].is_some());
    Ok(TransmitStates {
        position_m: pos.into_pyarray(py).unbind(),
        clock_s: clk.into_pyarray(py).unbind(),
        elevation_rad: el.into_pyarray(py).unbind(),
        azimuth_rad: az.into_pyarray(py).unbind(),
        valid: ok.into_pyarray(py).unbind(),
    })
}

/// Slant ionospheric group delay of the broadcast Klobuchar model (IS-GPS-200 20.3.3.5.2.5, the core's
/// `klobuchar_delay_m`), m, positive (code delayed, phase advanced): `coefficients` (8,) alpha0..3,
/// beta0..3 as broadcast (s and semicircle powers); the receiver's geodetic latitude and longitude, rad;
/// per evaluation (n,) GPST `t_gpst_ns`, satellite azimuth and elevation (rad) and carrier frequency (Hz;
/// the L1 delay scaled by `(f_L1 / f)^2`). 0 for a satellite at or below the horizon.
#[guard]
#[pyfunction]
#[pyo3(signature = (coefficients, t_gpst_ns, lat_rad, lon_rad, azimuth_rad, elevation_rad,
                    frequency_hz))]
#[allow(clippy::too_many_arguments)]
fn gnss_klobuchar_delay<'py>(
    py: Python<'py>,
    coefficients: PyReadonlyArray1<'py, f64>,
    t_gpst_ns: PyReadonlyArray1<'py, i64>,
    lat_rad: f64,
    lon_rad: f64,
    azimuth_rad: PyReadonlyArray1<'py, f64>,
    elevation_rad: PyReadonlyArray1<'py, f64>,
    frequency_hz: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let n = t_gpst_ns.as_array().len();
    evaluations(py, n)?;
    let coeffs = fixed::<8>(py, "coefficients", &coefficients)?;
    let t = exact(py, "t_gpst_ns", &t_gpst_ns, &[n])?;
    let half_pi = std::f64::consts::FRAC_PI_2;
    let tau = std::f64::consts::TAU;
    within(py, "lat_rad", &[lat_rad], -half_pi, half_pi, "rad")?;
    within(py, "lon_rad", &[lon_rad], -tau, tau, "rad")?;
    let mut columns = Vec::with_capacity(3);
    for (name, a, (lo, hi)) in [
        ("azimuth_rad", &azimuth_rad, (-2.0 * tau, 2.0 * tau)),
        ("elevation_rad", &elevation_rad, (-half_pi, half_pi)),
        ("frequency_hz", &frequency_hz, FREQUENCY_RANGE_HZ),
    ] {
        let v = values(py, name, a)?;
        if v.len() != n {
            return Err(crate::convert::shape_error(
                py,
                name,
                &format!("({n},) like t_gpst_ns"),
                &[v.len()],
            ));
        }
        within(
            py,
            name,
            &v,
            lo,
            hi,
            if name == "frequency_hz" { "Hz" } else { "rad" },
        )?;
        columns.push(v);
    }
    let (az, el, f) = (&columns[0], &columns[1], &columns[2]);
    let delay = interruptible::run(py, || {
        Ok((0..n)
            .map(|i| klobuchar_delay_m(&coeffs, t[i], lat_rad, lon_rad, az[i], el[i], f[i]))
            .collect::<Vec<_>>())
    })?;
    Ok(Array1::from(delay).into_pyarray(py))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<SatelliteStates>()?;
    m.add_class::<SinglePoints>()?;
    m.add_class::<TransmitStates>()?;
    m.add_function(wrap_pyfunction!(gnss_satellite_states, m)?)?;
    m.add_function(wrap_pyfunction!(gnss_transmit_states, m)?)?;
    m.add_function(wrap_pyfunction!(gnss_klobuchar_delay, m)?)?;
    m.add_function(wrap_pyfunction!(gnss_single_point, m)?)?;
    Ok(())
}
