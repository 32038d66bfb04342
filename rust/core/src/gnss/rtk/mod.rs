//! Double differences, float solution and integer fixing of a baseline (and of several baselines of one
//! rigid array: attitude mode), on epochs prepared by the session (no ephemerides, no files here).
//!
//! Model, per frequency slot `f` of system `s` (a *group*), satellites `k` and reference `r` of the group
//! (highest elevation at the base), single differences rover minus base in metres:
//!
//! - code `P_k = rho_k(b) + c dt + e`, phase `lambda_k phi_k = rho_k(b) + c dt + lambda_k N_k + e`, with
//!   `rho_k(b) = (|s_k^rover - x_base - b| - c dts_k^rover) - (|s_k^base - x_base| - c dts_k^base)`: exact
//!   ranges from each receiver's satellite geometry, linearised at `rover_prior` and iterated, so kilometre
//!   baselines need no approximation;
//! - double differences `P_k - P_r` and `lambda_k phi_k - lambda_r phi_r` remove the receiver clock `c dt`
//!   (no inter-system or inter-frequency differences are formed);
//! - unknowns: the baseline (3, ECEF m), one double-difference integer `a_kr = N_k - N_r` (cycles) per
//!   (arc, reference arc) pair, shared by every epoch where that pair occurs (static mode), and for a
//!   group whose wavelengths differ (GLONASS FDMA) the reference's single-difference ambiguity `N_r`
//!   (see below);
//! - covariance: single differences are independent across satellites with variance
//!   `sigma_base^2 + sigma_rover^2 = 2 sigma^2` (one undifferenced sigma per signal, the same at both
//!   receivers); the double differences' covariance is `C = D Sigma_SD D^T` exactly ([`dd`]);
//! - weighted least squares by Cholesky of the normal matrix ([`float`]);
//! - fixing with LAMBDA ([`crate::lambda`]): the full set when its bootstrapped success rate reaches
//!   [`FixOptions::min_success_rate`] and its ratio test passes, else the largest decorrelated subset that
//!   does (partial fixing); the baseline conditioned on the fixed integers ([`fix`]).
//!
//! GLONASS FDMA ([`glonass`]): with different wavelengths the double-differenced phase is
//! `lambda_k N_k - lambda_r N_r = lambda_k a_kr + (lambda_k - lambda_r) N_r`. The integer `a_kr` is what
//! LAMBDA fixes; the reference's single-difference ambiguity `N_r` is a float unknown determined by the
//! single-difference phase-minus-code of the reference satellite (`lambda_r phi_r - P_r = lambda_r N_r`),
//! as RTKLIB does for receivers of one make. Assumption: no inter-frequency (inter-channel) bias between
//! the two receivers, i.e. identical receivers; a common code-phase bias only shifts `N_r`, whose error
//! enters through `lambda_k - lambda_r` (at most 0.45 % of `lambda`, so a metre of code error in `N_r`
//! moves a double difference by under 5 mm times `(k_k - k_r) / 13`).
//!
//! Attitude mode ([`constrained`]): every rover's baseline from its own double differences, the integer
//! candidates screened and scored with the known antenna geometry (length constraint and the rigid-body
//! fit of the multivariate constrained LAMBDA, Teunissen 2010, J. Geodesy 84:751-762), then the rotation
//! ENU <- body from Wahba's problem ([`crate::wahba`]).
//!
//! A known antenna separation ([`known_length`], baseline mode): the length-constrained integer
//! least-squares problem of the GNSS compass (Teunissen 2010, J. Geodesy 84:433-447), searched by
//! expansion with a guarantee and gated by its own simulated success rate.
//!
//! Limits: [`MAX_SIGNALS`] signals per epoch, [`MAX_EPOCHS`] epochs per call, at most
//! [`crate::lambda::ldl::MAX_DIMENSION`] ambiguities in one solution; attitude mode: at most
//! [`constrained::MAX_ROVERS`] rovers, [`constrained::MAX_CANDIDATES`] integer candidates per rover and
//! [`constrained::MAX_COMBINATIONS`] combinations scored per search.
//!
//! Cost (`benches/gnss.rs`, group `rtk_87dd`, one epoch of 87 double differences, shared 2-core bench
//! machine): float solution about 0.36 ms, [`crate::lambda::Problem::new`] (decorrelation and its exact
//! checks) about 3 ms, `solve_baseline` 5-8 ms with partial fixing, which reuses the full set's
//! decorrelation; a fully fixed epoch of the simulated 58-DD session costs about 1.8 ms of CPU in all.

pub mod constrained;
pub mod dd;
pub mod filter;
pub mod fix;
pub mod float;
pub mod glonass;
pub mod known_length;
pub mod model;
pub mod rigid;

#[cfg(test)]
pub(crate) mod sim;
#[cfg(test)]
mod tests;

use nalgebra::{Matrix3, Vector3};

use super::geometry::{enu_from_ecef, geodetic_from_ecef, SatGeometry};
use super::signal::System;
use super::solution::N_SYSTEMS;

pub use constrained::{fix_attitude_filtered, solve_attitude, solve_attitude_held, HeldAttitude};
pub use fix::solve_baseline;
pub use known_length::solve_known_length;

/// Most signals (satellite x slot) in one epoch.
pub const MAX_SIGNALS: usize = 512;

/// Most epochs in one static solution.
pub const MAX_EPOCHS: usize = 100_000;

/// One (satellite, slot) observed with phase and code by base and rover.
#[derive(Debug, Clone, PartialEq)]
pub struct SignalPair {
    /// Session satellite index.
    pub sat: usize,
    pub system: System,
    /// Frequency slot, `0..MAX_FREQUENCIES`.
    pub slot: usize,
    /// Carrier wavelength of this signal, m.
    pub wavelength_m: f64,
    /// Satellite geometry seen from the base and from the rover (each from its own receiver time and
    /// clock; the rover's computed at `rover_prior_m`).
    pub base: SatGeometry,
    pub rover: SatGeometry,
    /// Pseudoranges, m.
    pub base_code_m: f64,
    pub rover_code_m: f64,
    /// Carrier phases, cycles (any integer offset).
    pub base_phase_cycles: f64,
    pub rover_phase_cycles: f64,
    /// Undifferenced standard deviations of one receiver (elevation-weighted), m.
    pub sigma_code_m: f64,
    pub sigma_phase_m: f64,
    /// Ambiguity identity: the same value while the arc has no slip (the session assigns it; a slip or a
    /// loss of lock gives a new value).
    pub arc: u64,
}

/// One epoch of one base-rover pair.
#[derive(Debug, Clone, PartialEq)]
pub struct DdEpoch {
    /// Base antenna, ECEF m.
    pub base_m: Vector3<f64>,
    /// Approximate rover antenna (code solution), ECEF m: the linearisation point.
    pub rover_prior_m: Vector3<f64>,
    pub signals: Vec<SignalPair>,
}

/// Acceptance of an integer fix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixOptions {
    /// Smallest bootstrapped success rate of the set fixed, in [0, 1].
    pub min_success_rate: f64,
    /// Ratio-test threshold, >= 1.
    pub ratio_threshold: f64,
    /// In [0, 0.1]; 0 turns it off. A full set below `min_success_rate` whose ratio passes
    /// `ratio_threshold` is still fixed when the ratio also passes the fixed-failure-rate threshold
    /// (Teunissen & Verhagen 2009) for this probability of accepting a wrong fix, computed for the epoch's
    /// own float covariance by a seeded simulation ([`crate::lambda::validation::fixed_failure_accepts`],
    /// `ceil(20 / max_failure_rate)` draws), for at most [`FFRT_MAX_AMBIGUITIES`] ambiguities.
    pub max_failure_rate: f64,
}

/// Largest float set the fixed-failure-rate test of [`FixOptions::max_failure_rate`] simulates (its cost
/// grows with the search's: about 2 ms per epoch at 6 ambiguities on one core); larger sets rely on the
/// success-rate gate and partial fixing alone.
pub const FFRT_MAX_AMBIGUITIES: usize = 32;

/// The solution of one baseline (one epoch or a static session).
#[derive(Debug, Clone, PartialEq)]
pub struct BaselineSolution {
    /// Rover minus base, ECEF m: fixed (conditioned on the integers fixed) or float.
    pub baseline_m: Vector3<f64>,
    /// Its covariance, m^2.
    pub covariance_m2: Matrix3<f64>,
    /// All ambiguities fixed and validated (or held).
    pub fixed: bool,
    /// Integer combinations fixed (held ones included) out of `ambiguities`.
    pub fixed_ambiguities: usize,
    /// Double-difference ambiguities of the float solution (held ones included).
    pub ambiguities: usize,
    /// Ratio-test statistic of the full float set (infinite when nothing was left to fix).
    pub ratio: f64,
    /// Bootstrapped success rate of the full float set (1 when nothing was left to fix).
    pub success_rate: f64,
    /// `(arc, reference arc, DD integer)` of every ambiguity fixed (or held), for holding.
    pub integers: Vec<(u64, u64, i64)>,
    /// Reference satellite per system (lowest slot with double differences), session index.
    pub reference_sats: [Option<usize>; N_SYSTEMS],
    /// Bit `slot` set when that slot contributed double differences.
    pub slots_used: u8,
    /// Satellites in the double differences, per system (reference included), largest over epochs.
    pub satellites_per_system: [u16; N_SYSTEMS],
    /// Weighted sum of squared residuals of the float solution and its degrees of freedom. In one epoch
    /// without held integers every phase row has its own ambiguity, so these are the code residuals'.
    pub float_chi2: f64,
    pub float_dof: usize,
}

/// Attitude of a rigid antenna array at one epoch.
#[derive(Debug, Clone, PartialEq)]
pub struct AttitudeSolution {
    /// Rotation ENU <- body at the base antenna (body frame of Bunyaeva et al.: X nose, Y up, Z right wing).
    pub rotation_enu_from_body: Matrix3<f64>,
    /// Each rover's baseline (rover minus base, ECEF m) and covariance; fixed with the constraint when
    /// `fixed`.
    pub baselines: Vec<BaselineSolution>,
    /// Every rover's ambiguities fixed with the geometry constraint and validated.
    pub fixed: bool,
    /// Second-best over best constrained objective (the acceptance statistic); NaN only when no
    /// candidate combination fixes a rotation (then `fixed` is false).
    pub ratio: f64,
    /// The constrained fix's simulated success rate ([`constrained`]; NaN when the ratio or the
    /// plausibility refused the fix first, 1 when every rover's filter fixed it).
    pub success_rate: f64,
}

/// Rotation ENU <- ECEF at an ECEF position (WGS-84 geodetic latitude and longitude).
pub(crate) fn enu_at(ecef_m: &Vector3<f64>) -> Matrix3<f64> {
    let (lat, lon, _) = geodetic_from_ecef(ecef_m);
    enu_from_ecef(lat, lon)
}
