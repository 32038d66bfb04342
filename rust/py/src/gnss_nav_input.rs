//! Broadcast navigation data from Python (`NavInput` of `gnssatt.rinex.nav`: one numpy array
//! per record field) into the core's `NavData`, held by the frozen [`Navigation`] that every GNSS binding
//! takes (converted and checked once, not on every call); and satellite ids from their text (`"G05"`).
//! Used by the ephemeris evaluations (`gnss_nav`) and the observation engine (`gnss`).

use gnssatt_core::gnss::navdata::{GlonassRecord, KeplerRecord, NavData};
use gnssatt_core::gnss::signal::{SatId, System};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{exact, fixed};
use crate::errors::invalid_input;
use crate::guard::guard;

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

/// The one-value float columns of the `kepler` table, in the order `kepler_records` reads them (`c(k)`
/// there is column `k` of this list).
const KEPLER_FLOAT_COLUMNS: [&str; 20] = [
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
    let cols = KEPLER_FLOAT_COLUMNS
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
/// of `gnssatt.rinex.nav`); the records' values are checked by `Ephemerides::new`.
fn nav_from_py(
    py: Python<'_>,
    kepler: Option<&Bound<PyDict>>,
    glonass: Option<&Bound<PyDict>>,
    klobuchar: Option<PyReadonlyArray1<f64>>,
    leap_seconds: Option<i32>,
) -> PyResult<NavData> {
    let klobuchar = klobuchar
        .map(|k| fixed::<8>(py, "klobuchar", &k))
        .transpose()?;
    let empty = PyDict::new(py);
    Ok(NavData {
        kepler: kepler_records(py, kepler.unwrap_or(&empty))?,
        glonass: glonass_records(py, glonass.unwrap_or(&empty))?,
        klobuchar,
        leap_seconds,
    })
}

/// Broadcast navigation data converted once into the core's `NavData` (`gnssatt._core.Navigation`), the
/// argument of every GNSS binding: `kepler` and `glonass` are the column arrays of
/// `gnssatt.rinex.nav.NavInput` (missing or empty: no record of that kind), `klobuchar` the (8,) GPS
/// alpha0..3, beta0..3, `leap_seconds` GPS - UTC. Frozen; the records' values are checked where they are
/// used (`Ephemerides::new`).
#[pyclass(frozen, module = "gnssatt._core")]
pub struct Navigation {
    pub nav: NavData,
}

#[guard]
#[pymethods]
impl Navigation {
    #[new]
    #[pyo3(signature = (*, kepler = None, glonass = None, klobuchar = None, leap_seconds = None))]
    fn new<'py>(
        py: Python<'py>,
        kepler: Option<Bound<'py, PyDict>>,
        glonass: Option<Bound<'py, PyDict>>,
        klobuchar: Option<PyReadonlyArray1<'py, f64>>,
        leap_seconds: Option<i32>,
    ) -> PyResult<Navigation> {
        let nav = nav_from_py(
            py,
            kepler.as_ref(),
            glonass.as_ref(),
            klobuchar,
            leap_seconds,
        )?;
        Ok(Navigation { nav })
    }

    /// Number of Keplerian records (GPS, Galileo, BeiDou, QZSS).
    #[getter]
    fn kepler_records(&self) -> usize {
        self.nav.kepler.len()
    }

    /// Number of GLONASS records.
    #[getter]
    fn glonass_records(&self) -> usize {
        self.nav.glonass.len()
    }

    /// The (8,) Klobuchar coefficients (a copy), or None.
    #[getter]
    fn klobuchar<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        self.nav.klobuchar.map(|k| PyArray1::from_slice(py, &k))
    }

    /// GPS - UTC, s, or None.
    #[getter]
    fn leap_seconds(&self) -> Option<i32> {
        self.nav.leap_seconds
    }

    fn __repr__(&self) -> String {
        let klobuchar = match self.nav.klobuchar {
            Some(_) => "array(shape=(8,), dtype=float64)",
            None => "None",
        };
        let leap = self
            .nav
            .leap_seconds
            .map_or("None".to_string(), |s| s.to_string());
        format!(
            "Navigation(kepler_records={}, glonass_records={}, klobuchar={klobuchar}, leap_seconds={leap})",
            self.nav.kepler.len(),
            self.nav.glonass.len()
        )
    }
}
