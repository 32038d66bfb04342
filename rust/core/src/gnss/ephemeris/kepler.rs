//! Keplerian broadcast orbits and clocks of GPS (IS-GPS-200 table 20-IV), Galileo (OS SIS ICD 5.1.1),
//! BeiDou MEO/IGSO and GEO (BDS-SIS-ICD-B1I 3.0, 5.2.4.12) and QZSS (IS-QZSS-PNT, as GPS).

use nalgebra::Vector3;

use super::super::navdata::KeplerRecord;
use super::super::signal::{System, SPEED_OF_LIGHT_M_S};
use super::super::time::{seconds_between, seconds_of_week};

/// Most Newton iterations of Kepler's equation. From the starter of [`eccentric_anomaly`] Newton's
/// method converges for every e in [0, 1) (Danby, "The solution of Kepler's equation III", 1987); it
/// takes under 6 iterations to 1e-15 rad for e <= 0.2 (E14, E18) and under 10 for e <= 0.9
/// (`kepler_solver_*` tests, against bisection).
pub const MAX_KEPLER_ITERATIONS: usize = 30;
/// Newton step below which Kepler's equation is solved, rad (a few ulp of pi).
const KEPLER_TOLERANCE_RAD: f64 = 1e-15;

/// The eccentric anomaly E of mean anomaly `m` (rad) on an ellipse of eccentricity `e` in [0, 1):
/// the root of `E - e sin E = M'` for M' = M reduced to [-pi, pi) (sines and cosines of E are those of
/// the unreduced root; E - M' lies in [-e, e]); `None` when `e` or
/// `m` is outside those domains or not finite, or (never seen) where Newton's method has not converged
/// after [`MAX_KEPLER_ITERATIONS`].
pub fn eccentric_anomaly(m: f64, e: f64) -> Option<f64> {
    if !(m.is_finite() && (0.0..1.0).contains(&e)) {
        return None;
    }
    use std::f64::consts::{PI, TAU};
    // M in [-pi, pi): E then lies in [-pi, pi] too, where Danby's starter M + 0.85 e sign(sin M)
    // keeps Newton's iterates from overshooting for any e < 1.
    let turns = ((m + PI) / TAU).floor();
    let mr = m - turns * TAU;
    let mut ea = mr + 0.85 * e * mr.sin().signum();
    for _ in 0..MAX_KEPLER_ITERATIONS {
        let step = (ea - e * ea.sin() - mr) / (1.0 - e * ea.cos());
        ea -= step;
        if step.abs() < KEPLER_TOLERANCE_RAD {
            return Some(ea);
        }
    }
    None
}

/// Each system's gravitational constant (m^3/s^2) and Earth rotation rate (rad/s) of its ICD.
pub(crate) fn constants(system: System) -> (f64, f64) {
    match system {
        // IS-GPS-200 20.3.3.4.3.1 and IS-QZSS-PNT (same values).
        System::Gps | System::Qzss => (3.986_005e14, 7.292_115_146_7e-5),
        // Galileo OS SIS ICD 5.1.1 (GTRF).
        System::Galileo => (3.986_004_418e14, 7.292_115_146_7e-5),
        // BDS-SIS-ICD 3.2 (CGCS2000).
        System::BeiDou => (3.986_004_418e14, 7.292_115e-5),
        // Not Keplerian; never asked (the record's system is checked by Ephemerides::new).
        System::Glonass => (3.986_004_418e14, 7.292_115e-5),
    }
}

/// BeiDou geostationary satellites: C01-C05 (BDS-2) and C59-C63 (BDS-3), whose broadcast elements are
/// given in an inertial frame tilted by 5 degrees about X (BDS-SIS-ICD 5.2.4.12).
pub(crate) fn is_beidou_geo(record: &KeplerRecord) -> bool {
    record.sat.system == System::BeiDou && (record.sat.prn <= 5 || record.sat.prn >= 59)
}

/// ECEF position (m) and clock (s, polynomial plus the relativistic term, no group delay) of `record` at
/// GPST `t_gpst_ns + offset_s`.
pub(crate) fn position_clock(
    record: &KeplerRecord,
    t_gpst_ns: i64,
    offset_s: f64,
) -> (Vector3<f64>, f64) {
    let system = record.sat.system;
    let (mu, omega_e) = constants(system);
    let tk = seconds_between(t_gpst_ns, record.toe_gpst_ns) + offset_s;
    let a = record.sqrt_a * record.sqrt_a;
    let n = (mu / (a * a * a)).sqrt() + record.delta_n;
    let m = record.m0 + n * tk;
    let e = record.e;
    // NaN where Kepler's equation has no usable root: `Ephemerides::state` then gives None.
    let ea = eccentric_anomaly(m, e).unwrap_or(f64::NAN);
    let (sin_e, cos_e) = ea.sin_cos();
    let nu = ((1.0 - e * e).sqrt() * sin_e).atan2(cos_e - e);
    let phi = nu + record.omega;
    let (s2, c2) = (2.0 * phi).sin_cos();
    let u = phi + record.cus * s2 + record.cuc * c2;
    let r = a * (1.0 - e * cos_e) + record.crs * s2 + record.crc * c2;
    let inc = record.i0 + record.cis * s2 + record.cic * c2 + record.idot * tk;
    let (xp, yp) = (r * u.cos(), r * u.sin());
    let toe_sow = seconds_of_week(system, record.toe_gpst_ns);
    let geo = is_beidou_geo(record);
    // GEO: the ascending node in the tilted inertial frame (no Earth rotation over tk); otherwise the
    // longitude of the node in the Earth-fixed frame.
    let big_omega = if geo {
        record.omega0 + record.omega_dot * tk - omega_e * toe_sow
    } else {
        record.omega0 + (record.omega_dot - omega_e) * tk - omega_e * toe_sow
    };
    let (so, co) = big_omega.sin_cos();
    let (si, ci) = inc.sin_cos();
    let mut p = Vector3::new(xp * co - yp * ci * so, xp * so + yp * ci * co, yp * si);
    if geo {
        // R_z(omega_e tk) R_x(-5 deg).
        let (s5, c5) = (-5f64).to_radians().sin_cos();
        let q = Vector3::new(p.x, c5 * p.y + s5 * p.z, -s5 * p.y + c5 * p.z);
        let (sz, cz) = (omega_e * tk).sin_cos();
        p = Vector3::new(cz * q.x + sz * q.y, -sz * q.x + cz * q.y, q.z);
    }
    let tc = seconds_between(t_gpst_ns, record.toc_gpst_ns) + offset_s;
    let f_rel = -2.0 * mu.sqrt() / (SPEED_OF_LIGHT_M_S * SPEED_OF_LIGHT_M_S);
    let clock = record.af[0]
        + record.af[1] * tc
        + record.af[2] * tc * tc
        + f_rel * e * record.sqrt_a * sin_e;
    (p, clock)
}
