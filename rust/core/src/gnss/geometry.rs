//! Satellite geometry seen from one receiver: transmit-time position in the ECEF frame of the reception
//! instant (light time iterated, Sagnac rotation), range, line of sight, elevation and azimuth.

use nalgebra::{Matrix3, Vector3};

use super::ephemeris::Ephemerides;
use super::signal::{SatId, SPEED_OF_LIGHT_M_S};

/// Earth rotation rate of the Sagnac correction, rad/s (WGS-84, IS-GPS-200).
pub const EARTH_ROTATION_RAD_S: f64 = 7.292_115_146_7e-5;
/// WGS-84 semi-major axis (m) and flattening.
pub const WGS84_A_M: f64 = 6_378_137.0;
pub const WGS84_F: f64 = 1.0 / 298.257_223_563;
/// Most light-time iterations; each gains a factor |range rate| / c ~ 1e-5, so three reach 1e-12 s.
pub const MAX_LIGHT_TIME_ITERATIONS: usize = 10;
/// Receivers closer than this to the Earth's centre have no defined local horizon (elevation and
/// azimuth are NaN then), m.
pub const MIN_HORIZON_RADIUS_M: f64 = 1e5;

/// One satellite seen from one receiver at one reception instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SatGeometry {
    /// At transmit time, rotated into the ECEF frame of the reception instant (Sagnac), m.
    pub position_m: Vector3<f64>,
    /// Satellite clock at transmit time (relativistic term included, no group delay), s.
    pub clock_s: f64,
    /// `|position - receiver|`, m.
    pub range_m: f64,
    /// Unit vector receiver -> satellite, ECEF.
    pub los_ecef: Vector3<f64>,
    /// Elevation and azimuth (clockwise from North) at the receiver's geodetic position, rad; NaN for a
    /// receiver within [`MIN_HORIZON_RADIUS_M`] of the Earth's centre.
    pub elevation_rad: f64,
    pub azimuth_rad: f64,
}

/// WGS-84 geodetic latitude (rad), longitude (rad) and height (m) of an ECEF position (Bowring's
/// iteration; converges to 1e-12 rad in a few steps for any point outside a 1e5 m sphere).
pub fn geodetic_from_ecef(p: &Vector3<f64>) -> (f64, f64, f64) {
    let e2 = WGS84_F * (2.0 - WGS84_F);
    let rho = p.x.hypot(p.y);
    let mut lat = p.z.atan2(rho * (1.0 - e2));
    let mut n = WGS84_A_M;
    for _ in 0..10 {
        let s = lat.sin();
        n = WGS84_A_M / (1.0 - e2 * s * s).sqrt();
        let next = (p.z + e2 * n * s).atan2(rho);
        let done = (next - lat).abs() < 1e-14;
        lat = next;
        if done {
            break;
        }
    }
    let c = lat.cos();
    let h = if c.abs() > 1e-10 {
        rho / c - n
    } else {
        p.z.abs() - n * (1.0 - e2)
    };
    (lat, p.y.atan2(p.x), h)
}

/// Rotation taking ECEF vectors into East-North-Up at latitude `lat`, longitude `lon` (rad): rows are
/// the East, North and Up unit vectors.
pub fn enu_from_ecef(lat: f64, lon: f64) -> Matrix3<f64> {
    let (sl, cl) = lat.sin_cos();
    let (so, co) = lon.sin_cos();
    Matrix3::new(-so, co, 0.0, -sl * co, -sl * so, cl, cl * co, cl * so, sl)
}

/// `p` rotated about Z by `-omega_e tau`: a position of the ECEF frame of `tau` seconds ago expressed
/// in the ECEF frame of now.
fn sagnac(p: &Vector3<f64>, tau: f64) -> Vector3<f64> {
    let (s, c) = (EARTH_ROTATION_RAD_S * tau).sin_cos();
    Vector3::new(c * p.x + s * p.y, -s * p.x + c * p.y, p.z)
}

/// A receiver position with what every satellite's geometry from it shares: its geodetic position and
/// East-North-Up rotation (`None` within [`MIN_HORIZON_RADIUS_M`] of the Earth's centre), computed once
/// per receiver and epoch instead of once per satellite.
#[derive(Debug, Clone, Copy)]
pub struct Site {
    pub position_m: Vector3<f64>,
    /// Latitude (rad), longitude (rad), height (m) ([`geodetic_from_ecef`]) and the rotation
    /// [`enu_from_ecef`] there.
    pub horizon: Option<((f64, f64, f64), Matrix3<f64>)>,
}

impl Site {
    pub fn new(position_m: &Vector3<f64>) -> Site {
        let horizon = (position_m.norm() >= MIN_HORIZON_RADIUS_M).then(|| {
            let geodetic = geodetic_from_ecef(position_m);
            (geodetic, enu_from_ecef(geodetic.0, geodetic.1))
        });
        Site {
            position_m: *position_m,
            horizon,
        }
    }
}

/// Geometry of `sat` for a reception at label `t_rx_gpst_ns` by a receiver at `receiver_m` (ECEF) whose
/// clock reads `rx_clock_s` ahead (true reception = label - clock): the light time is iterated from
/// the receiver position. `None` where the satellite has no usable record at that time or the receiver
/// coincides with the satellite. The geometry of many satellites from one position:
/// [`satellite_geometry_from`].
pub fn satellite_geometry(
    eph: &Ephemerides,
    sat: SatId,
    t_rx_gpst_ns: i64,
    rx_clock_s: f64,
    receiver_m: &Vector3<f64>,
) -> Option<SatGeometry> {
    satellite_geometry_from(eph, sat, t_rx_gpst_ns, rx_clock_s, &Site::new(receiver_m))
}

/// [`satellite_geometry`] from a [`Site`].
pub fn satellite_geometry_from(
    eph: &Ephemerides,
    sat: SatId,
    t_rx_gpst_ns: i64,
    rx_clock_s: f64,
    site: &Site,
) -> Option<SatGeometry> {
    let receiver_m = &site.position_m;
    if !rx_clock_s.is_finite() || !receiver_m.iter().all(|x| x.is_finite()) {
        return None;
    }
    // A first guess of the light time of a medium Earth orbit; the iteration does the rest.
    let mut tau = 0.075;
    let (mut transmit_m, mut clock_s) = eph.position_clock(sat, t_rx_gpst_ns, -rx_clock_s - tau)?;
    let mut position = sagnac(&transmit_m, tau);
    for _ in 0..MAX_LIGHT_TIME_ITERATIONS {
        let next = (position - receiver_m).norm() / SPEED_OF_LIGHT_M_S;
        let converged = (next - tau).abs() < 1e-12;
        tau = next;
        (transmit_m, clock_s) = eph.position_clock(sat, t_rx_gpst_ns, -rx_clock_s - tau)?;
        position = sagnac(&transmit_m, tau);
        if converged {
            break;
        }
    }
    let d = position - receiver_m;
    let range = d.norm();
    if range.is_nan() || range <= 1.0 {
        return None;
    }
    let los = d / range;
    let (elevation, azimuth) = match &site.horizon {
        Some((_, enu_from_ecef)) => {
            let enu = enu_from_ecef * los;
            (
                enu.z.clamp(-1.0, 1.0).asin(),
                enu.x.atan2(enu.y).rem_euclid(std::f64::consts::TAU),
            )
        }
        None => (f64::NAN, f64::NAN),
    };
    Some(SatGeometry {
        position_m: position,
        clock_s,
        range_m: range,
        los_ecef: los,
        elevation_rad: elevation,
        azimuth_rad: azimuth,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gnss::navdata::{KeplerRecord, NavData};
    use crate::gnss::signal::System;

    /// Closed-form geodetic -> ECEF (the direction this module does not compute).
    fn ecef(lat: f64, lon: f64, h: f64) -> Vector3<f64> {
        let e2 = WGS84_F * (2.0 - WGS84_F);
        let n = WGS84_A_M / (1.0 - e2 * lat.sin().powi(2)).sqrt();
        Vector3::new(
            (n + h) * lat.cos() * lon.cos(),
            (n + h) * lat.cos() * lon.sin(),
            (n * (1.0 - e2) + h) * lat.sin(),
        )
    }

    #[test]
    fn geodetic_inverts_the_closed_form_and_up_is_the_normal() {
        for (lat, lon, h) in [
            (0.0, 0.0, 0.0),
            (0.63, 2.44, 57.3),
            (-1.2, -0.3, 10_000.0),
            (1.55, 1.0, -100.0),
            (0.3, 3.1, 7.0e5),
        ] {
            let (la, lo, hh) = geodetic_from_ecef(&ecef(lat, lon, h));
            assert!(
                (la - lat).abs() < 1e-11 && (lo - lon).abs() < 1e-11,
                "{la} {lo}"
            );
            assert!((hh - h).abs() < 1e-5, "{hh} vs {h}");
            let up = enu_from_ecef(lat, lon).row(2).transpose();
            let normal = Vector3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin());
            assert!((up - normal).norm() < 1e-15);
        }
    }

    #[test]
    fn light_time_and_sagnac_satisfy_their_equations() {
        let t0 = 2138 * 604_800 * 1_000_000_000i64;
        let record = KeplerRecord {
            sat: SatId {
                system: System::Gps,
                prn: 3,
            },
            toc_gpst_ns: t0,
            toe_gpst_ns: t0,
            af: [2e-4, 0.0, 0.0],
            crs: 0.0,
            delta_n: 0.0,
            m0: 0.4,
            cuc: 0.0,
            e: 0.0,
            cus: 0.0,
            sqrt_a: 5153.7,
            cic: 0.0,
            omega0: 2.4,
            cis: 0.0,
            i0: 0.96,
            crc: 0.0,
            omega: 0.0,
            omega_dot: 0.0,
            idot: 0.0,
            health: 0.0,
            tgd_s: [0.0, f64::NAN],
            iode: 1.0,
            accuracy_m: 2.0,
            fit_interval_h: 4.0,
            data_source: f64::NAN,
        };
        let eph = Ephemerides::new(&NavData {
            kepler: vec![record],
            ..NavData::default()
        })
        .unwrap();
        let rx = ecef(0.6, 2.4, 50.0);
        let clock = 1e-3;
        let g = satellite_geometry(&eph, record.sat, t0, clock, &rx).unwrap();
        // tau = range / c; the satellite at t - clock - tau, its frame rotated by omega_E tau about Z.
        let tau = g.range_m / SPEED_OF_LIGHT_M_S;
        let s = eph.state(record.sat, t0, -clock - tau).unwrap();
        let (sn, cs) = (EARTH_ROTATION_RAD_S * tau).sin_cos();
        let p = s.position_m;
        let rotated = Vector3::new(cs * p.x + sn * p.y, -sn * p.x + cs * p.y, p.z);
        assert!((rotated - g.position_m).norm() < 1e-6);
        assert!((g.range_m - (g.position_m - rx).norm()).abs() < 1e-9);
        assert!((g.clock_s - s.clock_s).abs() < 1e-18);
        assert!(g.elevation_rad > 0.0, "{}", g.elevation_rad);
        assert!((g.los_ecef.norm() - 1.0).abs() < 1e-15);
        // From the Earth's centre there is no horizon.
        let c = satellite_geometry(&eph, record.sat, t0, 0.0, &Vector3::zeros()).unwrap();
        assert!(c.elevation_rad.is_nan() && c.azimuth_rad.is_nan());
    }
}
