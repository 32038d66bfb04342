//! Binding of the RINEX observation-body reader (`gnssatt_core::rinex`): `gnssatt.rinex.obs` parses the
//! header and passes the decompressed file and its layout; the epochs are read with the GIL released and a
//! fault of the file becomes `gnssatt.errors.RinexError` naming the file and the line.

use gnssatt_core::rinex::{read_obs_body, BodyError, BodyOptions, SystemLayout};
use numpy::ndarray::{Array1, Array3};
use numpy::{IntoPyArray, PyArray1, PyArray3};
use pyo3::prelude::*;
use pyo3::pybacked::PyBackedBytes;

use crate::errors::invalid_input;
use crate::guard::guard;
use crate::results::result_type;

pyo3::import_exception!(gnssatt.errors, RinexError);

result_type! {
    /// The epochs of an observation body: labels (ns since 1970, as written), flags, clock offsets (s,
    /// NaN where absent), the satellites (sorted) and the (epochs, satellites, codes) values, LLI and SSI;
    /// `cut` names the last epoch where the file ends inside it (left out), else None.
    ObsBody {
        time_ns: Py<PyArray1<i64>>,
        epoch_flag: Py<PyArray1<u8>>,
        clock_offset_s: Py<PyArray1<f64>>,
        sats: Vec<String>,
        data: Py<PyArray3<f64>>,
        lli: Py<PyArray3<u8>>,
        ssi: Py<PyArray3<u8>>,
        cut: Option<String>,
    }
}

/// One system's layout: (system letter or `"*"`, fields per record, kept fields, their columns in the
/// dense arrays, their scale factors).
type LayoutArg = (String, usize, Vec<usize>, Vec<usize>, Vec<f64>);

fn layout(
    py: Python<'_>,
    (key, n_fields, keep, columns, factors): LayoutArg,
) -> PyResult<SystemLayout> {
    let key = match key.as_bytes() {
        [k] => *k,
        _ => {
            return Err(invalid_input(
                py,
                format!("expected a one-letter layout key, got {key:?}"),
            ))
        }
    };
    let valid = keep.len() == columns.len()
        && keep.len() == factors.len()
        && keep.windows(2).all(|w| w[0] < w[1])
        && keep.last().is_none_or(|&k| k < n_fields)
        && factors.iter().all(|f| f.is_finite() && *f != 0.0);
    if !valid {
        return Err(invalid_input(
            py,
            format!("layout {}: expected increasing kept fields below {n_fields} with a column and a non-zero factor each", key as char),
        ));
    }
    Ok(SystemLayout {
        key,
        n_fields,
        keep,
        columns,
        factors,
    })
}

/// Reads the observation body of `text` (the whole file, decompressed) from line `first_line` (0-based).
#[guard]
#[pyfunction]
#[pyo3(signature = (path, text, first_line, v3, default_system, layouts, n_codes, header_labels, max_cells))]
#[allow(clippy::too_many_arguments)]
fn rinex_obs_body(
    py: Python<'_>,
    path: String,
    text: PyBackedBytes,
    first_line: usize,
    v3: bool,
    default_system: char,
    layouts: Vec<LayoutArg>,
    n_codes: usize,
    header_labels: Vec<String>,
    max_cells: u64,
) -> PyResult<ObsBody> {
    let layouts = layouts
        .into_iter()
        .map(|l| layout(py, l))
        .collect::<PyResult<Vec<_>>>()?;
    if layouts.is_empty()
        || layouts
            .iter()
            .any(|l| l.columns.iter().any(|&c| c >= n_codes))
    {
        return Err(invalid_input(
            py,
            format!("expected layouts with columns below n_codes = {n_codes}"),
        ));
    }
    if !default_system.is_ascii() {
        return Err(invalid_input(
            py,
            format!("expected an ASCII default_system, got {default_system:?}"),
        ));
    }
    let opts = BodyOptions {
        v3,
        default_system: default_system as u8,
        layouts,
        n_codes,
        header_labels,
        max_cells,
        first_line,
    };
    let body = py.detach(|| read_obs_body(&text, &opts)).map_err(|e| match e {
        BodyError::Malformed { line, message } => RinexError::new_err((path.clone(), line, message)),
        BodyError::TooLarge { epochs, sats, codes } => {
            let cells = epochs as u128 * sats as u128 * codes as u128;
            RinexError::new_err((
                path.clone(),
                None::<usize>,
                format!(
                    "{epochs} epochs x {sats} satellites x {codes} codes = {cells} values exceed the limit of \
                     {max_cells} (gnssatt.rinex.obs.MAX_CELLS); split the file by time or system"
                ),
            ))
        }
    })?;
    let shape = (body.time_ns.len(), body.sats.len(), n_codes);
    Ok(ObsBody {
        time_ns: Array1::from(body.time_ns).into_pyarray(py).unbind(),
        epoch_flag: Array1::from(body.flag).into_pyarray(py).unbind(),
        clock_offset_s: Array1::from(body.clock_s).into_pyarray(py).unbind(),
        sats: body.sats,
        data: cube(py, shape, body.data)?,
        lli: cube(py, shape, body.lli)?,
        ssi: cube(py, shape, body.ssi)?,
        cut: body.cut,
    })
}

/// A (epochs, satellites, codes) array of the core's row-major values (no copy).
fn cube<T: numpy::Element>(
    py: Python<'_>,
    shape: (usize, usize, usize),
    values: Vec<T>,
) -> PyResult<Py<PyArray3<T>>> {
    Ok(Array3::from_shape_vec(shape, values)
        .map_err(|e| invalid_input(py, e.to_string()))?
        .into_pyarray(py)
        .unbind())
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<ObsBody>()?;
    m.add_function(wrap_pyfunction!(rinex_obs_body, m)?)?;
    Ok(())
}
