//! LAMBDA integer ambiguity resolution: decorrelation, exact integer least-squares (ILS) search for the
//! best candidates, the bootstrapped success rate, validation (ratio test, partial fixing) and the one
//! gate that accepts or refuses a fix ([`gate`]).
//!
//! Float ambiguities `a` (cycles) with covariance `Q` (cycles^2) are decorrelated by a unimodular
//! integer `Z` (`z = Z^T a`, covariance `Z^T Q Z = L^T D L`), searched there, and mapped back with
//! `Z^-T`, which is integer too, so the answer is the exact ILS solution of the original problem.
//! Teunissen (1995), "The least-squares ambiguity decorrelation adjustment", J. Geodesy 70:65-82;
//! de Jonge & Tiberius (1996), LGR-12; Chang, Yang & Zhou (2005), "MLAMBDA", J. Geodesy 79:552-565.
//!
//! Guarantee: the answer is the exact ILS solution (up to ties within [`verify::NORM_TOLERANCE`]) or an
//! error. `Z` is integer and unimodular by checked integer arithmetic ([`reduction::MAX_Z_ENTRY`]),
//! `Z^T Q Z = L^T D L` is verified ([`reduction::IDENTITY_TOLERANCE`]), every returned squared norm is
//! recomputed from the original `a` and `Q` and must agree with the search's, and every returned integer
//! is exact (`|z| <= MAX_ABS_AMBIGUITY`); a failure of any of these is [`Error::Numerical`].
//! Limits: n <= [`ldl::MAX_DIMENSION`], at most [`MAX_CANDIDATES`] candidates, [`node_budget`]`(n)`
//! search nodes (at most [`DEFAULT_MAX_NODES`]); a batch ([`batch`]) bounds its whole work too.

pub mod batch;
pub mod bootstrap;
pub mod gate;
pub mod identity;
pub mod ldl;
pub mod reduction;
pub mod search;
pub mod validation;
pub mod verify;
pub mod workspace;

#[cfg(test)]
pub(crate) mod test_support;
#[cfg(test)]
mod tests;

use nalgebra::{DMatrix, DVector};

use crate::error::{ensure_finite, Error, Result};
pub use batch::{ils_batch, BatchSolution};
pub use bootstrap::bootstrap_success_rate;
pub use reduction::{reduce, Reduction, Transformed};
pub use search::{
    node_budget, search, Candidates, DEFAULT_MAX_NODES, MAX_CANDIDATES, NODES_PER_AMBIGUITY,
};
use verify::Metric;
pub use workspace::Workspace;
use workspace::{with_workspace, Decorrelated};

/// Largest `|a_i|` of a float ambiguity, and of any integer returned, in cycles: below 2^53, so that the
/// integers are exact as `f64` as well as `i64` and `a - round(a)` is exact.
pub const MAX_ABS_AMBIGUITY: f64 = 4.5e15;

/// The ILS solutions of one problem, in the original ambiguity space.
#[derive(Debug, Clone, PartialEq)]
pub struct IlsSolution {
    /// Integer ambiguity vectors, one per column (n x m), best first.
    pub fixed: DMatrix<i64>,
    /// `(a - z)^T Q^-1 (a - z)` of each column recomputed from the original `a` and `Q`, ascending.
    pub squared_norms: Vec<f64>,
    /// Nodes the search visited (see [`Candidates::nodes_visited`]).
    pub nodes_visited: u64,
}

/// A checked, decorrelated ambiguity problem, ready to be searched (possibly several times).
#[derive(Debug, Clone)]
pub struct Problem {
    /// The decorrelation of `Q`.
    pub reduction: Reduction,
    /// `round(a)`: the search runs on `a - round(a)`, so that integer shifts of `a` are exact.
    pub offset: DVector<i64>,
    /// `a - round(a)` (exact), cycles.
    pub frac: DVector<f64>,
    /// Decorrelated float ambiguities `Z^T (a - round(a))`, cycles.
    pub zhat: DVector<f64>,
    /// `Q Z` and `Z^T Q Z` as the identity check formed them (for partial fixing).
    pub transformed: Transformed,
    /// The original float ambiguities and covariance (conditioning after a partial fix).
    pub(crate) a: DVector<f64>,
    pub(crate) q: DMatrix<f64>,
    /// The original covariance, for recomputing norms.
    metric: Metric,
    /// `Z` as `f64` (exact), for `Z^T a`.
    zf: DMatrix<f64>,
}

impl Problem {
    /// Checks and decorrelates `(a, Q)`.
    ///
    /// # Arguments
    /// * `a` - n float ambiguities, cycles (|a_i| < [`MAX_ABS_AMBIGUITY`]).
    /// * `q` - n x n symmetric positive-definite covariance of `a`, cycles^2, n <= [`ldl::MAX_DIMENSION`].
    ///
    /// # Errors
    /// [`Error::Shape`] for n = 0 or mismatched sizes, [`Error::NonFinite`], [`Error::OutOfRange`] for an
    /// asymmetric or not positive-definite `q` or a float ambiguity too large, [`Error::TooLarge`] for
    /// n beyond the limit, [`Error::Numerical`] when the decorrelation cannot be done exactly.
    pub fn new(a: &DVector<f64>, q: &DMatrix<f64>) -> Result<Problem> {
        ensure_finite("float ambiguities", a.iter())?;
        ldl::check_covariance(q)?;
        check_floats(a.as_slice(), q.nrows())?;
        let (reduction, transformed) = reduction::reduce_checked(q)?;
        let metric = Metric::new("LAMBDA", q)?;
        let zf = reduction.z_f64();
        let Floats { offset, frac, zhat } = Floats::new(&zf, a);
        Ok(Problem {
            reduction,
            offset,
            frac,
            zhat,
            transformed,
            a: a.clone(),
            q: q.clone(),
            metric,
            zf,
        })
    }

    /// The `m` best integer vectors of another float vector `a` with this problem's covariance: the same
    /// answer (and nodes) as `Problem::new(a, q)?.solve(m, max_nodes)`, without decorrelating `q` again.
    ///
    /// # Errors
    /// Those of [`Problem::new`] about `a`, and those of [`Problem::solve`].
    pub fn solve_floats(&self, a: &DVector<f64>, m: usize, max_nodes: u64) -> Result<IlsSolution> {
        ensure_finite("float ambiguities", a.iter())?;
        check_floats(a.as_slice(), self.len())?;
        self.solve_vector(a.as_slice(), m, max_nodes)
    }

    /// Number of ambiguities.
    pub fn len(&self) -> usize {
        self.offset.len()
    }

    /// Always false: a problem has at least one ambiguity.
    pub fn is_empty(&self) -> bool {
        self.offset.is_empty()
    }

    /// The `m` best integer vectors, with their squared norms recomputed from the original `a` and `Q`.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for `m = 0`, [`Error::TooLarge`] for `m > MAX_CANDIDATES`;
    /// [`Error::Convergence`] past `max_nodes` nodes; [`Error::Numerical`] when a recomputed norm
    /// disagrees with the search's or an integer is beyond [`MAX_ABS_AMBIGUITY`].
    pub fn solve(&self, m: usize, max_nodes: u64) -> Result<IlsSolution> {
        self.solve_vector(self.a.as_slice(), m, max_nodes)
    }

    /// The parts of the decorrelation that a search of this problem reads.
    pub(crate) fn decorrelated(&self) -> Decorrelated<'_> {
        Decorrelated {
            factor: &self.reduction.factor,
            zf: &self.zf,
            steps: &self.reduction.steps,
            metric: &self.metric,
        }
    }

    fn own_floats(&self) -> FloatsRef<'_> {
        FloatsRef {
            offset: &self.offset,
            frac: &self.frac,
        }
    }

    /// The search of the checked float vector `a` (this problem's own, or another of its covariance)
    /// through this thread's workspace.
    fn solve_vector(&self, a: &[f64], m: usize, max_nodes: u64) -> Result<IlsSolution> {
        search::check_candidates(m)?;
        let n = self.len();
        let (mut fixed, mut norms) = (DMatrix::<i64>::zeros(n, m), vec![0.0; m]);
        let nodes_visited = with_workspace(|ws| {
            ws.solve_floats_checked(self, a, m, max_nodes, fixed.as_mut_slice(), &mut norms)
        })?;
        Ok(IlsSolution {
            fixed,
            squared_norms: norms,
            nodes_visited,
        })
    }

    /// `(a - z)^T Q^-1 (a - z)` from the original float vector and covariance.
    pub fn original_norm(&self, z: &DVector<i64>) -> f64 {
        self.norm_from(self.own_floats(), z)
    }

    fn norm_from(&self, f: FloatsRef<'_>, z: &DVector<i64>) -> f64 {
        self.norm_into(f, z.as_slice(), &mut DVector::zeros(self.len()))
    }

    /// [`Problem::norm_from`] through the residual buffer `r` (n).
    fn norm_into(&self, f: FloatsRef<'_>, z: &[i64], r: &mut DVector<f64>) -> f64 {
        // a - z = (a - round(a)) - (z - round(a)): the integer difference is small and exact.
        for (i, ri) in r.iter_mut().enumerate() {
            *ri = f.frac[i] - z[i].saturating_sub(f.offset[i]) as f64;
        }
        self.metric.squared_norm_mut(r)
    }

    /// Maps integers of the decorrelated (shifted) space back: `round(a) + Z^-T z`, in exact integer
    /// arithmetic.
    ///
    /// # Errors
    /// [`Error::Numerical`] for a non-integer or too large `z`, or a result beyond
    /// [`MAX_ABS_AMBIGUITY`].
    pub fn to_original(&self, z: &DVector<f64>) -> Result<DVector<i64>> {
        self.to_original_from(&self.offset, z)
    }

    fn to_original_from(&self, offset: &DVector<i64>, z: &DVector<f64>) -> Result<DVector<i64>> {
        let mut out = DVector::zeros(self.len());
        self.to_original_into(offset, z.as_slice(), out.as_mut_slice())?;
        Ok(out)
    }

    /// [`Problem::to_original_from`] into `out` (n), in exact integer arithmetic: Z^-T applied by
    /// replaying the reduction's steps.
    fn to_original_into(&self, offset: &DVector<i64>, z: &[f64], out: &mut [i64]) -> Result<()> {
        let mut z = DMatrix::from_column_slice(z.len(), 1, z);
        for (k, &v) in z.iter().enumerate() {
            exact_integer(k % self.len(), v)?;
        }
        let back = self.reduction.apply_z_inv_t(&mut z)?;
        let n = self.len();
        for (e, (o, &b)) in out.iter_mut().zip(&back).enumerate() {
            let i = e % n;
            *o = bounded_integer(i, (offset[i] as i128).saturating_add(b))?;
        }
        Ok(())
    }
}

/// The float-vector part of a problem: `round(a)`, `a - round(a)` (exact) and `Z^T (a - round(a))`.
struct Floats {
    offset: DVector<i64>,
    frac: DVector<f64>,
    zhat: DVector<f64>,
}

impl Floats {
    /// The floats of `a` for `Z` held as `f64` (`zf`).
    fn new(zf: &DMatrix<f64>, a: &DVector<f64>) -> Floats {
        let rounded = a.map(f64::round);
        let frac = a - &rounded;
        let zhat = zf.tr_mul(&frac);
        Floats {
            offset: rounded.map(|v| v as i64),
            frac,
            zhat,
        }
    }
}

/// A problem's own `round(a)` and `a - round(a)`, borrowed.
#[derive(Clone, Copy)]
struct FloatsRef<'a> {
    offset: &'a DVector<i64>,
    frac: &'a DVector<f64>,
}

/// Checks finite float ambiguities `a` against a covariance of dimension `n`: the length and
/// `|a_i| < MAX_ABS_AMBIGUITY`.
fn check_floats(a: &[f64], n: usize) -> Result<()> {
    if a.len() != n {
        return Err(Error::Shape {
            name: "float ambiguities",
            expected: format!("({n},) to match a ({n}, {n}) covariance"),
            actual: format!("({},)", a.len()),
        });
    }
    if let Some(i) = a.iter().position(|v| v.abs() >= MAX_ABS_AMBIGUITY) {
        return Err(Error::out_of_range(
            "float ambiguities",
            format!(
                "|a[{i}]| = {:e} exceeds {MAX_ABS_AMBIGUITY:e} cycles",
                a[i].abs()
            ),
        ));
    }
    Ok(())
}

/// Checks that decorrelated integer `k`, `v`, is an exact integer: integer-valued with `|v| <= 2^53`.
fn exact_integer(k: usize, v: f64) -> Result<()> {
    const EXACT: f64 = 9_007_199_254_740_992.0; // 2^53
    if v.fract() == 0.0 && v.abs() <= EXACT {
        Ok(())
    } else {
        Err(Error::numerical(
            "LAMBDA",
            format!("decorrelated integer {k} = {v:e} is not an exact integer"),
        ))
    }
}

/// An integer to be returned, refused beyond [`MAX_ABS_AMBIGUITY`] (element `i` in the message).
pub(crate) fn bounded_integer(i: usize, v: i128) -> Result<i64> {
    if (v.unsigned_abs() as f64) <= MAX_ABS_AMBIGUITY {
        Ok(v as i64)
    } else {
        Err(Error::numerical(
            "LAMBDA",
            format!(
                "integer {i} of the solution is {v}, beyond the exactly representable \
                 {MAX_ABS_AMBIGUITY:e} cycles"
            ),
        ))
    }
}

/// The `m` best integer least-squares solutions of float ambiguities `a` with covariance `q`.
///
/// Exact ILS or an error: see the module docs.
///
/// # Arguments
/// * `a` - n float ambiguities, cycles.
/// * `q` - n x n symmetric positive-definite covariance of `a`, cycles^2.
/// * `m` - number of candidates, 1 ..= [`MAX_CANDIDATES`].
///
/// # Errors
/// Those of [`Problem::new`] and [`Problem::solve`] (with [`node_budget`]`(n)` nodes).
pub fn ils(a: &DVector<f64>, q: &DMatrix<f64>, m: usize) -> Result<IlsSolution> {
    search::check_candidates(m)?;
    let n = a.len();
    let (mut fixed, mut norms) = (DMatrix::<i64>::zeros(n, m), vec![0.0; m]);
    // Problem::new(a, q)?.solve(m, node_budget(n)), in this thread's reusable buffers.
    let nodes_visited = with_workspace(|ws| {
        ws.solve(
            a.as_slice(),
            q,
            m,
            node_budget(n),
            fixed.as_mut_slice(),
            &mut norms,
        )
    })?;
    Ok(IlsSolution {
        fixed,
        squared_norms: norms,
        nodes_visited,
    })
}
