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
fn unusable_records_are_skipped_and_named() {
    let good = record(System::Gps, 2, 0);
    let mut nan = record(System::Gps, 1, 0);
    nan.e = f64::NAN;
    let mut hyperbola = record(System::Gps, 3, 0);
    hyperbola.e = 1.0;
    let mut inside = record(System::BeiDou, 16, 0);
    // A BeiDou C16 record of a real file: sqrt(A) 1992, e 0.49, perigee 2e6 m (inside the Earth).
    inside.sqrt_a = 1992.0;
    inside.e = 0.49;
    let mut health = record(System::Gps, 4, 0);
    health.health = 0.5;
    let eph = Ephemerides::new(&nav(vec![nan, good, hyperbola, inside, health])).unwrap();
    let reasons: Vec<(usize, SkipReason)> =
        eph.skipped().iter().map(|s| (s.index, s.reason)).collect();
    assert_eq!(
        reasons,
        vec![
            (0, SkipReason::NotFinite),
            (2, SkipReason::NotAnEllipse),
            (3, SkipReason::NotASatellite),
            (4, SkipReason::HealthWord)
        ]
    );
    assert!(eph.state(good.sat, T0, 0.0).is_some());
    assert!(eph.state(nan.sat, T0, 0.0).is_none() && !eph.has(nan.sat));
    let w = eph.skip_warnings();
    assert_eq!(w.len(), 4);
    assert!(w[0].starts_with("1 navigation record(s) skipped, a value that is not finite"));
    assert!(w[0].contains("Keplerian record 0 (G01): e NaN"), "{}", w[0]);
    assert!(w[2].contains("record 3 (C16)"), "{}", w[2]);
    // A record in the wrong table is the caller's defect: refused.
    let mut r = record(System::Gps, 1, 0);
    r.sat.system = System::Glonass;
    assert!(Ephemerides::new(&nav(vec![r])).is_err());
}

/// Root of E - e sin E = m on [-pi, pi] by bisection (E - e sin E is increasing there).
fn bisection_root(m: f64, e: f64) -> f64 {
    let (mut lo, mut hi) = (-std::f64::consts::PI, std::f64::consts::PI);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid - e * mid.sin() - m < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn kepler_solver_matches_bisection_up_to_high_eccentricity() {
    use std::f64::consts::{PI, TAU};
    for &e in &[
        0.0, 0.01, 0.1, 0.1639, 0.17, 0.3, 0.5, 0.7, 0.9, 0.97, 0.999,
    ] {
        for k in 0..=2000 {
            let m = -PI + TAU * f64::from(k) / 2000.0;
            for turns in [0.0, 3.0, -2.0] {
                let ea = kepler::eccentric_anomaly(m + turns * TAU, e)
                    .unwrap_or_else(|| panic!("no convergence at e {e}, m {m}"));
                // m = pi maps onto -pi: compare on the circle.
                let want = bisection_root(if m >= PI { m - TAU } else { m }, e);
                let d = (ea - want + PI).rem_euclid(TAU) - PI;
                assert!(d.abs() < 1e-12, "e {e} m {m}: {ea} vs {want}");
            }
        }
    }
    assert_eq!(kepler::eccentric_anomaly(0.3, 1.0), None);
    assert_eq!(kepler::eccentric_anomaly(f64::NAN, 0.1), None);
}

#[test]
fn kepler_solver_iterations_up_to_high_eccentricity() {
    // Count Newton steps from the same starter: the bound MAX_KEPLER_ITERATIONS documents.
    use std::f64::consts::{PI, TAU};
    let steps = |m: f64, e: f64| {
        let mut ea = m + 0.85 * e * m.sin().signum();
        for n in 1..=100 {
            let step = (ea - e * ea.sin() - m) / (1.0 - e * ea.cos());
            ea -= step;
            if step.abs() < 1e-15 {
                return n;
            }
        }
        100
    };
    for (e, most) in [(0.2, 6), (0.9, 10)] {
        let worst = (0..2000)
            .map(|k| steps(-PI + TAU * f64::from(k) / 2000.0, e))
            .max()
            .unwrap();
        assert!(worst <= most, "e {e}: {worst} steps");
    }
}

#[test]
fn eccentric_orbit_radius_and_clock_closed_form() {
    // Galileo E18-like orbit (e 0.1639, no harmonics): r = a (1 - e cos E) at the solved E, and the
    // relativistic clock term -2 sqrt(mu) e sqrt(A) sin E / c^2 of the OS SIS ICD 5.1.4.
    let mut r = record(System::Galileo, 18, 0);
    r.e = 0.1639;
    r.sqrt_a = 5289.9;
    r.m0 = 2.0;
    r.af = [0.0; 3];
    let eph = Ephemerides::new(&nav(vec![r])).unwrap();
    assert!(eph.skipped().is_empty());
    let mu = 3.986_004_418e14;
    let a = r.sqrt_a * r.sqrt_a;
    let n = (mu / (a * a * a)).sqrt();
    for t in [0i64, 1800, 7200] {
        let s = eph.state(r.sat, T0 + t * NS_PER_S, 0.0).unwrap();
        let m = r.m0 + n * t as f64;
        let ea = bisection_root(
            m - std::f64::consts::TAU
                * ((m + std::f64::consts::PI) / std::f64::consts::TAU).floor(),
            r.e,
        );
        let radius = a * (1.0 - r.e * ea.cos());
        assert!((s.position_m.norm() - radius).abs() < 1e-6, "{t}");
        let rel = -2.0 * mu.sqrt() * r.e * r.sqrt_a * ea.sin() / (299_792_458.0f64).powi(2);
        assert!((s.clock_s - rel).abs() < 1e-18, "{t}");
    }
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

#[test]
fn the_bounded_record_choice_is_the_scan_of_every_record() {
    // Records (reference time, healthy, rank) sorted by time with repeats, unhealthy ones, equal ages on
    // both sides and ranks that break ties; the choice of `nearest` against the first minimum of
    // (age, rank) over every usable record, at times before, between, on and after the records.
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(30);
    for trial in 0..400 {
        let n = rng.random_range(0..12usize);
        let mut records: Vec<(i64, bool, u8, usize)> = (0..n)
            .map(|i| {
                let t = rng.random_range(0..8i64) * 900 * NS_PER_S;
                (t, rng.random_bool(0.7), rng.random_range(0..2u8), i)
            })
            .collect();
        records.sort_by_key(|r| r.0);
        let max_age_s = [1000.0, 2000.0, 1e9][trial % 3];
        let usable = |r: &(i64, bool, u8, usize), age: f64| r.1 && age <= max_age_s;
        for step in -2..20i64 {
            let t = step * 450 * NS_PER_S;
            let got = nearest(&records, t, |r| r.0, usable, |r| r.2).map(|r| r.3);
            let want = records
                .iter()
                .filter_map(|r| {
                    let age = seconds_between(t, r.0).abs();
                    usable(r, age).then_some((age, r.2, r.3))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
                .map(|r| r.2);
            assert_eq!(got, want, "trial {trial}, t {t}, {records:?}");
        }
    }
}
