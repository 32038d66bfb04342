//! Variances of undifferenced observations from the elevation model `sigma^2 = a^2 + b^2 / sin^2(el)`
//! ([`ElevationSigma`]) and, for code positioning, the errors of the broadcast corrections.

use super::options::ElevationSigma;

/// Fraction of the Klobuchar delay taken as its one-sigma error (the model removes about half of the
/// ionospheric delay: IS-GPS-200 20.3.3.5.2.5, RTKLIB's ERR_BRDCI).
pub const KLOBUCHAR_ERROR_FRACTION: f64 = 0.5;
/// One-sigma error of the standard-atmosphere zenith troposphere, m, before mapping (RTKLIB's ERR_SAAS).
pub const TROPOSPHERE_ZENITH_ERROR_M: f64 = 0.3;

/// Variance of one undifferenced observation at elevation `elevation_rad`, m^2 (the elevation is
/// clamped below at 1 degree, see [`ElevationSigma::sigma_m`]).
pub fn variance_m2(sigma: &ElevationSigma, elevation_rad: f64) -> f64 {
    let s = sigma.sigma_m(elevation_rad);
    s * s
}

/// Variance of a single-frequency pseudorange corrected by Klobuchar (`iono_m`) and the standard
/// troposphere (`tropo_mapping`: slant over zenith delay), m^2: the code model plus each correction's
/// error.
pub fn code_variance_m2(
    sigma: &ElevationSigma,
    elevation_rad: f64,
    iono_m: f64,
    tropo_mapping: f64,
) -> f64 {
    let iono = KLOBUCHAR_ERROR_FRACTION * iono_m;
    let tropo = TROPOSPHERE_ZENITH_ERROR_M * tropo_mapping;
    variance_m2(sigma, elevation_rad) + iono * iono + tropo * tropo
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zenith_and_low_elevation_variances() {
        let s = ElevationSigma { a_m: 0.3, b_m: 0.4 };
        // At the zenith sin = 1: a^2 + b^2 = 0.25.
        assert!((variance_m2(&s, std::f64::consts::FRAC_PI_2) - 0.25).abs() < 1e-15);
        // At 30 deg sin = 1/2: a^2 + 4 b^2 = 0.09 + 0.64.
        assert!((variance_m2(&s, 30f64.to_radians()) - 0.73).abs() < 1e-12);
        assert!(
            (code_variance_m2(&s, std::f64::consts::FRAC_PI_2, 2.0, 1.0) - (0.25 + 1.0 + 0.09))
                .abs()
                < 1e-12
        );
    }
}
