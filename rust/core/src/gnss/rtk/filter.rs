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
//!    their covariance go through the same gate as a single epoch ([`super::fix::fix_float`]: ratio test,
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

use std::collections::{BTreeMap, BTreeSet};

use nalgebra::{Cholesky, DMatrix, DVector, Matrix3, Vector3};

use super::dd::{covariance, groups, validate, Group};
use super::fix::{fix_float, float_result};
use super::float::{Ambiguity, FloatSolution, Summary, CONVERGED_M, MAX_ITERATIONS};
use super::known_length::fix_known_length;
use super::model::SdRangeModel;
use super::rigid::{RigidLength, MIN_FIX_PHASES};
use super::{BaselineSolution, DdEpoch, FixOptions};
use crate::error::{Error, Result};
use crate::gnss::solution::{FixState, N_SYSTEMS};
use crate::lambda::ldl::MAX_DIMENSION;

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
    /// from the fixes this filter reports and those given to [`Self::learn`]) and refused beyond
    /// [`super::rigid::RIGID_LENGTH_SIGMAS`]; a refused fix is neither reported nor held.
    pub fn with_length(mut self, length: RigidLength) -> BaselineFilter {
        self.length = Some(length);
        self
    }

    /// Whether a fix of this epoch made elsewhere (the single-epoch fallback) passes the filter's own
    /// checks of a fix: [`MIN_FIX_PHASES`] double-differenced phases and the rigid pair's length.
    pub fn accepts(&self, sol: &BaselineSolution) -> bool {
        sol.ambiguities >= MIN_FIX_PHASES && self.length_ok(sol)
    }

    /// Adds a reported fix made elsewhere to the learned length.
    pub fn learn(&mut self, sol: &BaselineSolution) {
        if let Some(l) = &mut self.length {
            l.add(sol);
        }
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

    /// Step 1: the baseline (and velocity) propagated to `t`; the first epoch starts the state.
    fn predict(&mut self, epoch: &DdEpoch, t: i64) -> Result<()> {
        let nk = self.nk();
        let Some(t0) = self.time_ns else {
            self.x = DVector::zeros(nk);
            self.p = DMatrix::zeros(nk, nk);
            let b0 = epoch.rover_prior_m - epoch.base_m;
            for i in 0..3 {
                self.x[i] = b0[i];
                self.p[(i, i)] = INITIAL_BASELINE_SIGMA_M.powi(2);
                if nk == 6 {
                    self.p[(3 + i, 3 + i)] = INITIAL_VELOCITY_SIGMA_M_S.powi(2);
                }
            }
            self.time_ns = Some(t);
            return Ok(());
        };
        if t <= t0 {
            return Err(Error::out_of_range(
                "time_gpst_ns",
                format!("expected an epoch after the filter's last one ({t0} ns), got {t} ns"),
            ));
        }
        let dt = (t - t0) as f64 * 1e-9;
        self.time_ns = Some(t);
        match self.dynamics {
            Dynamics::Static => {}
            Dynamics::RandomWalk { q_m2_s } => {
                for i in 0..3 {
                    self.p[(i, i)] += q_m2_s * dt;
                }
            }
            Dynamics::ConstantVelocity { q_m2_s3 } => {
                let n = self.x.len();
                let mut f = DMatrix::<f64>::identity(n, n);
                for i in 0..3 {
                    f[(i, 3 + i)] = dt;
                }
                self.x = &f * &self.x;
                self.p = &f * &self.p * f.transpose();
                // Integrated white acceleration: [dt^3/3, dt^2/2; dt^2/2, dt] q per axis.
                for i in 0..3 {
                    self.p[(i, i)] += q_m2_s3 * dt.powi(3) / 3.0;
                    self.p[(i, 3 + i)] += q_m2_s3 * dt * dt / 2.0;
                    self.p[(3 + i, i)] += q_m2_s3 * dt * dt / 2.0;
                    self.p[(3 + i, 3 + i)] += q_m2_s3 * dt;
                }
            }
        }
        Ok(())
    }

    /// Step 2: states of arcs not observed removed (and their held integers), new arcs started; returns
    /// the number started.
    fn update_arcs(&mut self, epoch: &DdEpoch) -> usize {
        let nk = self.nk();
        let present: BTreeSet<u64> = epoch.signals.iter().map(|s| s.arc).collect();
        let keep: Vec<usize> = (0..nk)
            .chain(
                self.arcs
                    .iter()
                    .enumerate()
                    .filter(|(_, a)| present.contains(&a.arc))
                    .map(|(i, _)| nk + i),
            )
            .collect();
        if keep.len() != self.x.len() {
            self.x = DVector::from_fn(keep.len(), |i, _| self.x[keep[i]]);
            self.p = DMatrix::from_fn(keep.len(), keep.len(), |i, j| self.p[(keep[i], keep[j])]);
            self.arcs.retain(|a| present.contains(&a.arc));
            self.held.retain(|a, _| present.contains(a));
        }
        let known: BTreeSet<u64> = self.arcs.iter().map(|a| a.arc).collect();
        let mut started = 0;
        for s in &epoch.signals {
            if known.contains(&s.arc) {
                continue;
            }
            let start = (s.rover_phase_cycles - s.base_phase_cycles)
                - (s.rover_code_m - s.base_code_m) / s.wavelength_m;
            let offset = start.round() as i64; // |phase| <= 1e13, |code| <= 1e9 (validated): exact
            let n = self.x.len();
            self.x = self.x.clone().insert_row(n, start - offset as f64);
            let mut p = DMatrix::zeros(n + 1, n + 1);
            p.view_mut((0, 0), (n, n)).copy_from(&self.p);
            p[(n, n)] = (INITIAL_AMBIGUITY_SIGMA_M / s.wavelength_m).powi(2);
            self.p = p;
            self.arcs.push(ArcState { arc: s.arc, offset });
            started += 1;
        }
        started
    }

    /// The signal to restart after an update, if a held integer's phase residual at the baseline
    /// conditioned on every held integer exceeds [`HELD_RESIDUAL_CYCLES`]: the worst pair's member, or
    /// the group's reference when every held pair of the group is off by [`SLIP_MIN_CYCLES`]. Where integers are held the float
    /// ambiguities may still be metres loose (a moving baseline's float comes from code), so a slip of
    /// a few cycles hides in them; the held integers pin the baseline to millimetres and show it.
    /// GLONASS FDMA pairs are not checked (their receiver clock term does not cancel).
    fn held_outlier(&self, epoch: &DdEpoch, groups: &[Group]) -> Option<usize> {
        let nk = self.nk();
        // (group, member signal, state k, state r, held DD integer)
        let mut pairs = Vec::new();
        for (gi, g) in groups.iter().enumerate() {
            if g.fdma {
                continue;
            }
            let sr = &epoch.signals[g.reference];
            let Some(&hr) = self.held.get(&sr.arc) else {
                continue;
            };
            for &k in &g.members {
                if let Some(&hk) = self.held.get(&epoch.signals[k].arc) {
                    pairs.push((
                        gi,
                        k,
                        self.state_of(epoch.signals[k].arc),
                        self.state_of(sr.arc),
                        hk - hr,
                    ));
                }
            }
        }
        if pairs.is_empty() {
            return None;
        }
        // The baseline conditioned on the held integers: b - C_bh C_hh^-1 (a_h - z_h).
        let nh = pairs.len();
        let n = self.x.len();
        let mut t = DMatrix::<f64>::zeros(nh, n);
        let mut d = DVector::<f64>::zeros(nh);
        for (j, &(_, _, ik, ir, dd)) in pairs.iter().enumerate() {
            t[(j, ik)] = 1.0;
            t[(j, ir)] = -1.0;
            let offset = self.arcs[ik - nk].offset - self.arcs[ir - nk].offset;
            d[j] = self.x[ik] - self.x[ir] - (dd - offset) as f64;
        }
        let c_hh = &t * &self.p * t.transpose();
        let c_bh = self.p.rows(0, 3) * t.transpose();
        let chol = Cholesky::new((&c_hh + c_hh.transpose()) * 0.5)?;
        let db = &c_bh * chol.solve(&d);
        let b = Vector3::new(self.x[0] - db[0], self.x[1] - db[1], self.x[2] - db[2]);
        let model = SdRangeModel::new(&epoch.base_m, &(epoch.base_m + b));
        let mut worst: Option<(f64, usize)> = None;
        // Per group: held pairs off by more than SLIP_MIN_CYCLES, and in all.
        let mut over = vec![(0usize, 0usize); groups.len()];
        let mut residuals = Vec::with_capacity(nh);
        for &(gi, k, ik, ir, dd) in &pairs {
            let (sk, sr) = (&epoch.signals[k], &epoch.signals[groups[gi].reference]);
            let lam = sr.wavelength_m;
            let (ok, or) = (self.arcs[ik - nk].offset, self.arcs[ir - nk].offset);
            let phase = (sk.rover_phase_cycles - sk.base_phase_cycles - ok as f64)
                - (sr.rover_phase_cycles - sr.base_phase_cycles - or as f64);
            let range = (model.range_m(sk) - model.range_m(sr)) / lam;
            let r = (phase - range - (dd - ok + or) as f64).abs();
            over[gi].1 += 1;
            if r > SLIP_MIN_CYCLES {
                over[gi].0 += 1;
            }
            residuals.push(r);
        }
        for (&(gi, k, ..), &r) in pairs.iter().zip(&residuals) {
            if r > HELD_RESIDUAL_CYCLES && worst.is_none_or(|(w, _)| r > w) {
                let (bad, total) = over[gi];
                // A slip of the reference puts every pair of its group off by its cycles; one blunder
                // spread by the conditioning moves the others by a fraction of a cycle.
                let signal = if total >= 2 && bad == total {
                    groups[gi].reference
                } else {
                    k
                };
                worst = Some((r, signal));
            }
        }
        worst.map(|(_, s)| s)
    }

    /// The signal to restart after an update, if a double-difference ambiguity moved by more than
    /// [`OUTLIER_SIGMAS`] of its prior sigma and [`SLIP_MIN_CYCLES`] (a slip the arc tracker did not see:
    /// the update explains the jump of a phase by its ambiguity, whose prior it contradicts): the worst
    /// pair's member, or the group's reference when most of the group's pairs moved (a slip of the
    /// reference moves every pair).
    fn outlier(
        &self,
        epoch: &DdEpoch,
        groups: &[Group],
        x_prior: &DVector<f64>,
        p_prior: &DMatrix<f64>,
    ) -> Option<usize> {
        let mut worst: Option<(f64, usize)> = None;
        for g in groups {
            let ir = self.state_of(epoch.signals[g.reference].arc);
            let z: Vec<f64> = g
                .members
                .iter()
                .map(|&k| {
                    let ik = self.state_of(epoch.signals[k].arc);
                    // New arcs (the prior's dimension) have no prior to contradict.
                    if ik >= x_prior.len() || ir >= x_prior.len() {
                        return 0.0;
                    }
                    let moved = (self.x[ik] - self.x[ir]) - (x_prior[ik] - x_prior[ir]);
                    let var = p_prior[(ik, ik)] + p_prior[(ir, ir)] - 2.0 * p_prior[(ik, ir)];
                    if moved.abs() < SLIP_MIN_CYCLES {
                        0.0
                    } else {
                        moved.abs() / var.max(0.0).sqrt()
                    }
                })
                .collect();
            let m = z.len();
            let over = z.iter().filter(|&&v| v > OUTLIER_SIGMAS).count();
            if over > 0 {
                let (j, &v) = z
                    .iter()
                    .enumerate()
                    .max_by(|a, b| a.1.total_cmp(b.1))
                    .unwrap_or((0, &0.0));
                let signal = if m >= 2 && 2 * over > m {
                    g.reference
                } else {
                    g.members[j]
                };
                if worst.is_none_or(|(w, _)| v > w) {
                    worst = Some((v, signal));
                }
            }
        }
        worst.map(|(_, s)| s)
    }

    /// Starts the ambiguity state of `s`'s arc again (its phase minus code, uncorrelated, the initial
    /// sigma) and forgets its held integer.
    fn restart_arc(&mut self, s: &super::SignalPair) {
        let i = self.state_of(s.arc);
        let start = (s.rover_phase_cycles - s.base_phase_cycles)
            - (s.rover_code_m - s.base_code_m) / s.wavelength_m;
        let offset = start.round() as i64;
        let nk = self.nk();
        self.arcs[i - nk].offset = offset;
        self.x[i] = start - offset as f64;
        self.p.row_mut(i).fill(0.0);
        self.p.column_mut(i).fill(0.0);
        self.p[(i, i)] = (INITIAL_AMBIGUITY_SIGMA_M / s.wavelength_m).powi(2);
        self.held.remove(&s.arc);
    }

    /// The epoch's groups, each with its reference: the held arc of highest elevation where the group has
    /// held arcs (so that the hold carries over a change of the highest satellite), else the signal of
    /// highest elevation at the base.
    fn groups(&self, epoch: &DdEpoch) -> Vec<Group> {
        groups(epoch)
            .into_iter()
            .map(|mut g| {
                let all: Vec<usize> = std::iter::once(g.reference)
                    .chain(g.members.iter().copied())
                    .collect();
                let held_best = all
                    .iter()
                    .copied()
                    .filter(|&i| self.held.contains_key(&epoch.signals[i].arc))
                    .max_by(|&a, &b| {
                        let (sa, sb) = (&epoch.signals[a], &epoch.signals[b]);
                        sa.base
                            .elevation_rad
                            .total_cmp(&sb.base.elevation_rad)
                            .then(sb.sat.cmp(&sa.sat))
                    });
                if let Some(r) = held_best {
                    if r != g.reference {
                        g.members = all.into_iter().filter(|&i| i != r).collect();
                        g.reference = r;
                    }
                }
                g
            })
            .collect()
    }

    fn state_of(&self, arc: u64) -> usize {
        // Every signal's arc has a state after `update_arcs`.
        self.nk()
            + self
                .arcs
                .iter()
                .position(|a| a.arc == arc)
                .unwrap_or_default()
    }

    /// Step 3: the iterated measurement update; returns the innovations' chi-square and their count.
    fn update(&mut self, epoch: &DdEpoch, groups: &[Group]) -> Result<(f64, usize)> {
        let n = self.x.len();
        let rows: usize = groups.iter().map(|g| 2 * g.members.len()).sum();
        let mut r = DMatrix::<f64>::zeros(rows, rows);
        let mut row = 0;
        for g in groups {
            let m2 = 2 * g.members.len();
            let c = covariance(epoch, g);
            r.view_mut((row, row), (m2, m2))
                .copy_from(&c.view((0, 0), (m2, m2)));
            row += m2;
        }
        let x_prior = self.x.clone();
        let mut xi = x_prior.clone();
        let mut h = DMatrix::<f64>::zeros(rows, n);
        let mut first_chi2 = None;
        for _ in 0..MAX_ITERATIONS {
            let (hi, resid) = self.linearise(epoch, groups, &xi, rows);
            h = hi;
            // Innovation at the prior, to first order about xi: z - h(xi) - H (x_prior - xi).
            let v = &resid - &h * (&x_prior - &xi);
            let s = &h * &self.p * h.transpose() + &r;
            let chol = Cholesky::new((&s + s.transpose()) * 0.5).ok_or_else(|| {
                Error::numerical(
                    "filter update",
                    "the innovation covariance is not positive definite",
                )
            })?;
            if first_chi2.is_none() {
                first_chi2 = Some(v.dot(&chol.solve(&v)));
            }
            let k = chol.solve(&(&h * &self.p)).transpose(); // P H^T S^-1
            let next = &x_prior + &k * v;
            let moved = (0..3)
                .map(|i| (next[i] - xi[i]).powi(2))
                .sum::<f64>()
                .sqrt();
            xi = next;
            if moved < CONVERGED_M {
                let i_kh = DMatrix::<f64>::identity(n, n) - &k * &h;
                let p = &i_kh * &self.p * i_kh.transpose() + &k * &r * k.transpose();
                self.p = (&p + p.transpose()) * 0.5;
                self.x = xi;
                return Ok((first_chi2.unwrap_or(f64::NAN), rows));
            }
        }
        let _ = h;
        Err(Error::Convergence {
            what: "filter measurement update",
            iterations: MAX_ITERATIONS,
        })
    }

    /// Design matrix and `z - h(x)` of every group's double differences at state `x` (code rows then phase
    /// rows per group, the order of [`covariance`]).
    fn linearise(
        &self,
        epoch: &DdEpoch,
        groups: &[Group],
        x: &DVector<f64>,
        rows: usize,
    ) -> (DMatrix<f64>, DVector<f64>) {
        let n = x.len();
        let b = Vector3::new(x[0], x[1], x[2]);
        let model = SdRangeModel::new(&epoch.base_m, &(epoch.base_m + b));
        let mut h = DMatrix::<f64>::zeros(rows, n);
        let mut y = DVector::<f64>::zeros(rows);
        let mut row = 0;
        for g in groups {
            let m = g.members.len();
            let sr = &epoch.signals[g.reference];
            let (rho_r, u_r) = model.range_and_los(sr);
            let ir = self.state_of(sr.arc);
            let or = self.arcs[ir - self.nk()].offset as f64;
            let lam_r = sr.wavelength_m;
            for (j, &k) in g.members.iter().enumerate() {
                let sk = &epoch.signals[k];
                let (rho_k, u_k) = model.range_and_los(sk);
                let ik = self.state_of(sk.arc);
                let ok = self.arcs[ik - self.nk()].offset as f64;
                // One wavelength in a CDMA group (they agree to 1e-9): the large parts cancel exactly.
                let lam_k = if g.fdma { sk.wavelength_m } else { lam_r };
                let hb = -(u_k - u_r);
                let (rc, rp) = (row + j, row + m + j);
                for c in 0..3 {
                    h[(rc, c)] = hb[c];
                    h[(rp, c)] = hb[c];
                }
                h[(rp, ik)] = lam_k;
                h[(rp, ir)] = -lam_r;
                let code = (sk.rover_code_m - sk.base_code_m) - (sr.rover_code_m - sr.base_code_m);
                y[rc] = code - (rho_k - rho_r);
                let phase = lam_k * (sk.rover_phase_cycles - sk.base_phase_cycles - ok)
                    - lam_r * (sr.rover_phase_cycles - sr.base_phase_cycles - or);
                y[rp] = phase - (rho_k - rho_r) - (lam_k * x[ik] - lam_r * x[ir]);
            }
            row += 2 * m;
        }
        (h, y)
    }

    /// Steps 4-5: the epoch's fix, its state, whether a held set was rejected, whether a fix was refused
    /// for its length, the float solution it fixed; updates the held set.
    ///
    /// Beyond the gate: a fix of fewer than [`MIN_FIX_PHASES`] double-differenced phases is not
    /// reported (a fresh one is not held either; held integers stay held for when the satellites
    /// return), and a fix whose length disagrees with the rigid pair's is refused (a held one drops the
    /// held set).
    fn fix(
        &mut self,
        epoch: &DdEpoch,
        groups: &[Group],
        fix: &FixOptions,
        chi2: f64,
        dof: usize,
    ) -> Result<(BaselineSolution, FixState, bool, bool, FloatSolution)> {
        let nk = self.nk();
        let n = self.x.len();
        // Double-difference ambiguities of this epoch's references: a = T x.
        let mut amb: Vec<Ambiguity> = Vec::new();
        let mut t_rows: Vec<(usize, usize)> = Vec::new();
        let mut held_value: Vec<Option<i64>> = Vec::new();
        for g in groups {
            let sr = &epoch.signals[g.reference];
            let ir = self.state_of(sr.arc);
            for &k in &g.members {
                let sk = &epoch.signals[k];
                let ik = self.state_of(sk.arc);
                let offset = self.arcs[ik - nk].offset - self.arcs[ir - nk].offset;
                amb.push(Ambiguity {
                    arc: sk.arc,
                    reference_arc: sr.arc,
                    offset,
                });
                t_rows.push((ik, ir));
                held_value.push(match (self.held.get(&sk.arc), self.held.get(&sr.arc)) {
                    (Some(a), Some(b)) => Some(a - b),
                    _ => None,
                });
            }
        }
        let na = amb.len();
        let mut t = DMatrix::<f64>::zeros(3 + na, n);
        for i in 0..3 {
            t[(i, i)] = 1.0;
        }
        for (j, &(ik, ir)) in t_rows.iter().enumerate() {
            t[(3 + j, ik)] = 1.0;
            t[(3 + j, ir)] = -1.0;
        }
        let f = &t * &self.x;
        let c = {
            let c = &t * &self.p * t.transpose();
            (&c + c.transpose()) * 0.5
        };
        let summary = summary(epoch, groups);
        let float = |idx: &[usize], f: DVector<f64>, c: DMatrix<f64>, used: Vec<(u64, u64)>| {
            FloatSolution {
                baseline_m: Vector3::new(f[0], f[1], f[2]),
                ambiguities_cycles: f.rows(3, f.len() - 3).into_owned(),
                ambiguities: idx.iter().map(|&j| amb[j]).collect(),
                covariance: c,
                chi2,
                dof,
                used_held: used,
                summary: summary.clone(),
            }
        };
        let all: Vec<usize> = (0..na).collect();
        let float_all = float_result(&float(&all, f.clone(), c.clone(), Vec::new()), &[]);
        let redundant = na >= MIN_FIX_PHASES;
        // A known length: the constrained search on the filter's covariance.
        let fresh_float = float(&all, f.clone(), c.clone(), Vec::new());
        let mut fresh = match self.length.and_then(|l| l.known_m()) {
            Some(l) => fix_known_length(&fresh_float, &[], l, fix)?,
            None => fix_float(&fresh_float, &[], fix)?,
        };
        let mut length_refused = false;
        if fresh.fixed && !(redundant && self.length_ok(&fresh)) {
            length_refused = redundant;
            fresh = float_all.clone();
        }
        let fresh_state = if fresh.fixed {
            FixState::Fixed
        } else {
            FixState::Float
        };
        let held_idx: Vec<usize> = (0..na).filter(|&j| held_value[j].is_some()).collect();
        if held_idx.is_empty() {
            self.hold(&fresh);
            return Ok((fresh, fresh_state, false, length_refused, fresh_float));
        }
        // The held integers as values of the ambiguity unknowns (DD integer minus offset).
        let z_h = DVector::from_iterator(
            held_idx.len(),
            held_idx
                .iter()
                .map(|&j| (held_value[j].unwrap_or_default() - amb[j].offset) as f64),
        );
        let pick = |m: &DMatrix<f64>, r: &[usize], s: &[usize]| {
            DMatrix::from_fn(r.len(), s.len(), |i, j| m[(r[i], s[j])])
        };
        let h_rows: Vec<usize> = held_idx.iter().map(|&j| 3 + j).collect();
        let c_hh = pick(&c, &h_rows, &h_rows);
        let d = DVector::from_fn(held_idx.len(), |i, _| f[h_rows[i]]) - &z_h;
        let chol_h = Cholesky::new(c_hh).ok_or_else(|| {
            Error::numerical(
                "filter hold test",
                "the held ambiguities' covariance is not positive definite",
            )
        })?;
        let stat = d.dot(&chol_h.solve(&d));
        if stat > chi2_quantile(held_idx.len(), HOLD_TEST_Z) {
            self.held.clear();
            self.hold(&fresh);
            return Ok((fresh, fresh_state, true, length_refused, fresh_float));
        }
        // Condition the baseline and the other ambiguities on the held integers, then fix the rest.
        let free: Vec<usize> = (0..na).filter(|&j| held_value[j].is_none()).collect();
        let keep: Vec<usize> = (0..3).chain(free.iter().map(|&j| 3 + j)).collect();
        let c_kh = pick(&c, &keep, &h_rows);
        let gain = chol_h.solve(&c_kh.transpose()).transpose(); // C_kh C_hh^-1
        let f_c = DVector::from_fn(keep.len(), |i, _| f[keep[i]]) - &gain * &d;
        let c_c = pick(&c, &keep, &keep) - &gain * c_kh.transpose();
        let c_c = (&c_c + c_c.transpose()) * 0.5;
        let held_list: Vec<(u64, u64, i64)> = held_idx
            .iter()
            .map(|&j| {
                (
                    amb[j].arc,
                    amb[j].reference_arc,
                    held_value[j].unwrap_or_default(),
                )
            })
            .collect();
        let used: Vec<(u64, u64)> = held_list.iter().map(|&(a, r, _)| (a, r)).collect();
        let mut held_sol = fix_float(&float(&free, f_c, c_c, used), &held_list, fix)?;
        held_sol.ratio = fresh.ratio;
        held_sol.success_rate = fresh.success_rate;
        if held_sol.fixed && redundant && !self.length_ok(&held_sol) {
            // The held integers give a length the pair does not have: they were wrong or an arc
            // slipped unseen; the fresh fix (itself checked) takes over.
            self.held.clear();
            self.hold(&fresh);
            return Ok((fresh, fresh_state, true, true, fresh_float));
        }
        if fresh.fixed {
            let agrees = held_list
                .iter()
                .all(|h| fresh.integers.iter().any(|g| g == h));
            // A disagreeing fresh fix replaces the hold only when the data prefer it by the ratio
            // threshold (distances over the full set, same covariance).
            let replace = !agrees && {
                let held_full = held_sol
                    .fixed
                    .then(|| full_vector(&amb, &held_sol.integers));
                let fresh_full = full_vector(&amb, &fresh.integers);
                match (held_full, fresh_full) {
                    (Some(Some(zh)), Some(zf)) => {
                        let a = f.rows(3, na).into_owned();
                        let q = c.view((3, 3), (na, na)).into_owned();
                        match Cholesky::new(q) {
                            Some(ch) => {
                                let dist = |z: &DVector<f64>| {
                                    let e = &a - z;
                                    e.dot(&ch.solve(&e))
                                };
                                dist(&zh) > fix.ratio_threshold * dist(&zf)
                            }
                            None => false,
                        }
                    }
                    _ => true,
                }
            };
            if agrees || replace {
                self.held.clear();
                self.hold(&fresh);
                return Ok((fresh, FixState::Fixed, replace, length_refused, fresh_float));
            }
        }
        if held_sol.fixed {
            self.hold(&held_sol);
        } else {
            // Keep the held integers that occurred (re-expressed against this epoch's references).
            self.set_held(&held_list);
        }
        if !redundant {
            // Held, but nothing in this epoch's phases could show a wrong integer: reported float.
            return Ok((
                float_all,
                FixState::Float,
                false,
                length_refused,
                fresh_float,
            ));
        }
        let state = if held_sol.fixed {
            FixState::Held
        } else {
            FixState::Float
        };
        Ok((held_sol, state, false, length_refused, fresh_float))
    }

    /// Holds the integers of a fully fixed solution (nothing changes otherwise).
    fn hold(&mut self, sol: &BaselineSolution) {
        if sol.fixed {
            self.set_held(&sol.integers);
        }
    }

    /// The held set from `(arc, reference arc, DD integer)` triples of one epoch (one reference per group).
    fn set_held(&mut self, integers: &[(u64, u64, i64)]) {
        self.held.clear();
        for &(a, r, n) in integers {
            self.held.insert(r, 0);
            self.held.insert(a, n);
        }
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

/// The integer vector of the ambiguity unknowns (DD integer minus offset) from a full set of triples;
/// `None` when one is missing.
fn full_vector(amb: &[Ambiguity], integers: &[(u64, u64, i64)]) -> Option<DVector<f64>> {
    let v: Option<Vec<f64>> = amb
        .iter()
        .map(|a| {
            integers
                .iter()
                .find(|&&(x, r, _)| x == a.arc && r == a.reference_arc)
                .map(|&(_, _, n)| (n - a.offset) as f64)
        })
        .collect();
    v.map(DVector::from_vec)
}

/// Which signals and systems contributed (as [`super::float`] reports it).
fn summary(epoch: &DdEpoch, groups: &[Group]) -> Summary {
    let mut s = Summary {
        reference_sats: [None; N_SYSTEMS],
        slots_used: 0,
        satellites_per_system: [0; N_SYSTEMS],
    };
    let mut sats: [BTreeSet<usize>; N_SYSTEMS] = Default::default();
    let mut ref_slot: [usize; N_SYSTEMS] = [usize::MAX; N_SYSTEMS];
    for g in groups {
        let k = g.system.index();
        s.slots_used |= 1 << g.slot;
        for &i in std::iter::once(&g.reference).chain(&g.members) {
            sats[k].insert(epoch.signals[i].sat);
        }
        if g.slot < ref_slot[k] {
            ref_slot[k] = g.slot;
            s.reference_sats[k] = Some(epoch.signals[g.reference].sat);
        }
    }
    for (n, set) in s.satellites_per_system.iter_mut().zip(&sats) {
        *n = u16::try_from(set.len()).unwrap_or(u16::MAX);
    }
    s
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
