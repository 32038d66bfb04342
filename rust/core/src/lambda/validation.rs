//! Validation of the ILS solution: the ratio test with a fixed threshold or with a threshold chosen for
//! a fixed failure rate, and partial ambiguity resolution.
//!
//! Ratio test: accept the best candidate `z1` when `R = ||a - z2||^2_Q / ||a - z1||^2_Q >= c`, `z2` the
//! second best (Euler & Schaffrin 1991; the form used by RTKLIB with `c = 3`).
//!
//! Fixed failure rate (FFRT): `c` is the smallest threshold for which the probability of accepting a
//! wrong integer, `P(R >= c, z1 != z)`, is at most `P_f` under the model `a ~ N(z, Q)`. It is computed
//! here the way the published look-up tables were made, by simulation of the model itself
//! (Teunissen & Verhagen 2009, Survey Review 41:138-151; Verhagen & Teunissen 2013, GPS Solutions
//! 17:535-548), rather than read from those tables: `samples` draws of `Z^T a - Z^T z ~ N(0, L^T D L)`,
//! each searched for its two best candidates; `c` is set just above the `floor(P_f samples) + 1`-th
//! largest ratio among the wrong fixes. When the bootstrapped failure rate, an upper bound of the ILS one,
//! is already at most `P_f`, every fix is acceptable and `c = 1` without simulation (Verhagen &
//! Teunissen 2013, section 4). The estimate of `c` has Monte Carlo noise: use `samples >= 100 / P_f`.
//!
//! Partial fixing: fix the largest subset of decorrelated ambiguities, dropping them in order from the
//! least precise end of the conditional-variance order (index 0 of `L^T D L` first), whose bootstrapped
//! success rate reaches `min_success_rate` and whose ratio test passes (Teunissen, Joosten & Tiberius
//! 1999, "Geometry-free ambiguity success rates in case of partial fixing", ION NTM; LAMBDA 3.0 PAR).

use nalgebra::{Cholesky, DMatrix, DVector};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::bootstrap::success_rate;
use super::ldl::Ltdl;
use super::search::{search, DEFAULT_MAX_NODES};
use super::Problem;
use crate::error::{Error, Result};

/// How the ratio-test threshold `c` (accept when `R >= c`) is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RatioThreshold {
    /// A fixed `c >= 1` (RTKLIB's default is 3).
    Fixed(f64),
    /// The `c` that keeps the probability of accepting a wrong fix at `failure_rate`, by a seeded
    /// simulation of `samples` draws (see the module docs). Threads: rayon's global pool
    /// (`RAYON_NUM_THREADS`); the result does not depend on their number.
    FixedFailureRate {
        failure_rate: f64,
        samples: usize,
        seed: u64,
    },
}

impl RatioThreshold {
    fn check(&self) -> Result<()> {
        match *self {
            RatioThreshold::Fixed(c) if !(c >= 1.0 && c.is_finite()) => Err(Error::out_of_range(
                "threshold",
                format!("expected a finite ratio threshold >= 1, got {c}"),
            )),
            RatioThreshold::FixedFailureRate {
                failure_rate,
                samples,
                ..
            } => {
                if !(failure_rate > 0.0 && failure_rate < 1.0) {
                    return Err(Error::out_of_range(
                        "failure_rate",
                        format!("expected 0 < failure_rate < 1, got {failure_rate}"),
                    ));
                }
                if (samples as f64) * failure_rate < 1.0 {
                    return Err(Error::out_of_range(
                        "samples",
                        format!(
                            "expected at least 1 / failure_rate = {:.0} samples, got {samples}",
                            (1.0 / failure_rate).ceil()
                        ),
                    ));
                }
                Ok(())
            }
            RatioThreshold::Fixed(_) => Ok(()),
        }
    }

    /// The threshold for the ambiguities whose decorrelated factors are `factor`.
    fn value(&self, factor: &Ltdl) -> Result<f64> {
        match *self {
            RatioThreshold::Fixed(c) => Ok(c),
            RatioThreshold::FixedFailureRate {
                failure_rate,
                samples,
                seed,
            } => fixed_failure_threshold(factor, failure_rate, samples, seed),
        }
    }
}

/// Outcome of [`ratio_test`].
#[derive(Debug, Clone, PartialEq)]
pub struct RatioTest {
    /// `ratio >= threshold`.
    pub accepted: bool,
    /// `R`, the second-best over the best squared norm (infinite when `a` is an integer vector).
    pub ratio: f64,
    /// The threshold `c` used.
    pub threshold: f64,
    /// The best integer vector (n), whether accepted or not.
    pub fixed: DVector<i64>,
    /// The two best squared norms.
    pub squared_norms: [f64; 2],
}

/// Ratio test of the ILS solution of float ambiguities `a` with covariance `q`.
///
/// # Arguments
/// * `a` - n float ambiguities, cycles; `q` - their n x n covariance, cycles^2.
/// * `threshold` - fixed, or for a fixed failure rate.
///
/// # Errors
/// Those of [`Problem::new`]; [`Error::OutOfRange`] for a threshold below 1, a failure rate outside
/// (0, 1) or fewer than `1 / failure_rate` samples.
pub fn ratio_test(
    a: &DVector<f64>,
    q: &DMatrix<f64>,
    threshold: RatioThreshold,
) -> Result<RatioTest> {
    threshold.check()?;
    let p = Problem::new(a, q)?;
    let found = search(&p.reduction.factor, &p.zhat, 2, DEFAULT_MAX_NODES)?;
    let c = threshold.value(&p.reduction.factor)?;
    let ratio = ratio_of(&found.squared_norms);
    Ok(RatioTest {
        accepted: ratio >= c,
        ratio,
        threshold: c,
        fixed: p.to_original(&found.z.column(0).into_owned()),
        squared_norms: [found.squared_norms[0], found.squared_norms[1]],
    })
}

/// The fixed-failure-rate ratio threshold for covariance `q` (see the module docs).
///
/// # Errors
/// Those of [`super::reduce`]; [`Error::OutOfRange`] as in [`ratio_test`].
pub fn fixed_failure_rate_threshold(
    q: &DMatrix<f64>,
    failure_rate: f64,
    samples: usize,
    seed: u64,
) -> Result<f64> {
    let t = RatioThreshold::FixedFailureRate {
        failure_rate,
        samples,
        seed,
    };
    t.check()?;
    t.value(&super::reduce(q)?.factor)
}

/// The fixed-failure-rate threshold for decorrelated factors `factor` (inputs already checked).
pub fn fixed_failure_threshold(
    factor: &Ltdl,
    failure_rate: f64,
    samples: usize,
    seed: u64,
) -> Result<f64> {
    if 1.0 - success_rate(factor.d.as_slice()) <= failure_rate {
        return Ok(1.0);
    }
    let n = factor.d.len();
    let sd = factor.d.map(f64::sqrt);
    let trials: Vec<Option<f64>> = (0..samples)
        .into_par_iter()
        .map(|t| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            rng.set_stream(t as u64);
            let w = DVector::from_fn(n, |i, _| sd[i] * normal(&mut rng));
            let e = factor.l.tr_mul(&w);
            let found = search(factor, &e, 2, DEFAULT_MAX_NODES)?;
            let wrong = found.z.column(0).iter().any(|&v| v != 0.0);
            Ok(wrong.then(|| ratio_of(&found.squared_norms)))
        })
        .collect::<Result<_>>()?;
    let mut wrong: Vec<f64> = trials.into_iter().flatten().collect();
    let allowed = (failure_rate * samples as f64).floor() as usize;
    if wrong.len() <= allowed {
        return Ok(1.0);
    }
    wrong.sort_by(|a, b| b.total_cmp(a));
    Ok(wrong[allowed].next_up().max(1.0))
}

/// Outcome of [`partial_fix`].
#[derive(Debug, Clone, PartialEq)]
pub struct PartialFix {
    /// Number k of integer combinations fixed (0: nothing passed, n: full fix).
    pub fixed_count: usize,
    /// The fixed combinations as columns of an n x k integer matrix `Z_k` (the last k columns of `Z`).
    pub combinations: DMatrix<i64>,
    /// Their integer values: `Z_k^T a` fixed to these (k).
    pub values: DVector<i64>,
    /// Ratio-test statistic of the subset fixed (NaN when nothing was fixed).
    pub ratio: f64,
    /// Threshold it passed (NaN when nothing was fixed).
    pub threshold: f64,
    /// Bootstrapped success rate of the subset (1 when nothing was fixed).
    pub success_rate: f64,
    /// The float ambiguities conditioned on the fixed combinations (n), cycles; integers when k = n.
    pub ambiguities: DVector<f64>,
    /// Their covariance (n x n), cycles^2; zero when k = n.
    pub covariance: DMatrix<f64>,
}

/// Partial ambiguity resolution: the largest subset of decorrelated ambiguities that passes.
///
/// # Arguments
/// * `a` - n float ambiguities, cycles; `q` - their n x n covariance, cycles^2.
/// * `threshold` - the ratio test each subset must pass.
/// * `min_success_rate` - in [0, 1]: subsets with a lower bootstrapped success rate are skipped.
///
/// # Errors
/// Those of [`ratio_test`]; [`Error::OutOfRange`] for `min_success_rate` outside [0, 1].
pub fn partial_fix(
    a: &DVector<f64>,
    q: &DMatrix<f64>,
    threshold: RatioThreshold,
    min_success_rate: f64,
) -> Result<PartialFix> {
    threshold.check()?;
    if !(0.0..=1.0).contains(&min_success_rate) {
        return Err(Error::out_of_range(
            "min_success_rate",
            format!("expected a probability in [0, 1], got {min_success_rate}"),
        ));
    }
    let p = Problem::new(a, q)?;
    let n = p.len();
    for k in (1..=n).rev() {
        let sub = p.reduction.factor.trailing(k);
        let sr = success_rate(sub.d.as_slice());
        if sr < min_success_rate {
            continue;
        }
        let zsub = p.zhat.rows(n - k, k).into_owned();
        let found = search(&sub, &zsub, 2, DEFAULT_MAX_NODES)?;
        let ratio = ratio_of(&found.squared_norms);
        let c = threshold.value(&sub)?;
        if ratio >= c {
            let best = found.z.column(0).into_owned();
            return Ok(conditioned(&p, q, a, k, &sub, &zsub, &best, ratio, c, sr));
        }
    }
    Ok(PartialFix {
        fixed_count: 0,
        combinations: DMatrix::zeros(n, 0),
        values: DVector::zeros(0),
        ratio: f64::NAN,
        threshold: f64::NAN,
        success_rate: 1.0,
        ambiguities: a.clone(),
        covariance: q.clone(),
    })
}

/// The float solution conditioned on `Z_k^T a = offset-part + best`.
#[allow(clippy::too_many_arguments)]
fn conditioned(
    p: &Problem,
    q: &DMatrix<f64>,
    a: &DVector<f64>,
    k: usize,
    sub: &Ltdl,
    zsub: &DVector<f64>,
    best: &DVector<f64>,
    ratio: f64,
    threshold: f64,
    success_rate: f64,
) -> PartialFix {
    let n = p.len();
    let zk = p.reduction.z.columns(n - k, k).into_owned();
    let shift = zk.tr_mul(&p.offset);
    let values = DVector::from_fn(k, |i, _| (shift[i] + best[i]).round() as i64);
    let (ambiguities, covariance) = if k == n {
        (p.to_original(best).map(|v| v as f64), DMatrix::zeros(n, n))
    } else {
        let qz = sub.reconstruct();
        let chol = Cholesky::new((&qz + qz.transpose()) * 0.5)
            .expect("a block of a positive-definite matrix");
        let qzk = q * &zk; // n x k
        let gain = chol.solve(&qzk.transpose()).transpose(); // Q Z_k (Z_k^T Q Z_k)^-1
        let amb = a - &gain * (zsub - best);
        let cov = q - &gain * qzk.transpose();
        (amb, (&cov + cov.transpose()) * 0.5)
    };
    PartialFix {
        fixed_count: k,
        combinations: zk.map(|v| v.round() as i64),
        values,
        ratio,
        threshold,
        success_rate,
        ambiguities,
        covariance,
    }
}

fn ratio_of(norms: &[f64]) -> f64 {
    if norms[0] > 0.0 {
        norms[1] / norms[0]
    } else {
        f64::INFINITY
    }
}

/// Standard normal draw (Box-Muller, one of the pair).
fn normal(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}
