use nalgebra::{Matrix3, Matrix6, UnitQuaternion, Vector3};

use super::kinematics::{propagate, skew, unit};
use super::*;
use crate::error::Error;

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
            ratio_threshold: 3.0,
            min_success_rate: 0.999,
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
