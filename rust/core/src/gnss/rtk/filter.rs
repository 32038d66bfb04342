//! A multi-epoch Kalman filter of one baseline (baseline mode): float ambiguities carried across epochs,
//! the baseline propagated by a process model the user chooses, integers fixed on the filter's covariance
//! every epoch and held along their arcs.
//!
//! States: the baseline (3, ECEF m), its velocity (3, m/s) with [`Dynamics::ConstantVelocity`], and one
//! single-difference ambiguity per arc (cycles, minus an integer offset taken when the arc starts). The
//! measurements are the double differences of code and phase of each (system, slot) group, with their
//! exact covariance ([`super::dd::covariance`]); a double-differenced phase maps onto the states as
//! `lambda_k N_k - lambda_r N_r`, so the reference satellite of a group may change from one epoch to the
//! next without touching the states (and GLONASS FDMA needs no reference unknown of its own: the
//! parametrisation RTKLIB uses). The single-difference ambiguities' common part is unobservable and stays
//! at its prior; double differences of them are what the data determine and what is fixed.
//!
//! Per epoch:
//! 1. Prediction over the time since the previous epoch ([`Dynamics`]); ambiguities are constant.
//! 2. Arcs: the state of an arc that is not observed at this epoch is removed (the arc tracker gives a
//!    new arc at every slip, loss-of-lock indicator, gap or missing epoch, so an arc that ends never
//!    comes back); a new arc gets a state at its phase minus code with a sigma of
//!    [`INITIAL_AMBIGUITY_SIGMA_M`] (RTKLIB's initial bias variance), the baseline at the first epoch the
//!    rover's code solution with [`INITIAL_BASELINE_SIGMA_M`].
//! 3. Measurement update (iterated: the ranges are relinearised at the updated baseline until it moves by
//!    less than [`super::float::CONVERGED_M`]; Joseph form for the covariance).
//!    A double-difference ambiguity the update moves beyond [`OUTLIER_SIGMAS`] of its prior sigma is a
//!    slip the detectors missed: its arc is started again and the update repeated (at most
//!    [`MAX_RESTARTS_PER_EPOCH`] times).
//! 4. Fixing on the filter's covariance: the double-difference ambiguities of the epoch's references and
//!    their covariance go through the same gate as a single epoch (`fix::fix_float`: ratio test,
//!    bootstrapped success rate, fixed-failure-rate test, partial fixing).
//! 5. Hold: the integers of a fully fixed epoch are held for the next epochs on the arcs that continue.
//!    A held set is kept only while the filter's float ambiguities agree with it (the chi-square of their
//!    difference within its `1 - 1e-3` quantile, [`HOLD_TEST_Z`]); a fresh validated fix that disagrees
//!    with the held integers replaces them only when the data prefer it by the ratio threshold (the held
//!    candidate's squared distance over the fresh one's), else the epoch keeps the held integers: no jump
//!    from one integer set to another on the strength of one epoch. The held integers never feed back into
//!    the float states (a wrong hold cannot pull the float towards itself).
//!
//! The filter's state per epoch ([`FixState`]): `Fixed` when the epoch's own full set passed the gate (in
//! agreement with what was held), `Held` when every ambiguity is fixed through held integers (new arcs
//! fixed conditionally on them), `Float` otherwise (partially fixed epochs included). The engine then
//! solves a `Float` epoch on its own as well and reports that single-epoch fix instead where the
//! single-epoch gate passes it: the filter never fixes fewer epochs than single epochs do on the same
//! data. Where such a fix disagrees with the filter's float ([`FilterEpoch::agrees_with_float`]) the
//! engine warns: on the real moving rover of `docs/rtklib_comparison.md` the filter's float is biased
//! (its hold test rejects the held integers from the second epoch on) and these fixes agree with
//! RTKLIB's within millimetres.

use std::collections::BTreeMap;

use nalgebra::{Cholesky, DMatrix, DVector, Matrix3, Vector3};

use super::dd::validate;
use super::float::FloatSolution;
use super::rigid::{RigidLength, MIN_FIX_PHASES};
use super::{BaselineSolution, DdEpoch, FixOptions};
use crate::error::{Error, Result};
use crate::gnss::solution::FixState;
use crate::lambda::ldl::MAX_DIMENSION;

mod hold;
mod state;
mod update;

/// Standard deviation of the baseline's first state (per axis), m: the rover's code solution
/// (RTKLIB's initial position variance is 30^2 m^2).
pub const INITIAL_BASELINE_SIGMA_M: f64 = 30.0;
/// Standard deviation of a new velocity state (per axis), m/s (RTKLIB's initial velocity variance).
pub const INITIAL_VELOCITY_SIGMA_M_S: f64 = 10.0;
/// Standard deviation of a new single-difference ambiguity, m (its phase minus code is the start; RTKLIB's
/// initial bias sigma).
pub const INITIAL_AMBIGUITY_SIGMA_M: f64 = 30.0;
/// A double-difference ambiguity that an update moves by more than this many of its prior sigmas (and
/// by [`SLIP_MIN_CYCLES`]) restarts an arc: a slip the arc tracker did not see, which the float
/// ambiguity would otherwise absorb with a variance that no longer covers it. Without a slip the move
/// is Gaussian with at most the prior variance: beyond 6 sigma with probability 2e-9.
pub const OUTLIER_SIGMAS: f64 = 6.0;
/// Largest double-difference phase residual of a held integer, cycles, at the baseline conditioned on
/// the held integers; beyond it the pair's arc is started again (a slip no detector saw).
pub const HELD_RESIDUAL_CYCLES: f64 = 0.2;
/// Smallest move of a double-difference ambiguity counted as a slip, cycles (a slip is a whole or half
/// cycle; the ionosphere's drift on kilometre baselines moves a converged ambiguity by tenths).
pub const SLIP_MIN_CYCLES: f64 = 0.5;
/// Arcs restarted for post-fit outliers at most per epoch (the update is repeated after each).
pub const MAX_RESTARTS_PER_EPOCH: usize = 4;
/// Standard normal quantile of the hold test: a held set is dropped when the chi-square of the float
/// ambiguities' difference from it exceeds its quantile at this point (one-sided `1e-3`).
pub const HOLD_TEST_Z: f64 = 3.090;

/// The process model of the baseline between epochs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Dynamics {
    /// The baseline does not change: no process noise (a static pair; over a session this is the batch
    /// least-squares solution of every epoch).
    Static,
    /// Random walk: the baseline's variance grows by `q_m2_s` m^2 per second on each axis.
    RandomWalk { q_m2_s: f64 },
    /// Constant velocity: white acceleration of spectral density `q_m2_s3` (m/s^2)^2/Hz on each axis.
    ConstantVelocity { q_m2_s3: f64 },
}

impl Dynamics {
    /// Moving platform without a motion model (RTKLIB's kinematic mode resets its position state every
    /// epoch): a random walk of 30 m per square-root second, so that the baseline of each epoch comes
    /// from that epoch's observations and the carried ambiguities.
    pub const KINEMATIC: Dynamics = Dynamics::RandomWalk { q_m2_s: 900.0 };
    /// A vehicle: constant velocity with white acceleration of 1 (m/s^2)^2/Hz.
    pub const VELOCITY: Dynamics = Dynamics::ConstantVelocity { q_m2_s3: 1.0 };

    fn kinematic_states(&self) -> usize {
        match self {
            Dynamics::ConstantVelocity { .. } => 6,
            _ => 3,
        }
    }

    /// Checks the process noise: finite and non-negative.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] naming `--filter`.
    pub fn validate(&self) -> Result<()> {
        let q = match *self {
            Dynamics::Static => 0.0,
            Dynamics::RandomWalk { q_m2_s } => q_m2_s,
            Dynamics::ConstantVelocity { q_m2_s3 } => q_m2_s3,
        };
        if !(q.is_finite() && q >= 0.0) {
            return Err(Error::out_of_range(
                "--filter",
                format!("expected a finite process noise >= 0, got {q}"),
            ));
        }
        Ok(())
    }
}

/// One arc's ambiguity state.
#[derive(Debug, Clone, Copy)]
struct ArcState {
    arc: u64,
    /// Integer taken out of the state, cycles.
    offset: i64,
}

/// What one epoch of the filter gave.
#[derive(Debug, Clone)]
pub struct FilterEpoch {
    /// The epoch's baseline: fixed, held or float ([`Self::state`]).
    pub solution: BaselineSolution,
    pub state: FixState,
    /// The filter's float baseline and covariance after the update (nothing fixed), ECEF m, m^2.
    pub float_baseline_m: Vector3<f64>,
    pub float_covariance_m2: Matrix3<f64>,
    /// Arcs whose ambiguity state was started at this epoch (new satellites, slips, losses of lock).
    pub new_arcs: usize,
    /// Arcs restarted at this epoch because their phase did not fit the others' (an undetected slip).
    pub restarted_arcs: usize,
    /// Whether a held set was dropped at this epoch because the float ambiguities disagreed with it.
    pub hold_rejected: bool,
    /// Whether a fix (fresh or held) was refused at this epoch because its length disagreed with the
    /// rigid pair's ([`BaselineFilter::with_length`]).
    pub length_refused: bool,
    /// The filter's float solution of this epoch's double-difference ambiguities (nothing imposed): what
    /// attitude mode fixes under the body baselines ([`super::constrained`]).
    pub float: FloatSolution,
}

impl FilterEpoch {
    /// Whether the baseline of `other` (another solution of the same epoch: its own single-epoch fix)
    /// agrees with the filter's float baseline: the chi-square of their difference (covariance the sum
    /// of both, which over-covers: the epoch's observations are in the filter's float too) within its
    /// `1 - 1e-3` quantile ([`HOLD_TEST_Z`]). A disagreement says the filter's float is biased (errors
    /// correlated in time that the filter averages as white: code biases between tracking modes,
    /// multipath, the ionosphere of a long baseline) or the other solution is wrong.
    pub fn agrees_with_float(&self, other: &BaselineSolution) -> bool {
        let d = other.baseline_m - self.float_baseline_m;
        let c = self.float_covariance_m2 + other.covariance_m2;
        match Cholesky::new((c + c.transpose()) * 0.5) {
            Some(ch) => d.dot(&ch.solve(&d)) <= chi2_quantile(3, HOLD_TEST_Z),
            None => false,
        }
    }
}

/// The filter of one rover's baseline.
#[derive(Debug, Clone)]
pub struct BaselineFilter {
    dynamics: Dynamics,
    /// Baseline (and velocity) then one ambiguity per arc of `arcs`, in that order.
    x: DVector<f64>,
    p: DMatrix<f64>,
    arcs: Vec<ArcState>,
    time_ns: Option<i64>,
    /// Held integers: per arc, its integer relative to the other held arcs of its (system, slot) (any
    /// common constant: only differences within a group are used).
    held: BTreeMap<u64, i64>,
    /// The rigid pair's length that every fix is checked against (`None`: any length).
    length: Option<RigidLength>,
}

impl BaselineFilter {
    /// A filter with no state yet (the first epoch starts it).
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for a negative or non-finite process noise.
    pub fn new(dynamics: Dynamics) -> Result<BaselineFilter> {
        dynamics.validate()?;
        Ok(BaselineFilter {
            dynamics,
            x: DVector::zeros(0),
            p: DMatrix::zeros(0, 0),
            arcs: Vec::new(),
            time_ns: None,
            held: BTreeMap::new(),
            length: None,
        })
    }

    /// The filter of a rigid pair: every fix's length is checked against `length` (known, or learned
    /// from the fixes this filter reports and those given to `learn`) and refused beyond
    /// [`super::rigid::RIGID_LENGTH_SIGMAS`]; a refused fix is neither reported nor held.
    pub fn with_length(mut self, length: RigidLength) -> BaselineFilter {
        self.length = Some(length);
        self
    }

    /// Whether a fix of this epoch made elsewhere (the single-epoch fallback) passes the filter's own
    /// checks of a fix: [`MIN_FIX_PHASES`] double-differenced phases and the rigid pair's length. An
    /// accepted fix is added to the learned length; one refused for its length alone counts towards
    /// learning the length again ([`RigidLength::refused`]).
    pub fn admit(&mut self, sol: &BaselineSolution) -> bool {
        if sol.ambiguities < MIN_FIX_PHASES {
            return false;
        }
        let ok = self.length_ok(sol) || self.relearn(sol);
        if ok {
            self.learn(sol);
        }
        ok
    }

    /// Adds a reported fix to the learned length.
    fn learn(&mut self, sol: &BaselineSolution) {
        if let Some(l) = &mut self.length {
            l.add(sol);
        }
    }

    /// Counts a redundant fix refused for its length towards learning the length again; whether it
    /// was (the fix now agrees with the length).
    fn relearn(&mut self, sol: &BaselineSolution) -> bool {
        self.length.as_mut().is_some_and(|l| l.refused(sol))
    }

    /// The rigid pair's length as the filter knows it (`None`: not a rigid pair).
    pub fn length(&self) -> Option<&RigidLength> {
        self.length.as_ref()
    }

    fn length_ok(&self, sol: &BaselineSolution) -> bool {
        self.length
            .as_ref()
            .is_none_or(|l| l.consistent(&sol.baseline_m, &sol.covariance_m2))
    }

    fn nk(&self) -> usize {
        self.dynamics.kinematic_states()
    }

    /// Forgets everything but the rigid pair's length (the next epoch starts the filter again).
    pub fn reset(&mut self) {
        *self = BaselineFilter {
            dynamics: self.dynamics,
            x: DVector::zeros(0),
            p: DMatrix::zeros(0, 0),
            arcs: Vec::new(),
            time_ns: None,
            held: BTreeMap::new(),
            length: self.length,
        };
    }

    /// Processes one epoch at `time_gpst_ns` (after the previous one).
    ///
    /// # Errors
    /// The errors of [`validate`] for a bad epoch, [`Error::OutOfRange`] for a time not after the previous
    /// epoch's, [`Error::DegenerateGeometry`] when no group has two signals (the states are kept and
    /// predicted), [`Error::Numerical`] when the innovation covariance is not positive definite, and those
    /// of the fixing gate; [`Error::TooLarge`] beyond [`MAX_DIMENSION`] ambiguities.
    pub fn step(
        &mut self,
        epoch: &DdEpoch,
        time_gpst_ns: i64,
        fix: &FixOptions,
    ) -> Result<FilterEpoch> {
        fix.validate()?;
        validate(epoch, 0)?;
        if epoch.signals.len() > MAX_DIMENSION {
            return Err(Error::too_large(
                "signals",
                epoch.signals.len() as f64,
                MAX_DIMENSION as f64,
                "signals in one filtered epoch (one ambiguity state each)",
            ));
        }
        self.predict(epoch, time_gpst_ns)?;
        let new_arcs = self.update_arcs(epoch);
        let groups = self.groups(epoch);
        if groups.is_empty() {
            return Err(Error::DegenerateGeometry {
                what: "double differences: no system and slot has two satellites".into(),
                matrix: "filter innovation covariance",
                condition: f64::INFINITY,
            });
        }
        let (x_prior, p_prior) = (self.x.clone(), self.p.clone());
        let mut restarted_arcs = 0;
        let (chi2, dof) = loop {
            let (chi2, dof) = self.update(epoch, &groups)?;
            if restarted_arcs == MAX_RESTARTS_PER_EPOCH {
                break (chi2, dof);
            }
            let suspect = self
                .held_outlier(epoch, &groups)
                .or_else(|| self.outlier(epoch, &groups, &x_prior, &p_prior));
            let Some(signal) = suspect else {
                break (chi2, dof);
            };
            (self.x, self.p) = (x_prior.clone(), p_prior.clone());
            self.restart_arc(&epoch.signals[signal]);
            restarted_arcs += 1;
        };
        let float_baseline_m = Vector3::new(self.x[0], self.x[1], self.x[2]);
        let float_covariance_m2 = self.p.fixed_view::<3, 3>(0, 0).into_owned();
        let (solution, state, hold_rejected, length_refused, float) =
            self.fix(epoch, &groups, fix, chi2, dof)?;
        if state != FixState::Float {
            self.learn(&solution);
        }
        Ok(FilterEpoch {
            solution,
            state,
            float_baseline_m,
            float_covariance_m2,
            new_arcs,
            restarted_arcs,
            hold_rejected,
            length_refused,
            float,
        })
    }

    /// The filter's state vector and covariance (baseline first).
    pub fn state(&self) -> (&DVector<f64>, &DMatrix<f64>) {
        (&self.x, &self.p)
    }

    /// Adds `cycles` to the held integer of `arc` (tests: a wrong fix in the held set).
    #[cfg(test)]
    pub(crate) fn corrupt_held(&mut self, arc: u64, cycles: i64) -> bool {
        match self.held.get_mut(&arc) {
            Some(n) => {
                *n += cycles;
                true
            }
            None => false,
        }
    }

    /// The held arcs.
    pub fn held_arcs(&self) -> Vec<u64> {
        self.held.keys().copied().collect()
    }
}

/// Wilson-Hilferty approximation of the chi-square quantile with `dof` degrees of freedom at the standard
/// normal quantile `z` (relative error under 1 % for dof >= 3; at dof 1 and z = 3.09 it gives 11.4 where
/// the exact quantile is 10.8: conservative).
fn chi2_quantile(dof: usize, z: f64) -> f64 {
    let k = dof.max(1) as f64;
    let c = 2.0 / (9.0 * k);
    k * (1.0 - c + z * c.sqrt()).powi(3)
}

#[cfg(test)]
#[path = "filter_tests.rs"]
mod tests;
