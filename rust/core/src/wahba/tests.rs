use nalgebra::{Matrix3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::*;
use crate::error::Error;
use crate::rotation::euler::ZYX;

const METHODS: [Method; 3] = [Method::Svd, Method::Davenport, Method::Quest];

fn random_unit(rng: &mut ChaCha8Rng) -> Vector3<f64> {
    loop {
        let v = Vector3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        if v.norm() > 0.1 && v.norm() < 1.0 {
            return v.normalize();
        }
    }
}

fn random_rotation(rng: &mut ChaCha8Rng) -> Matrix3<f64> {
    ZYX.to_dcm([
        rng.random_range(-3.0..3.0),
        rng.random_range(-1.5..1.5),
        rng.random_range(-3.0..3.0),
    ])
}

#[test]
fn all_methods_recover_exact_rotations() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for _ in 0..200 {
        let a = random_rotation(&mut rng);
        let n = rng.random_range(2..6);
        let b: Vec<_> = (0..n).map(|_| random_unit(&mut rng)).collect();
        let r: Vec<_> = b.iter().map(|b| a * b).collect();
        let w: Vec<f64> = (0..n).map(|_| rng.random_range(0.1..2.0)).collect();
        for m in METHODS {
            let s = solve(&b, &r, &w, m).unwrap();
            assert!((s.dcm_ref_from_body - a).norm() < 1e-9, "{m:?}");
            assert!(s.loss < 1e-18);
        }
    }
}

#[test]
fn methods_agree_on_noisy_data_and_near_half_turns() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    for k in 0..300 {
        // Every third case is a rotation by nearly 180 deg, QUEST's singular case.
        let a = if k % 3 == 0 {
            let axis = random_unit(&mut rng);
            nalgebra::Rotation3::from_axis_angle(
                &nalgebra::Unit::new_normalize(axis),
                std::f64::consts::PI - rng.random_range(0.0..1e-3),
            )
            .into_inner()
        } else {
            random_rotation(&mut rng)
        };
        let b: Vec<_> = (0..4).map(|_| random_unit(&mut rng)).collect();
        let r: Vec<_> = b
            .iter()
            .map(|b| a * b + 0.05 * random_unit(&mut rng))
            .collect();
        let w = [1.0, 2.0, 0.5, 1.0];
        let svd = solve(&b, &r, &w, Method::Svd).unwrap();
        for m in [Method::Davenport, Method::Quest] {
            let s = solve(&b, &r, &w, m).unwrap();
            assert!(
                (s.dcm_ref_from_body - svd.dcm_ref_from_body).norm() < 1e-9,
                "{m:?} case {k}"
            );
        }
    }
}

#[test]
fn parallel_and_zero_vectors_are_rejected() {
    let v = Vector3::new(0.0, 0.0, 1.0);
    for m in METHODS {
        let e = solve(&[v, 2.0 * v], &[v, -v * 3.0], &[1.0, 1.0], m).unwrap_err();
        assert!(matches!(e, Error::DegenerateGeometry { .. }), "{e}");
        let e = solve(&[v, Vector3::zeros()], &[v, v], &[1.0, 1.0], m).unwrap_err();
        assert!(matches!(e, Error::Degenerate { .. }), "{e}");
    }
    let e = solve(&[v, v], &[v, v], &[1.0, -1.0], Method::Svd).unwrap_err();
    assert!(matches!(e, Error::OutOfRange { .. }));
}

#[test]
fn covariance_of_two_orthogonal_pairs() {
    // r1 = x, r2 = y with weights w: info = w1 diag(0,1,1) + w2 diag(1,0,1).
    let (x, y) = (Vector3::x(), Vector3::y());
    let s = solve(&[x, y], &[x, y], &[4.0, 1.0], Method::Quest).unwrap();
    let expected = Matrix3::from_diagonal(&Vector3::new(1.0, 0.25, 0.2));
    assert!((s.covariance_ref - expected).norm() < 1e-12);
}

#[test]
fn triad_matches_first_pair_exactly_and_is_a_rotation() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..100 {
        let a = random_rotation(&mut rng);
        let (b1, b2) = (random_unit(&mut rng) * 3.0, random_unit(&mut rng));
        let r1 = a * b1 / 3.0;
        let r2 = a * b2 + 0.1 * random_unit(&mut rng);
        let t = triad(&b1, &b2, &r1, &r2).unwrap();
        let m = t.dcm_ref_from_body;
        assert!((m.transpose() * m - Matrix3::identity()).norm() < 1e-12);
        assert!((m.determinant() - 1.0).abs() < 1e-12);
        assert!((m * b1.normalize() - r1.normalize()).norm() < 1e-12);
        // The second body vector lands in the plane of r1 and r2, on r2's side of r1.
        let n = r1.cross(&r2).normalize();
        assert!((m * b2).dot(&n).abs() < 1e-12);
    }
    let v = Vector3::z();
    let e = triad(&v, &(-v), &Vector3::x(), &Vector3::y()).unwrap_err();
    assert!(matches!(e, Error::Degenerate { .. }), "{e}");
}

#[test]
fn batch_names_the_failing_epoch() {
    let (x, y) = (Vector3::x(), Vector3::y());
    let body = [x, y, x, x];
    let e = solve_batch(&body, &body, &[1.0; 4], 2, Method::Svd).unwrap_err();
    assert!(e.to_string().starts_with("epoch 1:"), "{e}");
    assert!(matches!(
        solve_batch(&body, &body, &[1.0; 4], 3, Method::Svd),
        Err(Error::Shape { .. })
    ));
}

#[test]
fn widely_spread_weights_keep_full_accuracy() {
    // With w1 / w2 = 1e8 Wahba's optimum is within ~1e-8 rad of TRIAD (first pair exact); QUEST is only
    // held to 1e5 (see quest.rs), against Davenport.
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for _ in 0..50 {
        let a = random_rotation(&mut rng);
        let (b1, b2) = (random_unit(&mut rng), random_unit(&mut rng));
        let (r1, r2) = (a * b1, a * b2 + 0.1 * random_unit(&mut rng));
        let t = triad(&b1, &b2, &r1, &r2).unwrap().dcm_ref_from_body;
        for m in [Method::Svd, Method::Davenport] {
            let s = solve(&[b1, b2], &[r1, r2], &[1e8, 1.0], m).unwrap();
            let e = (s.dcm_ref_from_body - t).norm();
            assert!(e < 1e-6, "{m:?} {e:e}");
        }
        let d = solve(&[b1, b2], &[r1, r2], &[1e5, 1.0], Method::Davenport).unwrap();
        let q = solve(&[b1, b2], &[r1, r2], &[1e5, 1.0], Method::Quest).unwrap();
        let e = (q.dcm_ref_from_body - d.dcm_ref_from_body).norm();
        assert!(e < 1e-7, "QUEST at 1e5: {e:e}");
    }
}

#[test]
fn vectors_near_the_f64_limit_give_the_attitude_of_their_directions() {
    // |v| of 1e300-sized vectors overflows to infinity; the directions are what matter.
    let b = [
        Vector3::new(1e300, 1e300, 0.0),
        Vector3::new(0.0, 0.0, 1e-300),
    ];
    let r = [Vector3::new(1.0, 1.0, 0.0), Vector3::new(0.0, 0.0, 1.0)];
    let s = solve(&b, &r, &[1.0, 1.0], Method::Svd).unwrap();
    assert!((s.dcm_ref_from_body - Matrix3::identity()).norm() < 1e-12);
}

#[test]
fn weights_that_overflow_the_covariance_are_an_error_not_infinity() {
    let b = [Vector3::x(), Vector3::y()];
    // The information matrix overflows to infinity: the covariance would be 0 and the loss NaN.
    match solve(&b, &b, &[f64::MAX, f64::MAX], Method::Svd) {
        Err(Error::Numerical { .. }) | Err(Error::DegenerateGeometry { .. }) => {}
        other => panic!("{other:?}"),
    }
}
