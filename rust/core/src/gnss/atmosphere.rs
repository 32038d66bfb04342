//! Broadcast ionosphere (Klobuchar) and a standard troposphere (Saastamoinen zenith delays of a
//! standard atmosphere, Niell mapping functions).

use super::signal::{System, SPEED_OF_LIGHT_M_S};
use super::time::seconds_of_week;

/// GPS L1 carrier frequency, Hz (the Klobuchar model's reference).
const F_L1_HZ: f64 = 1_575.42e6;

/// Klobuchar ionospheric delay of a single-frequency code observation at `frequency_hz`, m (IS-GPS-200
/// 20.3.3.5.2.5, computed on L1 and scaled by `(f_L1 / f)^2`). `coeffs` are alpha0..3, beta0..3 as
/// broadcast (seconds and semicircle powers); latitude, longitude of the receiver, azimuth and elevation
/// in radians. 0 for a satellite at or below the horizon or a non-positive or non-finite frequency.
pub fn klobuchar_delay_m(
    coeffs: &[f64; 8],
    t_gpst_ns: i64,
    lat_rad: f64,
    lon_rad: f64,
    az_rad: f64,
    el_rad: f64,
    frequency_hz: f64,
) -> f64 {
    if !(el_rad > 0.0 && frequency_hz > 0.0 && frequency_hz.is_finite()) {
        return 0.0;
    }
    let pi = std::f64::consts::PI;
    // The ICD works in semicircles.
    let e = el_rad / pi;
    let psi = 0.0137 / (e + 0.11) - 0.022;
    let phi_i = (lat_rad / pi + psi * az_rad.cos()).clamp(-0.416, 0.416);
    let lambda_i = lon_rad / pi + psi * az_rad.sin() / (phi_i * pi).cos();
    let phi_m = phi_i + 0.064 * ((lambda_i - 1.617) * pi).cos();
    let t = (4.32e4 * lambda_i + seconds_of_week(System::Gps, t_gpst_ns)).rem_euclid(86_400.0);
    let f = 1.0 + 16.0 * (0.53 - e).powi(3);
    let poly = |c: &[f64]| c[0] + phi_m * (c[1] + phi_m * (c[2] + phi_m * c[3]));
    let amp = poly(&coeffs[0..4]).max(0.0);
    let per = poly(&coeffs[4..8]).max(72_000.0);
    let x = 2.0 * pi * (t - 50_400.0) / per;
    let delay_s = if x.abs() < 1.57 {
        f * (5e-9 + amp * (1.0 - x * x / 2.0 + x.powi(4) / 24.0))
    } else {
        f * 5e-9
    };
    let scale = (F_L1_HZ / frequency_hz).powi(2);
    let d = SPEED_OF_LIGHT_M_S * delay_s * scale;
    if d.is_finite() {
        d
    } else {
        0.0
    }
}

/// Niell (1996, JGR 101(B2):3227, table 3) coefficients a, b, c at latitudes 15, 30, 45, 60, 75 deg:
/// hydrostatic average, hydrostatic amplitude, wet.
const NIELL_LATITUDES_DEG: [f64; 5] = [15.0, 30.0, 45.0, 60.0, 75.0];
const NIELL_DRY_AVERAGE: [[f64; 5]; 3] = [
    [
        1.276_993_4e-3,
        1.268_323_0e-3,
        1.246_539_7e-3,
        1.219_604_9e-3,
        1.204_599_6e-3,
    ],
    [
        2.915_369_5e-3,
        2.915_229_9e-3,
        2.928_844_5e-3,
        2.902_256_5e-3,
        2.902_491_2e-3,
    ],
    [
        62.610_505e-3,
        62.837_393e-3,
        63.721_774e-3,
        63.824_265e-3,
        64.258_455e-3,
    ],
];
const NIELL_WET: [[f64; 5]; 3] = [
    [
        5.802_189_7e-4,
        5.679_484_7e-4,
        5.811_801_9e-4,
        5.972_754_2e-4,
        6.164_169_3e-4,
    ],
    [
        1.427_526_8e-3,
        1.513_862_5e-3,
        1.457_275_2e-3,
        1.500_742_8e-3,
        1.759_908_2e-3,
    ],
    [
        4.347_296_1e-2,
        4.672_951_0e-2,
        4.390_893_1e-2,
        4.462_698_2e-2,
        5.473_603_8e-2,
    ],
];
/// Niell's height correction of the hydrostatic mapping (a, b, c per km).
const NIELL_HEIGHT: [f64; 3] = [2.53e-5, 5.49e-3, 1.14e-3];

/// Marini's continued fraction normalised to 1 at the zenith.
fn marini(sin_el: f64, [a, b, c]: [f64; 3]) -> f64 {
    (1.0 + a / (1.0 + b / (1.0 + c))) / (sin_el + a / (sin_el + b / (sin_el + c)))
}

/// Table row interpolated linearly in |latitude| (held constant beyond 15 and 75 degrees).
fn interpolate(table: &[[f64; 5]; 3], lat_rad: f64) -> [f64; 3] {
    let lat = lat_rad.to_degrees().abs().clamp(15.0, 75.0);
    let i = (((lat - 15.0) / 15.0).floor() as usize).min(3);
    let w = (lat - NIELL_LATITUDES_DEG[i]) / 15.0;
    std::array::from_fn(|k| table[k][i] + w * (table[k][i + 1] - table[k][i]))
}

const NIELL_DRY_AMPLITUDE: [[f64; 5]; 3] = [
    [
        0.0,
        1.270_962_6e-5,
        2.652_366_2e-5,
        3.400_045_2e-5,
        4.120_219_1e-5,
    ],
    [
        0.0,
        2.141_497_9e-5,
        3.016_077_9e-5,
        7.256_272_2e-5,
        11.723_375e-5,
    ],
    [
        0.0,
        9.012_840_0e-5,
        4.349_703_7e-5,
        84.795_348e-5,
        170.372_06e-5,
    ],
];
/// Day of year of the hydrostatic coefficients' winter extreme in the northern hemisphere (Niell: 28).
const NIELL_PHASE_DAY: f64 = 28.0;

/// Day of year (1-based, fractional) of a GPST instant, to within a day (365.25-day years from
/// 1980-01-01: the seasonal term needs no better).
pub fn day_of_year(t_gpst_ns: i64) -> f64 {
    // The GPS epoch, 1980-01-06, is day 6 of its year.
    let days = t_gpst_ns as f64 / 86_400e9 + 5.0;
    days.rem_euclid(365.25) + 1.0
}

/// Niell hydrostatic and wet mapping functions at elevation `el_rad` (clamped to >= 0), latitude and
/// ellipsoidal height; `day_of_year` adds the hydrostatic seasonal term (half a year later in the
/// southern hemisphere), `None` takes its annual mean (up to 1.7e-3 in c at 75 deg latitude, a few cm
/// of slant delay at 10 deg elevation).
pub fn niell_mapping(
    lat_rad: f64,
    height_m: f64,
    el_rad: f64,
    day_of_year: Option<f64>,
) -> (f64, f64) {
    let s = el_rad.max(0.0).sin();
    let mut dry = interpolate(&NIELL_DRY_AVERAGE, lat_rad);
    if let Some(doy) = day_of_year {
        let doy = if lat_rad < 0.0 {
            doy + 365.25 / 2.0
        } else {
            doy
        };
        let season = (std::f64::consts::TAU * (doy - NIELL_PHASE_DAY) / 365.25).cos();
        let amplitude = interpolate(&NIELL_DRY_AMPLITUDE, lat_rad);
        for k in 0..3 {
            dry[k] -= amplitude[k] * season;
        }
    }
    let dry = marini(s, dry) + height_m / 1e3 * (1.0 / s.max(1e-3) - marini(s, NIELL_HEIGHT));
    let wet = marini(s, interpolate(&NIELL_WET, lat_rad));
    (dry, wet)
}

/// Saastamoinen hydrostatic and wet zenith delays (m) of a standard atmosphere at latitude `lat_rad`
/// and ellipsoidal height `height_m`: pressure `1013.25 (1 - 2.2557e-5 h)^5.2568` hPa and temperature
/// `15 - 6.5e-3 h` deg C up to the 11 km tropopause, an isothermal stratosphere above (scale height
/// 6341.6 m), relative humidity 0.7 below 11 km and none above (RTKLIB's standard atmosphere;
/// Saastamoinen 1972). Heights below -500 m are taken as -500 m.
pub fn saastamoinen_zenith_m(lat_rad: f64, height_m: f64) -> (f64, f64) {
    let h = height_m.max(-500.0);
    let ht = h.min(11_000.0);
    let temp_k = 15.0 - 6.5e-3 * ht + 273.16;
    let mut pressure = 1013.25 * (1.0 - 2.2557e-5 * ht).powf(5.2568);
    if h > 11_000.0 {
        pressure *= (-(h - 11_000.0) / 6341.6).exp();
    }
    let humidity = if h > 11_000.0 { 0.0 } else { 0.7 };
    let e = 6.108 * humidity * ((17.15 * temp_k - 4684.0) / (temp_k - 38.45)).exp();
    let dry =
        0.002_276_8 * pressure / (1.0 - 0.002_66 * (2.0 * lat_rad).cos() - 0.000_28 * h / 1e3);
    let wet = 0.002_277 * (1255.0 / temp_k + 0.05) * e;
    (dry, wet)
}

/// Slant tropospheric delay, m: Saastamoinen zenith delays of the standard atmosphere
/// ([`saastamoinen_zenith_m`]) times the Niell mapping functions ([`niell_mapping`]) with the annual
/// mean of the hydrostatic coefficients; 0 for non-finite arguments.
pub fn troposphere_delay_m(lat_rad: f64, height_m: f64, el_rad: f64) -> f64 {
    slant(lat_rad, height_m, el_rad, None)
}

/// [`troposphere_delay_m`] with the seasonal term of the hydrostatic mapping at GPST `t_gpst_ns`.
pub fn troposphere_delay_at_m(lat_rad: f64, height_m: f64, el_rad: f64, t_gpst_ns: i64) -> f64 {
    slant(lat_rad, height_m, el_rad, Some(day_of_year(t_gpst_ns)))
}

fn slant(lat_rad: f64, height_m: f64, el_rad: f64, day: Option<f64>) -> f64 {
    if !(lat_rad.is_finite() && height_m.is_finite() && el_rad.is_finite()) {
        return 0.0;
    }
    let (zd, zw) = saastamoinen_zenith_m(lat_rad, height_m);
    let (md, mw) = niell_mapping(lat_rad, height_m, el_rad, day);
    zd * md + zw * mw
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn klobuchar_night_floor_and_scaling() {
        // Outside the daytime cosine (|x| >= 1.57) the ICD gives F * 5 ns; at the zenith F = 1 + 16
        // (0.53 - 0.5)^3 = 1.000432.
        let zero = [0.0; 8];
        let t_night = 0; // 00:00 GPST at longitude 0: local time 0 h
        let d = klobuchar_delay_m(
            &zero,
            t_night,
            0.0,
            0.0,
            0.0,
            std::f64::consts::FRAC_PI_2,
            F_L1_HZ,
        );
        let f = 1.0 + 16.0 * (0.53f64 - 0.5).powi(3);
        assert!((d - SPEED_OF_LIGHT_M_S * 5e-9 * f).abs() < 1e-12);
        // L2 delay is (f1/f2)^2 = (77/60)^2 times L1's.
        let d2 = klobuchar_delay_m(
            &zero,
            t_night,
            0.0,
            0.0,
            0.0,
            std::f64::consts::FRAC_PI_2,
            1227.6e6,
        );
        assert!((d2 / d - (77.0f64 / 60.0).powi(2)).abs() < 1e-12);
        assert_eq!(
            klobuchar_delay_m(&zero, 0, 0.0, 0.0, 0.0, -0.1, F_L1_HZ),
            0.0
        );
    }

    #[test]
    fn klobuchar_local_noon_peak() {
        // At local 14:00 (t = 50400 s, x = 0) the delay is F (5 ns + AMP) with AMP = alpha0 when only
        // alpha0 is nonzero.
        let mut c = [0.0; 8];
        c[0] = 2e-8;
        c[4] = 1e5;
        let t = 50_400 * 1_000_000_000;
        let d = klobuchar_delay_m(&c, t, 0.0, 0.0, 0.0, std::f64::consts::FRAC_PI_2, F_L1_HZ);
        let f = 1.0 + 16.0 * (0.53f64 - 0.5).powi(3);
        assert!((d - SPEED_OF_LIGHT_M_S * f * 2.5e-8).abs() < 1e-9);
    }

    #[test]
    fn klobuchar_published_values() {
        // Klobuchar's worked example (Parkinson & Spilker vol. I ch. 12; libswiftnav's
        // check_ionosphere.c): 40 N 100 W, az 210, el 20, week 1042 593100 s -> 23.784 m; and
        // libswiftnav's second vector, 35.3 S 149.1 E, az 0, el 15, week 1875 479820 s -> 7.202 m.
        let cases = [
            (
                [
                    0.382e-7, 0.149e-7, -0.179e-6, 0.0, 0.143e6, 0.0, -0.328e6, 0.113e6,
                ],
                (40.0, 260.0, 210.0, 20.0),
                (1042, 593_100),
                23.784,
            ),
            (
                [
                    0.1583e-7, -0.7451e-8, -0.596e-7, 0.1192e-6, 0.129e6, -0.213e6, 0.6554e5,
                    0.3277e6,
                ],
                (-35.3, 149.1, 0.0, 15.0),
                (1875, 479_820),
                7.202,
            ),
        ];
        for (c, (lat, lon, az, el), (week, tow), expected) in cases {
            let t = week * 604_800 * 1_000_000_000 + tow * 1_000_000_000;
            let d = klobuchar_delay_m(
                &c,
                t,
                f64::to_radians(lat),
                f64::to_radians(lon),
                f64::to_radians(az),
                f64::to_radians(el),
                F_L1_HZ,
            );
            // The references print 1 mm.
            assert!((d - expected).abs() < 1e-3, "{d} vs {expected}");
        }
    }

    #[test]
    fn saastamoinen_sea_level_and_niell_zenith() {
        // Sea level, 45 deg: 2.3 m hydrostatic (Saastamoinen: 0.0022768 * 1013.25 / (1 - 0.00028*0)).
        let (zd, zw) = saastamoinen_zenith_m(45f64.to_radians(), 0.0);
        assert!((zd - 0.002_276_8 * 1013.25).abs() < 1e-12);
        assert!(zw > 0.05 && zw < 0.3);
        // Mapping functions are 1 at the zenith (continued fraction normalised) at sea level.
        let (md, mw) = niell_mapping(45f64.to_radians(), 0.0, std::f64::consts::FRAC_PI_2, None);
        assert!((md - 1.0).abs() < 1e-12 && (mw - 1.0).abs() < 1e-12);
        // Niell 1996, fig. 3: at 5 deg elevation the hydrostatic mapping is about 10.1-10.2.
        let (md5, _) = niell_mapping(45f64.to_radians(), 0.0, 5f64.to_radians(), None);
        assert!((10.0..10.4).contains(&md5), "{md5}");
        // Finite at and below the horizon, and above the tropopause.
        assert!(troposphere_delay_m(0.5, 0.0, -0.2).is_finite());
        let high = troposphere_delay_m(0.5, 30_000.0, 0.5);
        assert!(high.is_finite() && high > 0.0 && high < 0.1);
    }

    #[test]
    fn niell_seasonal_term() {
        let (lat, el) = (60f64.to_radians(), 10f64.to_radians());
        let mean = niell_mapping(lat, 0.0, el, None).0;
        // A quarter year from the phase day the seasonal cosine is 0: the annual mean.
        let quarter = niell_mapping(lat, 0.0, el, Some(28.0 + 365.25 / 4.0)).0;
        assert!((quarter - mean).abs() < 1e-12);
        // Day 28 in the north is day 28 + half a year in the south (Niell 1996, eq. 5 and text).
        let north = niell_mapping(lat, 0.0, el, Some(28.0)).0;
        let south = niell_mapping(-lat, 0.0, el, Some(28.0 + 365.25 / 2.0)).0;
        assert!((north - south).abs() < 1e-12 && (north - mean).abs() > 1e-4);
        // No seasonal term at 15 deg and below (zero amplitudes in Niell's table).
        let low = 10f64.to_radians();
        assert_eq!(
            niell_mapping(low, 0.0, el, Some(28.0)),
            niell_mapping(low, 0.0, el, None)
        );
        // 2021-01-01 00:00:14 GPST is day 1 (within a day).
        assert!((day_of_year(2138 * 604_800_000_000_000 + 432_014_000_000_000) - 1.0).abs() < 1.0);
    }
}
