use nalgebra::{Matrix3, Matrix6, UnitQuaternion, Vector3};

use super::kinematics::{propagate, skew, unit, MAX_ANGLE_PER_SAMPLE_RAD};
use super::*;
use crate::error::Error;
use crate::lambda::gate::Gate;

fn settings(baselines: Vec<Vector3<f64>>) -> Settings {
    Settings {
        noise: GyroNoise {
            arw: 1e-5,
            rrw: 0.0,
        },
        baselines,
        phase_sigma: 0.01,
        fix: FixSettings {
            enabled: true,
            gate: Gate {
                min_success_rate: 0.999,
                ratio_threshold: 3.0,
                max_failure_rate: 0.0,
            },
        },
        slip_threshold: 30.0,
        known_ambiguities: false,
        sensitivity: None,
        misalignment_sigma: None,
        output_every: 1,
    }
}

fn initial() -> Initial {
    Initial {
        quaternion: [0.0, 0.0, 0.0, 1.0],
        drift: Vector3::zeros(),
        covariance: Matrix6::identity() * 1e-4,
    }
}

/// Constant rate: the step is exact, so many small steps land on the closed form `exp(omega t)`.
#[test]
fn constant_rate_matches_closed_form() {
    let w = Vector3::new(0.01, -0.02, 0.03);
    let t: Vec<f64> = (0..=1000).map(|k| 0.1 * k as f64).collect();
    let rates = vec![w; t.len()];
    let q0 = [0.1, 0.2, 0.3, 0.9];
    let q = propagate(q0, &t, &rates).unwrap();
    let start = unit("q0", q0).unwrap();
    let closed = start * UnitQuaternion::from_scaled_axis(w * 100.0);
    let last = unit("q", q[1000]).unwrap();
    assert!(last.angle_to(&closed) < 1e-12);
}

/// Poisson's equation `dR/dt = R [omega x]` by central differences of the propagated attitude.
#[test]
fn propagation_satisfies_poisson_equation() {
    let w = Vector3::new(0.2, 0.1, -0.3);
    let h = 1e-4;
    let q = propagate([0.3, -0.1, 0.2, 0.9], &[0.0, h, 2.0 * h], &[w, w, w]).unwrap();
    let r = |k: usize| unit("q", q[k]).unwrap().to_rotation_matrix().into_inner();
    let derivative = (r(2) - r(0)) / (2.0 * h);
    assert!((derivative - r(1) * skew(&w)).norm() < 1e-7);
}

#[test]
fn non_increasing_times_and_non_finite_rates_are_rejected() {
    let w = vec![Vector3::zeros(); 3];
    let err = propagate([0.0, 0.0, 0.0, 1.0], &[0.0, 1.0, 1.0], &w).unwrap_err();
    assert!(matches!(err, Error::OutOfRange { name: "t", .. }), "{err}");
    let mut bad = w.clone();
    bad[1].y = f64::NAN;
    let err = propagate([0.0, 0.0, 0.0, 1.0], &[0.0, 1.0, 2.0], &bad).unwrap_err();
    assert_eq!(
        err,
        Error::NonFinite {
            name: "rates",
            index: 4
        }
    );
}

#[test]
fn zero_length_baseline_is_rejected() {
    let s = settings(vec![Vector3::new(1.0, 0.0, 0.0), Vector3::zeros()]);
    let t = [0.0, 1.0];
    let err = run(&s, &initial(), &t, &[Vector3::zeros(); 2], &[], &[]).unwrap_err();
    assert!(err.to_string().contains("baseline 1 has length"), "{err}");
}

#[test]
fn measurements_outside_the_gyro_record_are_rejected() {
    let s = settings(vec![Vector3::new(1.0, 0.0, 0.0)]);
    let fix = AttitudeFix {
        t: 5.0,
        quaternion: [0.0, 0.0, 0.0, 1.0],
        covariance: Matrix3::identity(),
    };
    let err = run(
        &s,
        &initial(),
        &[0.0, 1.0],
        &[Vector3::zeros(); 2],
        &[fix],
        &[],
    )
    .unwrap_err();
    assert!(err.to_string().contains("within the gyro record"), "{err}");
}

/// Without measurements the attitude covariance grows as the closed form for a static body:
/// `P_theta(t) = P0 + P_drift t^2 + arw^2 t` (no rotation couples the axes).
#[test]
fn gyro_only_covariance_matches_closed_form() {
    let s = settings(vec![Vector3::new(1.0, 0.0, 0.0)]);
    let t: Vec<f64> = (0..=100).map(|k| k as f64).collect();
    let out = run(
        &s,
        &initial(),
        &t,
        &vec![Vector3::zeros(); t.len()],
        &[],
        &[],
    )
    .unwrap();
    let p = out.covariance.last().unwrap();
    let expected = 1e-4 + 1e-4 * 100.0f64.powi(2) + 1e-10 * 100.0;
    assert!((p[(0, 0)] - expected).abs() < 1e-12 * expected.max(1.0));
    assert!((p[(0, 3)] - 1e-4 * 100.0).abs() < 1e-12);
}

#[test]
fn a_rate_that_turns_beyond_the_limit_per_sample_is_refused() {
    let t = [0.0, 1.0, 2.0];
    let mut w = vec![Vector3::zeros(); 3];
    // 1e200 rad/s: its angle per sample overflowed the quaternion exponential into NaN before.
    w[1] = Vector3::new(1e200, 1e200, 0.0);
    match propagate([0.0, 0.0, 0.0, 1.0], &t, &w) {
        Err(Error::OutOfRange {
            name: "rates",
            detail,
        }) => assert!(
            detail.contains("rates[1]") && detail.contains("1.414e200"),
            "{detail}"
        ),
        other => panic!("{other:?}"),
    }
    // At the limit the step is still the exact rotation: 1e6 rad about z is 1e6 mod 2 pi.
    let w = vec![Vector3::new(0.0, 0.0, MAX_ANGLE_PER_SAMPLE_RAD); 2];
    let q = propagate([0.0, 0.0, 0.0, 1.0], &[0.0, 1.0], &w).unwrap()[1];
    let angle = 2.0 * q[2].atan2(q[3]);
    let expected = MAX_ANGLE_PER_SAMPLE_RAD.rem_euclid(2.0 * std::f64::consts::PI);
    let diff = (angle - expected).rem_euclid(2.0 * std::f64::consts::PI);
    assert!(
        diff.min(2.0 * std::f64::consts::PI - diff) < 1e-9,
        "{angle} {expected}"
    );
}

#[test]
fn filter_work_beyond_the_limits_is_refused_before_it_starts() {
    let s = settings(vec![Vector3::new(1.0, 0.0, 0.0)]);
    // Samples: the count is refused before the (here invalid) time stamps are even read.
    let n = MAX_FILTER_SAMPLES as usize + 1;
    let err = run(
        &s,
        &initial(),
        &vec![0.0; n],
        &vec![Vector3::zeros(); n],
        &[],
        &[],
    )
    .unwrap_err();
    assert!(
        matches!(err, Error::TooLarge { name: "gyro_t", .. }),
        "{err}"
    );
    // States: one baseline and 600 satellites at one epoch, 606 error states.
    let obs = (0..600)
        .map(|j| PhaseObs {
            track: j,
            los: Vector3::z(),
            wavelength: 0.19,
            phase: vec![0.0],
        })
        .collect();
    let epochs = [PhaseEpoch { t: 0.5, obs }];
    let err = run(
        &s,
        &initial(),
        &[0.0, 1.0],
        &[Vector3::zeros(); 2],
        &[],
        &epochs,
    )
    .unwrap_err();
    match err {
        Error::TooLarge {
            name: "phases",
            requested,
            ..
        } => assert_eq!(requested, 606.0),
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_covariance_that_overflows_is_an_error_not_an_infinite_output() {
    let s = settings(vec![Vector3::new(1.0, 0.0, 0.0)]);
    let mut init = initial();
    // Drift variance 1e300 (rad/s)^2 grows the attitude variance as 1e300 t^2: infinite after 1e4 s.
    init.covariance = Matrix6::identity() * 1e300;
    let t = [0.0, 1e3, 1e5];
    match run(&s, &init, &t, &[Vector3::zeros(); 3], &[], &[]) {
        Err(Error::Numerical { .. }) | Err(Error::DegenerateGeometry { .. }) => {}
        other => panic!("{other:?}"),
    }
}
