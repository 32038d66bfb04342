//! From ECEF baselines and rotations to what an epoch reports: East-North-Up components at the reference
//! antenna, azimuth and elevation or heading, pitch and roll, and their one-sigma values.

use nalgebra::{Matrix3, Vector3};

use crate::rotation::euler::YZX;

/// Azimuth (clockwise from North, [0, 360)) and elevation of an ENU vector with their one-sigma values
/// from the ENU covariance (first-order propagation), degrees; NaN sigmas where the covariance is not
/// finite or the vector is vertical.
pub(crate) fn azimuth_elevation(enu: &Vector3<f64>, cov: &Matrix3<f64>) -> ([f64; 2], [f64; 2]) {
    let (e, n, u) = (enu.x, enu.y, enu.z);
    let h2 = e * e + n * n;
    let h = h2.sqrt();
    let l2 = h2 + u * u;
    let az = e.atan2(n).to_degrees().rem_euclid(360.0);
    let el = u.atan2(h).to_degrees();
    let j_az = Vector3::new(n / h2, -e / h2, 0.0);
    let j_el = Vector3::new(-u * e / (h * l2), -u * n / (h * l2), h / l2);
    let sigma = |j: Vector3<f64>| (j.transpose() * cov * j)[(0, 0)].sqrt().to_degrees();
    ([az, el], [sigma(j_az), sigma(j_el)])
}

/// Heading (compass, = -psi, [0, 360)), pitch and roll, degrees, of the rotation ENU <- body (seed 001's
/// Y-Z-X sequence in the North-Up-East frame).
pub(crate) fn heading_pitch_roll(enu_from_body: &Matrix3<f64>) -> [f64; 3] {
    let m = enu_from_body;
    // Rows (E, N, U) -> (N, U, E): the frame of eq. (5).
    let normal = Matrix3::from_rows(&[m.row(1), m.row(2), m.row(0)]);
    let [psi, theta, phi] = YZX.from_dcm(&normal);
    [
        (-psi).to_degrees().rem_euclid(360.0),
        theta.to_degrees(),
        phi.to_degrees(),
    ]
}

/// Row-major copy of a 3 x 3 matrix.
pub(crate) fn row_major(m: &Matrix3<f64>) -> [f64; 9] {
    let mut out = [0.0; 9];
    for r in 0..3 {
        for c in 0..3 {
            out[3 * r + c] = m[(r, c)];
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::likelihood::dcm_enu_from_body as enu_from_body;

    #[test]
    fn angles_and_sigmas_match_finite_differences() {
        let enu = Vector3::new(-0.6, 0.5, 0.3);
        let cov = Matrix3::new(4e-6, 1e-6, 0.0, 1e-6, 9e-6, 2e-6, 0.0, 2e-6, 1.6e-5);
        let ([az, el], [saz, sel]) = azimuth_elevation(&enu, &cov);
        assert!((az - (360.0 + (-0.6f64).atan2(0.5).to_degrees())).abs() < 1e-12);
        assert!((el - 0.3f64.atan2(0.61f64.sqrt()).to_degrees()).abs() < 1e-12);
        // Numerical Jacobian, then J C J^T.
        let h = 1e-7;
        let mut ja = Vector3::zeros();
        let mut je = Vector3::zeros();
        for k in 0..3 {
            let mut d = enu;
            d[k] += h;
            let ([a1, e1], _) = azimuth_elevation(&d, &cov);
            ja[k] = (a1 - az) / h;
            je[k] = (e1 - el) / h;
        }
        let s = |j: Vector3<f64>| (j.transpose() * cov * j)[(0, 0)].sqrt();
        assert!((s(ja) - saz).abs() < 1e-5 * saz);
        assert!((s(je) - sel).abs() < 1e-5 * sel);
    }

    #[test]
    fn heading_pitch_roll_inverts_the_seed_sequence() {
        let (psi, theta, phi) = (-0.7, 0.2, -0.35);
        let hpr = heading_pitch_roll(&enu_from_body(psi, theta, phi));
        assert!((hpr[0] - 0.7f64.to_degrees()).abs() < 1e-9);
        assert!((hpr[1] - 0.2f64.to_degrees()).abs() < 1e-9);
        assert!((hpr[2] + 0.35f64.to_degrees()).abs() < 1e-9);
        // The nose (body X) at zero angles points North.
        let m = enu_from_body(0.0, 0.0, 0.0);
        assert!((m.column(0) - Vector3::new(0.0, 1.0, 0.0)).norm() < 1e-15);
    }
}
