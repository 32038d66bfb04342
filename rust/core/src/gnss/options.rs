//! Settings of the observation engine, with the defaults a user would expect.

use super::rtk::filter::Dynamics;
use super::rtk::known_length::LENGTH_RANGE_M;
use super::signal::{System, MAX_FREQUENCIES};
use crate::error::{Error, Result};

/// Whether the antennas move during the session.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Motion {
    /// Ambiguities fixed once for the whole session (a static pair).
    Static,
    /// Every epoch fixed on its own (single-epoch), or held along slip-free arcs with `continuity`
    /// (baseline mode only).
    Moving,
}

/// The estimator of each epoch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// `Lambda` where every ambiguity of the epoch is fixed; otherwise the grid (`Ml`) below 100 m once
    /// the baseline length is known to 1 % (body baselines, or fixed epochs), else the `Lambda` float.
    Auto,
    /// Ambiguity-function grid on the wrapped single differences (crate::likelihood).
    Ml,
    /// Double differences, float solution, LAMBDA fixing.
    Lambda,
}

/// Elevation-dependent standard deviation `sigma^2 = a^2 + b^2 / sin^2(el)` of one observable type
/// (one receiver, undifferenced), m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElevationSigma {
    pub a_m: f64,
    pub b_m: f64,
}

impl ElevationSigma {
    /// `sigma(el)`, m, for an elevation in radians (clamped below at 1 degree so that it stays finite).
    pub fn sigma_m(&self, elevation_rad: f64) -> f64 {
        let s = elevation_rad.max(1f64.to_radians()).sin();
        (self.a_m * self.a_m + self.b_m * self.b_m / (s * s)).sqrt()
    }
}

/// Engine settings. `Default` gives: every system, every frequency slot, 10 degree mask, base position
/// from the code solution, moving platform, method auto, success-rate gate 0.5 (chosen by measured wrong-fix rates: docs/observation_engine.md), ratio 3, phase
/// 3 mm + 3 mm / sin(el), code 0.3 m + 0.3 m / sin(el) (RTKLIB's defaults with its code/phase ratio 100).
#[derive(Debug, Clone, PartialEq)]
pub struct EngineOptions {
    /// Systems used (at least one).
    pub systems: Vec<System>,
    /// Number of frequency slots used, 1..=MAX_FREQUENCIES (slots 0..frequencies).
    pub frequencies: usize,
    /// Elevation mask at the reference antenna, rad.
    pub elevation_mask_rad: f64,
    /// Surveyed position of the reference antenna, ECEF m; `None`: its code solution.
    pub base_position_m: Option<[f64; 3]>,
    pub motion: Motion,
    pub method: Method,
    /// Hold fixed integers along slip-free arcs in moving mode, baseline or attitude (refused when
    /// static).
    pub continuity: bool,
    /// Moving mode: a multi-epoch filter of each rover's baseline with this process model
    /// (`rtk::filter`): float ambiguities carried along their arcs, fixing on the filter's covariance,
    /// fix-and-hold; in attitude mode each rover's filter knows its body baseline's length and the
    /// filtered floats are fixed together under the body baselines (`rtk::constrained`). `None`: every
    /// epoch on its own (or `continuity`).
    pub filter: Option<Dynamics>,
    /// With `filter`: the two antennas are on one rigid body (a moving base on the rover's vehicle), so
    /// the baseline's length is a constant; the filter learns it from its fixes and refuses a fix whose
    /// length disagrees (`rtk::rigid`). Wrong for a rover moving against a static base. A known length
    /// (`baseline_lengths_m`) is rigid already.
    pub rigid: bool,
    /// Smallest bootstrapped success rate (from the float covariance) of the ambiguity set fixed; the
    /// largest subset that reaches it is fixed (partial fixing) when the full set does not.
    pub min_success_rate: f64,
    /// Ratio-test threshold (>= 1).
    pub ratio_threshold: f64,
    /// Probability of a wrong fix accepted below the success-rate gate: a full set whose success rate is
    /// under `min_success_rate` is still fixed when its ratio passes both `ratio_threshold` and the
    /// fixed-failure-rate threshold for this probability (`rtk::FixOptions::max_failure_rate`); 0 turns
    /// that off.
    pub max_failure_rate: f64,
    pub phase_sigma: ElevationSigma,
    pub code_sigma: ElevationSigma,
    /// Body-frame antenna positions relative to the reference antenna (attitude mode: Bunyaeva et al.'s body
    /// frame, X nose, Y up, Z right wing), m; empty in baseline mode.
    pub body_baselines_m: Vec<[f64; 3]>,
    /// Baseline mode: each rover's known distance from the reference antenna (a surveyed antenna
    /// separation), m, one per rover; empty when unknown. The integers are then fixed with the length
    /// constraint (`rtk::known_length`), and the grid uses the length.
    pub baseline_lengths_m: Vec<f64>,
    /// ML grid step, rad (`None`: eq. (15) of Bunyaeva et al.); window around the previous epoch's solution,
    /// rad (`None`: whole domain).
    pub ml_step_rad: Option<f64>,
    pub ml_window_rad: Option<f64>,
}

impl Default for EngineOptions {
    fn default() -> Self {
        EngineOptions {
            systems: System::ALL.to_vec(),
            frequencies: MAX_FREQUENCIES,
            elevation_mask_rad: 10f64.to_radians(),
            base_position_m: None,
            motion: Motion::Moving,
            method: Method::Auto,
            continuity: false,
            filter: None,
            rigid: false,
            min_success_rate: 0.5,
            ratio_threshold: 3.0,
            max_failure_rate: 0.0,
            phase_sigma: ElevationSigma {
                a_m: 0.003,
                b_m: 0.003,
            },
            code_sigma: ElevationSigma { a_m: 0.3, b_m: 0.3 },
            body_baselines_m: Vec::new(),
            baseline_lengths_m: Vec::new(),
            ml_step_rad: None,
            ml_window_rad: None,
        }
    }
}

impl EngineOptions {
    /// Checks every setting; the error names the setting as the CLI option it comes from.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] naming the option, the expectation and the value.
    pub fn validate(&self) -> Result<()> {
        self.validate_settings()?;
        self.validate_modes()?;
        self.validate_lengths_and_grid()
    }

    /// Each setting of the signals, the base, the gate, the noise and the body on its own.
    fn validate_settings(&self) -> Result<()> {
        if self.systems.is_empty() {
            return Err(Error::out_of_range(
                "--systems",
                "expected at least one system, got none",
            ));
        }
        if !(1..=MAX_FREQUENCIES).contains(&self.frequencies) {
            return Err(Error::out_of_range(
                "--frequencies",
                format!("expected 1..={MAX_FREQUENCIES}, got {}", self.frequencies),
            ));
        }
        if !(-std::f64::consts::FRAC_PI_2..=std::f64::consts::FRAC_PI_2)
            .contains(&self.elevation_mask_rad)
        {
            return Err(Error::out_of_range(
                "--elevation-mask",
                format!(
                    "expected -90..90 degrees, got {} rad",
                    self.elevation_mask_rad
                ),
            ));
        }
        if let Some(p) = self.base_position_m {
            let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            if !(5.0e6..=1.0e8).contains(&r) {
                return Err(Error::out_of_range(
                    "--base-position",
                    format!("expected an ECEF position 5e6..1e8 m from the Earth's centre, got {r:.6e} m"),
                ));
            }
        }
        check_gate(
            self.min_success_rate,
            self.ratio_threshold,
            self.max_failure_rate,
        )?;
        for (name, s) in [
            ("phase sigma", self.phase_sigma),
            ("code sigma", self.code_sigma),
        ] {
            let ok = |x: f64| x.is_finite() && (0.0..=1e3).contains(&x);
            if !(ok(s.a_m) && ok(s.b_m) && s.a_m + s.b_m > 0.0) {
                return Err(Error::out_of_range(
                    "sigma",
                    format!(
                        "expected {name} a, b in [0, 1000] m, not both 0, got {} and {}",
                        s.a_m, s.b_m
                    ),
                ));
            }
        }
        for (i, b) in self.body_baselines_m.iter().enumerate() {
            if !b.iter().all(|x| x.is_finite() && x.abs() <= 1e4) {
                return Err(Error::out_of_range(
                    "baselines",
                    format!("expected finite body coordinates within 1e4 m, row {i} is {b:?}"),
                ));
            }
        }
        Ok(())
    }

    /// The settings that choose the mode (motion, continuity, filter, rigid, body baselines, lengths)
    /// together: a combination one of them would ignore is refused.
    fn validate_modes(&self) -> Result<()> {
        if self.continuity && self.motion == Motion::Static {
            return Err(Error::out_of_range(
                "--continuity",
                "expected moving motion: a static session fixes one set of integers for all epochs \
                 already, got static and continuity",
            ));
        }
        if let Some(d) = self.filter {
            d.validate()?;
            let refused = if self.motion == Motion::Static {
                Some("static motion (the static mode is the batch solution of every epoch; the filter's \
                      static model is --filter static with moving motion)")
            } else if self.continuity {
                Some("--continuity (the filter holds its own integers)")
            } else if self.method == Method::Ml {
                Some("--method ml (the filter is double differences and LAMBDA)")
            } else {
                None
            };
            if let Some(what) = refused {
                return Err(Error::out_of_range(
                    "--filter",
                    format!("expected moving baseline mode with LAMBDA, got {what}"),
                ));
            }
        }
        if self.rigid
            && (self.filter.is_none()
                || !self.baseline_lengths_m.is_empty()
                || !self.body_baselines_m.is_empty())
        {
            return Err(Error::out_of_range(
                "--rigid",
                "expected --filter without --baseline-length or body baselines (the length of a rigid \
                 pair is learned by the filter; a known length or body baselines are rigid already), \
                 got --rigid without --filter, with a known length or with body baselines",
            ));
        }
        if !self.body_baselines_m.is_empty() && self.motion == Motion::Static {
            return Err(Error::out_of_range(
                "--motion",
                "expected moving with body baselines (attitude mode fixes every epoch on its own), \
                 got static; leave the body baselines out for a static baseline",
            ));
        }
        if !self.baseline_lengths_m.is_empty() && !self.body_baselines_m.is_empty() {
            return Err(Error::out_of_range(
                "--baseline-length",
                "expected either body baselines (attitude mode, their lengths are known) or baseline \
                 lengths (baseline mode), got both",
            ));
        }
        Ok(())
    }

    /// The known baseline lengths and the grid's step and window.
    fn validate_lengths_and_grid(&self) -> Result<()> {
        let (lo, hi) = LENGTH_RANGE_M;
        if let Some(l) = self
            .baseline_lengths_m
            .iter()
            .find(|l| !(lo..=hi).contains(*l))
        {
            return Err(Error::out_of_range(
                "--baseline-length",
                format!("expected lengths in [{lo}, {hi}] m, got {l} m"),
            ));
        }
        for (name, v) in [
            ("--step", self.ml_step_rad),
            ("--window", self.ml_window_rad),
        ] {
            if let Some(x) = v {
                if !(x > 0.0 && x.is_finite()) {
                    return Err(Error::out_of_range(
                        name,
                        format!("expected a positive angle, got {x} rad"),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// Largest `max_failure_rate` accepted: beyond it the fixed-failure-rate test accepts one wrong fix in
/// ten, which no user wants from a validation step.
pub const MAX_FAILURE_RATE: f64 = 0.1;

/// Checks the fixing gate: `min_success_rate` a probability, `ratio_threshold` finite and >= 1,
/// `max_failure_rate` in [0, [`MAX_FAILURE_RATE`]] (the one check, used by [`EngineOptions::validate`] and
/// `rtk::FixOptions::validate`).
///
/// # Errors
/// [`Error::OutOfRange`] naming the CLI option.
pub fn check_gate(
    min_success_rate: f64,
    ratio_threshold: f64,
    max_failure_rate: f64,
) -> Result<()> {
    if !(0.0..=MAX_FAILURE_RATE).contains(&max_failure_rate) {
        return Err(Error::out_of_range(
            "--max-failure-rate",
            format!("expected a probability in [0, {MAX_FAILURE_RATE}] (0: off), got {max_failure_rate}"),
        ));
    }
    if !(0.0..=1.0).contains(&min_success_rate) {
        return Err(Error::out_of_range(
            "--min-success-rate",
            format!("expected a probability in [0, 1], got {min_success_rate}"),
        ));
    }
    if !(ratio_threshold >= 1.0 && ratio_threshold.is_finite()) {
        return Err(Error::out_of_range(
            "--ratio-threshold",
            format!("expected a finite number >= 1, got {ratio_threshold}"),
        ));
    }
    Ok(())
}
