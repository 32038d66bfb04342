//! What the engine returns: one [`EpochSolution`] per epoch and a summary of the session.

use super::options::Method;
use super::signal::MAX_FREQUENCIES;

/// Number of systems (per-system counts are indexed by [`crate::gnss::signal::System::index`]).
pub const N_SYSTEMS: usize = 5;

/// How an epoch's integers were settled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FixState {
    /// Not every ambiguity fixed (float, or partially fixed).
    Float,
    /// Every ambiguity fixed and validated at this epoch (the gate on this epoch's own covariance).
    Fixed,
    /// Every ambiguity fixed through integers held from earlier epochs (`continuity`, the filter), not
    /// validated again on this epoch's own.
    Held,
}

impl FixState {
    /// `"float"`, `"fixed"` or `"held"`.
    pub fn name(&self) -> &'static str {
        match self {
            FixState::Float => "float",
            FixState::Fixed => "fixed",
            FixState::Held => "held",
        }
    }
}

/// The solution of one epoch.
#[derive(Debug, Clone, PartialEq)]
pub struct EpochSolution {
    pub time_gpst_ns: i64,
    /// The estimator that produced it (`Lambda` or `Ml`; never `Auto`).
    pub method: Method,
    /// Whether a solution was produced (enough satellites, geometry, convergence).
    pub solved: bool,
    /// Every ambiguity of the epoch fixed and validated (or held along an arc).
    pub fixed: bool,
    /// `Fixed` or `Held` exactly when `fixed`.
    pub fix_state: FixState,
    /// Ambiguities fixed (partial fixing fixes fewer than `ambiguities`).
    pub fixed_ambiguities: usize,
    /// Double-difference ambiguities of the float solution.
    pub ambiguities: usize,
    /// Ratio-test statistic of the set fixed, or of the full float set when nothing passed (a high ratio
    /// with nothing fixed means the success-rate gate refused the set); NaN for `Ml`.
    pub ratio: f64,
    /// Bootstrapped success rate of the full float ambiguity set (NaN for `Ml`).
    pub success_rate: f64,
    /// Rover minus reference antenna, one per rover, East-North-Up at the reference antenna, m (NaN
    /// where unsolved).
    pub baselines_enu_m: Vec<[f64; 3]>,
    /// Their covariances, m^2 (row-major 3 x 3 each).
    pub baseline_covariance_enu_m2: Vec<[f64; 9]>,
    /// Baseline mode: azimuth (clockwise from North) and elevation of the first baseline; attitude mode:
    /// heading, pitch, roll (compass heading = -psi of Bunyaeva et al.'s Y-Z-X sequence). Degrees; NaN where
    /// unsolved.
    pub angles_deg: Vec<f64>,
    /// One-sigma of each angle, degrees (first-order propagation of the baseline covariance).
    pub angle_sigmas_deg: Vec<f64>,
    /// Attitude mode: rotation matrix from body to ENU at the reference antenna, row-major.
    pub rotation_enu_from_body: Option<[f64; 9]>,
    /// Satellites used, per system ([`crate::gnss::signal::System::index`] order).
    pub satellites_per_system: [u16; N_SYSTEMS],
    /// Bit `slot` set when that frequency slot contributed double differences.
    pub frequency_slots_used: u8,
    /// Reference-antenna position used at this epoch, ECEF m.
    pub base_position_m: [f64; 3],
}

impl EpochSolution {
    pub fn satellites(&self) -> usize {
        self.satellites_per_system
            .iter()
            .map(|&n| usize::from(n))
            .sum()
    }
}

/// A session's solution.
#[derive(Debug, Clone, PartialEq)]
pub struct SessionSolution {
    pub epochs: Vec<EpochSolution>,
    /// Double differences formed over the session per system and frequency slot.
    pub double_differences: [[u64; MAX_FREQUENCIES]; N_SYSTEMS],
    /// Things a user should know (a base position far from the code solution, a system without
    /// ephemerides, ...), one sentence each.
    pub warnings: Vec<String>,
    /// Per rover, the code sigma scale estimated from the residuals at the end of the session
    /// (`stream::Engine::code_sigma_scale`; NaN where not estimated).
    pub code_sigma_scale: Vec<f64>,
}
