//! The buffers of one LAMBDA problem, kept between problems: a thread solving many problems of the same
//! size (a batch, a loop over epochs) allocates them once, not per problem.
//!
//! The arithmetic is that of [`Problem::new`] followed by [`Problem::solve`], in the same order and
//! through the same functions (`factorise_into`, `reduce_in_place`, `verify_parts`, `search_into`,
//! `replay_into`), so the integers, squared norms, node counts and errors are bit-for-bit those of a
//! [`Problem`]; only where the intermediate matrices live differs.

use std::cell::RefCell;

use nalgebra::{DMatrix, DVector};

use super::identity::{verify_parts, VerifyBuffers};
use super::ldl::{check_covariance, factorise_into, shape_to, Ltdl};
use super::reduction::{reduce_in_place, replay_into, Step, Transform};
use super::search::{check_candidates, search_into, SearchBuffers};
use super::verify::{agreeing_order_into, Metric};
use super::{bounded_integer, check_floats, exact_integer, Problem};
use crate::error::{ensure_finite, Result};

/// What a search needs of a decorrelated covariance (a [`Problem`]'s or a [`Workspace`]'s own).
#[derive(Clone, Copy)]
pub(crate) struct Decorrelated<'a> {
    pub(crate) factor: &'a Ltdl,
    /// `Z` as `f64` (exact integers).
    pub(crate) zf: &'a DMatrix<f64>,
    pub(crate) steps: &'a [Step],
    pub(crate) metric: &'a Metric,
}

/// The buffers of the search and the mapping back (one float vector against a decorrelated covariance).
#[derive(Default)]
pub(crate) struct SolveBuffers {
    offset: Vec<i64>,
    frac: DVector<f64>,
    zhat: DVector<f64>,
    search: SearchBuffers,
    candidates: Vec<f64>,
    searched: Vec<f64>,
    wide: Vec<i128>,
    residual: DVector<f64>,
    recomputed: Vec<f64>,
    order: Vec<usize>,
    unordered: Vec<i64>,
}

/// The buffers of a decorrelation and its checks.
#[derive(Default)]
struct DecorrelationBuffers {
    /// The lower triangle of `Q` mirrored: the matrix the factorisation used.
    lower: DMatrix<f64>,
    u: DMatrix<f64>,
    lt: DMatrix<f64>,
    factor: Ltdl,
    transform: Option<Transform>,
    verify: VerifyBuffers,
    metric: Option<Metric>,
}

/// Everything one problem needs, reusable: after the first problem of a size, solving another of the
/// same size and candidate count allocates nothing up to n = [`super::identity::OWN_PRODUCT_MAX_N`], and
/// above it only the packing buffers of the identity check's four blocked products (errors aside, which
/// format their messages).
#[derive(Default)]
pub struct Workspace {
    /// The covariance of the problem being solved, column-major.
    q: DMatrix<f64>,
    dec: DecorrelationBuffers,
    solve: SolveBuffers,
}

impl Default for Ltdl {
    fn default() -> Ltdl {
        Ltdl {
            l: DMatrix::zeros(0, 0),
            d: DVector::zeros(0),
        }
    }
}

impl Workspace {
    /// An empty workspace (its buffers grow to the first problem's size).
    pub fn new() -> Workspace {
        Workspace::default()
    }

    /// [`super::ils`] of `a` with the covariance `q` given row-major (n n values; a symmetric matrix reads
    /// the same either way, but the checks name entries as numpy does): the `m` best integer vectors
    /// into `fixed` (n m values, column after column, best first) and their squared norms into `norms`
    /// (m); returns the nodes visited.
    ///
    /// # Errors
    /// Those of [`super::ils`].
    pub fn solve_row_major(
        &mut self,
        a: &[f64],
        q: &[f64],
        m: usize,
        max_nodes: u64,
        fixed: &mut [i64],
        norms: &mut [f64],
    ) -> Result<u64> {
        let n = a.len();
        shape_to(&mut self.q, n, n);
        for (j, mut col) in self.q.column_iter_mut().enumerate() {
            for (i, v) in col.iter_mut().enumerate() {
                *v = q[i * n + j];
            }
        }
        let Workspace { q, dec, solve } = self;
        solve_with(dec, solve, a, q, m, max_nodes, fixed, norms)
    }

    /// [`Workspace::solve_row_major`] with the covariance as a matrix.
    ///
    /// # Errors
    /// Those of [`super::ils`].
    pub fn solve(
        &mut self,
        a: &[f64],
        q: &DMatrix<f64>,
        m: usize,
        max_nodes: u64,
        fixed: &mut [i64],
        norms: &mut [f64],
    ) -> Result<u64> {
        solve_with(
            &mut self.dec,
            &mut self.solve,
            a,
            q,
            m,
            max_nodes,
            fixed,
            norms,
        )
    }

    /// [`Problem::solve_floats`] of `problem` with the float vector `a`, into `fixed` and `norms` as
    /// [`Workspace::solve_row_major`]: the decorrelation is the problem's, only the search's buffers are
    /// this workspace's.
    ///
    /// # Errors
    /// Those of [`Problem::solve_floats`].
    pub fn solve_floats(
        &mut self,
        problem: &Problem,
        a: &[f64],
        m: usize,
        max_nodes: u64,
        fixed: &mut [i64],
        norms: &mut [f64],
    ) -> Result<u64> {
        ensure_finite("float ambiguities", a.iter())?;
        check_floats(a, problem.len())?;
        self.solve_floats_checked(problem, a, m, max_nodes, fixed, norms)
    }

    /// [`Workspace::solve_floats`] of a float vector already checked against `problem`.
    pub(crate) fn solve_floats_checked(
        &mut self,
        problem: &Problem,
        a: &[f64],
        m: usize,
        max_nodes: u64,
        fixed: &mut [i64],
        norms: &mut [f64],
    ) -> Result<u64> {
        solve_decorrelated(
            problem.decorrelated(),
            &mut self.solve,
            a,
            m,
            max_nodes,
            fixed,
            norms,
        )
    }
}

/// Checks and decorrelates `(a, q)` into `dec`, then searches with `solve`: [`Problem::new`] and
/// [`Problem::solve`] without their allocations.
#[allow(clippy::too_many_arguments)]
fn solve_with(
    dec: &mut DecorrelationBuffers,
    solve: &mut SolveBuffers,
    a: &[f64],
    q: &DMatrix<f64>,
    m: usize,
    max_nodes: u64,
    fixed: &mut [i64],
    norms: &mut [f64],
) -> Result<u64> {
    ensure_finite("float ambiguities", a.iter())?;
    check_covariance(q)?;
    check_floats(a, q.nrows())?;
    let n = q.nrows();
    factorise_into(q, &mut dec.u, &mut dec.lt, &mut dec.factor)?;
    let transform = dec.transform.get_or_insert_with(|| Transform::identity(n));
    reduce_in_place(&mut dec.factor.l, &mut dec.factor.d, transform)?;
    // As `reduction::reduce_checked`: the identity is checked against the factorised lower triangle.
    shape_to(&mut dec.lower, n, n);
    for j in 0..n {
        for i in 0..n {
            dec.lower[(i, j)] = q[(i.max(j), i.min(j))];
        }
    }
    verify_parts(
        &dec.lower,
        &transform.z,
        &transform.steps,
        &dec.factor,
        &mut dec.verify,
    )?;
    let metric = Metric::renew(dec.metric.take(), "LAMBDA", q)?;
    let metric = dec.metric.insert(metric);
    let decorrelated = Decorrelated {
        factor: &dec.factor,
        zf: &transform.z,
        steps: &transform.steps,
        metric,
    };
    solve_decorrelated(decorrelated, solve, a, m, max_nodes, fixed, norms)
}

/// The `m` best integer vectors of the checked float vector `a` against a decorrelated covariance, into
/// `fixed` (n m, column after column) and `norms` (m), through the buffers `b`: the search, the exact
/// mapping back `round(a) + Z^-T z` and the norms recomputed from the original `a` and `Q`, as
/// [`Problem::solve`].
///
/// # Errors
/// Those of [`Problem::solve`].
pub(crate) fn solve_decorrelated(
    dec: Decorrelated<'_>,
    b: &mut SolveBuffers,
    a: &[f64],
    m: usize,
    max_nodes: u64,
    fixed: &mut [i64],
    norms: &mut [f64],
) -> Result<u64> {
    check_candidates(m)?;
    let n = a.len();
    floats_into(dec.zf, a, b);
    b.candidates.clear();
    b.candidates.resize(n * m, 0.0);
    let nodes = search_into(
        dec.factor,
        b.zhat.as_slice(),
        m,
        max_nodes,
        &mut b.search,
        &mut b.candidates,
        &mut b.searched,
    )?;
    for (k, &v) in b.candidates.iter().enumerate() {
        exact_integer(k % n, v)?;
    }
    // Z^-T: the steps' S^-T = I + mu e_j e_i^T, last step first.
    replay_into(
        &mut b.candidates,
        n,
        dec.steps.iter().rev(),
        |i, j| (j, i),
        &mut b.wide,
    )?;
    for (e, (o, &w)) in fixed.iter_mut().zip(&b.wide).enumerate() {
        let i = e % n;
        *o = bounded_integer(i, (b.offset[i] as i128).saturating_add(w))?;
    }
    if b.residual.len() != n {
        b.residual = DVector::zeros(n);
    }
    b.recomputed.clear();
    for column in fixed.chunks_exact(n) {
        // a - z = (a - round(a)) - (z - round(a)): the integer difference is small and exact.
        for (i, ri) in b.residual.iter_mut().enumerate() {
            *ri = b.frac[i] - column[i].saturating_sub(b.offset[i]) as f64;
        }
        b.recomputed
            .push(dec.metric.squared_norm_mut(&mut b.residual));
    }
    agreeing_order_into("LAMBDA", &b.searched, &b.recomputed, &mut b.order)?;
    if b.order.iter().enumerate().all(|(c, &k)| c == k) {
        norms.copy_from_slice(&b.recomputed);
    } else {
        b.unordered.clear();
        b.unordered.extend_from_slice(fixed);
        for (c, &k) in b.order.iter().enumerate() {
            fixed[c * n..(c + 1) * n].copy_from_slice(&b.unordered[k * n..(k + 1) * n]);
            norms[c] = b.recomputed[k];
        }
    }
    Ok(nodes)
}

/// `round(a)`, `a - round(a)` (exact) and `Z^T (a - round(a))` into `b`, as `Floats::new`.
fn floats_into(zf: &DMatrix<f64>, a: &[f64], b: &mut SolveBuffers) {
    let n = a.len();
    if b.frac.len() != n {
        b.frac = DVector::zeros(n);
        b.zhat = DVector::zeros(n);
    }
    b.offset.clear();
    for (i, &v) in a.iter().enumerate() {
        let rounded = v.round();
        b.frac[i] = v - rounded;
        b.offset.push(rounded as i64);
    }
    zf.tr_mul_to(&b.frac, &mut b.zhat);
}

thread_local! {
    static WORKSPACE: RefCell<Workspace> = RefCell::new(Workspace::new());
}

/// `f` with this thread's workspace (a fresh one if it is already in use further up the stack).
pub(crate) fn with_workspace<T>(f: impl FnOnce(&mut Workspace) -> T) -> T {
    WORKSPACE.with(|cell| match cell.try_borrow_mut() {
        Ok(mut ws) => f(&mut ws),
        Err(_) => f(&mut Workspace::new()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Error;
    use crate::lambda::node_budget;
    use crate::lambda::test_support::{random_covariance, spectrum_covariance, Lcg};

    /// One workspace through problems of changing size and candidate count (buffers grown, shrunk and
    /// reused, errors in between) answers each exactly as a fresh `Problem` does.
    #[test]
    fn reused_workspace_answers_as_a_fresh_problem() {
        let mut rng = Lcg(29);
        let mut ws = Workspace::new();
        let sizes = [4usize, 9, 4, 1, 20, 20, 3, 33, 9];
        for (t, &n) in sizes.iter().enumerate() {
            let m = 1 + t % 3;
            let q = if t % 2 == 0 {
                random_covariance(&mut rng, n, 1e-2)
            } else {
                spectrum_covariance(&mut rng, n, 1e6)
            };
            let a: Vec<f64> = (0..n).map(|_| 100.0 * rng.uniform() - 50.0).collect();
            let want = Problem::new(&DVector::from_column_slice(&a), &q)
                .unwrap()
                .solve(m, node_budget(n))
                .unwrap();
            let (mut fixed, mut norms) = (vec![0; n * m], vec![0.0; m]);
            let nodes = ws
                .solve(&a, &q, m, node_budget(n), &mut fixed, &mut norms)
                .unwrap();
            assert_eq!(fixed, want.fixed.as_slice(), "problem {t}, n = {n}");
            assert_eq!(norms, want.squared_norms, "problem {t}");
            assert_eq!(nodes, want.nodes_visited, "problem {t}");
            // Row-major input of the transposed matrix: the same problem.
            let row: Vec<f64> = q.transpose().iter().copied().collect();
            let again = ws
                .solve_row_major(&a, &row, m, node_budget(n), &mut fixed, &mut norms)
                .unwrap();
            assert_eq!((fixed.as_slice(), again), (want.fixed.as_slice(), nodes));
            // A failing problem in between leaves nothing behind.
            let bad = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
            let e = ws
                .solve(&[0.1, 0.2], &bad, m, 10, &mut [0; 4], &mut [0.0; 2])
                .unwrap_err();
            assert!(matches!(e, Error::OutOfRange { .. }), "{e:?}");
        }
    }
}
