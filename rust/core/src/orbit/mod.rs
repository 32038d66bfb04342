//! Orbit models and orbit determination (Dzhepe Ali, chapter 1): the circular Keplerian reference orbit,
//! the GLONASS ICD Earth-fixed equations of motion integrated by RK4 with their state-transition matrix,
//! and the loosely / tightly coupled GNSS orbit-determination Kalman filter.
//!
//! State ordering everywhere: `(x, y, z, vx, vy, vz)`, Earth-fixed (ECEF / PZ-90) axes, m and m/s, velocity
//! relative to the rotating Earth.

pub mod circular;
pub mod filter;
pub mod glonass;

#[cfg(test)]
mod tests;

pub use circular::CircularOrbit;
pub use filter::{
    run as run_filter, Corrections, FilterConfig, FilterOutput, Fixes, Ranges, MAX_FILTER_STEPS,
    MAX_SATELLITES,
};
pub use glonass::{
    propagate, propagate_with_stm, GlonassModel, MAX_ESCAPE_SPEEDS, MAX_RK4_STEPS,
    MIN_RADIUS_FRACTION,
};
