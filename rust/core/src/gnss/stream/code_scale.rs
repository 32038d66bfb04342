//! The receivers' code noise against the model, estimated from the float solutions' residuals, and
//! the observation variances scaled by it.
//!
//! # One factor for the whole stochastic model
//! In a single epoch every carrier phase has its own float ambiguity, so the phases have no redundancy:
//! the float baseline is the code solution's, the float ambiguities `a = (phi - rho(b)) / lambda` do not
//! depend on how the code and phase variances are scaled, and the residuals, hence the estimate, are the
//! code's alone. The estimate is the a-posteriori variance factor of unit weight of the model
//! `code_sigma` + `phase_sigma`; a separate phase component is not estimable without phase redundancy
//! (Teunissen & Amiri-Simkooei 2008, J Geod 82:65-82, least-squares variance component estimation).
//! In baseline mode without a known length it is therefore applied to the code and the phase variances
//! together ([`scale_noise`]): a common factor `f` multiplies the float covariance by `f` and every ILS
//! objective `(a - z)^T Q^-1 (a - z)` by `1 / f`, so the ratio test (second best over best) gives the
//! model's ratio whatever `f`, which is what its threshold (3, RTKLIB's, with RTKLIB's code-to-phase
//! sigma ratio of 100) was set for, while the success rate, computed from the scaled covariance, follows
//! the receiver's measured noise. Scaling the code alone ([`scale_code`]) changes the covariance's shape
//! instead: a quiet receiver's code variances down by 4 leave the phase's unmodelled errors (the
//! ionosphere over kilometres, multipath) a larger share of the best candidate's objective, the ratio
//! falls, and epochs RTKLIB fixes with the unscaled model are refused (docs/observation_engine.md, "Code
//! noise scale", has the measurements). A rover with a known length and attitude mode keep the code-only
//! scale: their constrained objective and its gate were calibrated with it.

use std::borrow::Cow;

use crate::gnss::rtk::{BaselineSolution, DdEpoch};

/// Degrees of freedom of code residuals before the code noise scale (`CodeNoiseScale`) departs from the
/// model (its relative standard error is then `sqrt(2 / dof)` = 20 %).
pub const CODE_SCALE_MIN_DOF: f64 = 50.0;

/// Range of the code variance factor applied, both ways (see `CodeNoiseScale`): at least `1 / 4` (a
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
pub(super) struct CodeNoiseScale {
    /// Sum of weighted squared residuals with the model's (unscaled) variances.
    chi2: f64,
    dof: f64,
}

impl CodeNoiseScale {
    /// The variance factor to apply to the model's code variances.
    pub(super) fn factor(&self) -> f64 {
        let (lo, hi) = CODE_SCALE_FACTOR_RANGE;
        self.estimate().map_or(1.0, |f| f.clamp(lo, hi))
    }

    /// The variance factor of a rover with a known length: the estimate either way, within
    /// [`KNOWN_LENGTH_FACTOR_RANGE`]. The constrained fix is gated by a success rate simulated from the
    /// float covariance, which is only as right as the noise model; its ratio test is on the constrained
    /// objective, not the unconstrained ratio whose threshold the unscaled model was calibrated for.
    pub(super) fn known_length_factor(&self) -> f64 {
        let (lo, hi) = KNOWN_LENGTH_FACTOR_RANGE;
        self.estimate().map_or(1.0, |f| f.clamp(lo, hi))
    }

    /// The estimated variance factor, once [`CODE_SCALE_MIN_DOF`] degrees of freedom are in.
    pub(super) fn estimate(&self) -> Option<f64> {
        (self.dof >= CODE_SCALE_MIN_DOF).then(|| self.chi2 / self.dof)
    }

    /// Adds a solution computed with the code variances scaled by `factor`.
    pub(super) fn add(&mut self, sol: &BaselineSolution, factor: f64) {
        self.add_float(sol.float_chi2, sol.float_dof, factor);
    }

    /// Adds a float solution's weighted squared residuals `chi2` of `dof` degrees of freedom, computed
    /// with the code variances scaled by `factor`.
    pub(super) fn add_float(&mut self, chi2: f64, dof: usize, factor: f64) {
        if dof > 0 && chi2.is_finite() {
            self.chi2 += chi2 * factor;
            self.dof += dof as f64;
        }
    }
}

/// `dd` with every code sigma scaled by `sqrt(factor)`, borrowed unchanged when the factor is 1 (before
/// the estimate stands).
pub(super) fn scale_code(dd: &DdEpoch, factor: f64) -> Cow<'_, DdEpoch> {
    if factor == 1.0 {
        return Cow::Borrowed(dd);
    }
    let mut out = dd.clone();
    let s = factor.sqrt();
    out.signals.iter_mut().for_each(|p| p.sigma_code_m *= s);
    Cow::Owned(out)
}

/// `dd` with every code and phase sigma scaled by `sqrt(factor)`: the whole stochastic model scaled by the
/// variance factor (module documentation), borrowed unchanged when the factor is 1.
pub(super) fn scale_noise(dd: &DdEpoch, factor: f64) -> Cow<'_, DdEpoch> {
    if factor == 1.0 {
        return Cow::Borrowed(dd);
    }
    let mut out = dd.clone();
    let s = factor.sqrt();
    out.signals.iter_mut().for_each(|p| {
        p.sigma_code_m *= s;
        p.sigma_phase_m *= s;
    });
    Cow::Owned(out)
}

#[cfg(test)]
#[path = "code_scale_tests.rs"]
mod tests;
