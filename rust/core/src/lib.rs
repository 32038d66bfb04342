//! Numerical core of **gnssatt**: attitude determination from GNSS signals and complementary sensors.
//!
//! This crate has no Python dependency: `cargo test` and `cargo bench` exercise it directly, and the
//! `gnssatt-py` crate is a thin binding layer over it. Conventions (frames, rotation direction, Euler
//! sequences, quaternion order, units) are those of `docs/conventions.md`; every angle here is in radians
//! and every length in metres.

pub mod dynamics;
pub mod error;
pub mod gnss;
pub mod guard;
pub mod gyro_gnss;
pub mod interrupt;
pub mod kalman;
pub mod lambda;
pub mod likelihood;
pub mod magnetometer;
pub mod matrix_method;
pub mod orbit;
pub mod rinex;
pub mod rotation;
pub mod wahba;

pub use error::{Error, Result};
