//! Many independent ILS problems in one call, in parallel on rayon's global pool: a study of thousands of
//! float solutions pays the intake once instead of once per problem.
//!
//! Each problem is solved exactly as [`super::ils`] solves it alone (same decorrelation, checks, search
//! and node budget [`node_budget`]), so a batch's answers do not depend on its size, its order or the
//! number of threads. A covariance shared by every problem is decorrelated and checked once
//! ([`Problem::solve_floats`]): the answers are the same, the decorrelation's O(n^3) paid once. The work of the whole call is bounded twice, in the same units (about 2-3 ns of one
//! core each), so that a call finishes or is refused in about 10 s: before anything runs,
//! `k (n^3 + BATCH_FIXED_WORK)` must stay within [`BATCH_MAX_WORK`] (the decorrelation and its checks are
//! O(n^3) per problem); while it runs, the searches' nodes, `n + NODE_FIXED_WORK` units each, within
//! [`BATCH_MAX_SEARCH_WORK`] together. A small batch ([`is_short`]) runs on the calling thread.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

use super::search::{check_candidates, node_budget};
use super::workspace::with_workspace;
use super::{Problem, Workspace};
use crate::error::{Error, Result};
use crate::interrupt;

/// Work units charged per problem besides its `n^3`: the fixed cost of a problem (checks, allocations,
/// the mapping back), about that of the `n^3` part at n = 10.
pub const BATCH_FIXED_WORK: u64 = 1_000;

/// Most work units `k (n^3 + BATCH_FIXED_WORK)` of the decorrelations of one batch (2^31): measured at
/// 1-3 ns per unit on one core (n = 4 to 40, two candidates), at most about 5 s of one core.
pub const BATCH_MAX_WORK: u64 = 1 << 31;

/// Work units charged per search node besides its `n` (the partial sums a node updates): a node costs
/// about 60 ns at n = 40 (16 million a second), under the `n + 16 = 56` units' 110-170 ns.
pub const NODE_FIXED_WORK: u64 = 16;

/// Most work units `nodes (n + NODE_FIXED_WORK)` of all the searches of one batch together (2^31, about
/// 5 s of one core; 3.8e7 nodes at n = 40); past it the batch stops with [`Error::Numerical`] (a
/// `ConvergenceError` in Python). Whether a batch passes depends only on its problems: the total is the
/// sum of each search's own count. With [`BATCH_MAX_WORK`], a call's whole work stays within about 10 s
/// of one core (plus at most one search per thread in flight when the budget runs out).
pub const BATCH_MAX_SEARCH_WORK: u64 = 1 << 31;

/// Largest decorrelation work `k (n^3 + BATCH_FIXED_WORK)` of a batch solved on the calling thread
/// (2^16, well under a millisecond): below it, handing the problems to a pool costs more than it saves.
pub const SHORT_WORK: u64 = 1 << 16;

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

/// The decorrelation work `k (n^3 + BATCH_FIXED_WORK)` of `k` problems of `n` ambiguities (saturating).
pub fn batch_work(k: usize, n: usize) -> u64 {
    (n as u64)
        .saturating_pow(3)
        .saturating_add(BATCH_FIXED_WORK)
        .saturating_mul(k as u64)
}

/// Whether a batch is small enough to be solved on the calling thread ([`SHORT_WORK`]).
pub fn is_short(k: usize, n: usize) -> bool {
    batch_work(k, n) <= SHORT_WORK
}

/// Checks the size of a batch before any work: `k (n^3 + BATCH_FIXED_WORK) <= BATCH_MAX_WORK`.
///
/// # Errors
/// [`Error::TooLarge`] naming `float_ambiguities` with the work asked for.
pub fn check_batch_work(k: usize, n: usize) -> Result<()> {
    let work = batch_work(k, n);
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

/// Checks the searches' work so far, `total_nodes (n + NODE_FIXED_WORK)`, against
/// [`BATCH_MAX_SEARCH_WORK`], or one full search's budget `node_budget(n) (n + NODE_FIXED_WORK)` where
/// that is larger (n >= 59): a batch of one problem is never refused where [`super::ils`] would answer.
///
/// # Errors
/// [`Error::Numerical`] with the nodes, the work and the limit.
pub fn check_search_work(total_nodes: u64, n: usize) -> Result<()> {
    let per_node = n as u64 + NODE_FIXED_WORK;
    let work = total_nodes.saturating_mul(per_node);
    let limit = BATCH_MAX_SEARCH_WORK.max(node_budget(n).saturating_mul(per_node));
    if work > limit {
        return Err(Error::numerical(
            "LAMBDA batch",
            format!(
                "the searches of the batch visited {total_nodes} nodes together, {work} work units \
                 ({per_node} per node at n = {n}), more than the batch's search budget of {limit} \
                 (BATCH_MAX_SEARCH_WORK, or one search's budget if larger); split the batch"
            ),
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
/// starts with `problem p`), those of [`super::ils`]; [`Error::Numerical`] past
/// [`BATCH_MAX_SEARCH_WORK`];
/// [`Error::Interrupted`] on [`crate::interrupt::request`].
pub fn ils_batch(a: &[f64], q: &[f64], n: usize, m: usize) -> Result<BatchSolution> {
    check_candidates(m)?;
    let (k, shared) = batch_shape(a, q, n)?;
    check_batch_work(k, n)?;
    let nodes = AtomicU64::new(0);
    // The lowest problem known to fail: problems after it need not run (their answer is not returned).
    let first_failure = AtomicUsize::new(usize::MAX);
    // One covariance for every problem: decorrelated (and checked) once, with problem 0's float vector,
    // so that a failure there is problem 0's, the lowest failing one, as when each is solved alone.
    let base = if shared && k > 0 {
        let a0 = DVector::from_column_slice(&a[..n]);
        Some(Problem::new(&a0, &DMatrix::from_row_slice(n, n, q)).map_err(|e| at_problem(e, 0))?)
    } else {
        None
    };
    // Every answer is written in place: the only allocations of a batch are its outputs, the per-problem
    // outcomes and (once per thread) the workspace.
    let mut out = BatchSolution {
        fixed: vec![0; k * m * n],
        squared_norms: vec![0.0; k * m],
        nodes_visited: vec![0; k],
    };
    let run = |(p, ((fixed, norms), visited)): Slot<'_>| {
        if p > first_failure.load(Ordering::Relaxed) {
            return None;
        }
        let job = Job {
            p,
            a,
            q,
            n,
            m,
            base: base.as_ref(),
        };
        let outcome = with_workspace(|ws| job.solve(ws, fixed, norms, &nodes));
        match outcome {
            Ok(v) => *visited = v,
            Err(_) => {
                first_failure.fetch_min(p, Ordering::Relaxed);
            }
        }
        Some(outcome.map(|_| ()))
    };
    let chunk = (m * n).max(1);
    let solved: Vec<Option<Result<()>>> = if is_short(k, n) {
        out.fixed
            .chunks_mut(chunk)
            .zip(out.squared_norms.chunks_mut(m))
            .zip(out.nodes_visited.iter_mut())
            .enumerate()
            .map(run)
            .collect()
    } else {
        out.fixed
            .par_chunks_mut(chunk)
            .zip(out.squared_norms.par_chunks_mut(m))
            .zip(out.nodes_visited.par_iter_mut())
            .enumerate()
            .map(run)
            .collect()
    };
    first_error(solved)?;
    Ok(out)
}

/// The number of problems `k` of a batch of `a.len()` float ambiguities, `n` per problem, and whether
/// the covariances `q` are one shared by all (`n n` values) rather than one per problem (`k n n`).
fn batch_shape(a: &[f64], q: &[f64], n: usize) -> Result<(usize, bool)> {
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
    Ok((k, shared))
}

/// The error of the lowest-numbered problem that failed or was not run, named `problem p`; problems
/// after a failure are skipped, so an unsolved one comes only after the failure that stopped it.
fn first_error(solved: Vec<Option<Result<()>>>) -> Result<()> {
    for (p, s) in solved.into_iter().enumerate() {
        s.ok_or_else(|| Error::numerical("LAMBDA batch", format!("problem {p} was not solved")))?
            .map_err(|e| at_problem(e, p))?;
    }
    Ok(())
}

/// Problem p's place in the batch's output: its integers, norms and nodes.
type Slot<'a> = (usize, ((&'a mut [i64], &'a mut [f64]), &'a mut u64));

/// One problem of a batch.
struct Job<'a> {
    p: usize,
    a: &'a [f64],
    q: &'a [f64],
    n: usize,
    m: usize,
    base: Option<&'a Problem>,
}

impl Job<'_> {
    /// Solves problem `p` into its slices of the batch's output; returns its nodes.
    fn solve(
        &self,
        ws: &mut Workspace,
        fixed: &mut [i64],
        norms: &mut [f64],
        nodes: &AtomicU64,
    ) -> Result<u64> {
        interrupt::check("LAMBDA batch")?;
        let Job { p, n, m, .. } = *self;
        let nn = n * n;
        let av = &self.a[p * n..(p + 1) * n];
        let budget = node_budget(n);
        let visited = match self.base {
            Some(b) => ws.solve_floats(b, av, m, budget, fixed, norms)?,
            None => {
                let qp = &self.q[p * nn..(p + 1) * nn];
                ws.solve_row_major(av, qp, m, budget, fixed, norms)?
            }
        };
        check_search_work(nodes.fetch_add(visited, Ordering::Relaxed) + visited, n)?;
        Ok(visited)
    }
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
        // A shared covariance is checked once, as problem 0's; a float vector as its own problem's.
        let e = ils_batch(&a, &bad, n, 2).unwrap_err().to_string();
        assert!(
            e.contains("problem 0:") && e.contains("not positive definite"),
            "{e}"
        );
        let mut far = a.clone();
        far[2 * n + 1] = f64::NAN;
        let e = ils_batch(&far, &good, n, 2).unwrap_err().to_string();
        assert!(e.contains("problem 2 contains a non-finite"), "{e}");
        assert!(matches!(
            ils_batch(&a, &q[..6], n, 2),
            Err(Error::Shape { .. })
        ));
        assert!(matches!(
            ils_batch(&a[..3], &good, n, 2),
            Err(Error::Shape { .. })
        ));
        // 2^31 work units: refused before anything is allocated or solved.
        let e = check_batch_work(1 << 20, 256).unwrap_err();
        assert!(matches!(e, Error::TooLarge { .. }), "{e:?}");
        check_batch_work(1000, 64).unwrap();
        let k = (BATCH_MAX_WORK / (40u64.pow(3) + BATCH_FIXED_WORK)) as usize;
        check_batch_work(k, 40).unwrap();
        assert!(matches!(
            check_batch_work(k + 1, 40),
            Err(Error::TooLarge { .. })
        ));
        // The searches' budget: 2^31 units of n + 16 per node.
        check_search_work(BATCH_MAX_SEARCH_WORK / 56, 40).unwrap();
        let e = check_search_work(BATCH_MAX_SEARCH_WORK / 56 + 1, 40)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("BATCH_MAX_SEARCH_WORK") && e.contains("56 per node"),
            "{e}"
        );
        assert!(matches!(
            ils_batch(&a, &good, n, 0),
            Err(Error::OutOfRange { .. })
        ));
    }
}
