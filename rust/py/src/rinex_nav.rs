//! Binding of the RINEX navigation reader (`gnssatt_core::rinex::read_nav`): `gnssatt.rinex.nav` opens and
//! decompresses the file and converts the records into GPST arrays; the file is parsed with the GIL
//! released and a fault of the file becomes `gnssatt.errors.RinexError` naming the file and the line.

use gnssatt_core::rinex::{read_nav, BodyError, NavSkip, GLONASS_VALUES, KEPLER_VALUES};
use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::pybacked::PyBackedBytes;

use crate::errors::invalid_input;
use crate::guard::guard;
use crate::results::result_type;

pyo3::import_exception!(gnssatt.errors, RinexError);

result_type! {
    /// The records of a navigation file in file order: Keplerian (G, E, C, J) values (af0-af2 and the 26
    /// broadcast-orbit fields), satellites and times of clock as written (ns since 1970 of the label);
    /// GLONASS values (clock bias, gamma_n, frame time, 12 orbit fields), satellites and reference times
    /// (UTC label); the GPS Klobuchar alpha and beta (NaN where absent), the header's leap seconds; the
    /// records not read per message (`"EPH S SBAS"`, in order of appearance); the records left out as
    /// (`"not an orbit"` or `"cut"`, description); the number of lines of the file.
    NavRecords {
        kepler_values: Py<PyArray2<f64>>,
        kepler_sats: Vec<String>,
        kepler_toc_ns: Py<PyArray1<i64>>,
        glonass_values: Py<PyArray2<f64>>,
        glonass_sats: Vec<String>,
        glonass_tb_ns: Py<PyArray1<i64>>,
        iono_alpha: Py<PyArray1<f64>>,
        iono_beta: Py<PyArray1<f64>>,
        leap_seconds: Option<i64>,
        unused: Vec<(String, u64)>,
        skips: Vec<(String, String)>,
        lines: usize,
    }
}

/// Reads the navigation file `text` (the whole file, decompressed) named `path` in errors.
#[guard]
#[pyfunction]
#[pyo3(signature = (path, text, header_labels))]
fn rinex_nav_records(
    py: Python<'_>,
    path: String,
    text: PyBackedBytes,
    header_labels: Vec<String>,
) -> PyResult<NavRecords> {
    let nav = py
        .detach(|| read_nav(&text, &header_labels))
        .map_err(|e| match e {
            BodyError::Malformed { line, message } => {
                RinexError::new_err((path.clone(), line, message))
            }
            // the navigation reader has no size limit of its own (every record is one row)
            other @ BodyError::TooLarge { .. } => {
                RinexError::new_err((path.clone(), None::<usize>, format!("{other:?}")))
            }
        })?;
    let table = |values: Vec<f64>, width: usize| -> PyResult<Py<PyArray2<f64>>> {
        Ok(
            Array2::from_shape_vec((values.len() / width, width), values)
                .map_err(|e| invalid_input(py, e.to_string()))?
                .into_pyarray(py)
                .unbind(),
        )
    };
    Ok(NavRecords {
        kepler_values: table(nav.kepler_values, KEPLER_VALUES)?,
        kepler_sats: nav.kepler_sats,
        kepler_toc_ns: Array1::from(nav.kepler_toc_ns).into_pyarray(py).unbind(),
        glonass_values: table(nav.glonass_values, GLONASS_VALUES)?,
        glonass_sats: nav.glonass_sats,
        glonass_tb_ns: Array1::from(nav.glonass_tb_ns).into_pyarray(py).unbind(),
        iono_alpha: Array1::from(nav.iono_alpha.to_vec())
            .into_pyarray(py)
            .unbind(),
        iono_beta: Array1::from(nav.iono_beta.to_vec())
            .into_pyarray(py)
            .unbind(),
        leap_seconds: nav.leap_seconds,
        unused: nav.unused,
        skips: nav
            .skips
            .into_iter()
            .map(|(kind, what)| {
                let kind = match kind {
                    NavSkip::NotAnOrbit => "not an orbit",
                    NavSkip::CutRecord => "cut",
                };
                (kind.to_string(), what)
            })
            .collect(),
        lines: nav.lines,
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<NavRecords>()?;
    m.add_function(wrap_pyfunction!(rinex_nav_records, m)?)?;
    Ok(())
}
