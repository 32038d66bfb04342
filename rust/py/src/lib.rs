//! Python bindings of gnssatt-core, exposed as `gnssatt._core`. Bindings only: every function checks its
//! numpy inputs (`convert`), releases the GIL around the numerics, maps core errors (`errors`), and
//! turns a panic into an exception at every entry point (`guard`).

use pyo3::prelude::*;

mod convert;
mod dynamics;
mod errors;
mod gnss;
mod gnss_nav;
mod gnss_nav_input;
mod gnss_options;
mod gnss_session;
mod guard;
mod gyro_gnss;
mod gyro_gnss_options;
mod interruptible;
mod lambda;
mod likelihood;
mod matrix_method;
mod orbit;
mod pool;
mod results;
mod rinex;
mod rinex_nav;
mod rotation;
mod wahba;

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    rotation::register(m)?;
    matrix_method::register(m)?;
    likelihood::register(m)?;
    lambda::register(m)?;
    dynamics::register(m)?;
    wahba::register(m)?;
    orbit::register(m)?;
    gyro_gnss::register(m)?;
    gnss_nav::register(m)?;
    gnss::register(m)?;
    gnss_options::register(m)?;
    rinex::register(m)?;
    rinex_nav::register(m)?;
    guard::register(m)?;
    Ok(())
}
