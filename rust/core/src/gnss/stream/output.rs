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

/// Heading (compass, = -psi, [0, 360)), pitch and roll, degrees, of the rotation ENU <- body (Bunyaeva et
/// al.'s Y-Z-X sequence in the North-Up-East frame).
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

/// One-sigma of heading, pitch and roll (degrees) of an array whose rotation ENU <- body `r` was fitted
/// to baselines `baselines_enu` with covariances `covariances_enu` (ENU, m and m^2), by first-order
/// propagation: a small rotation `d` (ENU) moves baseline `v_i` by `d x v_i = -[v_i]x d`, so the
/// weighted least-squares rotation has covariance `(sum [v_i]x^T C_i^-1 [v_i]x)^-1`, carried to the angles
/// by the Jacobian of [`heading_pitch_roll`] (central differences). NaN where a covariance is singular
/// or the baselines do not determine the rotation.
pub(crate) fn attitude_sigmas_deg(
    r: &Matrix3<f64>,
    baselines_enu: &[Vector3<f64>],
    covariances_enu: &[Matrix3<f64>],
) -> [f64; 3] {
    let mut normal = Matrix3::zeros();
    for (v, c) in baselines_enu.iter().zip(covariances_enu) {
        let Some(w) = c.try_inverse() else {
            return [f64::NAN; 3];
        };
        let a = v.cross_matrix();
        normal += a.transpose() * w * a;
    }
    let Some(cov) = normal.try_inverse() else {
        return [f64::NAN; 3];
    };
    // Jacobian of the angles (degrees) with respect to the small rotation (rad), wrapped differences.
    const H: f64 = 1e-6;
    let mut j = Matrix3::zeros();
    for k in 0..3 {
        let mut d = Vector3::zeros();
        d[k] = H;
        let plus = heading_pitch_roll(&(nalgebra::Rotation3::new(d).into_inner() * r));
        let minus = heading_pitch_roll(&(nalgebra::Rotation3::new(-d).into_inner() * r));
        for a in 0..3 {
            let diff = (plus[a] - minus[a] + 180.0).rem_euclid(360.0) - 180.0;
            j[(a, k)] = diff / (2.0 * H);
        }
    }
    let angles = j * cov * j.transpose();
    [0, 1, 2].map(|a| angles[(a, a)].sqrt())
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
    fn attitude_sigmas_match_a_monte_carlo_of_the_wahba_fit() {
        // Two orthogonal 1 m baselines with 5 mm isotropic noise: the rotation is known to about
        // 5 mm / 1 m = 0.29 degree about each axis that moves a baseline; compare with the spread of
        // the SVD (Wahba) fit over 4000 seeded noisy samples (1-sigma statistical error of a standard
        // deviation from 4000 samples: 1.1 %).
        use rand::SeedableRng;
        let normal = rand_distr_free_normal;
        let r = enu_from_body(-0.5, 0.1, 0.05);
        let body = [Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.0, 0.0, 1.0)];
        let v: Vec<Vector3<f64>> = body.iter().map(|b| r * b).collect();
        let c = Matrix3::identity() * 0.005f64.powi(2);
        let sig = attitude_sigmas_deg(&r, &v, &[c, c]);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let n = 4000;
        let mut sum = [0.0; 3];
        let truth = heading_pitch_roll(&r);
        for _ in 0..n {
            let mut b = Matrix3::zeros();
            for (body_i, v_i) in body.iter().zip(&v) {
                let noisy = v_i + Vector3::from_fn(|_, _| 0.005 * normal(&mut rng));
                b += noisy * body_i.transpose();
            }
            let svd = b.svd(true, true);
            let (u, vt) = (svd.u.unwrap(), svd.v_t.unwrap());
            let d = (u * vt).determinant().signum();
            let fit = u * Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, d)) * vt;
            let a = heading_pitch_roll(&fit);
            for k in 0..3 {
                let e = (a[k] - truth[k] + 180.0).rem_euclid(360.0) - 180.0;
                sum[k] += e * e;
            }
        }
        for k in 0..3 {
            let empirical = (sum[k] / n as f64).sqrt();
            assert!(
                (empirical / sig[k] - 1.0).abs() < 0.05,
                "{k}: {empirical} vs {}",
                sig[k]
            );
        }
    }

    /// A standard normal draw (Box-Muller).
    fn rand_distr_free_normal(rng: &mut impl rand::Rng) -> f64 {
        let (u1, u2): (f64, f64) = (rng.random::<f64>().max(1e-300), rng.random());
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
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
