use nalgebra::{Matrix6, Vector3, Vector6};

use super::*;
use crate::error::Error;

fn two_body() -> GlonassModel {
    GlonassModel {
        j2: 0.0,
        omega_rad_s: 0.0,
        ..GlonassModel::pz90()
    }
}

/// A GLONASS-like state (the ICD appendix J input) in m, m/s.
const ICD_STATE: [f64; 6] = [
    7003.008789e3,
    -12206.626953e3,
    21280.765625e3,
    0.7835417e3,
    2.8042530e3,
    1.3525150e3,
];

#[test]
fn circular_orbit_closes_after_one_period() {
    // Inertial axes, central field: a circular orbit of radius a returns after 2 pi sqrt(a^3 / GM).
    let m = two_body();
    let a: f64 = 7_000_000.0;
    let v = (m.gm_m3_s2 / a).sqrt();
    let s0 = [a, 0.0, 0.0, 0.0, v * 0.6, v * 0.8];
    let period = 2.0 * std::f64::consts::PI * (a.powi(3) / m.gm_m3_s2).sqrt();
    let s1 = propagate(&m, &s0, period, 2.0).unwrap();
    // RK4's phase error per revolution on a circular orbit is 2 pi (n h)^4 / 120 rad (the first neglected
    // Taylor term of exp(i n h)): 5e-5 m with h = 2 s; 1 mm leaves room for round-off.
    for i in 0..3 {
        assert!((s1[i] - s0[i]).abs() < 1e-3, "{i}: {} vs {}", s1[i], s0[i]);
    }
    // Half a period: the antipode.
    let s_half = propagate(&m, &s0, 0.5 * period, 2.0).unwrap();
    assert!((s_half[0] + a).abs() < 1e-3);
}

fn jacobi_integral(m: &GlonassModel, s: &[f64; 6]) -> f64 {
    // Energy in the rotating frame with the J2 potential: v^2/2 - w^2 (x^2 + y^2)/2 + U, with
    // U = -mu/r + (mu J2 ae^2 / (2 r^3)) (3 z^2 / r^2 - 1); constant for a time-invariant field.
    let r = Vector3::new(s[0], s[1], s[2]);
    let v = Vector3::new(s[3], s[4], s[5]);
    let rn = r.norm();
    let u = -m.gm_m3_s2 / rn
        + m.gm_m3_s2 * m.j2 * m.equatorial_radius_m.powi(2) / (2.0 * rn.powi(3))
            * (3.0 * r.z * r.z / (rn * rn) - 1.0);
    0.5 * v.norm_squared() - 0.5 * m.omega_rad_s.powi(2) * (r.x * r.x + r.y * r.y) + u
}

#[test]
fn energy_and_jacobi_integral_are_conserved() {
    for m in [two_body(), GlonassModel::pz90()] {
        let e0 = jacobi_integral(&m, &ICD_STATE);
        let s1 = propagate(&m, &ICD_STATE, 6.0 * 3600.0, 30.0).unwrap();
        let e1 = jacobi_integral(&m, &s1);
        // |E| ~ 8e6 m^2/s^2; RK4 with 30 s steps on a 11 h orbit conserves it to well below 1e-9 relative.
        assert!(((e1 - e0) / e0).abs() < 1e-9, "{e0} -> {e1}");
    }
}

#[test]
fn jacobian_matches_central_differences() {
    let m = GlonassModel::pz90();
    let x = Vector6::from_column_slice(&ICD_STATE);
    let f = m.jacobian(&x.fixed_rows::<3>(0).into_owned());
    for j in 0..6 {
        let h = if j < 3 { 10.0 } else { 0.01 };
        let mut xp = x;
        let mut xm = x;
        xp[j] += h;
        xm[j] -= h;
        let ap = m.acceleration(&xp.fixed_rows::<3>(0).into(), &xp.fixed_rows::<3>(3).into());
        let am = m.acceleration(&xm.fixed_rows::<3>(0).into(), &xm.fixed_rows::<3>(3).into());
        let d = (ap - am) / (2.0 * h);
        for i in 0..3 {
            // Central differences are exact to O(h^2 a''') ~ 1e-15 here; compare to 1e-6 relative.
            let scale = f.fixed_view::<3, 6>(3, 0).abs().max();
            assert!((f[(3 + i, j)] - d[i]).abs() < 1e-6 * scale, "({i}, {j})");
        }
    }
}

#[test]
fn stm_matches_finite_differences_of_the_propagator() {
    let m = GlonassModel::pz90();
    let (_, phi) = propagate_with_stm(&m, &ICD_STATE, 600.0, 10.0).unwrap();
    let mut num = Matrix6::zeros();
    for j in 0..6 {
        let h = if j < 3 { 1.0 } else { 1e-3 };
        let mut sp = ICD_STATE;
        let mut sm = ICD_STATE;
        sp[j] += h;
        sm[j] -= h;
        let yp = propagate(&m, &sp, 600.0, 10.0).unwrap();
        let ym = propagate(&m, &sm, 600.0, 10.0).unwrap();
        for i in 0..6 {
            num[(i, j)] = (yp[i] - ym[i]) / (2.0 * h);
        }
    }
    // Second-order Taylor remainder over 600 s of a MEO orbit is ~1e-9 of the entries; allow 1e-6.
    let err = (phi - num).abs().max();
    assert!(err < 1e-6 * num.abs().max(), "max |Phi - numeric| = {err}");
}

#[test]
fn circular_orbit_state_is_consistent() {
    let o = CircularOrbit {
        radius_m: 6_978_137.0,
        inclination_rad: 1.7,
        raan_rad: 0.3,
        arg_latitude0_rad: 1.1,
        gm_m3_s2: 3.986004418e14,
    };
    let (r, v) = o.state_eci(123.0);
    assert!((r.norm() - o.radius_m).abs() < 1e-6);
    assert!(r.dot(&v).abs() < 1e-3);
    // The velocity is the derivative of the position.
    let (r1, _) = o.state_eci(123.001);
    let (r0, _) = o.state_eci(122.999);
    assert!(((r1 - r0) / 0.002 - v).norm() < 1e-3);
    // ECEF velocity is the derivative of the ECEF position.
    let w = 7.2921151467e-5;
    let (_, ve) = o.state_ecef(123.0, 0.4, w);
    let (re1, _) = o.state_ecef(123.001, 0.4, w);
    let (re0, _) = o.state_ecef(122.999, 0.4, w);
    assert!(((re1 - re0) / 0.002 - ve).norm() < 1e-3);
}

#[test]
fn bad_durations_and_states_are_errors() {
    let m = GlonassModel::pz90();
    assert!(matches!(
        propagate(&m, &ICD_STATE, -1.0, 1.0),
        Err(Error::OutOfRange {
            name: "duration_s",
            ..
        })
    ));
    assert!(matches!(
        propagate(&m, &ICD_STATE, 10.0, 20.0),
        Err(Error::OutOfRange { name: "step_s", .. })
    ));
    let mut bad = ICD_STATE;
    bad[4] = f64::NAN;
    assert!(matches!(
        propagate(&m, &bad, 10.0, 1.0),
        Err(Error::NonFinite { index: 4, .. })
    ));
    assert_eq!(propagate(&m, &ICD_STATE, 0.0, 1.0).unwrap(), ICD_STATE);
}

#[test]
fn work_beyond_the_step_limit_is_refused_before_it_starts() {
    let m = GlonassModel::pz90();
    // 1e9 steps of 1e-6 s (the call used to take minutes without a way to stop it).
    match propagate_with_stm(&m, &ICD_STATE, 1000.0, 1e-6) {
        Err(Error::TooLarge {
            name: "step_s",
            requested,
            limit,
            ..
        }) => assert!(requested == 1e9 && limit == MAX_RK4_STEPS),
        other => panic!("{other:?}"),
    }
}

#[test]
fn states_that_are_not_orbits_are_refused_with_their_numbers() {
    let m = GlonassModel::pz90();
    let mut fast = ICD_STATE;
    fast[3] = 1e7;
    match propagate(&m, &fast, 10.0, 1.0) {
        Err(Error::OutOfRange {
            name: "velocity_m_s",
            detail,
        }) => assert!(
            detail.contains("escape") && detail.contains("1.000"),
            "{detail}"
        ),
        other => panic!("{other:?}"),
    }
    let inside = [1e6, 0.0, 0.0, 0.0, 1000.0, 0.0];
    assert!(matches!(
        propagate(&m, &inside, 10.0, 1.0),
        Err(Error::OutOfRange {
            name: "position_m",
            ..
        })
    ));
}

#[test]
fn a_trajectory_that_meets_the_earth_stops_with_an_error() {
    let m = GlonassModel::pz90();
    // 300 km up, falling at 7 km/s: the surface is reached after about 40 s.
    let falling = [6_678_137.0, 0.0, 0.0, -7000.0, 0.0, 0.0];
    match propagate_with_stm(&m, &falling, 600.0, 1.0) {
        Err(Error::Numerical { detail, .. }) => {
            assert!(detail.contains("below the Earth's surface"), "{detail}")
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn orbit_filter_refuses_too_many_prediction_steps_and_satellites() {
    let cfg = FilterConfig {
        model: GlonassModel::pz90(),
        accel_psd_m2_s3: 1e-6,
        step_s: 1e-3,
    };
    let t = [0.0, 1e4];
    let pos = [[0.0; 3]; 2];
    let cov = [Matrix6::identity(); 2];
    let fixes = Fixes {
        position_m: &pos,
        velocity_m_s: &pos,
        covariance: &cov,
        valid: &[true, true],
    };
    let p0 = Matrix6::identity();
    match run_filter(&cfg, &t, &ICD_STATE, &p0, &Corrections::Loose(fixes)) {
        Err(Error::TooLarge {
            name: "step_s",
            requested,
            ..
        }) => assert_eq!(requested, 1e7), // 1e4 s in steps of 1e-3 s
        other => panic!("{other:?}"),
    }
    let n_sat = MAX_SATELLITES + 1;
    let sats = vec![[0.0; 3]; n_sat];
    let ranges = Ranges {
        n_sat,
        sat_position_m: &sats,
        sat_velocity_m_s: &sats,
        pseudorange_m: &vec![0.0; n_sat],
        doppler_hz: &vec![0.0; n_sat],
        visible: &vec![false; n_sat],
        wavelength_m: &vec![0.19; n_sat],
        system: &vec![0; n_sat],
        code_sigma_m: 1.0,
        doppler_sigma_hz: 0.0,
    };
    let cfg = FilterConfig {
        step_s: 10.0,
        ..cfg
    };
    assert!(matches!(
        run_filter(&cfg, &[0.0], &ICD_STATE, &p0, &Corrections::Tight(ranges)),
        Err(Error::TooLarge { name: "data", .. })
    ));
}
