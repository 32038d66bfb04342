//! Two antennas a known distance apart (the direction unknown): the length-constrained integer
//! least-squares problem of the GNSS compass (Teunissen 2010, "Integer least-squares theory for the GNSS
//! compass", J. Geodesy 84:433-447; Buist 2007, ION GNSS, "The baseline constrained LAMBDA method for
//! single epoch, single frequency attitude determination applications").
//!
//! The constrained ILS solution minimises over the integers `z`
//!
//! `F(z) = ||a - z||^2_{Q_a} + ||b(z) - b_l(z)||^2_{Q_b|a}`,
//!
//! with `b(z) = b - Q_ba Q_aa^-1 (a - z)` the conditioned baseline, `Q_b|a` its covariance and `b_l(z)` the
//! point of the sphere `|b| = l` nearest to it. Here the second term is taken to first order along
//! `u = b(z) / |b(z)|` (exact for an isotropic `Q_b|a`): `(|b(z)| - l)^2 / (u^T Q_b|a u + sigma_l^2)`, with
//! [`LENGTH_SIGMA_M`] for the length's own uncertainty.
//!
//! **Search** ("expansion", Teunissen 2010 sec. 5; Giorgi et al. 2010): `F(z) >= ||a - z||^2`, so the `m`
//! best unconstrained candidates contain the best and second-best constrained ones once the second-best
//! `F` among them is at most the `m`-th norm; `m` grows by [`EXPANSION`] from [`FIRST_CANDIDATES`] up to
//! [`MAX_CANDIDATES`] until that holds. When it does not hold there, nothing is fixed.
//!
//! **Validation.** The bootstrapped success rate of the unconstrained float ambiguities ignores the
//! constraint and is far too pessimistic for it (single-epoch GPS L1 on a 1-5 m baseline: a few percent
//! where the constrained estimator succeeds most of the time). The constrained estimator's success rate
//! has no closed form; the literature evaluates it by simulation (Teunissen 2010 sec. 6; Teunissen,
//! Giorgi & Buist 2011, GPS Solutions 15:15-28), and so does this module, for the epoch's own
//! covariance: [`SUCCESS_DRAWS`] seeded draws of the float errors around the fixed solution, each solved
//! by the same constrained search, the success rate the share whose best candidate is the truth (a draw
//! whose search cannot be completed counts as a failure). A fix is accepted by the constrained rule of
//! [`crate::lambda::gate`]: that rate reaches `min_success_rate` or [`MIN_SUCCESS_RATE`], whichever is
//! higher, the constrained ratio `F(second) / F(best)` reaches `ratio_threshold` (the
//! discrimination test used with C-LAMBDA), and `F(best)` is plausible (below the `1 - 1e-9` chi-square
//! quantile of `n + 1` degrees of freedom: a best that is only the least wrong of a list that missed the
//! truth is refused). Otherwise the epoch gets the unconstrained fix of [`super::fix`] (gate, ratio,
//! partial fixing).

use nalgebra::{Cholesky, DMatrix, DVector, Matrix3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::constrained::chi2_quantile;
use super::fix::{ambiguity_problem, fix_problem, float_result, validate_input};
use super::float::{self, FloatSolution};
use super::{BaselineSolution, DdEpoch, FixOptions};
use crate::error::{Error, Result};
use crate::lambda::ldl::Ltdl;
use crate::lambda::validation::normal;
use crate::lambda::{search, Problem};

/// Shortest and longest known length accepted, m (the body baselines' limits of attitude mode).
pub const LENGTH_RANGE_M: (f64, f64) = (0.01, super::constrained::MAX_BODY_M);

/// Standard deviation of the known length, m: a surveyed antenna separation (phase centres included) is
/// known to a few millimetres; this loosens the constraint by that much.
pub const LENGTH_SIGMA_M: f64 = 0.002;

/// Unconstrained candidates of the first search, and the factor between one search and the next.
pub const FIRST_CANDIDATES: usize = 16;
pub const EXPANSION: usize = 4;

/// Most unconstrained candidates searched (4^5 x 16 = 16384 would exceed the search's own limit).
pub const MAX_CANDIDATES: usize = 4096;

/// Draws of the simulated constrained success rate (its standard error at 0.5 is 0.035).
pub const SUCCESS_DRAWS: usize = 200;

/// Smallest simulated constrained success rate of a constrained fix (`min_success_rate` when higher).
/// The simulation draws around the fix found, taken as the truth, so a wrong fix overstates its own
/// rate. Measured on simulated single-epoch GPS L1 (6-10 satellites above 15 degrees, 1-5 m; candidates
/// passing the ratio test at 3 and the plausibility check): 2400 epochs of fixed 6, 7, 8 or 10
/// satellites, 7 wrong among 744 fixes at a gate of 0.5 (simulated rates of the wrong ones 0.52-0.82),
/// 0 wrong among 596 at 0.9 and 514 at 0.95; 2000 epochs of 6-10 satellites (other seeds), 12 wrong
/// among 663 with no gate, 0 among 550 at 0.9 and 474 at 0.95. A fixed-failure-rate count on the same
/// draws instead (accept when no wrong draw of 200 has a constrained ratio as large) let 5 wrong of 613
/// through: wrong fixes with constrained ratios up to 14.7 occur, which no ratio threshold separates.
pub const MIN_SUCCESS_RATE: f64 = 0.95;

/// Seed of the simulation: the same epoch gives the same decision in every run.
const SEED: u64 = 1616;

/// Nodes one search may visit (the draws add up to [`SUCCESS_DRAWS`] times this at most).
const MAX_NODES: u64 = 5_000_000;

/// The constrained problem in the decorrelated space of one [`Problem`].
struct Constrained<'a> {
    factor: &'a Ltdl,
    /// `Q_ba Q_aa^-1 Z^-T` as `(Z^-1 Q_aa^-1 Q_ab)`, n x 3: `b(v) = b - K^T (zhat - v)`.
    k: DMatrix<f64>,
    /// `Q_b|a`, m^2.
    q_cond: Matrix3<f64>,
    length_m: f64,
}

/// The best and second-best constrained candidates of one search.
struct Found {
    /// Decorrelated integers of the best.
    best: DVector<f64>,
    /// Its conditioned baseline, m.
    baseline_m: Vector3<f64>,
    cost: f64,
    second: f64,
}

impl Constrained<'_> {
    /// `F` of candidate `v` with unconstrained norm `norm`, and its conditioned baseline.
    fn cost(
        &self,
        b: &Vector3<f64>,
        zhat: &DVector<f64>,
        v: &DVector<f64>,
        norm: f64,
    ) -> (f64, Vector3<f64>) {
        let db = self.k.tr_mul(&(zhat - v));
        let bz = b - Vector3::new(db[0], db[1], db[2]);
        let l = bz.norm();
        let u = bz / l.max(f64::MIN_POSITIVE);
        let dl = l - self.length_m;
        let var = u.dot(&(self.q_cond * u)) + LENGTH_SIGMA_M * LENGTH_SIGMA_M;
        (norm + dl * dl / var, bz)
    }

    /// The best constrained candidate for float baseline `b` and decorrelated float ambiguities `zhat`,
    /// and the second best when `second`; `None` when [`MAX_CANDIDATES`] do not guarantee them.
    fn solve(&self, b: &Vector3<f64>, zhat: &DVector<f64>, second: bool) -> Result<Option<Found>> {
        let mut m = FIRST_CANDIDATES;
        loop {
            let c = search(self.factor, zhat, m, MAX_NODES)?;
            let mut best: Option<Found> = None;
            for (j, &norm) in c.squared_norms.iter().enumerate() {
                let v = c.z.column(j).into_owned();
                let (f, bz) = self.cost(b, zhat, &v, norm);
                match &mut best {
                    Some(x) if f >= x.cost => x.second = x.second.min(f),
                    _ => {
                        let second = best.as_ref().map_or(f64::INFINITY, |x| x.cost);
                        best = Some(Found {
                            best: v,
                            baseline_m: bz,
                            cost: f,
                            second,
                        });
                    }
                }
            }
            let largest = c.squared_norms.last().copied().unwrap_or(0.0);
            if best
                .as_ref()
                .is_some_and(|x| if second { x.second } else { x.cost } <= largest)
            {
                return Ok(best);
            }
            if m >= MAX_CANDIDATES {
                return Ok(None);
            }
            m = (m * EXPANSION).min(MAX_CANDIDATES);
        }
    }

    /// Share of [`SUCCESS_DRAWS`] draws around the truth (decorrelated integers 0 after a shift,
    /// baseline `truth_m`) whose constrained best is the truth (a draw whose search cannot be completed
    /// counts as a failure).
    fn success_rate(&self, truth_m: &Vector3<f64>) -> Result<f64> {
        let chol = Cholesky::new(self.q_cond + Matrix3::identity() * 1e-12)
            .ok_or_else(|| Error::numerical("known-length fix", "Q_b|a not positive"))?;
        let sd = self.factor.d.map(f64::sqrt);
        let successes = (0..SUCCESS_DRAWS)
            .into_par_iter()
            .map(|t| {
                let mut rng = ChaCha8Rng::seed_from_u64(SEED);
                rng.set_stream(t as u64);
                let w = DVector::from_fn(sd.len(), |i, _| sd[i] * normal(&mut rng));
                let e = self.factor.l.tr_mul(&w);
                let g = Vector3::from_fn(|_, _| normal(&mut rng));
                // b = truth + K^T e + e_b|a: the float baseline error correlated with the ambiguities'.
                let kb = self.k.tr_mul(&e);
                let b = truth_m + Vector3::new(kb[0], kb[1], kb[2]) + chol.l() * g;
                Ok(match self.solve(&b, &e, false) {
                    Ok(Some(f)) => usize::from(f.best.iter().all(|&v| v == 0.0)),
                    Ok(None) | Err(Error::Convergence { .. }) => 0,
                    Err(e) => return Err(e),
                })
            })
            .try_reduce(|| 0, |a, b| Ok(a + b))?;
        Ok(successes as f64 / SUCCESS_DRAWS as f64)
    }
}

/// Baseline of one epoch (or a static session, as [`super::solve_baseline`]) whose length is known.
///
/// # Arguments
/// * `epochs`, `held`, `fix` - as [`super::solve_baseline`].
/// * `length_m` - the antennas' distance, m, in [`LENGTH_RANGE_M`].
///
/// # Returns
/// The constrained fix when it passes (module documentation; `success_rate` then is the simulated
/// constrained success rate, `ratio` the constrained ratio), else [`super::solve_baseline`]'s result.
///
/// # Errors
/// [`Error::OutOfRange`] for a length outside [`LENGTH_RANGE_M`]; those of [`super::solve_baseline`].
pub fn solve_known_length(
    epochs: &[DdEpoch],
    held: &[(u64, u64, i64)],
    length_m: f64,
    fix: &FixOptions,
) -> Result<BaselineSolution> {
    let fl = known_length_float(epochs, held, length_m, fix)?;
    fix_known_length(&fl, held, length_m, fix)
}

/// The checks and the float solution of [`solve_known_length`].
pub(crate) fn known_length_float(
    epochs: &[DdEpoch],
    held: &[(u64, u64, i64)],
    length_m: f64,
    fix: &FixOptions,
) -> Result<FloatSolution> {
    let (lo, hi) = LENGTH_RANGE_M;
    if !(lo..=hi).contains(&length_m) {
        return Err(Error::out_of_range(
            "--baseline-length",
            format!("expected a length in [{lo}, {hi}] m, got {length_m} m"),
        ));
    }
    validate_input(epochs, fix)?;
    float::solve(epochs, held)
}

/// The fix of a float solution with a known length (in [`LENGTH_RANGE_M`]): the constrained fix when it
/// passes, else [`super::fix::fix_float`]'s. The float solution comes from [`known_length_float`] (the
/// observation engine computes a session's float solutions in order and fixes them in parallel) or from the
/// multi-epoch filter.
///
/// # Errors
/// Those of the constrained search and of LAMBDA.
pub(crate) fn fix_known_length(
    fl: &FloatSolution,
    held: &[(u64, u64, i64)],
    length_m: f64,
    fix: &FixOptions,
) -> Result<BaselineSolution> {
    let Some((problem, q_aa)) = ambiguity_problem(fl)? else {
        return Ok(float_result(fl, held));
    };
    match constrained_fix(fl, held, &problem, &q_aa, length_m, fix)? {
        Some(s) => Ok(s),
        None => fix_problem(fl, held, fix, &problem, &q_aa),
    }
}

/// The constrained fix when it passes the gate, the ratio test and the plausibility check.
fn constrained_fix(
    fl: &FloatSolution,
    held: &[(u64, u64, i64)],
    problem: &Problem,
    q_aa: &DMatrix<f64>,
    length_m: f64,
    fix: &FixOptions,
) -> Result<Option<BaselineSolution>> {
    let na = fl.ambiguities.len();
    let q_ab = fl.covariance.view((3, 0), (na, 3)).into_owned();
    let k_orig = Cholesky::new(q_aa.clone())
        .ok_or_else(|| {
            Error::numerical(
                "known-length fix",
                "float ambiguity covariance not positive",
            )
        })?
        .solve(&q_ab);
    let q_bb = fl.covariance.fixed_view::<3, 3>(0, 0).into_owned();
    let red = q_ab.transpose() * &k_orig;
    let q_cond = q_bb - Matrix3::from_fn(|i, j| 0.5 * (red[(i, j)] + red[(j, i)]));
    let c = Constrained {
        factor: &problem.reduction.factor,
        k: problem.reduction.z_inv()?.map(|v| v as f64) * k_orig,
        q_cond,
        length_m,
    };
    let found = match c.solve(&fl.baseline_m, &problem.zhat, true) {
        Ok(Some(f)) => f,
        Ok(None) | Err(Error::Convergence { .. }) => return Ok(None),
        Err(e) => return Err(e),
    };
    let ratio = if found.cost > 0.0 {
        found.second / found.cost
    } else {
        f64::INFINITY
    };
    // The baseline on the sphere, first order: the length as an observation of `u^T b`.
    let u = found.baseline_m / found.baseline_m.norm().max(f64::MIN_POSITIVE);
    let decision = fix.gate().decide_constrained(
        ratio,
        found.cost,
        chi2_quantile(na + 1),
        Some(MIN_SUCCESS_RATE),
        || c.success_rate(&(u * length_m)),
    )?;
    if !decision.accepted {
        return Ok(None);
    }
    let qu = q_cond * u;
    let s = u.dot(&qu) + LENGTH_SIGMA_M * LENGTH_SIGMA_M;
    let baseline_m = found.baseline_m + qu * ((length_m - found.baseline_m.norm()) / s);
    let covariance_m2 = q_cond - qu * qu.transpose() / s;
    let z = problem.to_original(&found.best)?;
    let mut out = float_result(fl, held);
    out.baseline_m = baseline_m;
    out.covariance_m2 = covariance_m2;
    out.fixed = true;
    out.fixed_ambiguities += na;
    out.ratio = ratio;
    out.success_rate = decision.success_rate;
    out.integers.extend(
        fl.ambiguities
            .iter()
            .zip(z.iter())
            .map(|(a, &v)| (a.arc, a.reference_arc, a.offset + v)),
    );
    Ok(Some(out))
}

#[cfg(test)]
#[path = "known_length_tests.rs"]
mod tests;
