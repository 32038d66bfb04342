//! Quaternions in scalar-last order `[x, y, z, w]`, as `scipy.spatial.transform.Rotation.as_quat` gives.
//! A quaternion `q` represents the same active rotation as the matrix returned by [`to_dcm`].

use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion};

use crate::error::{ensure_finite, Error, Result};

/// Matrix of the rotation represented by scalar-last quaternion `q` (normalised here).
///
/// # Errors
/// [`Error::NonFinite`], or [`Error::OutOfRange`] for a quaternion of norm below 1e-12.
pub fn to_dcm(q: [f64; 4]) -> Result<Matrix3<f64>> {
    ensure_finite("quaternion", q.iter())?;
    // Scaled by the largest component first: a quaternion of 1e300 would overflow its norm to infinity.
    let scale = q.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if scale == 0.0 {
        return Err(Error::out_of_range(
            "quaternion",
            "expected a non-zero quaternion, got norm 0",
        ));
    }
    let q = q.map(|v| v / scale);
    let quat = Quaternion::new(q[3], q[0], q[1], q[2]);
    let norm = quat.norm() * scale;
    if norm < 1e-12 {
        return Err(Error::out_of_range(
            "quaternion",
            format!("expected a non-zero quaternion, got norm {norm:.3e}"),
        ));
    }
    Ok(UnitQuaternion::from_quaternion(quat)
        .to_rotation_matrix()
        .into_inner())
}

/// Scalar-last unit quaternion of rotation matrix `m` (assumed proper), with `w >= 0`.
pub fn from_dcm(m: &Matrix3<f64>) -> [f64; 4] {
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*m));
    let s = if q.w < 0.0 { -1.0 } else { 1.0 };
    [s * q.i, s * q.j, s * q.k, s * q.w]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotation::{elementary, Axis};

    #[test]
    fn quarter_turn_about_z_matches_closed_form() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let m = to_dcm([0.0, 0.0, h, h]).unwrap();
        assert!((m - elementary(Axis::Z, std::f64::consts::FRAC_PI_2)).norm() < 1e-15);
        let q = from_dcm(&m);
        assert!((q[2] - h).abs() < 1e-15 && (q[3] - h).abs() < 1e-15);
    }

    #[test]
    fn zero_quaternion_is_rejected() {
        assert!(matches!(to_dcm([0.0; 4]), Err(Error::OutOfRange { .. })));
    }

    #[test]
    fn a_quaternion_near_the_f64_limit_is_normalised_not_zeroed() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let big = to_dcm([0.0, 0.0, 1e300, 1e300]).unwrap();
        assert!((big - to_dcm([0.0, 0.0, h, h]).unwrap()).norm() < 1e-15);
    }
}
