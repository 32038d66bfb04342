//! The one mechanism for typed results across the boundary: `result_type!` declares a frozen `#[pyclass]`
//! whose fields are read-only attributes (assignment raises `AttributeError`) and whose `__repr__` lists
//! them, arrays by shape and dtype so that a repr stays one line whatever the size of the run.

use numpy::{PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;

/// `name=value` for `__repr__`: arrays as `array(shape=(n, 3), dtype=float64)`, anything else by its repr.
pub fn field_repr(name: &str, value: &Bound<'_, PyAny>) -> PyResult<String> {
    let shown = match value.cast::<PyUntypedArray>() {
        Ok(a) => {
            let shape: Vec<String> = a.shape().iter().map(|d| d.to_string()).collect();
            let comma = if shape.len() == 1 { "," } else { "" };
            format!(
                "array(shape=({}{comma}), dtype={})",
                shape.join(", "),
                a.getattr("dtype")?.str()?
            )
        }
        Err(_) => value.repr()?.to_string(),
    };
    Ok(format!("{name}={shown}"))
}

/// Declares a frozen result pyclass in `gnssatt._core` with a getter per field and a one-line `__repr__`.
/// Fields hold numbers, flags, `Py<...>` numpy arrays, or lists of other result types.
macro_rules! result_type {
    ($(#[$doc:meta])* $name:ident { $($(#[$fdoc:meta])* $field:ident : $ty:ty),* $(,)? }) => {
        $(#[$doc])*
        #[pyo3::pyclass(frozen, get_all, module = "gnssatt._core")]
        pub struct $name {
            $($(#[$fdoc])* pub $field: $ty,)*
        }

        #[crate::guard::guard]
        #[pyo3::pymethods]
        impl $name {
            fn __repr__(&self, py: pyo3::Python<'_>) -> pyo3::PyResult<String> {
                use pyo3::IntoPyObjectExt;
                let fields = [$(crate::results::field_repr(
                    stringify!($field),
                    &(&self.$field).into_bound_py_any(py)?,
                )?),*];
                Ok(format!("{}({})", stringify!($name), fields.join(", ")))
            }
        }
    };
}

pub(crate) use result_type;
