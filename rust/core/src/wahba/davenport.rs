//! Davenport's q-method: the optimal quaternion is the eigenvector of the largest eigenvalue of the
//! symmetric 4x4 matrix `K` built from the attitude profile matrix (Davenport 1968; Keat, NASA X-733-77-4,
//! 1977; notation of Shuster & Oh, J. Guid. Control 4 (1981) 70).

use nalgebra::{Matrix3, Matrix4, SymmetricEigen, Vector3};

use crate::error::{ensure_finite, Result};
use crate::wahba::profile::shuster_attitude;

/// Davenport's `K = [[S - sigma I, z], [z^T, sigma]]` with `S = B + B^T`, `sigma = tr B`,
/// `z = [B23 - B32, B31 - B13, B12 - B21]` for Shuster's `B = sum_i w_i b_i r_i^T`.
pub fn k_matrix(b: &Matrix3<f64>) -> (Matrix3<f64>, Vector3<f64>, f64) {
    let s = b + b.transpose();
    let sigma = b.trace();
    let z = Vector3::new(
        b[(1, 2)] - b[(2, 1)],
        b[(2, 0)] - b[(0, 2)],
        b[(0, 1)] - b[(1, 0)],
    );
    (s, z, sigma)
}

/// The 4x4 `K` itself, for quaternions `[q1, q2, q3, q4]` (scalar last).
pub fn k4(b: &Matrix3<f64>) -> Matrix4<f64> {
    let (s, z, sigma) = k_matrix(b);
    let mut k = Matrix4::zeros();
    k.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(s - Matrix3::identity() * sigma));
    k.fixed_view_mut::<3, 1>(0, 3).copy_from(&z);
    k.fixed_view_mut::<1, 3>(3, 0).copy_from(&z.transpose());
    k[(3, 3)] = sigma;
    k
}

/// Body -> reference rotation maximising Wahba's gain for Shuster's profile matrix `b`
/// (`sum_i w_i b_i r_i^T`, body x reference).
///
/// # Errors
/// [`crate::Error::NonFinite`] for a non-finite `b`. Degeneracy (a repeated top eigenvalue) is checked by
/// the caller ([`crate::wahba::solve`]) through the information matrix.
pub fn solve(b: &Matrix3<f64>) -> Result<Matrix3<f64>> {
    ensure_finite("attitude profile matrix", b.iter())?;
    let k = k4(b);
    let eig = SymmetricEigen::new(k);
    let top = eig.eigenvalues.imax();
    let q = eig.eigenvectors.column(top);
    let q = [q[0], q[1], q[2], q[3]];
    // shuster_attitude is reference -> body; transpose for body -> reference.
    Ok(shuster_attitude(&q).transpose())
}
