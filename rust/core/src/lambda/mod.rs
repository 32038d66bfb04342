//! LAMBDA integer ambiguity resolution: decorrelation, exact integer least-squares (ILS) search for the
//! best candidates, the bootstrapped success rate, and validation (ratio test, partial fixing).
//!
//! Float ambiguities `a` (cycles) with covariance `Q` (cycles^2) are decorrelated by a unimodular
//! integer `Z` (`z = Z^T a`, covariance `Z^T Q Z = L^T D L`), searched there, and mapped back with
//! `Z^-T`, which is integer too, so the answer is the exact ILS solution of the original problem.
//! Teunissen (1995), "The least-squares ambiguity decorrelation adjustment", J. Geodesy 70:65-82;
//! de Jonge & Tiberius (1996), LGR-12; Chang, Yang & Zhou (2005), "MLAMBDA", J. Geodesy 79:552-565.

pub mod bootstrap;
pub mod ldl;
pub mod reduction;
pub mod search;
pub mod validation;

#[cfg(test)]
pub(crate) mod test_support;
#[cfg(test)]
mod tests;

use nalgebra::{DMatrix, DVector};

use crate::error::{ensure_finite, Error, Result};
pub use bootstrap::bootstrap_success_rate;
pub use reduction::{reduce, Reduction};
pub use search::{search, Candidates, DEFAULT_MAX_NODES};

/// Float ambiguities beyond this magnitude (cycles) cannot be returned exactly as `i64` via `f64`.
pub const MAX_ABS_AMBIGUITY: f64 = 4.5e15;

/// The ILS solutions of one problem, in the original ambiguity space.
#[derive(Debug, Clone, PartialEq)]
pub struct IlsSolution {
    /// Integer ambiguity vectors, one per column (n x m), best first.
    pub fixed: DMatrix<i64>,
    /// `(a - z)^T Q^-1 (a - z)` of each column, ascending.
    pub squared_norms: Vec<f64>,
    /// Nodes the search visited (see [`Candidates::nodes_visited`]).
    pub nodes_visited: u64,
}

/// A checked, decorrelated ambiguity problem, ready to be searched (possibly several times).
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// The decorrelation of `Q`.
    pub reduction: Reduction,
    /// `round(a)`: the search runs on `a - round(a)`, so that integer shifts of `a` are exact.
    pub offset: DVector<f64>,
    /// Decorrelated float ambiguities `Z^T (a - round(a))`, cycles.
    pub zhat: DVector<f64>,
}

impl Problem {
    /// Checks and decorrelates `(a, Q)`.
    ///
    /// # Arguments
    /// * `a` - n float ambiguities, cycles (|a_i| < [`MAX_ABS_AMBIGUITY`]).
    /// * `q` - n x n symmetric positive-definite covariance of `a`, cycles^2.
    ///
    /// # Errors
    /// [`Error::Shape`] for n = 0 or mismatched sizes, [`Error::NonFinite`], [`Error::OutOfRange`] for an
    /// asymmetric or not positive-definite `q` or a float ambiguity too large for `i64`.
    pub fn new(a: &DVector<f64>, q: &DMatrix<f64>) -> Result<Problem> {
        ensure_finite("float ambiguities", a.iter())?;
        ldl::check_covariance(q)?;
        if a.len() != q.nrows() {
            return Err(Error::Shape {
                name: "float ambiguities",
                expected: format!("({n},) to match a ({n}, {n}) covariance", n = q.nrows()),
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
        let reduction = reduce(q)?;
        let offset = a.map(f64::round);
        let zhat = reduction.z.tr_mul(&(a - &offset));
        Ok(Problem {
            reduction,
            offset,
            zhat,
        })
    }

    /// Number of ambiguities.
    pub fn len(&self) -> usize {
        self.offset.len()
    }

    /// Always false: a problem has at least one ambiguity.
    pub fn is_empty(&self) -> bool {
        self.offset.is_empty()
    }

    /// The `m` best integer vectors.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for `m = 0`; [`Error::Convergence`] past `max_nodes` nodes.
    pub fn solve(&self, m: usize, max_nodes: u64) -> Result<IlsSolution> {
        let found = search(&self.reduction.factor, &self.zhat, m, max_nodes)?;
        let n = self.len();
        let mut fixed = DMatrix::<i64>::zeros(n, m);
        for c in 0..m {
            let a = self.to_original(&found.z.column(c).into_owned());
            fixed.set_column(c, &a);
        }
        Ok(IlsSolution {
            fixed,
            squared_norms: found.squared_norms,
            nodes_visited: found.nodes_visited,
        })
    }

    /// Maps integers of the decorrelated (shifted) space back: `round(a) + Z^-T z`.
    pub fn to_original(&self, z: &DVector<f64>) -> DVector<i64> {
        let back = self.reduction.z_inv.tr_mul(z);
        DVector::from_fn(self.len(), |i, _| {
            (self.offset[i] as i64) + back[i].round() as i64
        })
    }
}

/// The `m` best integer least-squares solutions of float ambiguities `a` with covariance `q`.
///
/// # Arguments
/// * `a` - n float ambiguities, cycles.
/// * `q` - n x n symmetric positive-definite covariance of `a`, cycles^2.
/// * `m` - number of candidates, >= 1.
///
/// # Errors
/// Those of [`Problem::new`] and [`Problem::solve`] (with [`DEFAULT_MAX_NODES`]).
pub fn ils(a: &DVector<f64>, q: &DMatrix<f64>, m: usize) -> Result<IlsSolution> {
    if m == 0 {
        return Err(Error::out_of_range(
            "candidates",
            "expected at least 1, got 0",
        ));
    }
    Problem::new(a, q)?.solve(m, DEFAULT_MAX_NODES)
}
