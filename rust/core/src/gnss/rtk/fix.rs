//! Integer fixing of the float ambiguities: the full set when the gate accepts it (the ILS rule of
//! [`crate::lambda::gate`]: ratio test, bootstrapped success rate, fixed-failure-rate test below it),
//! else the largest decorrelated subset that does (partial fixing,
//! [`crate::lambda::validation::partial_fix`]); the baseline conditioned on what was fixed.

use nalgebra::{Cholesky, DMatrix, DVector, Matrix3, Vector3};

use super::dd::validate;
use super::float::{self, FloatSolution};
use super::{BaselineSolution, DdEpoch, FixOptions, MAX_EPOCHS};
use crate::error::{Error, Result};
use crate::lambda::gate::{Decision, Gate, Names};
use crate::lambda::validation::RatioThreshold;
use crate::lambda::{IlsSolution, Problem, DEFAULT_MAX_NODES};

/// Conditional variance (cycles^2) below which an ambiguity counts as fixed after partial fixing (the
/// conditioned covariance of a fixed ambiguity is zero up to rounding).
const FIXED_VARIANCE: f64 = 1e-10;

impl FixOptions {
    /// Checks `min_success_rate` in [0, 1], `ratio_threshold >= 1` and `max_failure_rate` in [0, 0.1].
    ///
    /// # Errors
    /// [`Error::OutOfRange`] naming the CLI option.
    pub fn validate(&self) -> Result<()> {
        self.gate().check(&Names::CLI)
    }

    /// The fixing gate these options set.
    pub fn gate(&self) -> Gate {
        Gate {
            min_success_rate: self.min_success_rate,
            ratio_threshold: self.ratio_threshold,
            max_failure_rate: self.max_failure_rate,
        }
    }
}

/// Checks the options and the epochs of [`solve_baseline`] and [`super::solve_attitude`].
pub(crate) fn validate_input(epochs: &[DdEpoch], fix: &FixOptions) -> Result<()> {
    fix.validate()?;
    if epochs.is_empty() {
        return Err(Error::Shape {
            name: "epochs",
            expected: "at least one epoch".into(),
            actual: "none".into(),
        });
    }
    if epochs.len() > MAX_EPOCHS {
        return Err(Error::too_large(
            "epochs",
            epochs.len() as f64,
            MAX_EPOCHS as f64,
            "epochs",
        ));
    }
    epochs
        .iter()
        .enumerate()
        .try_for_each(|(k, e)| validate(e, k))
}

/// Baseline of one epoch (`epochs.len() == 1`) or of a static pair over several epochs (one baseline, one
/// ambiguity per (arc, reference arc) pair), float then fixed.
///
/// # Arguments
/// * `epochs` - the prepared epochs (at most [`MAX_EPOCHS`]).
/// * `held` - `(arc, reference arc, DD integer)` imposed exactly (continuity); pairs that do not occur
///   are ignored.
/// * `fix` - the success-rate gate and the ratio threshold.
///
/// # Errors
/// [`Error::OutOfRange`], [`Error::NonFinite`], [`Error::Shape`] or [`Error::TooLarge`] for bad input;
/// [`Error::DegenerateGeometry`] when the double differences do not determine the baseline;
/// [`Error::Convergence`] or [`Error::Numerical`] from the float solution or LAMBDA.
pub fn solve_baseline(
    epochs: &[DdEpoch],
    held: &[(u64, u64, i64)],
    fix: &FixOptions,
) -> Result<BaselineSolution> {
    let fl = baseline_float(epochs, held, fix)?;
    fix_float(&fl, held, fix)
}

/// The checks and the float solution of [`solve_baseline`].
pub(crate) fn baseline_float(
    epochs: &[DdEpoch],
    held: &[(u64, u64, i64)],
    fix: &FixOptions,
) -> Result<FloatSolution> {
    validate_input(epochs, fix)?;
    float::solve(epochs, held)
}

/// The fixed (or partially fixed, or float) baseline of a float solution.
pub(crate) fn fix_float(
    fl: &FloatSolution,
    held: &[(u64, u64, i64)],
    fix: &FixOptions,
) -> Result<BaselineSolution> {
    match ambiguity_problem(fl)? {
        None => Ok(float_result(fl, held)),
        Some((problem, q_aa)) => fix_problem(fl, held, fix, &problem, &q_aa),
    }
}

/// The decorrelated float ambiguities of `fl` and their (symmetrised) covariance; `None` when every
/// ambiguity was held.
pub(crate) fn ambiguity_problem(fl: &FloatSolution) -> Result<Option<(Problem, DMatrix<f64>)>> {
    let na = fl.ambiguities.len();
    if na == 0 {
        return Ok(None);
    }
    let q_aa = symmetric(&fl.covariance.view((3, 3), (na, na)).into_owned());
    Ok(Some((Problem::new(&fl.ambiguities_cycles, &q_aa)?, q_aa)))
}

/// The float solution as a result: nothing fixed beyond the held integers.
pub(crate) fn float_result(fl: &FloatSolution, held: &[(u64, u64, i64)]) -> BaselineSolution {
    let na = fl.ambiguities.len();
    BaselineSolution {
        baseline_m: fl.baseline_m,
        covariance_m2: fl.covariance.fixed_view::<3, 3>(0, 0).into_owned(),
        fixed: na == 0,
        fixed_ambiguities: fl.used_held.len(),
        ambiguities: na + fl.used_held.len(),
        ratio: f64::INFINITY,
        success_rate: 1.0,
        integers: held_integers(fl, held),
        reference_sats: fl.summary.reference_sats,
        slots_used: fl.summary.slots_used,
        satellites_per_system: fl.summary.satellites_per_system,
        float_chi2: fl.chi2,
        float_dof: fl.dof,
    }
}

/// [`fix_float`] with the decorrelated problem of `fl` ([`ambiguity_problem`]) already made: the gate,
/// the ratio test, partial fixing.
pub(crate) fn fix_problem(
    fl: &FloatSolution,
    held: &[(u64, u64, i64)],
    fix: &FixOptions,
    problem: &Problem,
    q_aa: &DMatrix<f64>,
) -> Result<BaselineSolution> {
    let na = fl.ambiguities.len();
    let mut out = float_result(fl, held);
    let a = &fl.ambiguities_cycles;
    let (decision, best) = full_fix_decision(fix, problem)?;
    out.success_rate = decision.success_rate;
    out.ratio = decision.ratio;
    let accept = decision.accepted;
    let (conditioned, q_cond) = if accept {
        out.fixed = true;
        out.fixed_ambiguities += na;
        let z = best.fixed.column(0).map(|v| v as f64);
        (z, DMatrix::zeros(na, na))
    } else {
        let pf = problem.partial_fix(
            RatioThreshold::Fixed(fix.ratio_threshold),
            fix.min_success_rate,
        )?;
        if pf.fixed_count == 0 {
            return Ok(out);
        }
        out.fixed_ambiguities += pf.fixed_count;
        out.ratio = pf.ratio;
        (pf.ambiguities, pf.covariance)
    };
    let (b, cov) = condition(fl, q_aa, a, &conditioned, &q_cond)?;
    out.baseline_m = b;
    out.covariance_m2 = cov;
    for (i, amb) in fl.ambiguities.iter().enumerate() {
        let v = conditioned[i];
        if q_cond[(i, i)] < FIXED_VARIANCE && (v - v.round()).abs() < 1e-6 {
            out.integers
                .push((amb.arc, amb.reference_arc, amb.offset + v.round() as i64));
        }
    }
    Ok(out)
}

/// The gate's decision on the full set of `problem` and its two best candidates (the engine searches
/// whatever the success rate: partial fixing and the reported ratio need the search).
///
/// # Errors
/// Those of [`Problem::solve`] and [`Gate::decide`].
pub(crate) fn full_fix_decision(
    fix: &FixOptions,
    problem: &Problem,
) -> Result<(Decision, IlsSolution)> {
    let best = problem.solve(2, DEFAULT_MAX_NODES)?;
    Ok((fix.gate().decide(problem, &best)?, best))
}

/// The held integers that occurred, in the order given.
fn held_integers(fl: &FloatSolution, held: &[(u64, u64, i64)]) -> Vec<(u64, u64, i64)> {
    held.iter()
        .copied()
        .filter(|&(a, r, _)| fl.used_held.contains(&(a, r)))
        .collect()
}

fn symmetric(m: &DMatrix<f64>) -> DMatrix<f64> {
    (m + m.transpose()) * 0.5
}

/// Baseline and covariance conditioned on ambiguities moved from `a` (covariance `Q_aa`) to `a_c`
/// (covariance `Q_c`): `b - Q_ba Q_aa^-1 (a - a_c)`, `Q_bb - Q_ba Q_aa^-1 (Q_aa - Q_c) Q_aa^-1 Q_ab`.
/// Exact for any linear constraint on the ambiguities (the full fix has `Q_c = 0`).
fn condition(
    fl: &FloatSolution,
    q_aa: &DMatrix<f64>,
    a: &DVector<f64>,
    a_c: &DVector<f64>,
    q_c: &DMatrix<f64>,
) -> Result<(Vector3<f64>, Matrix3<f64>)> {
    let na = a.len();
    let q_ab = fl.covariance.view((3, 0), (na, 3)).into_owned();
    let chol = Cholesky::new(q_aa.clone()).ok_or_else(|| {
        Error::numerical(
            "ambiguity conditioning",
            "the float ambiguity covariance is not positive definite",
        )
    })?;
    let k = chol.solve(&q_ab); // Q_aa^-1 Q_ab (na x 3)
    let db = k.tr_mul(&(a - a_c));
    let q_bb = fl.covariance.fixed_view::<3, 3>(0, 0).into_owned();
    let reduction = k.transpose() * (q_aa - q_c) * &k;
    let cov = q_bb - Matrix3::from_fn(|i, j| 0.5 * (reduction[(i, j)] + reduction[(j, i)]));
    Ok((fl.baseline_m - Vector3::new(db[0], db[1], db[2]), cov))
}
