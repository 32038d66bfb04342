//! Common front end of the Wahba solvers: unit vectors, the attitude profile matrix, the information
//! matrix and the covariance (Shuster, J. Astronaut. Sci. 37 (1989) 79: `P = [sum_i w_i (I - r_i r_i^T)]^-1`).

use nalgebra::{Matrix3, SymmetricEigen, Vector3};

use crate::error::{ensure_finite, Error, Result};
use crate::guard;
use crate::wahba::{davenport, quest, svd};

/// Smallest accepted ratio of the smallest to the largest eigenvalue of the information matrix
/// `sum_i w_i (I - r_i r_i^T)`: below it the reference vectors are (numerically) all parallel.
pub const INFORMATION_RATIO_LIMIT: f64 = 1e-16;

/// Wahba solver.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Markley's SVD with the determinant fixed ([`svd::solve`]).
    Svd,
    /// Davenport's q-method: the top eigenvector of the 4x4 K matrix ([`davenport`]).
    Davenport,
    /// QUEST: Newton on the characteristic equation of K, sequential rotations near 180 deg ([`quest`]).
    Quest,
}

impl Method {
    /// `"svd"`, `"davenport"` or `"quest"`.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for any other name.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "svd" => Ok(Method::Svd),
            "davenport" => Ok(Method::Davenport),
            "quest" => Ok(Method::Quest),
            other => Err(Error::out_of_range(
                "method",
                format!("expected 'svd', 'davenport' or 'quest', got {other:?}"),
            )),
        }
    }
}

/// Attitude from one epoch of vector pairs.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// Body -> reference rotation matrix.
    pub dcm_ref_from_body: Matrix3<f64>,
    /// Covariance (rad^2) of the small rotation vector `delta` with `R_est = exp([delta]x) R_true`,
    /// `delta` in the *reference* frame; the body-frame covariance is `R^T P R`. It is the inverse Fisher
    /// information for body unit vectors with isotropic errors of standard deviation `sigma_i` when the
    /// weights are `w_i = 1 / sigma_i^2` (rad^-2); other weights scale it by a common factor.
    pub covariance_ref: Matrix3<f64>,
    /// Smallest over largest eigenvalue of the information matrix (1/condition number); small values mean
    /// the vectors are nearly parallel and the rotation about them is poorly fixed.
    pub information_ratio: f64,
    /// Wahba's loss `(1/2) sum_i w_i |r_i - R b_i|^2` at the estimate.
    pub loss: f64,
}

/// `v / |v|`, or [`Error::Degenerate`] naming `what` for a zero vector. A vector whose norm over- or
/// underflows (components near 1e300 or 1e-300) is scaled by its largest component first.
pub fn unit(v: &Vector3<f64>, what: impl FnOnce() -> String) -> Result<Vector3<f64>> {
    let n = v.norm();
    if n.is_finite() && n > f64::MIN_POSITIVE {
        return Ok(v / n);
    }
    let scale = v.amax();
    if scale.is_nan() || scale == 0.0 {
        return Err(Error::Degenerate {
            what: what(),
            quantity: "vector norm",
            value: scale,
            limit: f64::MIN_POSITIVE,
        });
    }
    let u = v / scale;
    Ok(u / u.norm())
}

/// Shuster's `B = sum_i w_i b_i r_i^T` (body x reference), whose `tr(A B^T)` the reference -> body
/// matrix `A` maximises.
pub fn profile_body_ref(b: &[Vector3<f64>], r: &[Vector3<f64>], w: &[f64]) -> Matrix3<f64> {
    b.iter()
        .zip(r)
        .zip(w)
        .map(|((b, r), w)| *w * b * r.transpose())
        .sum()
}

/// Reference -> body matrix of Shuster's quaternion `q = [q1, q2, q3, q4]` (scalar last, passive):
/// `A = (q4^2 - |e|^2) I + 2 e e^T - 2 q4 [e]x`.
pub fn shuster_attitude(q: &[f64; 4]) -> Matrix3<f64> {
    let e = Vector3::new(q[0], q[1], q[2]);
    let q4 = q[3];
    let ex = e.cross_matrix();
    Matrix3::identity() * (q4 * q4 - e.norm_squared()) + 2.0 * e * e.transpose() - 2.0 * q4 * ex
}

/// Body and reference vectors, each normalised to unit length.
type UnitPairs = (Vec<Vector3<f64>>, Vec<Vector3<f64>>);

/// `body` and `reference` checked against `weights` (lengths, finite, weights non-negative) and
/// normalised.
fn unit_pairs(
    body: &[Vector3<f64>],
    reference: &[Vector3<f64>],
    weights: &[f64],
) -> Result<UnitPairs> {
    let n = body.len();
    if reference.len() != n || weights.len() != n {
        return Err(Error::Shape {
            name: "reference vectors and weights",
            expected: format!("{n} of each (as many as body vectors)"),
            actual: format!("{} and {}", reference.len(), weights.len()),
        });
    }
    ensure_finite("weights", weights.iter())?;
    if let Some(k) = weights.iter().position(|w| *w < 0.0) {
        return Err(Error::out_of_range(
            "weights",
            format!(
                "expected non-negative weights, got {} at index {k}",
                weights[k]
            ),
        ));
    }
    let mut b = Vec::with_capacity(n);
    let mut r = Vec::with_capacity(n);
    for k in 0..n {
        ensure_finite("body vectors", body[k].iter())?;
        ensure_finite("reference vectors", reference[k].iter())?;
        b.push(unit(&body[k], || format!("body vector {k} is zero"))?);
        r.push(unit(&reference[k], || {
            format!("reference vector {k} is zero")
        })?);
    }
    Ok((b, r))
}

/// Shuster's covariance of the attitude error in the reference frame, the inverse of the information
/// matrix `sum_i w_i (I - r_i r_i^T)` of the unit reference vectors `r`, and the ratio of that matrix's
/// smallest to largest eigenvalue.
///
/// # Errors
/// [`Error::DegenerateGeometry`] when the ratio is at most [`INFORMATION_RATIO_LIMIT`] (the reference
/// vectors with positive weight all parallel).
fn covariance(r: &[Vector3<f64>], weights: &[f64]) -> Result<(Matrix3<f64>, f64)> {
    let info: Matrix3<f64> = r
        .iter()
        .zip(weights)
        .map(|(r, w)| *w * (Matrix3::identity() - r * r.transpose()))
        .sum();
    let eig = SymmetricEigen::new(info);
    let (lo, hi) = (eig.eigenvalues.min(), eig.eigenvalues.max());
    let ratio = if hi > 0.0 { lo.max(0.0) / hi } else { 0.0 };
    if ratio <= INFORMATION_RATIO_LIMIT {
        return Err(Error::DegenerateGeometry {
            what:
                "the vector pairs do not fix the attitude (the reference vectors are all parallel)"
                    .into(),
            matrix: "information matrix sum_i w_i (I - r_i r_i^T)",
            condition: 1.0 / ratio,
        });
    }
    let covariance_ref = eig.eigenvectors
        * Matrix3::from_diagonal(&eig.eigenvalues.map(|l| 1.0 / l))
        * eig.eigenvectors.transpose();
    Ok((covariance_ref, ratio))
}

/// Solves Wahba's problem for one epoch.
///
/// # Arguments
/// * `body` - vectors in the body frame (any length; normalised here), at least 2 not parallel.
/// * `reference` - the same directions in the reference frame, in the same order.
/// * `weights` - non-negative weights, `1 / sigma_i^2` (rad^-2) for a meaningful covariance.
/// * `method` - the solver; all three give the same optimum to rounding.
///
/// # Errors
/// [`Error::Shape`] for mismatched lengths, [`Error::NonFinite`], [`Error::OutOfRange`] for a negative
/// weight, [`Error::Degenerate`] for a zero vector, [`Error::DegenerateGeometry`] when the reference
/// vectors with positive weight are all parallel, [`Error::Convergence`] if QUEST's Newton iteration fails,
/// [`Error::Numerical`] for a result that is not finite (weights near the f64 limit).
///
/// Wahba (1965); covariance from Shuster (1989).
pub fn solve(
    body: &[Vector3<f64>],
    reference: &[Vector3<f64>],
    weights: &[f64],
    method: Method,
) -> Result<Solution> {
    let (b, r) = unit_pairs(body, reference, weights)?;
    let (covariance_ref, ratio) = covariance(&r, weights)?;
    let dcm = match method {
        Method::Svd => svd::solve(
            &b.iter()
                .zip(&r)
                .zip(weights)
                .map(|((b, r), w)| *w * r * b.transpose())
                .sum(),
        )?,
        Method::Davenport => davenport::solve(&profile_body_ref(&b, &r, weights))?,
        Method::Quest => quest::solve(&profile_body_ref(&b, &r, weights), weights.iter().sum())?,
    };
    let loss = 0.5
        * b.iter()
            .zip(&r)
            .zip(weights)
            .map(|((b, r), w)| w * (r - dcm * b).norm_squared())
            .sum::<f64>();
    guard::finite_output(
        "Wahba solution",
        dcm.iter()
            .chain(covariance_ref.iter())
            .chain([&ratio, &loss]),
        "scale the weights down (only their ratios matter to the attitude)",
    )?;
    Ok(Solution {
        dcm_ref_from_body: dcm,
        covariance_ref,
        information_ratio: ratio,
        loss,
    })
}
