//! Many independent ILS problems in one call, in parallel on rayon's global pool: a study of thousands of
//! float solutions pays the intake once instead of once per problem.
//!
//! Each problem is solved exactly as [`super::ils`] solves it alone (same decorrelation, checks, search
//! and node budget [`node_budget`]), so a batch's answers do not depend on its size, its order or the
//! number of threads. The work of the whole call is bounded twice: before anything runs,
//! `k (n^3 + BATCH_FIXED_WORK)` must stay within [`BATCH_MAX_WORK`] (the decorrelation and its checks are
//! O(n^3) per problem); while it runs, the nodes of all searches together within [`BATCH_MAX_NODES`].

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

use super::search::{check_candidates, node_budget};
use super::Problem;
use crate::error::{Error, Result};
use crate::interrupt;

/// Work units charged per problem besides its `n^3`: the fixed cost of a problem (checks, allocations,
/// the mapping back), about that of the `n^3` part at n = 10.
pub const BATCH_FIXED_WORK: u64 = 1_000;

/// Most work units `k (n^3 + BATCH_FIXED_WORK)` of one batch (2^32): measured at 2-3 ns per unit on one
/// core (n = 4 to 40, two candidates), about 10 s of one core.
pub const BATCH_MAX_WORK: u64 = 1 << 32;

/// Most search nodes of all the problems of one batch together (1e9, about a minute of one core at
/// n = 40); past it the batch stops with [`Error::Numerical`] (a `ConvergenceError` in Python). Whether
/// a batch passes depends only on its problems: the total is the sum of each search's own count.
pub const BATCH_MAX_NODES: u64 = 1_000_000_000;

/// The solutions of a batch of `k` problems of `n` ambiguities with `m` candidates each.
#[derive(Debug, Clone, PartialEq)]
pub struct BatchSolution {
    /// Integer vectors, `fixed[(p m + c) n + i]`: problem p, candidate c (best first), ambiguity i.
    pub fixed: Vec<i64>,
    /// `squared_norms[p m + c]`, recomputed from the original float vector and covariance, ascending per
    /// problem.
    pub squared_norms: Vec<f64>,
    /// Search nodes of each problem.
    pub nodes_visited: Vec<u64>,
}

/// Checks the size of a batch before any work: `k (n^3 + BATCH_FIXED_WORK) <= BATCH_MAX_WORK`.
///
/// # Errors
/// [`Error::TooLarge`] naming `float_ambiguities` with the work asked for.
pub fn check_batch_work(k: usize, n: usize) -> Result<()> {
    let per = (n as u64)
        .saturating_pow(3)
        .saturating_add(BATCH_FIXED_WORK);
    let work = per.saturating_mul(k as u64);
    if work > BATCH_MAX_WORK {
        return Err(Error::too_large(
            "float_ambiguities",
            work as f64,
            BATCH_MAX_WORK as f64,
            "work units (problems x (n^3 + 1000))",
        ));
    }
    Ok(())
}

/// The `m` best integer vectors of each of `k` problems.
///
/// # Arguments
/// * `a` - `k n` float ambiguities, problem after problem (row-major `(k, n)`), cycles.
/// * `q` - `n n` (one covariance shared by every problem) or `k n n` values (one per problem), each
///   covariance row-major, cycles^2.
/// * `n` - ambiguities per problem; `m` - candidates per problem.
///
/// # Errors
/// [`Error::Shape`] for sizes that do not fit, [`Error::TooLarge`] from [`check_batch_work`] and
/// [`check_candidates`]; otherwise the error of the lowest-numbered problem that fails (the message
/// starts with `problem p`), those of [`super::ils`]; [`Error::Numerical`] past [`BATCH_MAX_NODES`];
/// [`Error::Interrupted`] on [`crate::interrupt::request`].
pub fn ils_batch(a: &[f64], q: &[f64], n: usize, m: usize) -> Result<BatchSolution> {
    check_candidates(m)?;
    if n == 0 || !a.len().is_multiple_of(n) {
        return Err(Error::Shape {
            name: "float_ambiguities",
            expected: "(k, n) with n >= 1".into(),
            actual: format!("{} values for n = {n}", a.len()),
        });
    }
    let k = a.len() / n;
    let nn = n * n;
    let shared = q.len() == nn;
    if !shared && q.len() != k * nn {
        return Err(Error::Shape {
            name: "covariance",
            expected: format!("({n}, {n}) or ({k}, {n}, {n})"),
            actual: format!("{} values", q.len()),
        });
    }
    check_batch_work(k, n)?;
    let nodes = AtomicU64::new(0);
    // The lowest problem known to fail: problems after it need not run (their answer is not returned).
    let first_failure = AtomicUsize::new(usize::MAX);
    let solved: Vec<Option<Result<super::IlsSolution>>> = (0..k)
        .into_par_iter()
        .map(|p| {
            if p > first_failure.load(Ordering::Relaxed) {
                return None;
            }
            let out = solve_one(p, a, q, n, m, shared, &nodes);
            if out.is_err() {
                first_failure.fetch_min(p, Ordering::Relaxed);
            }
            Some(out)
        })
        .collect();
    let mut out = BatchSolution {
        fixed: Vec::with_capacity(k * m * n),
        squared_norms: Vec::with_capacity(k * m),
        nodes_visited: Vec::with_capacity(k),
    };
    for (p, s) in solved.into_iter().enumerate() {
        let s = s
            .ok_or_else(|| Error::numerical("LAMBDA batch", format!("problem {p} was not solved")))?
            .map_err(|e| at_problem(e, p))?;
        for c in 0..m {
            out.fixed.extend(s.fixed.column(c).iter());
        }
        out.squared_norms.extend(&s.squared_norms);
        out.nodes_visited.push(s.nodes_visited);
    }
    Ok(out)
}

fn solve_one(
    p: usize,
    a: &[f64],
    q: &[f64],
    n: usize,
    m: usize,
    shared: bool,
    nodes: &AtomicU64,
) -> Result<super::IlsSolution> {
    interrupt::check("LAMBDA batch")?;
    let nn = n * n;
    let qp = if shared { q } else { &q[p * nn..(p + 1) * nn] };
    let av = DVector::from_column_slice(&a[p * n..(p + 1) * n]);
    let qm = DMatrix::from_row_slice(n, n, qp);
    let s = Problem::new(&av, &qm)?.solve(m, node_budget(n))?;
    let total = nodes.fetch_add(s.nodes_visited, Ordering::Relaxed) + s.nodes_visited;
    if total > BATCH_MAX_NODES {
        return Err(Error::numerical(
            "LAMBDA batch",
            format!(
                "the searches of the batch visited more than {BATCH_MAX_NODES:e} nodes together (the \
                 batch's node budget); split the batch"
            ),
        ));
    }
    Ok(s)
}

/// `e` with the number of the problem it belongs to in its message (its class unchanged).
fn at_problem(e: Error, p: usize) -> Error {
    match e {
        Error::Shape {
            name,
            expected,
            actual,
        } => Error::Shape {
            name,
            expected,
            actual: format!("{actual} (problem {p})"),
        },
        Error::NonFinite { name, index } => Error::out_of_range(
            name,
            format!("problem {p} contains a non-finite value at index {index}"),
        ),
        Error::OutOfRange { name, detail } => Error::OutOfRange {
            name,
            detail: format!("problem {p}: {detail}"),
        },
        Error::Convergence { what, iterations } => Error::numerical(
            "LAMBDA batch",
            format!("problem {p}: {what} did not converge after {iterations} iterations"),
        ),
        Error::Numerical { what, detail } => Error::Numerical {
            what,
            detail: format!("problem {p}: {detail}"),
        },
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lambda::ils;
    use crate::lambda::test_support::{random_covariance, Lcg};

    #[test]
    fn batch_equals_one_call_per_problem() {
        let mut rng = Lcg(17);
        for n in [1usize, 3, 8, 20] {
            let k = 9;
            let qs: Vec<DMatrix<f64>> = (0..k)
                .map(|_| random_covariance(&mut rng, n, 1e-2))
                .collect();
            let a: Vec<f64> = (0..k * n).map(|_| 40.0 * rng.uniform() - 20.0).collect();
            let q: Vec<f64> = qs
                .iter()
                .flat_map(|m| m.transpose().iter().copied().collect::<Vec<_>>())
                .collect();
            for (shared, qv) in [(false, q.clone()), (true, q[..n * n].to_vec())] {
                let got = ils_batch(&a, &qv, n, 3).unwrap();
                for p in 0..k {
                    let qp = if shared { &qs[0] } else { &qs[p] };
                    let one =
                        ils(&DVector::from_column_slice(&a[p * n..(p + 1) * n]), qp, 3).unwrap();
                    for c in 0..3 {
                        let row = &got.fixed[(p * 3 + c) * n..(p * 3 + c + 1) * n];
                        assert_eq!(row, one.fixed.column(c).as_slice());
                        assert_eq!(got.squared_norms[p * 3 + c], one.squared_norms[c]);
                    }
                    assert_eq!(got.nodes_visited[p], one.nodes_visited);
                }
            }
        }
    }

    #[test]
    fn failures_name_the_lowest_problem_and_limits_come_first() {
        let n = 2;
        // problem 1 and 3 are not positive definite
        let good = [1.0, 0.0, 0.0, 1.0];
        let bad = [1.0, 2.0, 2.0, 1.0];
        let q: Vec<f64> = [good, bad, good, bad].concat();
        let a = vec![0.2; 4 * n];
        let e = ils_batch(&a, &q, n, 2).unwrap_err().to_string();
        assert!(
            e.contains("problem 1:") && e.contains("not positive definite"),
            "{e}"
        );
        assert!(matches!(
            ils_batch(&a, &q[..6], n, 2),
            Err(Error::Shape { .. })
        ));
        assert!(matches!(
            ils_batch(&a[..3], &good, n, 2),
            Err(Error::Shape { .. })
        ));
        // 2^32 work units: refused before anything is allocated or solved.
        let e = check_batch_work(1 << 20, 256).unwrap_err();
        assert!(matches!(e, Error::TooLarge { .. }), "{e:?}");
        check_batch_work(1000, 64).unwrap();
        assert!(matches!(
            ils_batch(&a, &good, n, 0),
            Err(Error::OutOfRange { .. })
        ));
    }
}
