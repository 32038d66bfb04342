//! Direction-cosine matrices: elementary rotations, validity checks, nearest proper rotation.

use nalgebra::Matrix3;

use crate::error::{ensure_finite, Error, Result};
use crate::rotation::euler::Axis;
use crate::wahba;

/// Active elementary rotation by `angle_rad` about a coordinate axis (right-handed, counter-clockwise
/// when looking down the axis towards the origin). Equals `scipy Rotation.from_euler(axis, angle)`.
pub fn elementary(axis: Axis, angle_rad: f64) -> Matrix3<f64> {
    let (s, c) = angle_rad.sin_cos();
    match axis {
        Axis::X => Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c),
        Axis::Y => Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c),
        Axis::Z => Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0),
    }
}

/// Checks that `m` is a proper rotation: finite, `m^T m = I` to `tol` (Frobenius) and `det m > 0`.
///
/// # Errors
/// [`Error::NonFinite`] or [`Error::OutOfRange`] saying how far from orthogonal or which determinant.
pub fn check_rotation(name: &'static str, m: &Matrix3<f64>, tol: f64) -> Result<()> {
    ensure_finite(name, m.iter())?;
    let err = (m.transpose() * m - Matrix3::identity()).norm();
    if err > tol {
        return Err(Error::out_of_range(
            name,
            format!(
                "expected an orthogonal matrix, got |M^T M - I| = {err:.3e} (tolerance {tol:.1e})"
            ),
        ));
    }
    let det = m.determinant();
    if det <= 0.0 {
        return Err(Error::out_of_range(
            name,
            format!("expected a proper rotation (det = +1), got det = {det:.6}"),
        ));
    }
    Ok(())
}

/// The proper rotation closest to `m` in the Frobenius norm (the proper polar factor).
///
/// # Errors
/// [`Error::DegenerateGeometry`] when `m` has rank below 2, where the answer is not unique.
pub fn nearest_rotation(m: &Matrix3<f64>) -> Result<Matrix3<f64>> {
    wahba::svd::solve(m)
}
