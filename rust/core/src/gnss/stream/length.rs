//! The baseline length from the LAMBDA solutions so far (the grid's in baseline mode).

use nalgebra::{Matrix3, Vector3};

use super::GRID_LENGTH_RELATIVE_SIGMA;

/// Inverse-variance mean of baseline lengths: `sum l / sigma^2` and `sum 1 / sigma^2`, `sigma` the
/// baseline's standard deviation along itself.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct LengthEstimate {
    weighted_sum: f64,
    weight: f64,
}

impl LengthEstimate {
    pub(super) fn add(&mut self, baseline_m: &Vector3<f64>, covariance_m2: &Matrix3<f64>) {
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
    pub(super) fn known(&self) -> std::result::Result<f64, (f64, f64)> {
        let l = self.weighted_sum / self.weight;
        let sigma = self.weight.sqrt().recip();
        if l > 0.0 && sigma < GRID_LENGTH_RELATIVE_SIGMA * l {
            Ok(l)
        } else {
            Err((l, sigma))
        }
    }
}
