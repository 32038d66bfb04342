//! The single-difference range model of one signal, shared by the float solution and the check of held
//! integers: rover minus base of (geometric range - c * satellite clock + slant troposphere).
//!
//! The troposphere is the standard atmosphere's (Saastamoinen zenith delays, Niell mapping with the annual
//! mean coefficients: [`troposphere_delay_m`]) at each antenna's own height and elevation. It does not
//! cancel between antennas at different heights (about 0.3 mm of zenith delay per metre of height, times
//! the mapping function: 8 mm at 10 degrees for GEONET 0759 -> 3040, 4.6 m apart in height), and RTKLIB
//! models the same delay at both receivers. The rover's height is that of the current baseline estimate,
//! not of its code solution, whose metres of height error would put the same millimetres back; the
//! delay's height derivative (a central difference over [`HEIGHT_STEP_M`]) enters the rover's partials, so
//! that conditioning on fixed integers and re-solving with them held agree.
use nalgebra::Vector3;

use super::SignalPair;
use crate::gnss::atmosphere::troposphere_delay_m;
use crate::gnss::geometry::geodetic_from_ecef;
use crate::gnss::signal::SPEED_OF_LIGHT_M_S;

/// Height step of the troposphere's numerical derivative, m (the delay is smooth over kilometres).
pub const HEIGHT_STEP_M: f64 = 1.0;

/// The two antennas of a single difference, with their geodetic latitude and height.
#[derive(Debug, Clone, Copy)]
pub struct SdRangeModel {
    base_m: Vector3<f64>,
    rover_m: Vector3<f64>,
    /// Latitude (rad) and ellipsoidal height (m) of the base and of the rover.
    base_lat_h: (f64, f64),
    rover_lat_h: (f64, f64),
    /// Local vertical at the rover (ECEF unit vector).
    rover_up: Vector3<f64>,
}

impl SdRangeModel {
    /// The model for antennas at `base_m` and `rover_m` (ECEF, m).
    pub fn new(base_m: &Vector3<f64>, rover_m: &Vector3<f64>) -> SdRangeModel {
        let (lat_b, _, h_b) = geodetic_from_ecef(base_m);
        let (lat_r, lon_r, h_r) = geodetic_from_ecef(rover_m);
        SdRangeModel {
            base_m: *base_m,
            rover_m: *rover_m,
            base_lat_h: (lat_b, h_b),
            rover_lat_h: (lat_r, h_r),
            rover_up: Vector3::new(
                lat_r.cos() * lon_r.cos(),
                lat_r.cos() * lon_r.sin(),
                lat_r.sin(),
            ),
        }
    }

    /// Modelled single difference of `s` (rover minus base), m, and minus its gradient with respect to
    /// the rover's position (ECEF): the unit line of sight rover -> satellite less the troposphere's
    /// height derivative along the vertical.
    pub fn range_and_los(&self, s: &SignalPair) -> (f64, Vector3<f64>) {
        let to_rover = s.rover.position_m - self.rover_m;
        let r_rover = to_rover.norm();
        let (lat, h) = self.rover_lat_h;
        let el = s.rover.elevation_rad;
        let tropo = |h: f64| troposphere_delay_m(lat, h, el);
        let d_tropo_dh =
            (tropo(h + HEIGHT_STEP_M) - tropo(h - HEIGHT_STEP_M)) / (2.0 * HEIGHT_STEP_M);
        let rover = r_rover - SPEED_OF_LIGHT_M_S * s.rover.clock_s + tropo(h);
        let base = (s.base.position_m - self.base_m).norm() - SPEED_OF_LIGHT_M_S * s.base.clock_s
            + troposphere_delay_m(self.base_lat_h.0, self.base_lat_h.1, s.base.elevation_rad);
        (
            rover - base,
            to_rover / r_rover - d_tropo_dh * self.rover_up,
        )
    }

    /// Modelled single difference of `s`, m.
    pub fn range_m(&self, s: &SignalPair) -> f64 {
        self.range_and_los(s).0
    }
}
