//! The observation engine, one epoch after another: code solutions, satellite geometry, signal
//! selection, arc identities, then double differences and integer fixing ([`crate::gnss::rtk`]) or the
//! ambiguity-function grid ([`crate::likelihood`]), and the epoch's baseline, angles and their sigmas.
//!
//! [`crate::gnss::session::run`] is this engine fed every epoch of a session at once: there is one
//! mechanism, and a stream fed in chunks gives the epochs a whole session gives, except where noted
//! below (static mode and the ML window look at the epochs of one call).
//!
//! # Per epoch
//! 1. Single-point positioning of every receiver ([`crate::gnss::spp::single_point`], seeded with the
//!    receiver's previous solution). The reference antenna ("base", receiver 0) sits at
//!    `base_position_m` when given (a warning, once, when its code solution is more than
//!    [`BASE_WARNING_DISTANCE_M`] away) or at its code solution. An epoch where a receiver has no code
//!    solution is unsolved (a warning names the first such epoch of each receiver).
//! 2. Satellite geometry per receiver at its own reception time and clock (the clock of the
//!    satellite's system from the code solution).
//! 3. Signal selection, per rover: systems in `systems`, slots below `frequencies`, code and phase at
//!    both receivers, a usable ephemeris (geometry exists), base elevation at least the mask, carrier
//!    frequency known (GLONASS channel). Sigmas are elevation-weighted (`phase_sigma`, `code_sigma` at
//!    the base's elevation). Arc identities come from the slip detection of [`arcs`].
//! 4. Estimation: `Lambda`: [`crate::gnss::rtk::solve_baseline`] per rover (baseline mode, no body
//!    baselines; [`crate::gnss::rtk::solve_known_length`] for a rover whose distance is in
//!    `baseline_lengths_m`) or [`crate::gnss::rtk::solve_attitude`] (attitude mode). `Ml`: the likelihood grid on
//!    single differences at the base's reception instant (see [`ml`]); in baseline mode the baseline
//!    length is the known one (`baseline_lengths_m`), else the inverse-variance mean of the LAMBDA solutions' lengths so far (fixed, partially fixed
//!    or float; epochs taken as independent), used once its sigma is below
//!    [`GRID_LENGTH_RELATIVE_SIGMA`] of it. Until then the grid is not run: the epochs keep their LAMBDA
//!    solution and a warning says so (a grid searched at a wrong length returns wrong directions).
//!    `Auto`: `Lambda`, and `Ml` for the epochs `Lambda` does not fix when the baseline is shorter than
//!    [`AUTO_ML_MAX_BASELINE_M`] and its length is known that way (in attitude mode the body baselines
//!    give it). A validated
//!    integer fix is the most accurate answer there is (millimetres), so it is kept whenever it passes
//!    the gate; the grid needs no integers and still gives a direction when the gate refuses them, but
//!    its error grows with the baseline length over wavelength ratio it must search, so beyond 100 m the
//!    float solution is returned instead.
//!
//! # Continuity and static mode
//! With `continuity` (moving, baseline mode) the integers fixed at one epoch are imposed at the next on
//! the arcs that continue (every pair of arcs held against one reference, so a change of reference
//! satellite keeps them); when the fixed solution's double-difference phase residuals of held arcs
//! exceed [`HELD_RESIDUAL_CYCLES`] (an undetected slip), or the held solution is not fixed, or (a rover
//! with a known length) the held integers' chi-square on the epoch's float solution exceeds its
//! [`crate::gnss::rtk::constrained::HOLD_Z`] quantile, the epoch is fixed again without them. In
//! attitude mode `continuity` holds the integers of every rover together
//! ([`crate::gnss::rtk::solve_attitude_held`]): checked each epoch against the float solutions and the
//! body baselines by their chi-square, new arcs fixed on them, replaced by a fresh fix only when the data
//! prefer it by the ratio threshold; a slip restarts only its own arc. In static mode (baseline mode) every call solves one baseline over all
//! epochs seen so far ([`crate::gnss::rtk::solve_baseline`] with every epoch), then each epoch of the
//! call gets its baseline from those integers: over a whole session that is the static solution;
//! streamed, each chunk gets the running solution. Attitude mode has no static mode.

mod arcs;
mod ml;
mod output;
mod parallel;
#[cfg(test)]
mod tests;

use std::borrow::Cow;
use std::collections::BTreeSet;

use nalgebra::{Matrix3, Vector3};

use self::arcs::ArcTracker;
use self::output::{attitude_sigmas_deg, azimuth_elevation, heading_pitch_roll, row_major};
use super::ephemeris::Ephemerides;
use super::geometry::{
    enu_from_ecef, geodetic_from_ecef, satellite_geometry_from, SatGeometry, Site,
};
use super::navdata::NavData;
use super::observations::{Observations, MAX_RECEIVERS};
use super::options::{EngineOptions, Method, Motion};
use super::rtk::constrained::{chi2_quantile_at, HOLD_Z};
use super::rtk::filter::BaselineFilter;
use super::rtk::float;
use super::rtk::rigid::RigidLength;
use super::rtk::{
    model::SdRangeModel, solve_attitude_held, solve_baseline, solve_known_length, AttitudeSolution,
    BaselineSolution, DdEpoch, FixOptions, SignalPair,
};
use super::signal::{SatId, MAX_FREQUENCIES};
use super::solution::{EpochSolution, FixState, N_SYSTEMS};
use super::spp::SppSolution;
use crate::error::{Error, Result};
use crate::interrupt;
use crate::likelihood::dcm_enu_from_body;
use crate::likelihood::{ml_attitude_series, ml_baseline_series, MlEpoch};

/// Distance between `base_position_m` and the base's code solution beyond which a warning is given, m
/// (a code solution is within a few metres; 30 m means a wrong or mistyped survey position, which
/// biases every baseline by about its distance x baseline length / range).
pub const BASE_WARNING_DISTANCE_M: f64 = 30.0;
/// `Method::Auto` falls back to the grid for unfixed epochs only below this baseline length, m.
pub const AUTO_ML_MAX_BASELINE_M: f64 = 100.0;
/// Baseline-mode grid: a LAMBDA epoch gives the baseline length when the length's sigma is below this
/// fraction of it. A length error `dl` shifts each satellite's phase by up to `dl / lambda`; 1 % of 1 m
/// is 0.05 L1 cycles, while 5 % already moved the grid's maximum to a wrong direction in the tests.
pub const GRID_LENGTH_RELATIVE_SIGMA: f64 = 0.01;
/// Largest double-difference phase residual of a held integer, cycles, before the hold is dropped.
pub const HELD_RESIDUAL_CYCLES: f64 = 0.2;

/// One epoch made ready for estimation.
struct Prepared {
    time_gpst_ns: i64,
    /// Reference-antenna position, ECEF m (`None`: unsolved epoch).
    base_m: Option<Vector3<f64>>,
    /// Receiver clocks per system, s (index: receiver; NaN where not estimated).
    clocks_s: Vec<[f64; N_SYSTEMS]>,
    /// Per rover (receiver 1..): its double-difference epoch, `None` where it has no code solution.
    rovers: Vec<Option<DdEpoch>>,
}

/// What an epoch's estimator gave, East-North-Up at the base.
struct Estimate {
    method: Method,
    fixed: bool,
    fix_state: FixState,
    fixed_ambiguities: usize,
    ambiguities: usize,
    ratio: f64,
    success_rate: f64,
    baselines_enu_m: Vec<Vector3<f64>>,
    covariances_enu_m2: Vec<Matrix3<f64>>,
    enu_from_body: Option<Matrix3<f64>>,
    attitude_sigmas_deg: Option<[f64; 3]>,
}

/// The streaming engine: state carried from one call of [`Engine::process`] to the next.
pub struct Engine {
    eph: Ephemerides,
    nav: NavData,
    opts: EngineOptions,
    sats: Vec<SatId>,
    glonass_channel: Vec<Option<i8>>,
    n_receivers: usize,
    arcs: ArcTracker,
    previous_time_ns: Option<i64>,
    spp_prior: Vec<Option<Vector3<f64>>>,
    /// Per rover: integers held from the previous epoch (continuity).
    held: Vec<Vec<(u64, u64, i64)>>,
    /// Per rover: the multi-epoch filter (`EngineOptions::filter`).
    filters: Vec<BaselineFilter>,
    /// Per rover: the baseline length from the LAMBDA solutions so far (the grid's in baseline mode).
    length: Vec<LengthEstimate>,
    /// Per rover: every epoch seen (static mode).
    static_epochs: Vec<Vec<DdEpoch>>,
    /// Per rover: the code noise scale estimated so far (moving mode).
    code_scale: Vec<CodeNoiseScale>,
    double_differences: [[u64; MAX_FREQUENCIES]; N_SYSTEMS],
    usable_signals: u64,
    warnings: Vec<String>,
    warned: BTreeSet<String>,
}

/// Degrees of freedom of code residuals before [`CodeNoiseScale`] departs from the model (its relative
/// standard error is then `sqrt(2 / dof)` = 20 %).
pub const CODE_SCALE_MIN_DOF: f64 = 50.0;

/// Range of the code variance factor applied, both ways (see [`CodeNoiseScale`]): at least `1 / 4` (a
/// sigma half the model's: 0.15 m + 0.15 m / sin el, about what a geodetic receiver's code shows with
/// multipath), at most `10^2`. The floor: the estimate comes from the session's first 50 degrees of
/// freedom (a few minutes, one satellite geometry), while code multipath changes over tens of minutes,
/// and the gate's success rate scales with the code sigma; a receiver that looked quieter than half the
/// model over its first epochs is not trusted further.
pub const CODE_SCALE_FACTOR_RANGE: (f64, f64) = (0.25, 100.0);

/// Range of the code variance factor applied to a rover with a known length (both ways, see
/// `CodeNoiseScale::known_length_factor`): at most `10^2` up, `10^-2` down.
pub const KNOWN_LENGTH_FACTOR_RANGE: (f64, f64) = (0.01, 100.0);

/// Variance-component estimate of the receivers' code noise against the model (`code_sigma`,
/// `a^2 + b^2 / sin^2 el`): the float solutions' weighted squared residuals over their degrees of freedom,
/// summed over the epochs solved so far in moving mode (single epochs without held integers, where the
/// residuals are the code double differences'). A receiver noisier than the model makes the float
/// ambiguities look better than they are and the success-rate gate too permissive: the code variances are
/// then scaled up by the estimate, once [`CODE_SCALE_MIN_DOF`] residual degrees of freedom are in. A quieter
/// receiver (the usual case: GEONET's is 0.37 of the model's sigma) makes the gate refuse epochs the data
/// fix: its variances are scaled down, to [`CODE_SCALE_FACTOR_RANGE`]'s floor at most
/// (docs/observation_engine.md has the fix rates and wrong fixes measured either way). A rover with a
/// known length is scaled within [`KNOWN_LENGTH_FACTOR_RANGE`] ([`CodeNoiseScale::known_length_factor`]).
#[derive(Debug, Clone, Copy, Default)]
struct CodeNoiseScale {
    /// Sum of weighted squared residuals with the model's (unscaled) variances.
    chi2: f64,
    dof: f64,
}

impl CodeNoiseScale {
    /// The variance factor to apply to the model's code variances.
    fn factor(&self) -> f64 {
        let (lo, hi) = CODE_SCALE_FACTOR_RANGE;
        self.estimate().map_or(1.0, |f| f.clamp(lo, hi))
    }

    /// The variance factor of a rover with a known length: the estimate either way, within
    /// [`KNOWN_LENGTH_FACTOR_RANGE`]. The constrained fix is gated by a success rate simulated from the
    /// float covariance, which is only as right as the noise model; its ratio test is on the constrained
    /// objective, not the unconstrained ratio whose threshold the unscaled model was calibrated for.
    fn known_length_factor(&self) -> f64 {
        let (lo, hi) = KNOWN_LENGTH_FACTOR_RANGE;
        self.estimate().map_or(1.0, |f| f.clamp(lo, hi))
    }

    /// The estimated variance factor, once [`CODE_SCALE_MIN_DOF`] degrees of freedom are in.
    fn estimate(&self) -> Option<f64> {
        (self.dof >= CODE_SCALE_MIN_DOF).then(|| self.chi2 / self.dof)
    }

    /// Adds a solution computed with the code variances scaled by `factor`.
    fn add(&mut self, sol: &BaselineSolution, factor: f64) {
        self.add_float(sol.float_chi2, sol.float_dof, factor);
    }

    /// Adds a float solution's weighted squared residuals `chi2` of `dof` degrees of freedom, computed
    /// with the code variances scaled by `factor`.
    fn add_float(&mut self, chi2: f64, dof: usize, factor: f64) {
        if dof > 0 && chi2.is_finite() {
            self.chi2 += chi2 * factor;
            self.dof += dof as f64;
        }
    }
}

/// `dd` with every code sigma scaled by `sqrt(factor)`, borrowed unchanged when the factor is 1 (before
/// the estimate stands).
fn scale_code(dd: &DdEpoch, factor: f64) -> Cow<'_, DdEpoch> {
    if factor == 1.0 {
        return Cow::Borrowed(dd);
    }
    let mut out = dd.clone();
    let s = factor.sqrt();
    out.signals.iter_mut().for_each(|p| p.sigma_code_m *= s);
    Cow::Owned(out)
}

/// Inverse-variance mean of baseline lengths: `sum l / sigma^2` and `sum 1 / sigma^2`, `sigma` the
/// baseline's standard deviation along itself.
#[derive(Debug, Clone, Copy, Default)]
struct LengthEstimate {
    weighted_sum: f64,
    weight: f64,
}

impl LengthEstimate {
    fn add(&mut self, baseline_m: &Vector3<f64>, covariance_m2: &Matrix3<f64>) {
        let l = baseline_m.norm();
        if !(l > 0.0 && l.is_finite()) {
            return;
        }
        let u = baseline_m / l;
        let variance = (u.transpose() * covariance_m2 * u)[(0, 0)];
        if variance.is_finite() {
            // A fixed baseline's variance can round to 0: a floor of (0.1 mm)^2 keeps the weight finite.
            let w = 1.0 / variance.max(1e-8);
            self.weighted_sum += w * l;
            self.weight += w;
        }
    }

    /// The length, m, when its sigma is below [`GRID_LENGTH_RELATIVE_SIGMA`] of it; else the length and
    /// sigma so far (NaN before any solution).
    fn known(&self) -> std::result::Result<f64, (f64, f64)> {
        let l = self.weighted_sum / self.weight;
        let sigma = self.weight.sqrt().recip();
        if l > 0.0 && sigma < GRID_LENGTH_RELATIVE_SIGMA * l {
            Ok(l)
        } else {
            Err((l, sigma))
        }
    }
}

/// Errors that leave an epoch unsolved rather than stop the session: everything but an interrupt or a
/// refused amount of work.
fn leaves_epoch_unsolved(e: &Error) -> bool {
    !matches!(e, Error::Interrupted { .. } | Error::TooLarge { .. })
}

impl Engine {
    /// Checks the options and builds the ephemerides.
    ///
    /// # Arguments
    /// * `nav` - broadcast records of the session.
    /// * `opts` - settings ([`EngineOptions::validate`]); attitude mode when `body_baselines_m` is not
    ///   empty, which then needs `n_receivers == body_baselines_m.len() + 1`.
    /// * `sats`, `glonass_channel` - the satellites of every later [`Observations`] and their channels.
    /// * `n_receivers` - antennas, the reference antenna first, 2..=[`MAX_RECEIVERS`].
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for a bad option, receiver count or channel list;
    /// the errors of [`Ephemerides::new`].
    pub fn new(
        nav: &NavData,
        opts: EngineOptions,
        sats: Vec<SatId>,
        glonass_channel: Vec<Option<i8>>,
        n_receivers: usize,
    ) -> Result<Engine> {
        opts.validate()?;
        if !(2..=MAX_RECEIVERS).contains(&n_receivers) {
            return Err(Error::out_of_range(
                "observations",
                format!("expected 2..={MAX_RECEIVERS} receivers, got {n_receivers}"),
            ));
        }
        if !opts.body_baselines_m.is_empty() && opts.body_baselines_m.len() + 1 != n_receivers {
            return Err(Error::out_of_range(
                "baselines",
                format!(
                    "expected one body baseline per rover ({}), got {}",
                    n_receivers - 1,
                    opts.body_baselines_m.len()
                ),
            ));
        }
        if !opts.baseline_lengths_m.is_empty() && opts.baseline_lengths_m.len() + 1 != n_receivers {
            return Err(Error::out_of_range(
                "--baseline-length",
                format!(
                    "expected one length per rover ({}), got {}",
                    n_receivers - 1,
                    opts.baseline_lengths_m.len()
                ),
            ));
        }
        if glonass_channel.len() != sats.len() {
            return Err(Error::Shape {
                name: "glonass_channel",
                expected: format!("({},)", sats.len()),
                actual: format!("({},)", glonass_channel.len()),
            });
        }
        let eph = Ephemerides::new(nav)?;
        let mut warnings = eph.skip_warnings();
        for &system in &opts.systems {
            let seen: Vec<&SatId> = sats.iter().filter(|s| s.system == system).collect();
            if !seen.is_empty() && !seen.iter().any(|&&s| eph.has(s)) {
                warnings.push(format!(
                    "--systems includes {} ({}), but the navigation data has no ephemeris of any of its \
                     {} satellites observed: none of them is used",
                    system.letter(),
                    system.slot_names()[0],
                    seen.len()
                ));
            }
        }
        let n_rovers = n_receivers - 1;
        let filters = match opts.filter {
            Some(d) => (0..n_rovers)
                .map(|r| {
                    let f = BaselineFilter::new(d)?;
                    Ok(match opts.baseline_lengths_m.get(r) {
                        Some(&l) => f.with_length(RigidLength::known(l)),
                        None if opts.rigid => f.with_length(RigidLength::learned()),
                        None => f,
                    })
                })
                .collect::<Result<Vec<_>>>()?,
            None => Vec::new(),
        };
        Ok(Engine {
            eph,
            nav: nav.clone(),
            arcs: ArcTracker::new(sats.len(), n_receivers),
            opts,
            glonass_channel,
            n_receivers,
            previous_time_ns: None,
            spp_prior: vec![None; n_receivers],
            held: vec![Vec::new(); n_rovers],
            filters,
            length: vec![LengthEstimate::default(); n_rovers],
            static_epochs: vec![Vec::new(); n_rovers],
            code_scale: vec![CodeNoiseScale::default(); n_rovers],
            double_differences: [[0; MAX_FREQUENCIES]; N_SYSTEMS],
            usable_signals: 0,
            warnings,
            warned: BTreeSet::new(),
            sats,
        })
    }

    /// Things a user should know, one sentence each, in the order they arose.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Double differences formed so far per system and slot.
    pub fn double_differences(&self) -> [[u64; MAX_FREQUENCIES]; N_SYSTEMS] {
        self.double_differences
    }

    /// Per rover, the estimated code sigma scale against the model (square root of the variance factor,
    /// [`CodeNoiseScale`]: applied when above 1); NaN until [`CODE_SCALE_MIN_DOF`] residual degrees of
    /// freedom are in, and in static mode.
    pub fn code_sigma_scale(&self) -> Vec<f64> {
        self.code_scale
            .iter()
            .map(|c| c.estimate().map_or(f64::NAN, f64::sqrt))
            .collect()
    }

    /// Whether every rover's code noise scale has its [`CODE_SCALE_MIN_DOF`] degrees of freedom.
    pub fn code_scale_calibrated(&self) -> bool {
        self.code_scale.iter().all(|c| c.estimate().is_some())
    }

    /// Starts this engine's code noise scale from `other`'s residuals (an engine of the same receivers
    /// that processed the first epochs of the session: see [`crate::gnss::session::run`]).
    pub fn calibrate_code_scale(&mut self, other: &Engine) {
        if other.code_scale.len() == self.code_scale.len() {
            self.code_scale.clone_from(&other.code_scale);
        }
    }

    /// Signals (satellite and slot pairs at base and rover) selected so far over every epoch.
    pub fn usable_signals(&self) -> u64 {
        self.usable_signals
    }

    fn attitude_mode(&self) -> bool {
        !self.opts.body_baselines_m.is_empty()
    }

    fn warn_once(&mut self, key: String, message: String) {
        if self.warned.insert(key) {
            self.warnings.push(message);
        }
    }

    /// Processes the epochs of `obs`, which has the satellites, channels and receivers given to
    /// [`Engine::new`] and epochs after every epoch processed before.
    ///
    /// # Returns
    /// One [`EpochSolution`] per epoch of `obs`, unsolved (NaN, `solved == false`) where the epoch had
    /// no code solution or too few signals.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] / [`Error::Shape`] for observations that do not match the engine or are
    /// not after the epochs already processed, the errors of [`Observations::validate`],
    /// [`Error::Interrupted`] on [`crate::interrupt::request`], [`Error::TooLarge`] from the estimators.
    pub fn process(&mut self, obs: &Observations) -> Result<Vec<EpochSolution>> {
        obs.validate()?;
        if obs.sats != self.sats || obs.glonass_channel != self.glonass_channel {
            return Err(Error::out_of_range(
                "observations",
                "expected the satellites and GLONASS channels the engine was created with",
            ));
        }
        if obs.receivers.len() != self.n_receivers {
            return Err(Error::out_of_range(
                "observations",
                format!(
                    "expected {} receivers, the number the engine was created with, got {}",
                    self.n_receivers,
                    obs.receivers.len()
                ),
            ));
        }
        if let (Some(prev), Some(&first)) = (self.previous_time_ns, obs.time_gpst_ns.first()) {
            if first <= prev {
                return Err(Error::out_of_range(
                    "time_gpst_ns",
                    format!(
                        "expected epochs after the last one processed ({prev} ns), got {first} ns"
                    ),
                ));
            }
        }
        let mut prepared = Vec::with_capacity(obs.n_epochs());
        for start in (0..obs.n_epochs()).step_by(parallel::BLOCK) {
            let end = (start + parallel::BLOCK).min(obs.n_epochs());
            for (k, spp) in (start..end).zip(self.code_solutions(obs, start..end)) {
                interrupt::check("GNSS engine")?;
                prepared.push(self.prepare(obs, k, spp)?);
                self.previous_time_ns = Some(obs.time_gpst_ns[k]);
            }
        }
        let mut estimates = self.lambda(&prepared)?;
        if self.opts.method != Method::Lambda && self.opts.filter.is_none() {
            self.grid(&prepared, &mut estimates)?;
        }
        Ok(prepared
            .iter()
            .zip(estimates)
            .map(|(p, e)| self.epoch_solution(p, e))
            .collect())
    }

    /// Step 1-3 of the module documentation for epoch `k` of `obs`, from its code solutions `spp` (one
    /// per receiver, [`Engine::code_solutions`]).
    fn prepare(
        &mut self,
        obs: &Observations,
        k: usize,
        spp: Vec<Result<SppSolution>>,
    ) -> Result<Prepared> {
        self.arcs.advance(obs, k);
        let t = obs.time_gpst_ns[k];
        let mut positions = Vec::with_capacity(self.n_receivers);
        let mut clocks_s = Vec::with_capacity(self.n_receivers);
        for (r, spp) in spp.into_iter().enumerate() {
            match spp {
                Ok(spp) => {
                    positions.push(Some((spp.position_m, spp.geometry)));
                    clocks_s.push(spp.clock_s);
                }
                Err(e) if leaves_epoch_unsolved(&e) => {
                    self.warn_once(
                        format!("spp {r}"),
                        format!(
                            "receiver {r} has no code solution at epoch {k} ({t} ns GPST): {e}; epochs \
                             without one are unsolved"
                        ),
                    );
                    positions.push(None);
                    clocks_s.push([f64::NAN; N_SYSTEMS]);
                }
                Err(e) => return Err(e),
            }
        }
        // The base's geometry: the code solution's, or at the surveyed position (computed with the code
        // solution: `Engine::code_solutions`).
        let base = match (self.opts.base_position_m, positions[0].take()) {
            (Some(given), code) => {
                let given = Vector3::from(given);
                if let Some((code, geometry)) = code {
                    let d = (code - given).norm();
                    if d > BASE_WARNING_DISTANCE_M {
                        self.warn_once(
                            "base far".into(),
                            format!(
                                "the reference antenna's code solution is {d:.1} m from --base-position \
                                 at epoch {k} ({t} ns GPST), more than {BASE_WARNING_DISTANCE_M} m: \
                                 check --base-position"
                            ),
                        );
                    }
                    Some((given, geometry))
                } else {
                    None
                }
            }
            (None, code) => code,
        };
        let base_m = base.as_ref().map(|b| b.0);
        let mut rovers = vec![None; self.n_receivers - 1];
        if let Some((base, base_geometry)) = &base {
            for r in 1..self.n_receivers {
                let Some((rover, rover_geometry)) = &positions[r] else {
                    continue;
                };
                let signals = self.select(obs, k, r, base_geometry, rover_geometry);
                self.usable_signals += signals.len() as u64;
                rovers[r - 1] = Some(DdEpoch {
                    base_m: *base,
                    rover_prior_m: *rover,
                    signals,
                });
            }
        }
        Ok(Prepared {
            time_gpst_ns: t,
            base_m,
            clocks_s,
            rovers,
        })
    }

    /// Geometry of every selected-system satellite seen from `receiver_m` with the receiver's clocks
    /// (the clock of the satellite's system, else the first estimated).
    fn geometry(
        &self,
        t: i64,
        clocks_s: &[f64; N_SYSTEMS],
        receiver_m: &Vector3<f64>,
    ) -> Vec<Option<SatGeometry>> {
        let fallback = clocks_s.iter().copied().find(|c| c.is_finite());
        let site = Site::new(receiver_m);
        self.sats
            .iter()
            .map(|&sat| {
                if !self.opts.systems.contains(&sat.system) {
                    return None;
                }
                let own = clocks_s[sat.system.index()];
                let clock = if own.is_finite() { Some(own) } else { fallback }?;
                satellite_geometry_from(&self.eph, sat, t, clock, &site)
            })
            .collect()
    }

    /// Signal pairs of rover `r` at epoch `k` (step 3).
    fn select(
        &self,
        obs: &Observations,
        k: usize,
        r: usize,
        base_geometry: &[Option<SatGeometry>],
        rover_geometry: &[Option<SatGeometry>],
    ) -> Vec<SignalPair> {
        let (b, v) = (&obs.receivers[0], &obs.receivers[r]);
        let mut signals = Vec::new();
        for (s, &sat) in self.sats.iter().enumerate() {
            let (Some(bg), Some(rg)) = (&base_geometry[s], &rover_geometry[s]) else {
                continue;
            };
            if bg.elevation_rad < self.opts.elevation_mask_rad {
                continue;
            }
            for slot in 0..self.opts.frequencies {
                let Some(f) = obs.frequency_hz(s, slot) else {
                    continue;
                };
                let i = obs.index(k, s, slot);
                let values = [
                    b.code_m[i],
                    v.code_m[i],
                    b.phase_cycles[i],
                    v.phase_cycles[i],
                ];
                if !values.iter().all(|x| x.is_finite()) {
                    continue;
                }
                let wavelength_m = super::signal::SPEED_OF_LIGHT_M_S / f;
                signals.push(SignalPair {
                    sat: s,
                    system: sat.system,
                    slot,
                    wavelength_m,
                    base: *bg,
                    rover: *rg,
                    base_code_m: values[0],
                    rover_code_m: values[1],
                    base_phase_cycles: values[2],
                    rover_phase_cycles: values[3],
                    sigma_code_m: self.opts.code_sigma.sigma_m(bg.elevation_rad),
                    sigma_phase_m: self.opts.phase_sigma.sigma_m(bg.elevation_rad),
                    arc: self.arcs.arc(r, s, slot),
                });
            }
        }
        signals
    }

    fn fix_options(&self) -> FixOptions {
        FixOptions {
            min_success_rate: self.opts.min_success_rate,
            ratio_threshold: self.opts.ratio_threshold,
            max_failure_rate: self.opts.max_failure_rate,
        }
    }

    /// Counts the double differences of one rover's epoch: per system and slot, signals - 1.
    fn count_double_differences(&mut self, dd: &DdEpoch) {
        let mut n = [[0u64; MAX_FREQUENCIES]; N_SYSTEMS];
        for s in &dd.signals {
            n[s.system.index()][s.slot] += 1;
        }
        for (total, per) in self.double_differences.iter_mut().zip(n) {
            for (t, c) in total.iter_mut().zip(per) {
                *t += c.saturating_sub(1);
            }
        }
    }

    /// LAMBDA estimates of every epoch (`None`: unsolved), in moving, continuity or static mode.
    fn lambda(&mut self, prepared: &[Prepared]) -> Result<Vec<Option<Estimate>>> {
        let fix = self.fix_options();
        if self.attitude_mode() && self.opts.method == Method::Ml {
            // The grid needs nothing from the integer fix when the body baselines are known.
            return Ok(prepared.iter().map(|_| None).collect());
        }
        if self.attitude_mode() {
            let mut out = Vec::with_capacity(prepared.len());
            for (k, p) in prepared.iter().enumerate() {
                interrupt::check("GNSS engine")?;
                let Some(dds) = p
                    .rovers
                    .iter()
                    .map(Option::as_ref)
                    .collect::<Option<Vec<&DdEpoch>>>()
                else {
                    out.push(None);
                    continue;
                };
                dds.iter().for_each(|d| self.count_double_differences(d));
                let factors: Vec<f64> = self.code_scale.iter().map(|c| c.factor()).collect();
                let dds: Vec<DdEpoch> = dds
                    .into_iter()
                    .zip(&factors)
                    .map(|(d, &f)| scale_code(d, f).into_owned())
                    .collect();
                let body = self.opts.body_baselines_m.clone();
                let held: Vec<Vec<(u64, u64, i64)>> = if self.opts.continuity {
                    self.held
                        .iter()
                        .zip(&dds)
                        .map(|(h, d)| present(h, d))
                        .collect()
                } else {
                    Vec::new()
                };
                out.push(match solve_attitude_held(&dds, &body, &fix, &held) {
                    Ok(h) => {
                        for ((c, b), &f) in
                            self.code_scale.iter_mut().zip(&h.fresh.baselines).zip(&factors)
                        {
                            c.add(b, f);
                        }
                        if h.rejected {
                            self.warn_once(
                                "attitude hold rejected".into(),
                                format!(
                                    "held integers disagreed with the data at epoch {k} ({} ns GPST) \
                                     and were dropped (an undetected slip, a wrong fix, or a fresh fix \
                                     the data prefer); the epoch is fixed afresh",
                                    p.time_gpst_ns
                                ),
                            );
                        }
                        let a = h.solution;
                        if self.opts.continuity {
                            if a.fixed {
                                for (held, b) in self.held.iter_mut().zip(&a.baselines) {
                                    held.clone_from(&b.integers);
                                }
                            } else if !h.held {
                                self.held.iter_mut().for_each(Vec::clear);
                            }
                        }
                        let state = match (a.fixed, h.held) {
                            (false, _) => FixState::Float,
                            (true, true) => FixState::Held,
                            (true, false) => FixState::Fixed,
                        };
                        p.base_m.map(|b| self.attitude_estimate(&b, &a, state))
                    }
                    Err(e) if leaves_epoch_unsolved(&e) => {
                        self.note_unsolved(k, p.time_gpst_ns, &e);
                        self.held.iter_mut().for_each(Vec::clear);
                        None
                    }
                    Err(e) => return Err(e),
                });
            }
            return Ok(out);
        }
        let n_rovers = self.n_receivers - 1;
        // Per rover, per epoch.
        let mut solutions: Vec<Vec<Option<(BaselineSolution, FixState)>>> =
            Vec::with_capacity(n_rovers);
        for r in 0..n_rovers {
            let mut per_epoch = Vec::with_capacity(prepared.len());
            let static_session = if self.opts.motion == Motion::Static {
                // Epochs without a signal add nothing to the static solution.
                self.static_epochs[r].extend(
                    prepared
                        .iter()
                        .filter_map(|p| p.rovers[r].clone())
                        .filter(|d| !d.signals.is_empty()),
                );
                let all = std::mem::take(&mut self.static_epochs[r]);
                let sol = match self.solve(r, &all, &[], &fix) {
                    Ok(s) => Some(s),
                    Err(e) if leaves_epoch_unsolved(&e) => {
                        self.warn_once(
                            format!("static {r}"),
                            format!("the static baseline of rover {r} has no solution: {e}"),
                        );
                        None
                    }
                    Err(e) => return Err(e),
                };
                self.static_epochs[r] = all;
                sol
            } else {
                None
            };
            if self.opts.motion == Motion::Moving
                && !self.opts.continuity
                && self.opts.filter.is_none()
            {
                solutions.push(self.single_epochs(r, prepared, &fix)?);
                continue;
            }
            for (k, p) in prepared.iter().enumerate() {
                interrupt::check("GNSS engine")?;
                let Some(dd) = &p.rovers[r] else {
                    per_epoch.push(None);
                    continue;
                };
                self.count_double_differences(dd);
                if self.opts.filter.is_some() {
                    let scaled = scale_code(dd, self.code_scale[r].factor());
                    match self.filters[r].step(scaled.as_ref(), p.time_gpst_ns, &fix) {
                        Ok(f) => {
                            if f.hold_rejected {
                                self.warn_once(
                                    format!("hold rejected {r}"),
                                    format!(
                                        "rover {}: held integers disagreed with the filter's float \
                                         ambiguities at epoch {k} ({} ns GPST) and were dropped (an \
                                         undetected slip or a wrong fix); the filter fixes again",
                                        r + 1,
                                        p.time_gpst_ns
                                    ),
                                );
                            }
                            if f.length_refused {
                                self.warn_once(
                                    format!("length refused {r}"),
                                    format!(
                                        "rover {}: a fix at epoch {k} ({} ns GPST) whose length \
                                         disagreed with the pair's (known or learned from earlier \
                                         fixes) was refused",
                                        r + 1,
                                        p.time_gpst_ns
                                    ),
                                );
                            }
                            // An epoch the filter leaves float is solved on its own too (through the
                            // filter's checks of a fix): the filter never fixes fewer epochs than
                            // single epochs.
                            let single = match f.state {
                                FixState::Float => self
                                    .solve(r, std::slice::from_ref(scaled.as_ref()), &[], &fix)
                                    .ok()
                                    .filter(|s| s.fixed && self.filters[r].accepts(s)),
                                _ => None,
                            };
                            if let Some(s) = &single {
                                self.filters[r].learn(s);
                            }
                            if single.as_ref().is_some_and(|s| !f.agrees_with_float(s)) {
                                self.warn_once(
                                    format!("filter float biased {r}"),
                                    format!(
                                        "rover {}: the epoch's own fix at epoch {k} ({} ns GPST) \
                                         disagrees with the filter's float baseline beyond its \
                                         covariance (errors correlated in time, such as code biases \
                                         or the ionosphere, bias the float); the single-epoch fix, \
                                         which passed the gate, is reported",
                                        r + 1,
                                        p.time_gpst_ns
                                    ),
                                );
                            }
                            let (solution, state) = match single {
                                Some(s) => (s, FixState::Fixed),
                                None => (f.solution, f.state),
                            };
                            self.length[r].add(&solution.baseline_m, &solution.covariance_m2);
                            per_epoch.push(Some((solution, state)));
                        }
                        Err(e) if leaves_epoch_unsolved(&e) => {
                            self.note_unsolved(k, p.time_gpst_ns, &e);
                            per_epoch.push(None);
                        }
                        Err(e) => return Err(e),
                    }
                    continue;
                }
                let held = match (&static_session, self.opts.continuity) {
                    (Some(s), _) => present(&s.integers, dd),
                    (None, true) => present(&self.held[r], dd),
                    (None, false) => Vec::new(),
                };
                let factor = if self.opts.baseline_lengths_m.is_empty() {
                    self.code_scale[r].factor()
                } else {
                    self.code_scale[r].known_length_factor()
                };
                let scaled = scale_code(dd, factor);
                let mut result = self.solve(r, std::slice::from_ref(scaled.as_ref()), &held, &fix);
                let mut unheld = held.is_empty();
                let holding = !held.is_empty() && static_session.is_none();
                if static_session.is_none() && !held.is_empty() {
                    // A known length's held set is also checked against the epoch's float solution (the
                    // constrained fix of new arcs leans on it): its chi-square, as attitude mode's.
                    let known_length = self.opts.baseline_lengths_m.get(r).is_some();
                    let keep = matches!(&result, Ok(s) if s.fixed && held_consistent(dd, s, &held))
                        && (!known_length || held_chi2_consistent(scaled.as_ref(), &held));
                    if !keep {
                        result = self.solve(r, std::slice::from_ref(scaled.as_ref()), &[], &fix);
                        unheld = true;
                    }
                }
                if let (Ok(sol), true, None) = (&result, unheld, &static_session) {
                    self.code_scale[r].add(sol, factor);
                }
                match result {
                    Ok(mut sol) => {
                        if self.opts.continuity && static_session.is_none() {
                            self.held[r] = if sol.fixed {
                                sol.integers.clone()
                            } else {
                                Vec::new()
                            };
                        }
                        if let Some(s) = &static_session {
                            sol.ratio = s.ratio;
                            sol.success_rate = s.success_rate;
                        }
                        self.length[r].add(&sol.baseline_m, &sol.covariance_m2);
                        let state = match (sol.fixed, holding && !unheld) {
                            (false, _) => FixState::Float,
                            (true, true) => FixState::Held,
                            (true, false) => FixState::Fixed,
                        };
                        per_epoch.push(Some((sol, state)));
                    }
                    Err(e) if leaves_epoch_unsolved(&e) => {
                        self.note_unsolved(k, p.time_gpst_ns, &e);
                        self.held[r].clear();
                        per_epoch.push(None);
                    }
                    Err(e) => return Err(e),
                }
            }
            solutions.push(per_epoch);
        }
        Ok((0..prepared.len())
            .map(|k| {
                let base = prepared[k].base_m?;
                let sols: Option<Vec<&(BaselineSolution, FixState)>> =
                    solutions.iter().map(|s| s[k].as_ref()).collect();
                let sols = sols?;
                let states: Vec<FixState> = sols.iter().map(|s| s.1).collect();
                let sols: Vec<&BaselineSolution> = sols.iter().map(|s| &s.0).collect();
                Some(baseline_estimate(&base, &sols, &states))
            })
            .collect())
    }

    /// Rover `r`'s baseline over `epochs`: with its known length when there is one.
    fn solve(
        &self,
        r: usize,
        epochs: &[DdEpoch],
        held: &[(u64, u64, i64)],
        fix: &FixOptions,
    ) -> Result<BaselineSolution> {
        match self.opts.baseline_lengths_m.get(r) {
            Some(&l) => solve_known_length(epochs, held, l, fix),
            None => solve_baseline(epochs, held, fix),
        }
    }

    fn note_unsolved(&mut self, k: usize, t: i64, e: &Error) {
        self.warn_once(
            format!("unsolved {:?}", std::mem::discriminant(e)),
            format!("epoch {k} ({t} ns GPST) has no solution: {e}; such epochs are unsolved"),
        );
    }

    /// Attitude-mode estimate from the constrained fix: baselines and covariances in ENU at the base,
    /// angle sigmas propagated from the rovers' baseline covariances.
    fn attitude_estimate(
        &self,
        base: &Vector3<f64>,
        a: &AttitudeSolution,
        fix_state: FixState,
    ) -> Estimate {
        let (lat, lon, _) = geodetic_from_ecef(base);
        let r = enu_from_ecef(lat, lon);
        let baselines_enu_m: Vec<Vector3<f64>> =
            a.baselines.iter().map(|b| r * b.baseline_m).collect();
        let covariances_enu_m2: Vec<Matrix3<f64>> = a
            .baselines
            .iter()
            .map(|b| r * b.covariance_m2 * r.transpose())
            .collect();
        let sigmas = attitude_sigmas_deg(
            &a.rotation_enu_from_body,
            &baselines_enu_m,
            &covariances_enu_m2,
        );
        Estimate {
            method: Method::Lambda,
            fixed: a.fixed,
            fix_state,
            fixed_ambiguities: a.baselines.iter().map(|b| b.fixed_ambiguities).sum(),
            ambiguities: a.baselines.iter().map(|b| b.ambiguities).sum(),
            ratio: a.ratio,
            success_rate: a.success_rate,
            baselines_enu_m,
            covariances_enu_m2,
            enu_from_body: Some(a.rotation_enu_from_body),
            attitude_sigmas_deg: Some(sigmas),
        }
    }

    /// Replaces the estimates the method gives to the grid (step 4): every solvable epoch for `Ml`,
    /// the unfixed ones within [`AUTO_ML_MAX_BASELINE_M`] for `Auto`.
    fn grid(&mut self, prepared: &[Prepared], estimates: &mut [Option<Estimate>]) -> Result<()> {
        let method = self.opts.method;
        let wanted = move |e: &Option<Estimate>, length: f64| match method {
            Method::Ml => true,
            _ => !e.as_ref().is_some_and(|e| e.fixed) && length < AUTO_ML_MAX_BASELINE_M,
        };
        if self.attitude_mode() {
            let picks: Vec<usize> = (0..prepared.len())
                .filter(|&k| prepared[k].rovers.iter().all(Option::is_some))
                .filter(|&k| wanted(&estimates[k], 0.0))
                .collect();
            let epochs: Vec<Option<MlEpoch>> = picks
                .iter()
                .map(|&k| ml::epoch(&self.eph, &self.sats, &prepared[k], self.n_receivers - 1))
                .collect();
            let solvable: Vec<usize> = (0..picks.len()).filter(|&i| epochs[i].is_some()).collect();
            if solvable.is_empty() {
                return Ok(());
            }
            let series: Vec<MlEpoch> = epochs.into_iter().flatten().collect();
            let sols = match ml_attitude_series(
                &series,
                &self.opts.body_baselines_m,
                self.opts.ml_step_rad,
                self.opts.ml_window_rad,
            ) {
                Ok(s) => s,
                Err(e) if leaves_epoch_unsolved(&e) => {
                    self.warn_once("ml".into(), format!("the likelihood grid failed: {e}"));
                    return Ok(());
                }
                Err(e) => return Err(e),
            };
            for (i, sol) in solvable.into_iter().zip(sols) {
                if !sol.solved {
                    continue;
                }
                let k = picks[i];
                let [psi, theta, phi] = sol.euler_gost_rad;
                let m = dcm_enu_from_body(psi, theta, phi);
                estimates[k] = Some(Estimate {
                    baselines_enu_m: self
                        .opts
                        .body_baselines_m
                        .iter()
                        .map(|b| m * Vector3::from(*b))
                        .collect(),
                    covariances_enu_m2: vec![Matrix3::from_element(f64::NAN); self.n_receivers - 1],
                    enu_from_body: Some(m),
                    attitude_sigmas_deg: Some([f64::NAN; 3]),
                    ..ml_estimate()
                });
            }
            return Ok(());
        }
        if self.n_receivers != 2 {
            // The baseline grid has one baseline; several rovers in baseline mode keep LAMBDA.
            return Ok(());
        }
        // The grid's baseline length: a few percent of error in it moves the grid's maximum to a wrong
        // direction, so the grid runs only once the length is known.
        let known = match self.opts.baseline_lengths_m.first() {
            Some(&l) => Ok(l),
            None => self.length[0].known(),
        };
        let length = match known {
            Ok(l) => l,
            Err((l, sigma)) => {
                if self.opts.method == Method::Ml {
                    self.warn_once(
                        "ml length".into(),
                        format!(
                            "the likelihood grid needs the baseline length to {:.0} %, and the solutions so \
                             far give {l:.3} +- {sigma:.3} m: those epochs keep their double-difference \
                             solution (--method lambda), later ones use the grid once the length is known",
                            100.0 * GRID_LENGTH_RELATIVE_SIGMA
                        ),
                    );
                }
                return Ok(());
            }
        };
        let picks: Vec<usize> = (0..prepared.len())
            .filter(|&k| prepared[k].rovers[0].is_some() && wanted(&estimates[k], length))
            .collect();
        let epochs: Vec<Option<MlEpoch>> = picks
            .iter()
            .map(|&k| ml::epoch(&self.eph, &self.sats, &prepared[k], 1))
            .collect();
        let solvable: Vec<usize> = (0..picks.len()).filter(|&i| epochs[i].is_some()).collect();
        if solvable.is_empty() {
            return Ok(());
        }
        let series: Vec<MlEpoch> = epochs.into_iter().flatten().collect();
        let sols = match ml_baseline_series(
            &series,
            length,
            self.opts.ml_step_rad,
            self.opts.ml_window_rad,
        ) {
            Ok(s) => s,
            Err(e) if leaves_epoch_unsolved(&e) => {
                self.warn_once("ml".into(), format!("the likelihood grid failed: {e}"));
                return Ok(());
            }
            Err(e) => return Err(e),
        };
        for (i, sol) in solvable.into_iter().zip(sols) {
            if !sol.solved {
                continue;
            }
            let [az, el] = sol.direction_rad;
            let unit = Vector3::new(az.sin() * el.cos(), az.cos() * el.cos(), el.sin());
            estimates[picks[i]] = Some(Estimate {
                baselines_enu_m: vec![unit * length],
                covariances_enu_m2: vec![Matrix3::from_element(f64::NAN)],
                ..ml_estimate()
            });
        }
        Ok(())
    }

    /// The reported epoch (angles, sigmas, counts) from its estimate.
    fn epoch_solution(&self, p: &Prepared, e: Option<Estimate>) -> EpochSolution {
        let n_rovers = self.n_receivers - 1;
        let n_angles = if self.attitude_mode() { 3 } else { 2 };
        let mut satellites_per_system = [0u16; N_SYSTEMS];
        let mut frequency_slots_used = 0u8;
        let dds: Vec<&DdEpoch> = p.rovers.iter().flatten().collect();
        if e.is_some() {
            if let Some(dd) = dds.first() {
                let mut seen = BTreeSet::new();
                for s in &dd.signals {
                    if seen.insert(s.sat) {
                        satellites_per_system[s.system.index()] += 1;
                    }
                    frequency_slots_used |= 1 << s.slot;
                }
            }
        }
        let base = p.base_m.map_or([f64::NAN; 3], |b| [b.x, b.y, b.z]);
        let Some(e) = e else {
            return EpochSolution {
                time_gpst_ns: p.time_gpst_ns,
                method: match self.opts.method {
                    Method::Ml => Method::Ml,
                    _ => Method::Lambda,
                },
                solved: false,
                fixed: false,
                fix_state: FixState::Float,
                fixed_ambiguities: 0,
                ambiguities: 0,
                ratio: f64::NAN,
                success_rate: f64::NAN,
                baselines_enu_m: vec![[f64::NAN; 3]; n_rovers],
                baseline_covariance_enu_m2: vec![[f64::NAN; 9]; n_rovers],
                angles_deg: vec![f64::NAN; n_angles],
                angle_sigmas_deg: vec![f64::NAN; n_angles],
                rotation_enu_from_body: None,
                satellites_per_system,
                frequency_slots_used,
                base_position_m: base,
            };
        };
        let (angles_deg, angle_sigmas_deg) = match e.enu_from_body {
            Some(m) => (
                heading_pitch_roll(&m).to_vec(),
                e.attitude_sigmas_deg.unwrap_or([f64::NAN; 3]).to_vec(),
            ),
            None => {
                let (a, s) = azimuth_elevation(&e.baselines_enu_m[0], &e.covariances_enu_m2[0]);
                (a.to_vec(), s.to_vec())
            }
        };
        EpochSolution {
            time_gpst_ns: p.time_gpst_ns,
            method: e.method,
            solved: true,
            fixed: e.fixed,
            fix_state: e.fix_state,
            fixed_ambiguities: e.fixed_ambiguities,
            ambiguities: e.ambiguities,
            ratio: e.ratio,
            success_rate: e.success_rate,
            baselines_enu_m: e.baselines_enu_m.iter().map(|b| [b.x, b.y, b.z]).collect(),
            baseline_covariance_enu_m2: e.covariances_enu_m2.iter().map(row_major).collect(),
            angles_deg,
            angle_sigmas_deg,
            rotation_enu_from_body: e.enu_from_body.as_ref().map(row_major),
            satellites_per_system,
            frequency_slots_used,
            base_position_m: base,
        }
    }
}

/// An ML estimate's fields that do not depend on the mode.
fn ml_estimate() -> Estimate {
    Estimate {
        method: Method::Ml,
        fixed: false,
        fix_state: FixState::Float,
        fixed_ambiguities: 0,
        ambiguities: 0,
        ratio: f64::NAN,
        success_rate: f64::NAN,
        baselines_enu_m: Vec::new(),
        covariances_enu_m2: Vec::new(),
        enu_from_body: None,
        attitude_sigmas_deg: None,
    }
}

/// The held integers whose two arcs both have a signal at this epoch, for every pair of arcs held
/// against one reference: `N(a, b) = N(a, r) - N(b, r)` and `N(r, b) = -N(b, r)`, so that a change of
/// reference satellite (the float solution keys its ambiguities by arc and reference arc) keeps them.
fn present(held: &[(u64, u64, i64)], dd: &DdEpoch) -> Vec<(u64, u64, i64)> {
    let arcs: BTreeSet<u64> = dd.signals.iter().map(|s| s.arc).collect();
    let mut by_reference: std::collections::BTreeMap<u64, Vec<(u64, i64)>> = Default::default();
    for &(a, r, n) in held {
        if arcs.contains(&a) && arcs.contains(&r) {
            by_reference.entry(r).or_default().push((a, n));
        }
    }
    let mut out = Vec::new();
    for (r, members) in by_reference {
        let with_reference: Vec<(u64, i64)> = std::iter::once((r, 0)).chain(members).collect();
        for &(a, na) in &with_reference {
            for &(b, nb) in &with_reference {
                if a != b {
                    out.push((a, b, na - nb));
                }
            }
        }
    }
    out
}

/// Whether every held integer agrees with the fixed baseline: the double-difference phase minus the
/// ranges to `base + baseline` minus the integer stays within [`HELD_RESIDUAL_CYCLES`] (GLONASS pairs of
/// different wavelengths, whose receiver clock term does not cancel, are not checked).
fn held_consistent(dd: &DdEpoch, sol: &BaselineSolution, held: &[(u64, u64, i64)]) -> bool {
    let model = SdRangeModel::new(&dd.base_m, &(dd.base_m + sol.baseline_m));
    let sd = |s: &SignalPair| {
        (s.rover_phase_cycles - s.base_phase_cycles) - model.range_m(s) / s.wavelength_m
    };
    held.iter().all(|&(arc, reference, n)| {
        let find = |a: u64| dd.signals.iter().find(|s| s.arc == a);
        match (find(arc), find(reference)) {
            (Some(i), Some(j)) if i.wavelength_m == j.wavelength_m => {
                (sd(i) - sd(j) - n as f64).abs() <= HELD_RESIDUAL_CYCLES
            }
            _ => true,
        }
    })
}

/// Whether `held` agrees with the epoch's float solution: the weighted squared residuals the held
/// integers add (chi-square with them imposed minus without) stay within the
/// [`crate::gnss::rtk::constrained::HOLD_Z`] chi-square quantile of the number imposed.
fn held_chi2_consistent(dd: &DdEpoch, held: &[(u64, u64, i64)]) -> bool {
    let one = std::slice::from_ref(dd);
    let (Ok(free), Ok(with)) = (float::solve(one, &[]), float::solve(one, held)) else {
        return false;
    };
    let n = with.used_held.len();
    n == 0 || with.chi2 - free.chi2 <= chi2_quantile_at(n, HOLD_Z)
}

/// Baseline-mode estimate from one solution per rover, East-North-Up at the base.
fn baseline_estimate(
    base: &Vector3<f64>,
    sols: &[&BaselineSolution],
    states: &[FixState],
) -> Estimate {
    let (lat, lon, _) = geodetic_from_ecef(base);
    let r = enu_from_ecef(lat, lon);
    let first = sols[0];
    let fixed = sols.iter().all(|s| s.fixed);
    Estimate {
        method: Method::Lambda,
        fixed,
        fix_state: if !fixed {
            FixState::Float
        } else if states.contains(&FixState::Held) {
            FixState::Held
        } else {
            FixState::Fixed
        },
        fixed_ambiguities: sols.iter().map(|s| s.fixed_ambiguities).sum(),
        ambiguities: sols.iter().map(|s| s.ambiguities).sum(),
        ratio: first.ratio,
        success_rate: first.success_rate,
        baselines_enu_m: sols.iter().map(|s| r * s.baseline_m).collect(),
        covariances_enu_m2: sols
            .iter()
            .map(|s| r * s.covariance_m2 * r.transpose())
            .collect(),
        enu_from_body: None,
        attitude_sigmas_deg: None,
    }
}
