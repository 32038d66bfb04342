//! QUEST (QUaternion ESTimator): the largest eigenvalue of Davenport's K by Newton's method on its
//! characteristic equation, then the quaternion from the adjugate of `(lambda + sigma) I - S`; the method
//! of sequential rotations handles attitudes near 180 deg. Shuster & Oh, J. Guid. Control 4 (1981) 70.
//!
//! Limitation: the characteristic quartic cannot resolve `lambda_max` better than about
//! `eps lambda0^2 / gap`, so when the weights span more than about 1e6 (e.g. 1e8 : 1) QUEST can return
//! a wrong eigenvector (seen: errors up to 180 deg). Use the SVD or Davenport solvers there; the
//! Python layer warns through the information ratio in such geometry.

use nalgebra::{Matrix3, Vector3};

use crate::error::{ensure_finite, Error, Result};
use crate::wahba::davenport::k_matrix;
use crate::wahba::profile::shuster_attitude;

/// Newton iterations allowed before [`Error::Convergence`].
pub const MAX_ITERATIONS: usize = 200;

/// Below this |q4| (rotation angle above about 169 deg) the quaternion is recomputed with the reference
/// frame turned by 180 deg about x, y or z, and the best-conditioned of the three is kept.
const SEQUENTIAL_ROTATION_Q4: f64 = 0.1;

fn adjugate(m: &Matrix3<f64>) -> Matrix3<f64> {
    let c = |i: usize, j: usize| {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
        m[(i1, j1)] * m[(i2, j2)] - m[(i1, j2)] * m[(i2, j1)]
    };
    // adj(M)_{ij} = cofactor_{ji}; the cyclic index form already carries the sign.
    Matrix3::from_fn(|i, j| c(j, i))
}

/// Largest root of Shuster's characteristic equation
/// `lambda^4 - (a + b) lambda^2 - c lambda + (a b + c sigma - d) = 0`, by Newton from `lambda0`.
fn lambda_max(s: &Matrix3<f64>, z: &Vector3<f64>, sigma: f64, lambda0: f64) -> Result<f64> {
    let kappa = adjugate(s).trace();
    let a = sigma * sigma - kappa;
    let b = sigma * sigma + z.norm_squared();
    let c = s.determinant() + z.dot(&(s * z));
    let d = z.dot(&(s * (s * z)));
    let mut lambda = lambda0;
    let mut previous = f64::INFINITY;
    for _ in 0..MAX_ITERATIONS {
        let l2 = lambda * lambda;
        let f = l2 * l2 - (a + b) * l2 - c * lambda + (a * b + c * sigma - d);
        let df = 4.0 * l2 * lambda - 2.0 * (a + b) * lambda - c;
        if df == 0.0 {
            break;
        }
        let step = f / df;
        lambda -= step;
        // Converged, or stalled at the rounding level of the quartic (steps stop shrinking).
        if step.abs() <= 1e-12 * lambda0.abs().max(f64::MIN_POSITIVE) || step.abs() >= previous {
            return Ok(lambda);
        }
        previous = step.abs();
    }
    Err(Error::Convergence {
        what: "QUEST Newton iteration for the largest eigenvalue",
        iterations: MAX_ITERATIONS,
    })
}

/// Shuster quaternion `[adj(M) z, det M]` (normalised), `M = (lambda + sigma) I - S`.
fn quaternion(b: &Matrix3<f64>, lambda0: f64) -> Result<[f64; 4]> {
    let (s, z, sigma) = k_matrix(b);
    let mut lambda = lambda_max(&s, &z, sigma, lambda0)?;
    let mut q = [0.0; 4];
    // The quartic loses accuracy when the weights span many decades; two Rayleigh-quotient updates
    // lambda = q^T K q (second-order accurate in the quaternion) restore it at negligible cost.
    for pass in 0..3 {
        let m = Matrix3::identity() * (lambda + sigma) - s;
        let x = adjugate(&m) * z;
        let v = [x[0], x[1], x[2], m.determinant()];
        let n = v.iter().map(|v| v * v).sum::<f64>().sqrt();
        q = v.map(|v| v / n);
        if pass < 2 {
            let e = Vector3::new(q[0], q[1], q[2]);
            lambda = e.dot(&(s * e)) - sigma * e.norm_squared()
                + 2.0 * q[3] * z.dot(&e)
                + sigma * q[3] * q[3];
        }
    }
    Ok(q)
}

/// Body -> reference rotation maximising Wahba's gain for Shuster's profile matrix `b`
/// (`sum_i w_i b_i r_i^T`, body x reference) with weights summing to `weight_sum` (unit vectors).
///
/// # Errors
/// [`Error::NonFinite`]; [`Error::Convergence`] if Newton's method fails (not seen on valid input).
/// Degeneracy is checked by the caller ([`crate::wahba::solve`]).
pub fn solve(b: &Matrix3<f64>, weight_sum: f64) -> Result<Matrix3<f64>> {
    ensure_finite("attitude profile matrix", b.iter())?;
    let q = quaternion(b, weight_sum)?;
    if q[3].abs() >= SEQUENTIAL_ROTATION_Q4 {
        return Ok(shuster_attitude(&q).transpose());
    }
    // Sequential rotations: with reference vectors r' = T r (T a half turn, symmetric), B' = B T and
    // A = A' T.
    let mut best = (q[3].abs(), shuster_attitude(&q));
    for axis in 0..3 {
        let t = Matrix3::from_fn(|i, j| match (i == j, i == axis) {
            (true, true) => 1.0,
            (true, false) => -1.0,
            _ => 0.0,
        });
        let qt = quaternion(&(b * t), weight_sum)?;
        if qt[3].abs() > best.0 {
            best = (qt[3].abs(), shuster_attitude(&qt) * t);
        }
    }
    Ok(best.1.transpose())
}
