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
use super::search::{node_budget, search, DEFAULT_MAX_NODES};
use super::verify::agreeing_order;
use super::{bounded_integer, Problem};
use crate::error::{Error, Result};

/// Largest number of simulated samples of the fixed-failure-rate threshold (enough for a failure rate of
/// 1e-4 at the recommended `100 / failure_rate`).
pub const MAX_SAMPLES: usize = 1_000_000;

/// Nodes all the simulated searches of one threshold may visit together: each sample gets
/// `min(DEFAULT_MAX_NODES, SIMULATION_MAX_NODES / samples)`, which bounds the simulation to about a
/// minute of one core at n = 64 whatever `samples` is, and keeps the result independent of threads.
pub const SIMULATION_MAX_NODES: u64 = 1_000_000_000;

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
                if samples > MAX_SAMPLES {
                    return Err(Error::too_large(
                        "samples",
                        samples as f64,
                        MAX_SAMPLES as f64,
                        "simulated draws",
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
/// The two best candidates and their norms are those of [`super::ils`] (exact or an error).
///
/// # Errors
/// Those of [`Problem::new`] and [`Problem::solve`]; [`Error::OutOfRange`] for a threshold below 1, a
/// failure rate outside (0, 1) or fewer than `1 / failure_rate` samples; [`Error::TooLarge`] beyond
/// [`MAX_SAMPLES`].
pub fn ratio_test(
    a: &DVector<f64>,
    q: &DMatrix<f64>,
    threshold: RatioThreshold,
) -> Result<RatioTest> {
    threshold.check()?;
    let p = Problem::new(a, q)?;
    let found = p.solve(2, node_budget(p.len()))?;
    let c = threshold.value(&p.reduction.factor)?;
    let norms = [found.squared_norms[0], found.squared_norms[1]];
    let ratio = ratio_of(norms);
    Ok(RatioTest {
        accepted: ratio >= c,
        ratio,
        threshold: c,
        fixed: found.fixed.column(0).into_owned(),
        squared_norms: norms,
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
    let draw = Draws::new(factor, samples, seed);
    let trials: Vec<Option<f64>> = (0..samples)
        .into_par_iter()
        .map(|t| draw.wrong_fix_ratio(t))
        .collect::<Result<_>>()?;
    let mut wrong: Vec<f64> = trials.into_iter().flatten().collect();
    let allowed = (failure_rate * samples as f64).floor() as usize;
    if wrong.len() <= allowed {
        return Ok(1.0);
    }
    wrong.sort_by(|a, b| b.total_cmp(a));
    Ok(wrong[allowed].next_up().max(1.0))
}

/// Draws simulated between two checks of the count in [`fixed_failure_accepts`] (the decision does not
/// depend on it).
const ACCEPT_BLOCK: usize = 1024;

/// Whether ratio `ratio` passes the fixed-failure-rate test, `ratio >= fixed_failure_threshold(..)` with
/// the same draws, decided without sorting: it passes exactly when at most `floor(P_f samples)` wrong draws
/// have a ratio of at least `ratio`. Counting lets a failing test stop after the first block of draws that
/// exceeds the count, which is most of the cost saved where most tests fail (weak single-frequency sets).
///
/// # Errors
/// Those of the search ([`Error::Convergence`] at the node cap).
pub fn fixed_failure_accepts(
    factor: &Ltdl,
    ratio: f64,
    failure_rate: f64,
    samples: usize,
    seed: u64,
) -> Result<bool> {
    if ratio < 1.0 {
        return Ok(false);
    }
    if 1.0 - success_rate(factor.d.as_slice()) <= failure_rate {
        return Ok(true);
    }
    let draw = Draws::new(factor, samples, seed);
    let allowed = (failure_rate * samples as f64).floor() as usize;
    let mut count = 0usize;
    for start in (0..samples).step_by(ACCEPT_BLOCK) {
        let end = (start + ACCEPT_BLOCK).min(samples);
        count += (start..end)
            .into_par_iter()
            .map(|t| {
                Ok(usize::from(
                    draw.wrong_fix_ratio(t)?.is_some_and(|r| r >= ratio),
                ))
            })
            .try_reduce(|| 0, |a, b| Ok(a + b))?;
        if count > allowed {
            return Ok(false);
        }
    }
    Ok(true)
}

/// The simulation of the fixed-failure-rate test: draw `t` is `Z^T a - Z^T z = L^T w`, `w ~ N(0, D)`, from
/// ChaCha stream `t` of `seed`, so that every draw is reproducible on its own whatever the threads.
struct Draws<'a> {
    factor: &'a Ltdl,
    sd: DVector<f64>,
    seed: u64,
    max_nodes: u64,
}

impl<'a> Draws<'a> {
    fn new(factor: &'a Ltdl, samples: usize, seed: u64) -> Self {
        Draws {
            factor,
            sd: factor.d.map(f64::sqrt),
            seed,
            max_nodes: DEFAULT_MAX_NODES.min(SIMULATION_MAX_NODES / samples.max(1) as u64),
        }
    }

    /// The ratio of draw `t` when its best candidate is wrong, `None` when it is right.
    fn wrong_fix_ratio(&self, t: usize) -> Result<Option<f64>> {
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        rng.set_stream(t as u64);
        let w = DVector::from_fn(self.sd.len(), |i, _| self.sd[i] * normal(&mut rng));
        let e = self.factor.l.tr_mul(&w);
        let found = search(self.factor, &e, 2, self.max_nodes)?;
        let wrong = found.z.column(0).iter().any(|&v| v != 0.0);
        let norms = [found.squared_norms[0], found.squared_norms[1]];
        Ok(wrong.then(|| ratio_of(norms)))
    }
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
    check_partial(&threshold, min_success_rate)?;
    Problem::new(a, q)?.partial_fix(threshold, min_success_rate)
}

/// Checks the arguments of [`partial_fix`].
fn check_partial(threshold: &RatioThreshold, min_success_rate: f64) -> Result<()> {
    threshold.check()?;
    if !(0.0..=1.0).contains(&min_success_rate) {
        return Err(Error::out_of_range(
            "min_success_rate",
            format!("expected a probability in [0, 1], got {min_success_rate}"),
        ));
    }
    Ok(())
}

impl Problem {
    /// [`partial_fix`] of this problem's float ambiguities and covariance, on its decorrelation (one
    /// reduction serves the full set's ratio test and every subset).
    ///
    /// # Errors
    /// Those of [`partial_fix`] other than the decorrelation's.
    pub fn partial_fix(
        &self,
        threshold: RatioThreshold,
        min_success_rate: f64,
    ) -> Result<PartialFix> {
        check_partial(&threshold, min_success_rate)?;
        let n = self.len();
        let mut nested: Option<Nested> = None;
        for k in (1..=n).rev() {
            let sub = self.reduction.factor.trailing(k);
            let sr = success_rate(sub.d.as_slice());
            if sr < min_success_rate {
                continue;
            }
            let nested = match &mut nested {
                Some(m) => m,
                None => nested.insert(Nested::new(&self.transformed.zqz)?),
            };
            let zhat = self.zhat.rows(n - k, k).into_owned();
            let found = search(&sub, &zhat, 2, node_budget(k))?;
            let recomputed: Vec<f64> = found
                .z
                .column_iter()
                .map(|c| nested.squared_norm(&(&zhat - c)))
                .collect();
            let order = agreeing_order("LAMBDA partial fix", &found.squared_norms, &recomputed)?;
            let ratio = ratio_of([recomputed[order[0]], recomputed[order[1]]]);
            let c = threshold.value(&sub)?;
            if ratio >= c {
                let best = found.z.column(order[0]).into_owned();
                return conditioned(self, nested, &zhat, &best, ratio, c, sr);
            }
        }
        Ok(PartialFix {
            fixed_count: 0,
            combinations: DMatrix::zeros(n, 0),
            values: DVector::zeros(0),
            ratio: f64::NAN,
            threshold: f64::NAN,
            success_rate: 1.0,
            ambiguities: self.a.clone(),
            covariance: self.q.clone(),
        })
    }
}

/// The covariances of every subset of partial fixing at once: the subset of the last `k` decorrelated
/// ambiguities has covariance `M_k`, the trailing `k x k` block of `M = Z^T Q Z` (formed from `Q` and
/// the exact `Z`, see [`super::Transformed`]). With `M` in reversed order factorised by Cholesky,
/// `P M P = C C^T`, the reversed `M_k` is the leading block, whose Cholesky factor is the leading block of
/// `C`: one factorisation serves every `k` for recomputing the search's norms and for conditioning.
struct Nested {
    /// `C` (lower triangle; the upper one is not referenced).
    c: DMatrix<f64>,
}

impl Nested {
    fn new(zqz: &DMatrix<f64>) -> Result<Nested> {
        let n = zqz.nrows();
        let reversed = DMatrix::from_fn(n, n, |i, j| zqz[(n - 1 - i, n - 1 - j)]);
        let chol = Cholesky::new(reversed).ok_or_else(|| {
            Error::numerical(
                "LAMBDA partial fix",
                format!(
                    "the Cholesky factorisation of the {n} x {n} decorrelated covariance fails in \
                     floating point (not positive definite to working precision)"
                ),
            )
        })?;
        Ok(Nested {
            c: chol.l_dirty().clone(),
        })
    }

    /// `C_k^-1 P b` for `b` of `k` rows in decorrelated order.
    fn whiten(&self, b: &DMatrix<f64>) -> Option<DMatrix<f64>> {
        let k = b.nrows();
        let reversed = DMatrix::from_fn(k, b.ncols(), |i, j| b[(k - 1 - i, j)]);
        self.c
            .view((0, 0), (k, k))
            .solve_lower_triangular(&reversed)
    }

    /// `r^T M_k^-1 r` for a residual `r` of the last `k` decorrelated ambiguities.
    fn squared_norm(&self, r: &DVector<f64>) -> f64 {
        let b = DMatrix::from_column_slice(r.len(), 1, r.as_slice());
        self.whiten(&b).map_or(f64::INFINITY, |y| y.norm_squared())
    }

    /// `M_k^-1 b` for `b` of `k` rows.
    fn solve(&self, b: &DMatrix<f64>) -> Result<DMatrix<f64>> {
        let k = b.nrows();
        let x = self
            .whiten(b)
            .and_then(|y| self.c.view((0, 0), (k, k)).tr_solve_lower_triangular(&y))
            .ok_or_else(|| {
                Error::numerical(
                    "LAMBDA partial fix",
                    "singular Cholesky factor of the decorrelated covariance",
                )
            })?;
        Ok(DMatrix::from_fn(k, b.ncols(), |i, j| x[(k - 1 - i, j)]))
    }
}

/// The float solution conditioned on `Z_k^T a = Z_k^T round(a) + best` (`zhat`: `Z_k^T (a - round(a))`).
fn conditioned(
    p: &Problem,
    nested: &Nested,
    zhat: &DVector<f64>,
    best: &DVector<f64>,
    ratio: f64,
    threshold: f64,
    success_rate: f64,
) -> Result<PartialFix> {
    let n = p.len();
    let k = best.len();
    let combinations = p.reduction.z.columns(n - k, k).into_owned();
    // Z_k^T round(a) + best in exact integer arithmetic: |Z| <= 2^52, |round(a)| < 2^53, n <= 256.
    let values = (0..k)
        .map(|c| {
            let shift: i128 = (0..n)
                .map(|l| combinations[(l, c)] as i128 * p.offset[l] as i128)
                .sum();
            bounded_integer(c, shift + best[c] as i128)
        })
        .collect::<Result<Vec<_>>>()?;
    let (ambiguities, covariance) = if k == n {
        (p.to_original(best)?.map(|v| v as f64), DMatrix::zeros(n, n))
    } else {
        let qzk = p.transformed.qz.columns(n - k, k); // Q Z_k (n x k)
        let gain = nested.solve(&qzk.transpose())?.transpose(); // Q Z_k (Z_k^T Q Z_k)^-1
        let amb = &p.a - &gain * (zhat - best);
        let cov = &p.q - &gain * qzk.transpose();
        (amb, (&cov + cov.transpose()) * 0.5)
    };
    Ok(PartialFix {
        fixed_count: k,
        combinations,
        values: DVector::from_vec(values),
        ratio,
        threshold,
        success_rate,
        ambiguities,
        covariance,
    })
}

/// `second / best` of two squared norms (infinite for a zero best: the float vector is an integer one).
pub(crate) fn ratio_of(norms: [f64; 2]) -> f64 {
    if norms[0] > 0.0 {
        norms[1] / norms[0]
    } else {
        f64::INFINITY
    }
}
/// Standard normal draw (Box-Muller, one of the pair).
pub(crate) fn normal(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

#[cfg(test)]
mod accepts_tests {
    use super::*;
    use crate::lambda::reduce;
    use nalgebra::DMatrix;

    /// A covariance with conditional variances of a weak single-frequency epoch (success rate well
    /// below 1), random correlations.
    fn weak_covariance(n: usize, seed: u64) -> DMatrix<f64> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let a = DMatrix::from_fn(n, n, |_, _| normal(&mut rng));
        let q = &a * a.transpose() * 0.08 + DMatrix::identity(n, n) * 0.02;
        (&q + q.transpose()) * 0.5
    }

    #[test]
    fn accepts_equals_the_threshold_function() {
        let mut decided = [0usize; 2];
        for seed in 0..12u64 {
            let n = 3 + (seed as usize % 5);
            let q = weak_covariance(n, seed);
            let factor = reduce(&q).unwrap().factor;
            let (rate, draws) = (0.01, 2000);
            let c = fixed_failure_threshold(&factor, rate, draws, 7).unwrap();
            // Ratios just below and at the threshold, and values around it.
            let mut ratios = vec![c, c * 1.5, 1.0, 2.0, 3.0, 10.0];
            if c > 1.0 {
                ratios.push(c.next_down());
            }
            for r in ratios {
                let yes = fixed_failure_accepts(&factor, r, rate, draws, 7).unwrap();
                assert_eq!(yes, r >= c, "seed {seed} ratio {r} threshold {c}");
                decided[usize::from(yes)] += 1;
            }
        }
        // Both outcomes occurred: the test compares something.
        assert!(decided[0] > 0 && decided[1] > 0, "{decided:?}");
    }
}
