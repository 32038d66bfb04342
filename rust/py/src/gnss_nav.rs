//! Broadcast navigation data from Python (`NavInput` of `gnssatt.rinex.session_input`: one numpy array
//! per record field) into the core's `NavData`; evaluations of the ephemerides (at a time, or at
//! transmission for a reception), of the Klobuchar ionosphere (the simulator's) and of single-point
//! positioning (test-facing).

use gnssatt_core::gnss::atmosphere::klobuchar_delay_m;
use gnssatt_core::gnss::ephemeris::Ephemerides;
use gnssatt_core::gnss::geometry::satellite_geometry;
use gnssatt_core::gnss::navdata::{GlonassRecord, KeplerRecord, NavData};
use gnssatt_core::gnss::observations::{Observations, ReceiverObservations};
use gnssatt_core::gnss::options::EngineOptions;
use gnssatt_core::gnss::signal::{SatId, System, MAX_FREQUENCIES};
use gnssatt_core::gnss::spp::single_point;
use nalgebra::Vector3;
use numpy::ndarray::{Array1, Array2};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use gnssatt_core::Error;

use crate::convert::{exact, fixed, rows, values};
use crate::errors::{invalid_input, IntoPyResult};
use crate::interruptible;

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

/// A satellite id `"G05"`: a system letter and a PRN 1..=99.
pub fn sat_from_str(py: Python<'_>, name: &str, s: &str) -> PyResult<SatId> {
    let mut chars = s.chars();
    let system = chars.next().and_then(System::from_letter);
    let prn = chars
        .as_str()
        .trim()
        .parse::<u8>()
        .ok()
        .filter(|p| (1..=99).contains(p));
    match (system, prn) {
        (Some(system), Some(prn)) => Ok(SatId { system, prn }),
        _ => Err(invalid_input(
            py,
            format!(
                "expected {name} entries like 'G05' (a letter of GRECJ and a PRN 1..99), got {s:?}"
            ),
        )),
    }
}

/// The columns of one record table: every array of the dict, all of one length `n`.
struct Table<'a, 'py> {
    dict: &'a Bound<'py, PyDict>,
    table: &'static str,
    n: usize,
}

impl<'py> Table<'_, 'py> {
    fn item(&self, key: &str) -> PyResult<Bound<'py, PyAny>> {
        let py = self.dict.py();
        self.dict.get_item(key)?.ok_or_else(|| {
            invalid_input(
                py,
                format!("expected {}[{key:?}], the key is missing", self.table),
            )
        })
    }

    fn sats(&self) -> PyResult<Vec<String>> {
        let py = self.dict.py();
        let v = self.item("sat")?;
        let list = if v.hasattr("tolist")? {
            v.call_method0("tolist")?
        } else {
            v
        };
        list.extract::<Vec<String>>().map_err(|_| {
            invalid_input(
                py,
                format!(
                    "expected {}[\"sat\"] a 1-d array of satellite ids (str)",
                    self.table
                ),
            )
        })
    }

    fn floats(&self, key: &str, width: usize) -> PyResult<Vec<f64>> {
        let py = self.dict.py();
        let name = format!("{}[{key:?}]", self.table);
        let v = converted(&self.item(key)?, "fiu", "float64")?;
        let shape: Vec<usize> = if width == 1 {
            vec![self.n]
        } else {
            vec![self.n, width]
        };
        let arr = v.extract::<numpy::PyReadonlyArrayDyn<f64>>().map_err(|_| {
            invalid_input(
                py,
                format!("expected {name} a real (float or integer) array of shape {shape:?}"),
            )
        })?;
        exact(py, &name, &arr, &shape)
    }

    fn ints(&self, key: &str) -> PyResult<Vec<i64>> {
        let py = self.dict.py();
        let name = format!("{}[{key:?}]", self.table);
        let v = converted(&self.item(key)?, "i", "int64")?;
        let arr = v.extract::<numpy::PyReadonlyArrayDyn<i64>>().map_err(|_| {
            invalid_input(
                py,
                format!(
                    "expected {name} a signed integer array of shape ({},)",
                    self.n
                ),
            )
        })?;
        exact(py, &name, &arr, &[self.n])
    }
}

/// A numpy array whose dtype kind is one of `kinds` (`f` float, `i` signed, `u` unsigned integer),
/// converted to `dtype` (exact for integers into int64, and for every integer and float into float64
/// up to 2^53); anything else is returned as it is, for the caller's typed extraction to refuse.
fn converted<'py>(v: &Bound<'py, PyAny>, kinds: &str, dtype: &str) -> PyResult<Bound<'py, PyAny>> {
    let kind = v
        .getattr("dtype")
        .and_then(|d| d.getattr("kind"))
        .and_then(|k| k.extract::<String>());
    match kind {
        Ok(k) if !k.is_empty() && kinds.contains(k.as_str()) => v.call_method1("astype", (dtype,)),
        _ => Ok(v.clone()),
    }
}

fn length(py: Python<'_>, dict: &Bound<'_, PyDict>, table: &'static str) -> PyResult<usize> {
    if dict.is_empty() {
        return Ok(0);
    }
    let sat = dict.get_item("sat")?.ok_or_else(|| {
        invalid_input(py, format!("expected {table}[\"sat\"], the key is missing"))
    })?;
    sat.len()
}

fn kepler_records(py: Python<'_>, dict: &Bound<'_, PyDict>) -> PyResult<Vec<KeplerRecord>> {
    let n = length(py, dict, "kepler")?;
    if n == 0 {
        return Ok(Vec::new());
    }
    let t = Table {
        dict,
        table: "kepler",
        n,
    };
    let sats = t.sats()?;
    let toc = t.ints("toc_gpst_ns")?;
    let toe = t.ints("toe_gpst_ns")?;
    let af = t.floats("af", 3)?;
    let tgd = t.floats("tgd_s", 2)?;
    let names = [
        "crs",
        "delta_n",
        "m0",
        "cuc",
        "e",
        "cus",
        "sqrt_a",
        "cic",
        "omega0",
        "cis",
        "i0",
        "crc",
        "omega",
        "omega_dot",
        "idot",
        "health",
        "iode",
        "accuracy_m",
        "fit_interval_h",
        "data_source",
    ];
    let cols = names
        .iter()
        .map(|k| t.floats(k, 1))
        .collect::<PyResult<Vec<_>>>()?;
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let sat = sat_from_str(py, "kepler[\"sat\"]", &sats[i])?;
        if sat.system == System::Glonass {
            return Err(invalid_input(
                py,
                format!(
                    "expected kepler[\"sat\"] of GPS, Galileo, BeiDou or QZSS, row {i} is {sat}"
                ),
            ));
        }
        let c = |k: usize| cols[k][i];
        out.push(KeplerRecord {
            sat,
            toc_gpst_ns: toc[i],
            toe_gpst_ns: toe[i],
            af: [af[3 * i], af[3 * i + 1], af[3 * i + 2]],
            crs: c(0),
            delta_n: c(1),
            m0: c(2),
            cuc: c(3),
            e: c(4),
            cus: c(5),
            sqrt_a: c(6),
            cic: c(7),
            omega0: c(8),
            cis: c(9),
            i0: c(10),
            crc: c(11),
            omega: c(12),
            omega_dot: c(13),
            idot: c(14),
            health: c(15),
            tgd_s: [tgd[2 * i], tgd[2 * i + 1]],
            iode: c(16),
            accuracy_m: c(17),
            fit_interval_h: c(18),
            data_source: c(19),
        });
    }
    Ok(out)
}

fn glonass_records(py: Python<'_>, dict: &Bound<'_, PyDict>) -> PyResult<Vec<GlonassRecord>> {
    let n = length(py, dict, "glonass")?;
    if n == 0 {
        return Ok(Vec::new());
    }
    let t = Table {
        dict,
        table: "glonass",
        n,
    };
    let sats = t.sats()?;
    let tb = t.ints("tb_gpst_ns")?;
    let bias = t.floats("clock_bias_s", 1)?;
    let gamma = t.floats("gamma_n", 1)?;
    let pos = t.floats("position_m", 3)?;
    let vel = t.floats("velocity_m_s", 3)?;
    let acc = t.floats("acceleration_m_s2", 3)?;
    let channel = t.ints("channel")?;
    let health = t.floats("health", 1)?;
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let sat = sat_from_str(py, "glonass[\"sat\"]", &sats[i])?;
        if sat.system != System::Glonass {
            return Err(invalid_input(
                py,
                format!("expected glonass[\"sat\"] of GLONASS, row {i} is {sat}"),
            ));
        }
        let ch = i8::try_from(channel[i])
            .ok()
            .filter(|k| (-7..=13).contains(k));
        let Some(ch) = ch else {
            return Err(invalid_input(
                py,
                format!(
                    "expected glonass[\"channel\"] in -7..=13, row {i} is {}",
                    channel[i]
                ),
            ));
        };
        let v3 = |a: &[f64]| [a[3 * i], a[3 * i + 1], a[3 * i + 2]];
        out.push(GlonassRecord {
            sat,
            tb_gpst_ns: tb[i],
            clock_bias_s: bias[i],
            gamma_n: gamma[i],
            position_m: v3(&pos),
            velocity_m_s: v3(&vel),
            acceleration_m_s2: v3(&acc),
            channel: ch,
            health: health[i],
        });
    }
    Ok(out)
}

/// `NavData` from the arrays of a `NavInput` (one array per record field, see the module documentation
/// of `gnssatt.rinex.session_input`); the records' values are checked by `Ephemerides::new`.
pub fn nav_from_py(
    kepler: &Bound<PyDict>,
    glonass: &Bound<PyDict>,
    klobuchar: Option<PyReadonlyArray1<f64>>,
    leap_seconds: Option<i32>,
) -> PyResult<NavData> {
    let py = kepler.py();
    let klobuchar = klobuchar
        .map(|k| fixed::<8>(py, "klobuchar", &k))
        .transpose()?;
    Ok(NavData {
        kepler: kepler_records(py, kepler)?,
        glonass: glonass_records(py, glonass)?,
        klobuchar,
        leap_seconds,
    })
}

type States<'py> = (
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<bool>>,
);

/// Broadcast positions (n, 3) ECEF m (frame of the transmit instant), clocks (n,) s (relativistic term
/// included, no group delay) and validity (n,) of `sats[i]` at GPST `t_gpst_ns[i] + offset_s[i]`;
/// NaN where not valid (no healthy record within its validity interval).
#[pyfunction]
#[pyo3(signature = (kepler, glonass, klobuchar, leap_seconds, sats, t_gpst_ns, *, offset_s=None))]
#[allow(clippy::too_many_arguments)]
fn gnss_satellite_states<'py>(
    py: Python<'py>,
    kepler: &Bound<'py, PyDict>,
    glonass: &Bound<'py, PyDict>,
    klobuchar: Option<PyReadonlyArray1<'py, f64>>,
    leap_seconds: Option<i32>,
    sats: Vec<String>,
    t_gpst_ns: PyReadonlyArray1<'py, i64>,
    offset_s: Option<PyReadonlyArray1<'py, f64>>,
) -> PyResult<States<'py>> {
    let nav = nav_from_py(kepler, glonass, klobuchar, leap_seconds)?;
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
    let states = interruptible::run(py, || {
        let eph = Ephemerides::new(&nav)?;
        Ok((0..n)
            .map(|i| eph.state(ids[i], t[i], off[i]))
            .collect::<Vec<_>>())
    })?;
    let pos = Array2::from_shape_fn((n, 3), |(i, j)| {
        states[i].map_or(f64::NAN, |s| s.position_m[j])
    });
    let clk = Array1::from_shape_fn(n, |i| states[i].map_or(f64::NAN, |s| s.clock_s));
    let ok = Array1::from_shape_fn(n, |i| states[i].is_some());
    Ok((
        pos.into_pyarray(py),
        clk.into_pyarray(py),
        ok.into_pyarray(py),
    ))
}

type Points<'py> = (
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<f64>>,
);

/// Single-point solutions of one receiver at every epoch (test-facing): code `code_m` (n_ep, n_sat, 3)
/// m, NaN where absent; `glonass_channel` (n_sat,), 99 where none. Returns position (n_ep, 3) ECEF m,
/// clocks (n_ep, 5) s per system (NaN where not estimated), satellites used (n_ep,) and residual RMS
/// (n_ep,) m; rows of epochs without a solution are NaN (and 0 satellites).
#[pyfunction]
#[pyo3(signature = (kepler, glonass, klobuchar, leap_seconds, time_gpst_ns, sats, glonass_channel,
                    code_m, *, approx_position_m=None, systems="GRECJ", frequencies=1,
                    elevation_mask_deg=10.0))]
#[allow(clippy::too_many_arguments)]
fn gnss_single_point<'py>(
    py: Python<'py>,
    kepler: &Bound<'py, PyDict>,
    glonass: &Bound<'py, PyDict>,
    klobuchar: Option<PyReadonlyArray1<'py, f64>>,
    leap_seconds: Option<i32>,
    time_gpst_ns: PyReadonlyArray1<'py, i64>,
    sats: Vec<String>,
    glonass_channel: PyReadonlyArray1<'py, i64>,
    code_m: PyReadonlyArray3<'py, f64>,
    approx_position_m: Option<PyReadonlyArray1<'py, f64>>,
    systems: &str,
    frequencies: usize,
    elevation_mask_deg: f64,
) -> PyResult<Points<'py>> {
    let nav = nav_from_py(kepler, glonass, klobuchar, leap_seconds)?;
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
    let solutions = interruptible::run(py, || {
        opts.validate()?;
        obs.validate()?;
        let eph = Ephemerides::new(&nav)?;
        let mut prior: Option<Vector3<f64>> = None;
        let mut out = Vec::with_capacity(ne);
        for e in 0..ne {
            gnssatt_core::interrupt::check_every(e, "single point")?;
            let s = single_point(&obs, 0, e, &eph, &nav, &opts, prior.as_ref()).ok();
            if let Some(s) = &s {
                prior = Some(s.position_m);
            }
            out.push(s);
        }
        Ok(out)
    })?;
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
    Ok((
        pos.into_pyarray(py),
        clk.into_pyarray(py),
        n.into_pyarray(py),
        rms.into_pyarray(py),
    ))
}

type Transmits<'py> = (
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<bool>>,
);

/// Satellite `sats[i]` as received at GPST label `t_rx_gpst_ns[i]` by a receiver at `receiver_m[i]`
/// (ECEF, m) whose clock reads `receiver_clock_s[i]` ahead (true reception = label - clock): light time
/// iterated from the receiver, Earth rotation during it (the core's `satellite_geometry`). Returns the
/// transmit-time position in the ECEF frame of reception (n, 3) m, the satellite clock at transmission
/// (n,) s (relativistic term included, no group delay), elevation and azimuth (clockwise from North) at
/// the receiver's geodetic position (n,) rad, and validity (n,); NaN where not valid (no usable record).
#[pyfunction]
#[pyo3(signature = (kepler, glonass, klobuchar, leap_seconds, sats, t_rx_gpst_ns, receiver_m,
                    receiver_clock_s))]
#[allow(clippy::too_many_arguments)]
fn gnss_transmit_states<'py>(
    py: Python<'py>,
    kepler: &Bound<'py, PyDict>,
    glonass: &Bound<'py, PyDict>,
    klobuchar: Option<PyReadonlyArray1<'py, f64>>,
    leap_seconds: Option<i32>,
    sats: Vec<String>,
    t_rx_gpst_ns: PyReadonlyArray1<'py, i64>,
    receiver_m: PyReadonlyArray2<'py, f64>,
    receiver_clock_s: PyReadonlyArray1<'py, f64>,
) -> PyResult<Transmits<'py>> {
    let n = sats.len();
    evaluations(py, n)?;
    let nav = nav_from_py(kepler, glonass, klobuchar, leap_seconds)?;
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
    let geometry = interruptible::run(py, || {
        let eph = Ephemerides::new(&nav)?;
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
        Ok(out)
    })?;
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
    Ok((
        pos.into_pyarray(py),
        clk.into_pyarray(py),
        el.into_pyarray(py),
        az.into_pyarray(py),
        ok.into_pyarray(py),
    ))
}

/// Slant ionospheric group delay of the broadcast Klobuchar model (IS-GPS-200 20.3.3.5.2.5, the core's
/// `klobuchar_delay_m`), m, positive (code delayed, phase advanced): `coefficients` (8,) alpha0..3,
/// beta0..3 as broadcast (s and semicircle powers); the receiver's geodetic latitude and longitude, rad;
/// per evaluation (n,) GPST `t_gpst_ns`, satellite azimuth and elevation (rad) and carrier frequency (Hz;
/// the L1 delay scaled by `(f_L1 / f)^2`). 0 for a satellite at or below the horizon.
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
    m.add_function(wrap_pyfunction!(gnss_satellite_states, m)?)?;
    m.add_function(wrap_pyfunction!(gnss_transmit_states, m)?)?;
    m.add_function(wrap_pyfunction!(gnss_klobuchar_delay, m)?)?;
    m.add_function(wrap_pyfunction!(gnss_single_point, m)?)?;
    Ok(())
}
