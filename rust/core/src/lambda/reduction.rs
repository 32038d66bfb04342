//! Decorrelation of the ambiguities: a unimodular integer `Z` such that `Z^T Q Z = L^T D L` has a
//! size-reduced `L` (`|L_ij| <= 1/2` below the diagonal) and conditional variances `d` as close to sorted
//! decreasing as the swap rule of LAMBDA allows, which makes the search tree narrow.
//! Teunissen (1995), J. Geodesy 70:65-82; integer Gauss transformations and permutations as in
//! de Jonge & Tiberius (1996), LGR-12, section 3.4, with the symmetric pivoting and deferred size
//! reduction of Chang, Yang & Zhou (2005), "MLAMBDA", J. Geodesy 79:552-565, section 3.2.

use nalgebra::DMatrix;

use super::ldl::{ltdl, Ltdl};
use crate::error::Result;

/// A swap is made only when it lowers `d_{k+1}` by more than this relative amount, so that rounding
/// cannot make the reduction cycle.
pub const SWAP_TOLERANCE: f64 = 1e-12;

/// The decorrelating transformation and the factors of the decorrelated covariance.
#[derive(Debug, Clone, PartialEq)]
pub struct Reduction {
    /// Unimodular integer `Z` (n x n, integer entries stored as `f64`): decorrelated ambiguities are
    /// `z = Z^T a` with covariance `Z^T Q Z`.
    pub z: DMatrix<f64>,
    /// `Z^-1`, also integer: `a = Z^-T z`.
    pub z_inv: DMatrix<f64>,
    /// `Z^T Q Z = L^T D L`.
    pub factor: Ltdl,
}

/// Decorrelates the covariance of float ambiguities.
///
/// # Arguments
/// * `q` - n x n symmetric positive-definite covariance, cycles^2.
///
/// # Errors
/// Those of [`ltdl`]: bad shape, non-finite, asymmetric or not positive-definite covariance.
pub fn reduce(q: &DMatrix<f64>) -> Result<Reduction> {
    Ok(reduce_factor(ltdl(q)?))
}

/// Decorrelates an already factorised covariance `Q = L^T D L` (no checks).
pub fn reduce_factor(factor: Ltdl) -> Reduction {
    let Ltdl { mut l, mut d } = factor;
    let n = d.len();
    let mut r = Reduction {
        z: DMatrix::identity(n, n),
        z_inv: DMatrix::identity(n, n),
        factor: Ltdl {
            l: DMatrix::zeros(0, 0),
            d: d.clone(),
        },
    };
    if n >= 2 {
        // Symmetric pivoting (MLAMBDA): k walks from the second-to-last column towards the first; only
        // the subdiagonal entry that decides a swap is reduced in the loop, and only when column k may
        // have changed since it was last reduced (k <= `touched`). A swap at k changes the subdiagonal
        // entries of columns k and k+1 (it exchanges L[k+2, k] and L[k+2, k+1]), so touched = k+1.
        let mut k = n - 2;
        let mut touched = n - 2;
        loop {
            if k <= touched {
                gauss(&mut l, &mut r, k + 1, k);
            }
            let lk = l[(k + 1, k)];
            let delta = d[k] + lk * lk * d[k + 1];
            if delta < d[k + 1] * (1.0 - SWAP_TOLERANCE) {
                swap(&mut l, &mut d, &mut r, k, delta);
                touched = (k + 1).min(n - 2);
                k = n - 2;
            } else if k == 0 {
                break;
            } else {
                k -= 1;
            }
        }
        // Deferred size reduction of the whole of L (it changes no d, so no swap becomes admissible).
        for j in (0..n - 1).rev() {
            for i in (j + 1)..n {
                gauss(&mut l, &mut r, i, j);
            }
        }
    }
    r.factor = Ltdl { l, d };
    r
}

/// Integer Gauss transformation `Z <- Z (I - mu e_i e_j^T)` with `mu = round(L_ij)`, `i > j`: makes
/// `|L_ij| <= 1/2`.
fn gauss(l: &mut DMatrix<f64>, r: &mut Reduction, i: usize, j: usize) {
    let mu = l[(i, j)].round();
    if mu == 0.0 {
        return;
    }
    let n = l.nrows();
    for k in i..n {
        l[(k, j)] -= mu * l[(k, i)];
    }
    for k in 0..n {
        r.z[(k, j)] -= mu * r.z[(k, i)];
        r.z_inv[(i, k)] += mu * r.z_inv[(j, k)];
    }
}

/// Swaps ambiguities `k` and `k+1`, updating `L` and `D` so that `L^T D L` stays the transformed
/// covariance; `delta` is the new `d_{k+1} = d_k + L_{k+1,k}^2 d_{k+1}`.
fn swap(
    l: &mut DMatrix<f64>,
    d: &mut nalgebra::DVector<f64>,
    r: &mut Reduction,
    k: usize,
    delta: f64,
) {
    let n = l.nrows();
    let lk = l[(k + 1, k)];
    let eta = d[k] / delta;
    let lambda = d[k + 1] * lk / delta;
    d[k] = eta * d[k + 1];
    d[k + 1] = delta;
    for j in 0..k {
        let (a0, a1) = (l[(k, j)], l[(k + 1, j)]);
        l[(k, j)] = a1 - lk * a0;
        l[(k + 1, j)] = eta * a0 + lambda * a1;
    }
    l[(k + 1, k)] = lambda;
    for i in (k + 2)..n {
        l.swap((i, k), (i, k + 1));
    }
    r.z.swap_columns(k, k + 1);
    r.z_inv.swap_rows(k, k + 1);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lambda::test_support::{random_covariance, Lcg};

    fn check(q: &DMatrix<f64>) -> Reduction {
        let red = reduce(q).unwrap();
        let n = q.nrows();
        // Z and its inverse are integer and inverse to each other, so |det Z| = 1.
        for v in red.z.iter().chain(red.z_inv.iter()) {
            assert_eq!(*v, v.round());
        }
        let eye = &red.z * &red.z_inv;
        assert!((eye - DMatrix::<f64>::identity(n, n)).amax() == 0.0);
        assert!((red.z.determinant().abs() - 1.0).abs() < 1e-6);
        // The factors are those of Z^T Q Z, and they match a fresh factorisation.
        let qz = red.z.transpose() * q * &red.z;
        let scale = qz.amax();
        assert!((red.factor.reconstruct() - &qz).amax() < 1e-9 * scale);
        let fresh = ltdl(&((&qz + qz.transpose()) * 0.5)).unwrap();
        assert!((&fresh.d - &red.factor.d).amax() < 1e-7 * red.factor.d.amax());
        // Size-reduced, and no admissible swap left.
        for j in 0..n {
            for i in (j + 1)..n {
                assert!(red.factor.l[(i, j)].abs() <= 0.5 + 1e-9);
            }
        }
        let (l, d) = (&red.factor.l, &red.factor.d);
        for k in 0..n.saturating_sub(1) {
            let delta = d[k] + l[(k + 1, k)].powi(2) * d[k + 1];
            assert!(delta >= d[k + 1] * (1.0 - 1e-9));
        }
        red
    }

    #[test]
    fn classic_example_is_decorrelated() {
        let q = DMatrix::from_row_slice(
            3,
            3,
            &[
                6.290, 5.978, 0.544, 5.978, 6.292, 2.340, 0.544, 2.340, 6.288,
            ],
        );
        let red = check(&q);
        // The product of the d (= det Q) is invariant; the spread of d shrinks.
        let before = ltdl(&q).unwrap().d;
        let after = &red.factor.d;
        assert!((before.product() - after.product()).abs() < 1e-9 * before.product());
        assert!(after.max() / after.min() <= before.max() / before.min());
    }

    #[test]
    fn random_covariances_are_decorrelated() {
        let mut rng = Lcg(7);
        for n in [1usize, 2, 3, 5, 8, 13, 20, 40, 64] {
            for _ in 0..5 {
                let q = random_covariance(&mut rng, n, 1e-3);
                let red = check(&q);
                let before = ltdl(&q).unwrap();
                // Every swap narrows the spread of d: max d never grows, min d never shrinks.
                assert!(red.factor.d.max() <= before.d.max() * (1.0 + 1e-9));
                assert!(red.factor.d.min() >= before.d.min() * (1.0 - 1e-9));
            }
        }
    }
}
