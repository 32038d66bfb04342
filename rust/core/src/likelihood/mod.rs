//! Maximum-likelihood attitude from raw carrier phases over a grid of Euler angles.
//!
//! Bunyaeva, Piskorzh, Cheranovsky (KhAI): sufficient statistics (8)-(9), (10)-(14) and
//! (17)-(18), grid step (15), parabolic refinement (16), per-node vectors (19).
//!
//! # Conventions
//! Body axes X forward (nose), Y up, Z right wing. Eq. (5) is written in the GOST normal frame with axis
//! order (North, Up, East): `R_normal_from_body = Ry(psi) Rz(theta) Rx(phi)` (active matrices, the
//! intrinsic sequence [`crate::rotation::euler::YZX`]); at zero angles the nose points North. Positive
//! `psi` turns the nose West (compass heading `= -psi`), positive `theta` raises the nose, positive `phi`
//! lowers the right wing. Lines of sight come in East-North-Up and are permuted to (N, U, E) on intake;
//! [`dcm_enu_from_body`] gives the body -> ENU matrix.
//!
//! # Measurement model
//! `phase_diffs[i][k]` (rad) is the carrier phase at antenna `i + 1` minus antenna 0 for satellite `k`,
//! RINEX sign: `phase_diff_ik = -2 pi / lambda_k * los_k . (R r_i) + osc_i + 2 pi n_ik`, with `osc_i`
//! the oscillator phase of receiver `i` relative to receiver 0 (one value per baseline, the same for
//! every satellite and, for a static platform, every epoch) and `n_ik` an arbitrary integer.
//!
//! # Statistics
//! With `x_ik(R) = phase_diff_ik + g_k . (R r_i)` and `g_k = 2 pi los_k / lambda_k` (rad/m):
//! - [`Statistic::AmbiguityFunction`]: `Z = sum_i | sum_k exp(j x_ik) |`, the oscillator phases
//!   maximised out per baseline. Epochs of a static platform are summed *inside* the modulus (the
//!   oscillator phase is modelled as constant over the batch, so it is one nuisance parameter per
//!   baseline); each (epoch, satellite) pair is then one more term. Works on wrapped phases.
//! - [`Statistic::Mean`]: eqs. (10)-(14) as written, per epoch: `Z = sum_k |1 + sum_i exp(j[dphi_ik +
//!   dg_k . R r_i])|` with the satellite-mean of the (wrapped) phase differences and of `g_k` removed.
//!   The phases enter the mean as given (eq. (13)'s `[.]mod 2 pi` is what a receiver outputs); the
//!   mean of wrapped phases leaves a per-antenna offset `2 pi (sum of integers) / M`, so this
//!   statistic peaks in the wrong place unless the integer cycles are already consistent.
//! - [`Statistic::DoubleDifference`]: eqs. (17)-(18), differences against the highest-elevation
//!   satellite of each epoch; immune to wrapping.
//!
//! With different wavelengths (GLONASS FDMA) the differencing is applied to `g_k = 2 pi los_k /
//! lambda_k`, which is what eqs. (11), (14), (18) become when `lambda` is per satellite.

mod bnb;
mod bound;
mod direction;
mod dirmap;
mod grid;
mod kernel;
mod model;
mod refine;
mod search;
mod series;
#[cfg(test)]
mod series_tests;
#[cfg(test)]
mod tests;

pub use bnb::{box_limit, branch_and_bound, BnbStats, MAX_WORK};
pub use grid::{Axis, Grid};
pub use kernel::{sincos_f32, SINCOS_ABS_ERROR};
pub use model::{dcm_enu_from_body, dcm_normal_from_body, Epoch, Model, Statistic};
pub use refine::{
    estimate, parabolic, polish, Estimate, Refine, Search, AUTO_MAX_STEP, AUTO_MIN_CELLS,
};
pub use search::{evaluate_cells, evaluate_grid, exhaustive_max, GridMax, MAX_CELLS};
pub use series::{
    ml_attitude_series, ml_baseline_series, series_work, MlEpoch, MlSolution, EPOCH_OVERHEAD_CELLS,
    MAX_SERIES_WORK,
};
