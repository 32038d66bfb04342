//! GNSS observables: from recorded code and carrier-phase observations of several antennas and broadcast
//! navigation data to baselines, fixed integer ambiguities and attitude.
//!
//! Data flow, base to top: [`signal`] (systems, satellites, carrier frequencies), [`time`], the shared
//! input types [`observations`] and [`navdata`], [`options`] and the output [`solution`]; then
//! [`ephemeris`] (broadcast orbits and clocks), [`atmosphere`] (Klobuchar, Saastamoinen), [`weights`]
//! (elevation-dependent variances), [`geometry`] (satellite positions at transmit time seen from one
//! receiver), [`spp`] (single-point positioning); then [`rtk`] (double differences, float solution,
//! integer fixing with a success-rate gate, partial fixing) and on top [`session`] (one call for a whole
//! session) and [`stream`] (the same engine one epoch at a time, state carried between calls).
//!
//! Every time is GPST in integer nanoseconds since the GPS epoch (1980-01-06 00:00:00); positions are
//! ECEF (WGS-84) in metres; angles in radians unless a name says `_deg`.

pub mod atmosphere;
pub mod ephemeris;
pub mod geometry;
pub mod navdata;
pub mod observations;
pub mod options;
pub mod rtk;
pub mod session;
pub mod signal;
pub mod solution;
pub mod spp;
pub mod stream;
pub mod synthetic;
pub mod time;
pub mod weights;
