use super::*;
use crate::rotation::euler::ZYX;

fn scenario(
    baselines: &[Vector3<f64>],
    los: &[Vector3<f64>],
    dcm_ref_from_body: &Matrix3<f64>,
) -> DMatrix<f64> {
    let a = dcm_ref_from_body.transpose();
    DMatrix::from_fn(baselines.len(), los.len(), |i, j| {
        baselines[i].dot(&(a * los[j]))
    })
}

fn unit(x: f64, y: f64, z: f64) -> Vector3<f64> {
    Vector3::new(x, y, z).normalize()
}

fn tetra() -> Vec<Vector3<f64>> {
    vec![
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(0.0, 1.2, 0.0),
        Vector3::new(0.1, 0.2, 0.9),
    ]
}

fn sats() -> Vec<Vector3<f64>> {
    vec![
        unit(0.3, 0.2, 1.0),
        unit(-0.7, 0.1, 0.5),
        unit(0.2, -0.8, 0.4),
        unit(0.6, 0.6, 0.3),
    ]
}

#[test]
fn every_method_is_exact_without_noise() {
    let truth = ZYX.to_dcm([2.0, 0.3, -0.5]);
    let r = scenario(&tetra(), &sats(), &truth);
    for method in [
        Method::ClosedForm,
        Method::Paper,
        Method::Svd,
        Method::MaxLikelihood,
    ] {
        let sol = solve(&tetra(), &sats(), &r, method).unwrap();
        assert!((sol.dcm_ref_from_body - truth).norm() < 1e-12, "{method:?}");
        assert!(sol.residual_rms_m < 1e-12);
    }
}

#[test]
fn coplanar_array_needs_svd() {
    let s3 = 3f64.sqrt() / 2.0;
    let tri = vec![Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.5, s3, 0.0)];
    let truth = ZYX.to_dcm([std::f64::consts::PI, 0.0, 0.0]);
    let r = scenario(&tri, &sats()[..3], &truth);
    let sol = solve(&tri, &sats()[..3], &r, Method::Svd).unwrap();
    assert!((sol.dcm_ref_from_body - truth).norm() < 1e-12);
    for method in [Method::ClosedForm, Method::Paper] {
        let err = solve(&tri, &sats()[..3], &r, method).unwrap_err();
        assert!(
            matches!(err, Error::DegenerateGeometry { matrix, .. } if matrix.starts_with("baseline"))
        );
    }
}

#[test]
fn two_satellites_suffice_with_a_non_coplanar_array() {
    let truth = ZYX.to_dcm([-1.0, 0.2, 0.4]);
    let r = scenario(&tetra(), &sats()[..2], &truth);
    let sol = solve(&tetra(), &sats()[..2], &r, Method::Svd).unwrap();
    assert!((sol.dcm_ref_from_body - truth).norm() < 1e-12);
}

#[test]
fn collinear_baselines_are_degenerate() {
    let line = vec![Vector3::new(1.0, 0.0, 0.0), Vector3::new(2.0, 0.0, 0.0)];
    let r = scenario(&line, &sats(), &Matrix3::identity());
    assert!(matches!(
        solve(&line, &sats(), &r, Method::Svd),
        Err(Error::DegenerateGeometry { .. })
    ));
}

#[test]
fn bad_input_is_named() {
    let r = DMatrix::zeros(3, 4);
    let err = solve(&tetra(), &sats(), &DMatrix::zeros(2, 4), Method::Svd).unwrap_err();
    assert!(err.to_string().contains("range_diffs"), "{err}");
    let mut los = sats();
    los[1] *= 2.0;
    assert!(solve(&tetra(), &los, &r, Method::Svd)
        .unwrap_err()
        .to_string()
        .contains("row 1"));
    let mut nan = r.clone();
    nan[(1, 1)] = f64::NAN;
    assert!(matches!(
        solve(&tetra(), &sats(), &nan, Method::Svd),
        Err(Error::NonFinite { .. })
    ));
}

#[test]
fn tiny_and_underflowing_baselines_never_panic() {
    // The condition is scale invariant: baselines of 1e-60 m give the same attitude as of 1 m.
    let truth = ZYX.to_dcm([0.4, -0.2, 1.1]);
    let tiny: Vec<Vector3<f64>> = tetra().iter().map(|b| b * 1e-60).collect();
    let r = scenario(&tiny, &sats(), &truth);
    for method in [
        Method::ClosedForm,
        Method::Paper,
        Method::Svd,
        Method::MaxLikelihood,
    ] {
        let sol = solve(&tiny, &sats(), &r, method).unwrap();
        assert!((sol.dcm_ref_from_body - truth).amax() < 1e-9, "{method:?}");
    }
    // The hostile case of issue 15 (used to panic in `expect("condition checked")`): an answer or a
    // geometry error, for every method.
    let eye: Vec<Vector3<f64>> = (0..3).map(|i| Vector3::ith(i, 1e-60)).collect();
    let los: Vec<Vector3<f64>> = (0..3).map(|i| Vector3::ith(i, 1.0)).collect();
    let zeros = DMatrix::zeros(3, 3);
    for method in [
        Method::ClosedForm,
        Method::Paper,
        Method::Svd,
        Method::MaxLikelihood,
    ] {
        match solve(&eye, &los, &zeros, method) {
            Ok(sol) => assert!(sol.dcm_ref_from_body.iter().all(|v| v.is_finite())),
            Err(e) => assert!(
                matches!(
                    e,
                    Error::DegenerateGeometry { .. } | Error::Degenerate { .. }
                ),
                "{method:?}: {e:?}"
            ),
        }
    }
    // Baselines whose squares underflow (1e-170 m: G = B B^T is subnormal, 1e-200 m: zero, as is their
    // norm): refused as a degenerate geometry or a zero-length baseline, never a panic or NaN.
    for scale in [1e-170, 1e-200] {
        let under: Vec<Vector3<f64>> = tetra().iter().map(|b| b * scale).collect();
        let r = scenario(&under, &sats(), &truth);
        for method in [Method::ClosedForm, Method::Svd] {
            match solve(&under, &sats(), &r, method) {
                Ok(sol) => assert!((sol.dcm_ref_from_body - truth).amax() < 1e-6),
                Err(e) => assert!(
                    matches!(
                        e,
                        Error::DegenerateGeometry { .. } | Error::OutOfRange { .. }
                    ),
                    "{scale} {method:?}: {e:?}"
                ),
            }
        }
    }
}
