//! The fixed-failure-rate ratio test of one epoch as a yes/no decision, stopped as soon as it is known.
//!
//! [`crate::lambda::validation::fixed_failure_threshold`] simulates `N` draws of the float ambiguities
//! under their own covariance, `Z^T (a - z) ~ N(0, L^T D L)`, and sets the threshold `c` just above the
//! `floor(P_f N) + 1`-th largest ratio among the draws whose best candidate is wrong (Teunissen & Verhagen
//! 2009, Survey Review 41:138-151). An observed ratio `R` passes (`R >= c`) exactly when at most
//! `floor(P_f N)` wrong draws have a ratio of at least `R`. Counting those draws instead of sorting them
//! lets a failing epoch stop after the first block that exceeds the count, which is most of the cost
//! saved: in weak single-frequency sets most epochs below the success-rate gate fail. The draws (seed,
//! one ChaCha stream per draw, Box-Muller) are those of the threshold function, so both give the same
//! decision (`accepts_equals_the_threshold_function` checks it).

use nalgebra::DVector;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::error::Result;
use crate::lambda::bootstrap::success_rate;
use crate::lambda::ldl::Ltdl;
use crate::lambda::search::{search, DEFAULT_MAX_NODES};
use crate::lambda::validation::SIMULATION_MAX_NODES;

/// Draws simulated between two checks of the count (the decision does not depend on it).
const BLOCK: usize = 1024;

/// Whether ratio `ratio` passes the fixed-failure-rate test for `failure_rate` with `draws` draws of
/// seed `seed` under the decorrelated factors `factor` (`ratio >= fixed_failure_threshold(..)`).
///
/// # Errors
/// Those of the search ([`crate::error::Error::Convergence`] at the node cap).
pub fn accepts(
    factor: &Ltdl,
    ratio: f64,
    failure_rate: f64,
    draws: usize,
    seed: u64,
) -> Result<bool> {
    if ratio < 1.0 {
        return Ok(false);
    }
    // The bootstrapped failure rate bounds the ILS one: every fix is then acceptable (threshold 1).
    if 1.0 - success_rate(factor.d.as_slice()) <= failure_rate {
        return Ok(true);
    }
    let n = factor.d.len();
    let sd = factor.d.map(f64::sqrt);
    let max_nodes = DEFAULT_MAX_NODES.min(SIMULATION_MAX_NODES / draws.max(1) as u64);
    let allowed = (failure_rate * draws as f64).floor() as usize;
    let mut count = 0usize;
    for start in (0..draws).step_by(BLOCK) {
        let end = (start + BLOCK).min(draws);
        count += (start..end)
            .into_par_iter()
            .map(|t| {
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                rng.set_stream(t as u64);
                let w = DVector::from_fn(n, |i, _| sd[i] * normal(&mut rng));
                let e = factor.l.tr_mul(&w);
                let found = search(factor, &e, 2, max_nodes)?;
                let wrong = found.z.column(0).iter().any(|&v| v != 0.0);
                let r = if found.squared_norms[0] > 0.0 {
                    found.squared_norms[1] / found.squared_norms[0]
                } else {
                    f64::INFINITY
                };
                Ok(usize::from(wrong && r >= ratio))
            })
            .try_reduce(|| 0, |a, b| Ok(a + b))?;
        if count > allowed {
            return Ok(false);
        }
    }
    Ok(true)
}

/// Standard normal draw (Box-Muller, one of the pair), as the threshold function draws it.
fn normal(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lambda::reduce;
    use crate::lambda::validation::fixed_failure_threshold;
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
                let yes = accepts(&factor, r, rate, draws, 7).unwrap();
                assert_eq!(yes, r >= c, "seed {seed} ratio {r} threshold {c}");
                decided[usize::from(yes)] += 1;
            }
        }
        // Both outcomes occurred: the test compares something.
        assert!(decided[0] > 0 && decided[1] > 0, "{decided:?}");
    }
}
