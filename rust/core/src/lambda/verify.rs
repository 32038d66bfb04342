//! Squared norms recomputed independently of the search, and the rule that judges whether they agree.
//!
//! The search works in the decorrelated space on the factors `L^T D L` that the reduction updated; its
//! norms are right only if those factors still represent `Z^T Q Z`. Every candidate's norm is therefore
//! recomputed from the float vector and covariance it answers (the original `a` and `Q` for a full fix,
//! `Z_k^T a` and `Z_k^T Q Z_k` formed from `Q` for a partial one) through nalgebra's Cholesky
//! factorisation, which shares no code with the reduction or the search.

use nalgebra::{Cholesky, DMatrix, DVector, Dyn};

use crate::error::{Error, Result};

/// Two squared norms of the same candidate agree when they differ by at most this times
/// `1 + max(norm)`: relative for large norms, absolute (in units of chi^2) below 1, where a difference of
/// 1e-6 decides nothing.
///
/// Both computations are backward stable; the recomputed one is accurate to about `n eps sqrt(cond Q)`
/// relative (1e-10 at n = 64, condition 1e8), the search's to the identity tolerance of the reduction
/// amplified by the conditioning of the decorrelated covariance. 1e-6 is passed by every valid problem
/// of the reference test (88 of 88, n <= 64, condition <= 1e8) and is still far below anything that
/// could change an accepted ratio test. Candidates whose norms agree to it are ties; they are returned in
/// the order of the recomputed norms.
pub const NORM_TOLERANCE: f64 = 1e-6;

/// The Cholesky factor of a covariance, for recomputing squared norms.
#[derive(Debug, Clone)]
pub struct Metric {
    chol: Cholesky<f64, Dyn>,
}

impl Metric {
    /// Factorises `q` (symmetric positive definite; only its lower triangle is read).
    ///
    /// # Errors
    /// [`Error::Numerical`] when the factorisation fails in floating point (`q` positive definite by the
    /// LDL check, but not to the working precision of a Cholesky factorisation).
    pub fn new(what: &'static str, q: &DMatrix<f64>) -> Result<Metric> {
        let chol = Cholesky::new(q.clone()).ok_or_else(|| not_factorised(what, q))?;
        Ok(Metric { chol })
    }

    /// [`Metric::new`] in the storage of `previous` when it has the size of `q` (no allocation), else
    /// in a copy of `q`; the same factor either way.
    ///
    /// # Errors
    /// Those of [`Metric::new`].
    pub(crate) fn renew(
        previous: Option<Metric>,
        what: &'static str,
        q: &DMatrix<f64>,
    ) -> Result<Metric> {
        let mut buffer = match previous {
            Some(m) if m.chol.l_dirty().shape() == q.shape() => m.chol.unpack_dirty(),
            _ => return Metric::new(what, q),
        };
        buffer.copy_from(q);
        Cholesky::new(buffer)
            .map(|chol| Metric { chol })
            .ok_or_else(|| not_factorised(what, q))
    }

    /// `r^T Q^-1 r = |L^-1 r|^2`.
    pub fn squared_norm(&self, r: &DVector<f64>) -> f64 {
        self.squared_norm_mut(&mut r.clone())
    }

    /// [`Metric::squared_norm`] in place: `r` is overwritten by `L^-1 r`.
    pub fn squared_norm_mut(&self, r: &mut DVector<f64>) -> f64 {
        if self.chol.l_dirty().solve_lower_triangular_mut(r) {
            r.norm_squared()
        } else {
            f64::INFINITY
        }
    }

    /// `(Q^-1)` applied to the columns of `b`: `Q^-1 b`.
    pub fn solve(&self, b: &DMatrix<f64>) -> DMatrix<f64> {
        self.chol.solve(b)
    }
}

/// The error of a covariance whose Cholesky factorisation fails.
fn not_factorised(what: &'static str, q: &DMatrix<f64>) -> Error {
    Error::numerical(
        what,
        format!(
            "the Cholesky factorisation of the {n} x {n} covariance fails in floating point (not \
             positive definite to working precision)",
            n = q.nrows()
        ),
    )
}

/// The order of the candidates by their recomputed norms, after checking that every recomputed norm is
/// finite and agrees with the search's (see [`NORM_TOLERANCE`]).
///
/// # Errors
/// [`Error::Numerical`] naming the first candidate whose norms disagree, with both values.
pub fn agreeing_order(
    what: &'static str,
    searched: &[f64],
    recomputed: &[f64],
) -> Result<Vec<usize>> {
    let mut order = Vec::new();
    agreeing_order_into(what, searched, recomputed, &mut order)?;
    Ok(order)
}

/// [`agreeing_order`] into `order` (cleared first; its storage reused).
///
/// # Errors
/// Those of [`agreeing_order`].
pub(crate) fn agreeing_order_into(
    what: &'static str,
    searched: &[f64],
    recomputed: &[f64],
    order: &mut Vec<usize>,
) -> Result<()> {
    for (c, (&s, &r)) in searched.iter().zip(recomputed).enumerate() {
        let agree =
            s.is_finite() && r.is_finite() && (s - r).abs() <= NORM_TOLERANCE * (1.0 + s.max(r));
        if !agree {
            return Err(Error::numerical(
                what,
                format!(
                    "candidate {c}: the search found the squared norm {s:.9e} but the original float \
                     vector and covariance give {r:.9e} (they must agree to {NORM_TOLERANCE:e} x (1 + \
                     norm)); the covariance is too ill-conditioned for an exact answer"
                ),
            ));
        }
    }
    order.clear();
    order.extend(0..recomputed.len());
    order.sort_by(|&a, &b| recomputed[a].total_cmp(&recomputed[b]));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn norms_and_agreement() {
        let q = DMatrix::from_row_slice(2, 2, &[4.0, 2.0, 2.0, 3.0]);
        let m = Metric::new("t", &q).unwrap();
        let r = DVector::from_vec(vec![1.0, -2.0]);
        // Closed form: r^T Q^-1 r with Q^-1 = [[3, -2], [-2, 4]] / 8 -> (3 + 8 + 16) / 8.
        assert!((m.squared_norm(&r) - 27.0 / 8.0).abs() < 1e-15);
        // A tie within tolerance is reordered; a material disagreement is refused.
        assert_eq!(
            agreeing_order("t", &[1.0, 1.0 + 1e-7], &[1.0 + 1e-7, 1.0]).unwrap(),
            vec![1, 0]
        );
        let e = agreeing_order("t", &[0.0], &[8e40])
            .unwrap_err()
            .to_string();
        assert!(e.contains("8.0") && e.contains("candidate 0"), "{e}");
        assert!(agreeing_order("t", &[1.0], &[f64::NAN]).is_err());
        assert!(agreeing_order("t", &[f64::INFINITY], &[f64::INFINITY]).is_err());
        let singular = DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0]);
        assert!(matches!(
            Metric::new("t", &singular),
            Err(Error::Numerical { .. })
        ));
    }
}
