//! Input checks on an ambiguity covariance and its `Q = L^T D L` factorisation (`L` unit lower
//! triangular, `D` diagonal), the form on which LAMBDA's decorrelation and search work: `d_n` is the
//! variance of the last ambiguity and `d_i` the variance of ambiguity `i` conditioned on `i+1..n`.
//! de Jonge & Tiberius (1996), "The LAMBDA method for integer ambiguity estimation: implementation
//! aspects", LGR series 12, section 3.3.

use nalgebra::{DMatrix, DVector};

use crate::error::{ensure_finite, Error, Result};

/// Largest allowed `|Q_ij - Q_ji|`, relative to the largest `|Q_ij|`.
pub const SYMMETRY_TOLERANCE: f64 = 1e-9;

/// Largest number of ambiguities accepted. The reduction and its checks cost O(n^3) per pass; the tests
/// verify exact answers against an independent solver up to n = 64 (condition numbers up to 1e8) and serve
/// n = 256 itself; 256 bounds the work and memory of one call (a few MB) while leaving room above every
/// GNSS use (n < 100).
pub const MAX_DIMENSION: usize = 256;

/// A pivot `d_i` at or below this many machine epsilons times `Q_ii` (times n) counts as not positive.
const PIVOT_EPSILONS: f64 = 1.0;

/// The factors of `Q = L^T diag(d) L`.
#[derive(Debug, Clone, PartialEq)]
pub struct Ltdl {
    /// Unit lower-triangular `L` (n x n).
    pub l: DMatrix<f64>,
    /// Conditional variances `d` (n), all positive, cycles^2.
    pub d: DVector<f64>,
}

impl Ltdl {
    /// The factors of the trailing `k x k` block of `Q`, i.e. of the last `k` ambiguities alone.
    ///
    /// Because `L` is lower triangular, `Q[n-k.., n-k..] = L[n-k.., n-k..]^T D[n-k..] L[n-k.., n-k..]`.
    pub fn trailing(&self, k: usize) -> Ltdl {
        let n = self.d.len();
        let s = n - k.min(n);
        Ltdl {
            l: self.l.view((s, s), (n - s, n - s)).into_owned(),
            d: self.d.rows(s, n - s).into_owned(),
        }
    }

    /// `L^T diag(d) L`, the matrix factorised.
    pub fn reconstruct(&self) -> DMatrix<f64> {
        let dl = DMatrix::from_diagonal(&self.d) * &self.l;
        self.l.transpose() * dl
    }
}

/// Checks that `q` is a usable covariance: non-empty, square, at most [`MAX_DIMENSION`], finite,
/// symmetric.
///
/// Positive definiteness is checked by [`ltdl`], which needs the factorisation anyway.
///
/// # Errors
/// [`Error::Shape`] for an empty or non-square matrix, [`Error::TooLarge`] beyond [`MAX_DIMENSION`],
/// [`Error::NonFinite`], and [`Error::OutOfRange`]
/// naming the worst asymmetric pair when `|Q_ij - Q_ji| > SYMMETRY_TOLERANCE * max|Q|`.
pub fn check_covariance(q: &DMatrix<f64>) -> Result<()> {
    let (r, c) = q.shape();
    if r == 0 || r != c {
        return Err(Error::Shape {
            name: "covariance",
            expected: "(n, n) with n >= 1".into(),
            actual: format!("({r}, {c})"),
        });
    }
    if r > MAX_DIMENSION {
        return Err(Error::too_large(
            "covariance",
            r as f64,
            MAX_DIMENSION as f64,
            "ambiguities",
        ));
    }
    // Row-major flat index in the message, as numpy users count (the transposed copy only on failure).
    if !q.iter().all(|v| v.is_finite()) {
        ensure_finite("covariance", q.transpose().iter())?;
    }
    let scale = q.amax();
    let mut worst = (0.0, 0, 0);
    for j in 0..c {
        for i in (j + 1)..r {
            let gap = (q[(i, j)] - q[(j, i)]).abs();
            if gap > worst.0 {
                worst = (gap, i, j);
            }
        }
    }
    let (gap, i, j) = worst;
    if gap > SYMMETRY_TOLERANCE * scale {
        return Err(Error::out_of_range(
            "covariance",
            format!(
                "not symmetric: Q[{i}, {j}] = {:e} but Q[{j}, {i}] = {:e} (difference {gap:.3e} exceeds \
                 {SYMMETRY_TOLERANCE:e} x max|Q| = {:.3e})",
                q[(i, j)],
                q[(j, i)],
                SYMMETRY_TOLERANCE * scale
            ),
        ));
    }
    Ok(())
}

/// Factorises a covariance as `Q = L^T D L`, from the last row up.
///
/// The strictly upper triangle is ignored after the symmetry check (the lower triangle is used).
///
/// # Arguments
/// * `q` - n x n symmetric positive-definite covariance of the float ambiguities, cycles^2.
///
/// # Errors
/// Those of [`check_covariance`], and [`Error::OutOfRange`] when `q` is not (numerically) positive
/// definite, naming the failing pivot.
pub fn ltdl(q: &DMatrix<f64>) -> Result<Ltdl> {
    check_covariance(q)?;
    factorise(q)
}

/// [`ltdl`] of a covariance that passed [`check_covariance`].
pub(crate) fn factorise(q: &DMatrix<f64>) -> Result<Ltdl> {
    let n = q.nrows();
    let mut f = Ltdl {
        l: DMatrix::zeros(n, n),
        d: DVector::zeros(n),
    };
    let (mut u, mut lt) = (DMatrix::zeros(n, n), DMatrix::zeros(n, n));
    factorise_into(q, &mut u, &mut lt, &mut f)?;
    Ok(f)
}

/// Gives `m` the shape `r x c` (reallocating only when it differs: a reused buffer keeps its storage).
pub(crate) fn shape_to<T: nalgebra::Scalar + Default>(m: &mut DMatrix<T>, r: usize, c: usize) {
    if m.shape() != (r, c) {
        *m = DMatrix::from_element(r, c, T::default());
    }
}

/// [`factorise`] into `out` (resized to n when needed), through the scratch matrices `u` and `lt`: no
/// allocation once the buffers have the size of `q`.
pub(crate) fn factorise_into(
    q: &DMatrix<f64>,
    u: &mut DMatrix<f64>,
    lt: &mut DMatrix<f64>,
    out: &mut Ltdl,
) -> Result<()> {
    let n = q.nrows();
    shape_to(u, n, n);
    shape_to(lt, n, n);
    shape_to(&mut out.l, n, n);
    if out.d.len() != n {
        out.d = DVector::zeros(n);
    }
    // Both factors are built transposed, so that every inner loop runs down a (contiguous) column of
    // nalgebra's column-major storage: `u[(k, j)]` (k <= j) holds the lower-triangle entry `Q[j, k]`
    // being reduced, `lt[(k, i)]` holds `L[i, k]`. The arithmetic, and its order, is that of the
    // row-wise algorithm.
    q.transpose_to(u);
    lt.fill_with_identity();
    let d = &mut out.d;
    for i in (0..n).rev() {
        let pivot = u[(i, i)];
        let floor = PIVOT_EPSILONS * n as f64 * f64::EPSILON * q[(i, i)].abs();
        // A subnormal pivot has lost its precision (and 1 / pivot overflows): not positive definite to
        // working precision, whatever the scale of Q.
        if pivot.is_nan() || pivot <= floor || pivot < f64::MIN_POSITIVE {
            return Err(Error::out_of_range(
                "covariance",
                format!(
                    "not positive definite to working precision: the conditional variance of ambiguity \
                     {i} given those after it (its pivot) is {pivot:.3e}, needs to exceed {:.3e} (Q[{i}, \
                     {i}] = {:.3e})",
                    floor.max(f64::MIN_POSITIVE),
                    q[(i, i)]
                ),
            ));
        }
        d[i] = pivot;
        for j in 0..i {
            lt[(j, i)] = u[(j, i)] / pivot;
        }
        let li = &lt.as_slice()[i * n..i * n + i];
        let cols = u.as_mut_slice();
        for j in 0..i {
            let lij = li[j] * pivot;
            for (a, &l) in cols[j * n..j * n + j + 1].iter_mut().zip(li) {
                *a -= lij * l;
            }
        }
    }
    lt.transpose_to(&mut out.l);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example() -> DMatrix<f64> {
        // Teunissen's classic 3-D example (de Jonge & Tiberius 1996, eq. 3.34).
        DMatrix::from_row_slice(
            3,
            3,
            &[
                6.290, 5.978, 0.544, 5.978, 6.292, 2.340, 0.544, 2.340, 6.288,
            ],
        )
    }

    #[test]
    fn reconstructs_q() {
        let q = example();
        let f = ltdl(&q).unwrap();
        assert!((f.reconstruct() - &q).amax() < 1e-12);
        for i in 0..3 {
            assert_eq!(f.l[(i, i)], 1.0);
            for j in (i + 1)..3 {
                assert_eq!(f.l[(i, j)], 0.0);
            }
        }
        // d_n is the unconditional variance of the last ambiguity.
        assert_eq!(f.d[2], q[(2, 2)]);
    }

    #[test]
    fn trailing_block_is_the_marginal() {
        let q = example();
        let f = ltdl(&q).unwrap();
        let t = f.trailing(2).reconstruct();
        assert!((t - q.view((1, 1), (2, 2))).amax() < 1e-12);
    }

    #[test]
    fn rejects_bad_covariances() {
        let empty = DMatrix::<f64>::zeros(0, 0);
        assert!(matches!(ltdl(&empty), Err(Error::Shape { .. })));
        let rect = DMatrix::<f64>::zeros(2, 3);
        assert!(matches!(ltdl(&rect), Err(Error::Shape { .. })));
        let mut q = example();
        q[(0, 2)] += 1e-3;
        let e = ltdl(&q).unwrap_err().to_string();
        assert!(e.contains("not symmetric"), "{e}");
        let mut q = example();
        q[(1, 1)] = f64::NAN;
        assert!(matches!(ltdl(&q), Err(Error::NonFinite { index: 4, .. })));
        let q = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        let e = ltdl(&q).unwrap_err().to_string();
        assert!(e.contains("not positive definite"), "{e}");
        // Subnormal: positive, but not to working precision (the former index-out-of-bounds panic).
        let e = ltdl(&DMatrix::from_element(1, 1, 1e-320))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("working precision") && e.contains("1.000e-320"),
            "{e}"
        );
        // Tiny but normal is fine: the factorisation is scale invariant.
        assert_eq!(
            ltdl(&DMatrix::from_element(1, 1, 1e-300)).unwrap().d[0],
            1e-300
        );
        let big = DMatrix::<f64>::identity(MAX_DIMENSION + 1, MAX_DIMENSION + 1);
        assert!(matches!(ltdl(&big), Err(Error::TooLarge { .. })));
    }
}
