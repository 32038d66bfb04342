//! The one decision whether to accept an integer fix, used by the gyro + GNSS filter
//! ([`crate::gyro_gnss`]), the observation engine's baseline fix ([`crate::gnss::rtk::fix`]), its attitude
//! mode ([`crate::gnss::rtk::constrained`]) and its known-length fix ([`crate::gnss::rtk::known_length`]).
//!
//! Two rules share the settings ([`Gate`]) and the outcome ([`Decision`]):
//! - **ILS** ([`Gate::decide`]): the best integer least-squares candidate is accepted when its ratio test
//!   passes (`R = ||a - z2||^2_Q / ||a - z1||^2_Q >= ratio_threshold`) and either the bootstrapped success
//!   rate of the full set reaches `min_success_rate` or, when `max_failure_rate > 0` and at most
//!   [`FFRT_MAX_AMBIGUITIES`] ambiguities are fixed, the ratio also passes the fixed-failure-rate test
//!   for that probability of a wrong fix ([`super::validation::fixed_failure_accepts`], `ceil(20 /
//!   max_failure_rate)` seeded draws of the epoch's own covariance). [`Gate::before_search`] refuses
//!   without searching when the success rate alone already decides.
//! - **Constrained** ([`Gate::decide_constrained`]): the best candidate of a constrained search (array
//!   geometry, known length) is accepted when its constrained ratio passes, its objective is plausible
//!   (below a chi-square quantile the caller gives) and, where the caller asks for it, its simulated
//!   success rate reaches `min_success_rate` or a floor, whichever is higher (the bootstrapped rate of
//!   the unconstrained float ignores the constraint and is far too pessimistic for it).

use super::bootstrap::success_rate;
use super::validation::{fixed_failure_accepts, ratio_of};
use super::{IlsSolution, Problem};
use crate::error::{Error, Result};

/// Largest `max_failure_rate`: the fixed-failure-rate simulation costs `20 / max_failure_rate` draws, and
/// a larger probability of a wrong fix is no validation.
pub const MAX_FAILURE_RATE: f64 = 0.1;

/// Largest float set the fixed-failure-rate test simulates (its cost grows with the search's: about 2 ms
/// per epoch at 6 ambiguities on one core); larger sets rely on the success-rate gate alone.
pub const FFRT_MAX_AMBIGUITIES: usize = 32;

/// Draws of the fixed-failure-rate simulation per unit of `1 / max_failure_rate`: the threshold is then
/// set by the 21st largest wrong-fix ratio of the draws (relative standard error of the failure rate
/// about 1 / sqrt(20) = 22 %).
const FFRT_DRAWS_PER_FAILURE: f64 = 20.0;

/// Seed of the simulation: the same float solution gives the same decision in every run.
const FFRT_SEED: u64 = 16;

/// The settings of the fixing gate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gate {
    /// Smallest success rate of the set fixed (bootstrapped, or simulated for a constrained rule), in
    /// [0, 1].
    pub min_success_rate: f64,
    /// Ratio-test threshold, finite and >= 1.
    pub ratio_threshold: f64,
    /// Probability of a wrong fix allowed by the fixed-failure-rate test below the success-rate gate, in
    /// [0, [`MAX_FAILURE_RATE`]]; 0 turns the test off.
    pub max_failure_rate: f64,
}

/// The names the caller's users know the three settings by (for the messages of [`Gate::check`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Names {
    pub min_success_rate: &'static str,
    pub ratio_threshold: &'static str,
    pub max_failure_rate: &'static str,
}

impl Names {
    /// The command-line options of the observation engine.
    pub const CLI: Names = Names {
        min_success_rate: "--min-success-rate",
        ratio_threshold: "--ratio-threshold",
        max_failure_rate: "--max-failure-rate",
    };
    /// The Python keyword arguments.
    pub const PYTHON: Names = Names {
        min_success_rate: "min_success_rate",
        ratio_threshold: "ratio_threshold",
        max_failure_rate: "max_failure_rate",
    };
}

/// Why a fix was accepted or refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reason {
    /// Every test passed.
    Passed,
    /// The success rate is below the gate (and no fixed-failure-rate test could admit it).
    LowSuccessRate,
    /// The ratio is below `ratio_threshold`.
    LowRatio,
    /// Below the success-rate gate, and the ratio fails the fixed-failure-rate test.
    FailureRate,
    /// The constrained objective of the best candidate exceeds its plausible limit.
    Implausible,
    /// The caller's search could not be completed (node cap, or no exact answer): nothing to accept.
    Unsearched,
}

/// The outcome of the gate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Decision {
    /// The success rate judged (bootstrapped, or simulated for a constrained rule; NaN when a
    /// constrained fix was refused before it was simulated).
    pub success_rate: f64,
    /// Second-best over best squared norm (constrained objective); infinite for a zero best; 0 when the
    /// gate refused before searching.
    pub ratio: f64,
    pub accepted: bool,
    pub reason: Reason,
}

impl Gate {
    /// Checks `min_success_rate` in [0, 1], `ratio_threshold` finite and >= 1 and `max_failure_rate` in
    /// [0, [`MAX_FAILURE_RATE`]].
    ///
    /// # Errors
    /// [`Error::OutOfRange`] naming the setting as `names` gives it, the range expected and the value.
    pub fn check(&self, names: &Names) -> Result<()> {
        if !(0.0..=MAX_FAILURE_RATE).contains(&self.max_failure_rate) {
            return Err(Error::out_of_range(
                names.max_failure_rate,
                format!(
                    "expected a probability in [0, {MAX_FAILURE_RATE}] (0: off), got {}",
                    self.max_failure_rate
                ),
            ));
        }
        if !(0.0..=1.0).contains(&self.min_success_rate) {
            return Err(Error::out_of_range(
                names.min_success_rate,
                format!(
                    "expected a probability in [0, 1], got {}",
                    self.min_success_rate
                ),
            ));
        }
        if !(self.ratio_threshold >= 1.0 && self.ratio_threshold.is_finite()) {
            return Err(Error::out_of_range(
                names.ratio_threshold,
                format!(
                    "expected a finite number >= 1, got {}",
                    self.ratio_threshold
                ),
            ));
        }
        Ok(())
    }

    /// Whether the fixed-failure-rate test can admit a set of `n` ambiguities below the success-rate gate.
    fn failure_rate_applies(&self, n: usize) -> bool {
        self.max_failure_rate > 0.0 && n <= FFRT_MAX_AMBIGUITIES
    }

    /// The ILS rule's refusal before any search: `Some` when the bootstrapped success rate of `problem`
    /// is below the gate and no fixed-failure-rate test can admit it (ratio reported 0), else `None`.
    pub fn before_search(&self, problem: &Problem) -> Option<Decision> {
        let rate = success_rate(problem.reduction.factor.d.as_slice());
        (rate < self.min_success_rate && !self.failure_rate_applies(problem.len())).then_some(
            Decision {
                success_rate: rate,
                ratio: 0.0,
                accepted: false,
                reason: Reason::LowSuccessRate,
            },
        )
    }

    /// The ILS rule (module docs) for `problem` and its two best candidates `best`
    /// ([`Problem::solve`] with at least 2).
    ///
    /// # Errors
    /// [`Error::Shape`] when `best` holds fewer than two candidates; those of
    /// [`fixed_failure_accepts`] (the simulation's search at its node cap: [`Error::Convergence`]).
    pub fn decide(&self, problem: &Problem, best: &IlsSolution) -> Result<Decision> {
        let &[first, second, ..] = best.squared_norms.as_slice() else {
            return Err(Error::Shape {
                name: "ILS candidates",
                expected: "the two best candidates for the ratio test".into(),
                actual: format!("{}", best.squared_norms.len()),
            });
        };
        let rate = success_rate(problem.reduction.factor.d.as_slice());
        let ratio = ratio_of([first, second]);
        // The simulation runs last: only a set that passes the ratio but not the success rate needs it.
        let reason = if !at_least(ratio, self.ratio_threshold) {
            Reason::LowRatio
        } else if rate >= self.min_success_rate {
            Reason::Passed
        } else if !self.failure_rate_applies(problem.len()) {
            Reason::LowSuccessRate
        } else if fixed_failure_accepts(
            &problem.reduction.factor,
            ratio,
            self.max_failure_rate,
            (FFRT_DRAWS_PER_FAILURE / self.max_failure_rate).ceil() as usize,
            FFRT_SEED,
        )? {
            Reason::Passed
        } else {
            Reason::FailureRate
        };
        Ok(Decision {
            success_rate: rate,
            ratio,
            accepted: reason == Reason::Passed,
            reason,
        })
    }

    /// The constrained rule (module docs) for the best candidate of a constrained search.
    ///
    /// # Arguments
    /// * `ratio` - second-best over best constrained objective (NaN when there is no second).
    /// * `cost`, `cost_limit` - the best's objective and its plausible limit (a chi-square quantile).
    /// * `floor` - `Some(f)`: the success rate must reach `max(min_success_rate, f)`; `None`: it is
    ///   reported, not gated.
    /// * `success` - computes the success rate, called only once the ratio and the plausibility pass
    ///   (a simulation is costly).
    ///
    /// # Errors
    /// Those of `success`.
    pub fn decide_constrained(
        &self,
        ratio: f64,
        cost: f64,
        cost_limit: f64,
        floor: Option<f64>,
        success: impl FnOnce() -> Result<f64>,
    ) -> Result<Decision> {
        let refused = |reason| Decision {
            success_rate: f64::NAN,
            ratio,
            accepted: false,
            reason,
        };
        if !at_least(ratio, self.ratio_threshold) {
            return Ok(refused(Reason::LowRatio));
        }
        if !at_least(cost_limit, cost) {
            return Ok(refused(Reason::Implausible));
        }
        let rate = success()?;
        let gated = floor.is_some_and(|f| !at_least(rate, self.min_success_rate.max(f)));
        Ok(Decision {
            success_rate: rate,
            ratio,
            accepted: !gated,
            reason: if gated {
                Reason::LowSuccessRate
            } else {
                Reason::Passed
            },
        })
    }
}

/// `value >= minimum`, false when either is NaN: a NaN ratio, objective or rate never passes a test.
fn at_least(value: f64, minimum: f64) -> bool {
    value >= minimum
}

#[cfg(test)]
#[path = "gate_tests.rs"]
mod tests;
