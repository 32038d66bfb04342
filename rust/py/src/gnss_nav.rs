//! Broadcast navigation data from Python (`NavInput` of `gnssatt.rinex.session_input`: one numpy array
//! per record field) into the core's `NavData`, and test-facing evaluations of the ephemerides and of
//! single-point positioning.

use gnssatt_core::gnss::ephemeris::Ephemerides;
use gnssatt_core::gnss::navdata::{GlonassRecord, KeplerRecord, NavData};
use gnssatt_core::gnss::observations::{Observations, ReceiverObservations};
use gnssatt_core::gnss::options::EngineOptions;
use gnssatt_core::gnss::signal::{SatId, System, MAX_FREQUENCIES};
use gnssatt_core::gnss::spp::single_point;
use nalgebra::Vector3;
use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{exact, fixed};
use crate::errors::invalid_input;
use crate::interruptible;

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

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(gnss_satellite_states, m)?)?;
    m.add_function(wrap_pyfunction!(gnss_single_point, m)?)?;
    Ok(())
}
