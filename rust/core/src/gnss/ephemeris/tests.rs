//! Record choice, health, group delays and record checks against the ICD rules they implement.

use super::*;
use crate::gnss::time::{NS_PER_S, WEEK_NS};

const T0: i64 = 2138 * WEEK_NS + 432_000 * NS_PER_S;

fn record(system: System, prn: u8, toe_offset_s: i64) -> KeplerRecord {
    KeplerRecord {
        sat: SatId { system, prn },
        toc_gpst_ns: T0 + toe_offset_s * NS_PER_S,
        toe_gpst_ns: T0 + toe_offset_s * NS_PER_S,
        af: [1e-4, 0.0, 0.0],
        crs: 0.0,
        delta_n: 0.0,
        m0: 0.1,
        cuc: 0.0,
        e: 0.0,
        cus: 0.0,
        sqrt_a: 5153.7,
        cic: 0.0,
        omega0: 1.0,
        cis: 0.0,
        i0: 0.96,
        crc: 0.0,
        omega: 0.2,
        omega_dot: 0.0,
        idot: 0.0,
        health: 0.0,
        tgd_s: [-4e-9, 2e-9],
        iode: 1.0,
        accuracy_m: 2.0,
        fit_interval_h: 4.0,
        data_source: f64::NAN,
    }
}

fn nav(kepler: Vec<KeplerRecord>) -> NavData {
    NavData {
        kepler,
        ..NavData::default()
    }
}

#[test]
fn nearest_healthy_record_within_its_interval() {
    let mut sick = record(System::Gps, 1, 3600);
    sick.health = 1.0;
    sick.af[0] = 3e-4;
    let mut late = record(System::Gps, 1, 7200);
    late.af[0] = 2e-4;
    let eph = Ephemerides::new(&nav(vec![late, record(System::Gps, 1, 0), sick])).unwrap();
    let sat = SatId {
        system: System::Gps,
        prn: 1,
    };
    let clock_at = |s: i64| eph.state(sat, T0 + s * NS_PER_S, 0.0).map(|x| x.clock_s);
    // Nearest usable record: the unhealthy one at +1 h is never chosen.
    assert_eq!(clock_at(3500), Some(1e-4));
    assert_eq!(clock_at(3700), Some(2e-4));
    // Beyond both intervals (fit 4 h: +-2 h around each toe).
    assert_eq!(clock_at(-7201), None);
    assert_eq!(clock_at(14_401), None);
    assert!(eph.has(sat));
    assert!(!eph.has(SatId {
        system: System::Gps,
        prn: 2
    }));
}

#[test]
fn galileo_prefers_inav_at_the_same_toe() {
    let mut fnav = record(System::Galileo, 3, 0);
    fnav.data_source = 258.0;
    fnav.af[0] = 5e-4;
    let mut inav = record(System::Galileo, 3, 0);
    inav.data_source = 517.0;
    let sat = inav.sat;
    for records in [vec![fnav, inav], vec![inav, fnav]] {
        let eph = Ephemerides::new(&nav(records)).unwrap();
        assert_eq!(eph.state(sat, T0, 0.0).map(|s| s.clock_s), Some(1e-4));
    }
}

#[test]
fn group_delays_per_slot() {
    let eph = Ephemerides::new(&nav(vec![
        record(System::Gps, 1, 0),
        record(System::Galileo, 2, 0),
        record(System::BeiDou, 9, 0),
    ]))
    .unwrap();
    let gd = |system, prn, slot| eph.group_delay_s(SatId { system, prn }, slot, T0);
    // IS-GPS-200 20.3.3.3.3.2: L1 -TGD, L2 -gamma TGD with gamma = (77/60)^2.
    assert_eq!(gd(System::Gps, 1, 0), 4e-9);
    assert!((gd(System::Gps, 1, 1) - (77.0f64 / 60.0).powi(2) * 4e-9).abs() < 1e-21);
    // Galileo E1 with the I/NAV pair: -BGD(E1,E5b); E5a: -(f_E1/f_E5a)^2 BGD(E1,E5a) = -(154/115)^2 BGD.
    assert_eq!(gd(System::Galileo, 2, 0), -2e-9);
    assert!((gd(System::Galileo, 2, 2) - (154.0f64 / 115.0).powi(2) * 4e-9).abs() < 1e-21);
    // BeiDou: B1I -TGD1, B2I -TGD2, B3I 0 (the broadcast clock's reference).
    assert_eq!(gd(System::BeiDou, 9, 0), 4e-9);
    assert_eq!(gd(System::BeiDou, 9, 1), -2e-9);
    assert_eq!(gd(System::BeiDou, 9, 2), 0.0);
    // No record: 0.
    assert_eq!(gd(System::Gps, 5, 0), 0.0);
}

#[test]
fn records_are_checked() {
    let mut r = record(System::Gps, 1, 0);
    r.e = f64::NAN;
    let err = Ephemerides::new(&nav(vec![r])).unwrap_err();
    assert!(err
        .to_string()
        .contains("Keplerian record 0 (G01): expected a finite e"));
    let mut r = record(System::Gps, 1, 0);
    r.health = 0.5;
    assert!(Ephemerides::new(&nav(vec![r])).is_err());
    let mut r = record(System::Gps, 1, 0);
    r.sat.system = System::Glonass;
    assert!(Ephemerides::new(&nav(vec![r])).is_err());
}

#[test]
fn beidou_validity_and_qzss_interval() {
    let eph = Ephemerides::new(&nav(vec![
        record(System::BeiDou, 20, 0),
        record(System::Qzss, 1, 0),
    ]))
    .unwrap();
    let ok = |system, prn, s: i64| {
        eph.state(SatId { system, prn }, T0 + s * NS_PER_S, 0.0)
            .is_some()
    };
    assert!(ok(System::BeiDou, 20, 21_600) && !ok(System::BeiDou, 20, 21_601));
    assert!(ok(System::Qzss, 1, 3600) && !ok(System::Qzss, 1, 3601));
}

#[test]
fn circular_orbit_velocity_closed_form() {
    // e = 0: in inertial axes the speed is n a; the ECEF velocity adds -omega_E x r.
    let r = record(System::Gps, 1, 0);
    let eph = Ephemerides::new(&nav(vec![r])).unwrap();
    let s = eph.state(r.sat, T0 + 1000 * NS_PER_S, 0.25).unwrap();
    let a = r.sqrt_a * r.sqrt_a;
    let n = (3.986_005e14 / (a * a * a)).sqrt();
    let omega = Vector3::new(0.0, 0.0, 7.292_115_146_7e-5);
    let inertial = s.velocity_m_s + omega.cross(&s.position_m);
    assert!((s.position_m.norm() - a).abs() < 1e-6);
    // Forward difference over 1 ms: n^2 a h / 2 = 3e-4 m/s of truncation.
    assert!(
        (inertial.norm() - n * a).abs() < 1e-3,
        "{}",
        inertial.norm() - n * a
    );
    assert!(s.clock_drift_s_s.abs() < 1e-15);
}
