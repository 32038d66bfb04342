//! The local East-North-Up frame at an ECEF position on the WGS-84 ellipsoid.

use nalgebra::{Matrix3, Vector3};

/// WGS-84 semi-major axis, m, and first eccentricity squared (NIMA TR8350.2).
const WGS84_A_M: f64 = 6_378_137.0;
const WGS84_E2: f64 = 6.694_379_990_141_316e-3;

/// Geodetic latitude and longitude (rad) of an ECEF position (m), by fixed-point iteration of
/// `tan(lat) = z / (p (1 - e^2 N / (N + h)))`, which converges to 1e-14 rad within 10 steps for any point
/// above 100 km from the Earth's centre. Near the poles (p < 1 mm) longitude is 0.
pub fn latitude_longitude(ecef_m: &Vector3<f64>) -> (f64, f64) {
    let (x, y, z) = (ecef_m[0], ecef_m[1], ecef_m[2]);
    let p = x.hypot(y);
    if p < 1e-3 {
        return (std::f64::consts::FRAC_PI_2.copysign(z), 0.0);
    }
    let mut lat = z.atan2(p * (1.0 - WGS84_E2));
    for _ in 0..10 {
        let s = lat.sin();
        let n = WGS84_A_M / (1.0 - WGS84_E2 * s * s).sqrt();
        let h = p / lat.cos() - n;
        lat = z.atan2(p * (1.0 - WGS84_E2 * n / (n + h)));
    }
    (lat, y.atan2(x))
}

/// Rotation ENU <- ECEF at `ecef_m` (rows: East, North, Up unit vectors in ECEF).
pub fn enu_from_ecef(ecef_m: &Vector3<f64>) -> Matrix3<f64> {
    let (lat, lon) = latitude_longitude(ecef_m);
    let (sl, cl) = lat.sin_cos();
    let (so, co) = lon.sin_cos();
    Matrix3::new(-so, co, 0.0, -sl * co, -sl * so, cl, cl * co, cl * so, sl)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Closed form: the point at geodetic (lat, lon, h) is
    /// `((N + h) cos lat cos lon, (N + h) cos lat sin lon, (N (1 - e^2) + h) sin lat)`.
    #[test]
    fn latitude_of_the_closed_form_point() {
        for &(lat, lon, h) in &[
            (0.6, 2.4, 50.0),
            (-1.2, -0.3, 3000.0),
            (0.0, 0.0, 0.0),
            (1.5, 1.0, 2e7),
        ] {
            let s: f64 = f64::sin(lat);
            let n = WGS84_A_M / (1.0 - WGS84_E2 * s * s).sqrt();
            let p = Vector3::new(
                (n + h) * lat.cos() * f64::cos(lon),
                (n + h) * lat.cos() * f64::sin(lon),
                (n * (1.0 - WGS84_E2) + h) * s,
            );
            let (la, lo) = latitude_longitude(&p);
            assert!((la - lat).abs() < 1e-12, "{la} {lat}");
            assert!((lo - lon).abs() < 1e-12);
            let r = enu_from_ecef(&p);
            // Up is the ellipsoid normal (cos lat cos lon, cos lat sin lon, sin lat); orthonormal.
            let up = Vector3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), s);
            assert!((r.row(2).transpose() - up).norm() < 1e-12);
            assert!((r * r.transpose() - Matrix3::identity()).norm() < 1e-14);
            assert!((r.determinant() - 1.0).abs() < 1e-14);
        }
    }
}
