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
//!    the base's elevation). Arc identities come from the slip detection of the private `arcs` module.
//! 4. Estimation: `Lambda`: [`crate::gnss::rtk::solve_baseline`] per rover (baseline mode, no body
//!    baselines; [`crate::gnss::rtk::solve_known_length`] for a rover whose distance is in
//!    `baseline_lengths_m`) or [`crate::gnss::rtk::solve_attitude`] (attitude mode). `Ml`: the likelihood grid on
//!    single differences at the base's reception instant (the private `ml` module); in baseline mode the baseline
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
mod attitude;
mod code_scale;
mod filter;
mod grid;
mod held;
mod lambda;
mod length;
mod ml;
mod output;
mod parallel;
#[cfg(test)]
mod parallel_tests;
#[cfg(test)]
mod tests;

use std::collections::BTreeSet;

use nalgebra::{Matrix3, Vector3};

use self::arcs::ArcTracker;
use self::code_scale::CodeNoiseScale;
pub use self::code_scale::{
    CODE_SCALE_FACTOR_RANGE, CODE_SCALE_MIN_DOF, KNOWN_LENGTH_FACTOR_RANGE,
};
use self::length::LengthEstimate;
use self::output::{azimuth_elevation, heading_pitch_roll, row_major};
use super::ephemeris::Ephemerides;
use super::geometry::SatGeometry;
use super::navdata::NavData;
use super::observations::{Observations, MAX_RECEIVERS};
use super::options::{EngineOptions, Method};
use super::rtk::filter::BaselineFilter;
use super::rtk::rigid::RigidLength;
use super::rtk::{DdEpoch, FixOptions, SignalPair};
use super::signal::{SatId, MAX_FREQUENCIES};
use super::solution::{EpochSolution, FixState, N_SYSTEMS};
use super::spp::SppSolution;
use crate::error::{Error, Result};
use crate::interrupt;

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

/// Errors that leave an epoch unsolved rather than stop the session: everything but an interrupt or a
/// refused amount of work.
fn leaves_epoch_unsolved(e: &Error) -> bool {
    !matches!(e, Error::Interrupted { .. } | Error::TooLarge { .. })
}

/// The receiver count against [`MAX_RECEIVERS`] and the per-rover option lists (body baselines, baseline
/// lengths): each empty or one entry per rover.
fn check_receivers(opts: &EngineOptions, n_receivers: usize) -> Result<()> {
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
    Ok(())
}

/// One warning per requested system that is observed but has no ephemeris for any of its satellites:
/// otherwise the user would see its satellites silently unused.
fn warn_systems_without_ephemeris(
    opts: &EngineOptions,
    sats: &[SatId],
    eph: &Ephemerides,
    warnings: &mut Vec<String>,
) {
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
}

/// One baseline filter per rover when `opts.filter` asks for one (none otherwise), each with its rigid
/// length: a given length (metres) first, else the body baseline's norm (attitude mode), else learned
/// when `opts.rigid`.
fn rover_filters(opts: &EngineOptions, n_rovers: usize) -> Result<Vec<BaselineFilter>> {
    Ok(match opts.filter {
        Some(d) => (0..n_rovers)
            .map(|r| {
                let f = BaselineFilter::new(d)?;
                // Attitude mode: each rover's body baseline gives its length.
                let body = opts
                    .body_baselines_m
                    .get(r)
                    .map(|b| Vector3::from(*b).norm());
                Ok(match opts.baseline_lengths_m.get(r).copied().or(body) {
                    Some(l) => f.with_length(RigidLength::known(l)),
                    None if opts.rigid => f.with_length(RigidLength::learned()),
                    None => f,
                })
            })
            .collect::<Result<Vec<_>>>()?,
        None => Vec::new(),
    })
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
        check_receivers(&opts, n_receivers)?;
        if glonass_channel.len() != sats.len() {
            return Err(Error::Shape {
                name: "glonass_channel",
                expected: format!("({},)", sats.len()),
                actual: format!("({},)", glonass_channel.len()),
            });
        }
        let eph = Ephemerides::new(nav)?;
        let mut warnings = eph.skip_warnings();
        warn_systems_without_ephemeris(&opts, &sats, &eph, &mut warnings);
        let n_rovers = n_receivers - 1;
        let filters = rover_filters(&opts, n_rovers)?;
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
    /// `CodeNoiseScale`: applied when above 1); NaN until [`CODE_SCALE_MIN_DOF`] residual degrees of
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
            // The one place that decides which systems are used: every mode's double differences and
            // the grid's single differences come from these pairs.
            if !self.opts.systems.contains(&sat.system) {
                continue;
            }
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

    fn note_unsolved(&mut self, k: usize, t: i64, e: &Error) {
        self.warn_once(
            format!("unsolved {:?}", std::mem::discriminant(e)),
            format!("epoch {k} ({t} ns GPST) has no solution: {e}; such epochs are unsolved"),
        );
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
