//! Gyro + multi-antenna GNSS attitude filter (Dzhepe Ali, chapters 2-3): an error-state Kalman filter whose
//! attitude is propagated by the gyro rates and corrected either by the receiver's own attitude solutions
//! (loosely coupled) or by carrier-phase first differences between the master and slave antennas (tightly
//! coupled, float ambiguities in the state, fixed by LAMBDA with validation).
//!
//! Models (conventions in `docs/conventions.md`, section "Gyro + GNSS filter"):
//! - Attitude `R = dcm_ref_from_body` (scalar-last quaternion); the reference frame is inertial (ECI), so
//!   the gyros measure the body rate relative to it.
//! - Gyro: `omega_meas = omega - nu`, `nu = drift + white noise` (angle random walk `arw`, rad/s/sqrt(Hz)),
//!   the drift constant or a random walk (`rrw`, rad/s^2/sqrt(Hz)). `omega_meas[k]` is the mean rate over
//!   `[t_k, t_{k+1}]` (an integrating gyro's angle increment over the interval).
//! - Error state `x = [dtheta (3), ddrift (3), [dmu (3),] N (m per tracked satellite)]`: true attitude
//!   `R = R_hat exp([dtheta x])` (a body-frame rotation vector), `ddrift = drift - drift_hat`, and the float
//!   ambiguities themselves (cycles). Continuous model `dtheta' = -[omega_hat x] (dtheta + dmu) + ddrift + w`,
//!   `dmu = mu - mu_hat` the error of the optional misalignment estimate of the gyro triad, whose rates are
//!   taken to the body by `omega_hat = exp([mu_hat x]) (omega_meas + drift_hat)`.
//! - Phase first difference of slave antenna `i` minus the master for satellite `k`, cycles:
//!   `z_ik = -los_k . (R b_i) / lambda_k + N_ik + v` — one multi-antenna receiver with a common oscillator,
//!   so no clock or oscillator term survives the difference. `los_k` in the reference frame (receiver to
//!   satellite), `b_i` the body baseline (slave minus master), m.

mod filter;
pub mod kinematics;

#[cfg(test)]
mod tests;

use nalgebra::{Matrix3, Matrix6, Vector3};

use crate::lambda::gate::Gate;

pub use filter::{run, MAX_FILTER_SAMPLES, MAX_FILTER_STATES};

/// Gyro noise densities.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GyroNoise {
    /// Angle random walk (white rate noise), rad/s/sqrt(Hz).
    pub arw: f64,
    /// Drift random walk, rad/s^2/sqrt(Hz); 0 for a constant drift.
    pub rrw: f64,
}

/// Integer ambiguity fixing and its validation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixSettings {
    /// Try to fix the float ambiguities after every phase update.
    pub enabled: bool,
    /// Accepts or refuses each attempt: the ILS rule of [`crate::lambda::gate`] (bootstrapped success
    /// rate, ratio test, fixed-failure-rate test when `max_failure_rate > 0`), the one the observation
    /// engine uses. Partial fixing is not attempted: a fixed decorrelated combination spans several
    /// tracks, so the state would keep ambiguities with a singular covariance that the next attempt's
    /// decorrelation refuses, and a satellite that sets would take a share of fixed combinations with it.
    pub gate: Gate,
}

/// Unmodelled errors of the sensitivity analysis: the filter ignores them, the covariance of the TRUE
/// estimation error accounts for them (independent zero-mean priors).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensitivity {
    /// Standard deviation of each component of the gyro-triad misalignment rotation vector, rad.
    pub misalignment_sigma: f64,
    /// Standard deviation of each component of each baseline vector error, m.
    pub baseline_sigma: f64,
}

/// Everything the filter is told about its sensors.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    pub noise: GyroNoise,
    /// Body baselines slave minus master, m (non-zero length).
    pub baselines: Vec<Vector3<f64>>,
    /// Standard deviation of one phase first difference, cycles.
    pub phase_sigma: f64,
    pub fix: FixSettings,
    /// A tracked satellite whose innovations' NIS exceeds this is declared slipped and its ambiguities are
    /// reset; `f64::INFINITY` disables the test.
    pub slip_threshold: f64,
    /// The phases are given with their integers removed (no ambiguity states).
    pub known_ambiguities: bool,
    /// Propagate the true-error covariance against these unmodelled errors (needs `known_ambiguities`).
    pub sensitivity: Option<Sensitivity>,
    /// Estimate the misalignment of the gyro triad (three more states, this prior sigma per axis, rad).
    pub misalignment_sigma: Option<f64>,
    /// Record the state every `output_every` gyro samples (and at the first one).
    pub output_every: usize,
}

/// Initial estimate and its error covariance (attitude error, drift error).
#[derive(Debug, Clone, PartialEq)]
pub struct Initial {
    /// Body -> reference, scalar-last.
    pub quaternion: [f64; 4],
    /// Drift estimate, rad/s.
    pub drift: Vector3<f64>,
    /// Covariance of `[dtheta, ddrift]`, rad^2 and (rad/s)^2.
    pub covariance: Matrix6<f64>,
}

/// One attitude solution of the receiver (loosely coupled measurement).
#[derive(Debug, Clone, PartialEq)]
pub struct AttitudeFix {
    pub t: f64,
    /// Body -> reference, scalar-last.
    pub quaternion: [f64; 4],
    /// Covariance of its body-frame rotation-vector error, rad^2.
    pub covariance: Matrix3<f64>,
}

/// The phase first differences of one satellite at one epoch.
#[derive(Debug, Clone, PartialEq)]
pub struct PhaseObs {
    /// Identifies a continuous arc of carrier tracking: a new value starts new ambiguities.
    pub track: i64,
    /// Unit line of sight receiver -> satellite, reference frame.
    pub los: Vector3<f64>,
    /// Wavelength, m.
    pub wavelength: f64,
    /// One first difference per baseline, cycles.
    pub phase: Vec<f64>,
}

/// The phase observations of one epoch.
#[derive(Debug, Clone, PartialEq)]
pub struct PhaseEpoch {
    pub t: f64,
    pub obs: Vec<PhaseObs>,
}

/// One attempt to fix the float ambiguities.
#[derive(Debug, Clone, PartialEq)]
pub struct FixAttempt {
    pub t: f64,
    pub accepted: bool,
    /// Ratio of the second-best to the best squared norm (0 when the gate refused before the search or
    /// the search could not be completed; infinite for a zero best norm).
    pub ratio: f64,
    pub success_rate: f64,
    /// `(track, baseline index, integer)` of the best candidate.
    pub values: Vec<(i64, usize, i64)>,
}

/// A detected cycle slip (or wrong fix): the track's ambiguities were reset.
#[derive(Debug, Clone, PartialEq)]
pub struct Slip {
    pub t: f64,
    pub track: i64,
    pub nis: f64,
}

/// Normalised innovation squared of one measurement update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nis {
    pub t: f64,
    pub nis: f64,
    pub dof: usize,
}

/// What the filter produced.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FilterRun {
    /// Output times, s.
    pub t: Vec<f64>,
    /// Attitude estimates, body -> reference, scalar-last.
    pub quaternion: Vec<[f64; 4]>,
    /// Drift estimates, rad/s.
    pub drift: Vec<Vector3<f64>>,
    /// The filter's covariance of `[dtheta, ddrift]`.
    pub covariance: Vec<Matrix6<f64>>,
    /// The covariance of the TRUE error `[dtheta, ddrift]` (sensitivity analysis only).
    pub true_covariance: Vec<Matrix6<f64>>,
    /// Misalignment estimates (rad) and their covariance (zero when not estimated).
    pub misalignment: Vec<Vector3<f64>>,
    pub misalignment_covariance: Vec<Matrix3<f64>>,
    /// Float and fixed ambiguities held at each output time.
    pub n_float: Vec<usize>,
    pub n_fixed: Vec<usize>,
    pub fixes: Vec<FixAttempt>,
    pub slips: Vec<Slip>,
    pub nis: Vec<Nis>,
}
