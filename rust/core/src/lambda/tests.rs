//! End-to-end checks of the LAMBDA pipeline: published reference vectors, invariances, validation.

use nalgebra::{DMatrix, DVector};

use super::bootstrap::success_rate;
use super::test_support::{random_covariance, Lcg};
use super::validation::{fixed_failure_rate_threshold, partial_fix, ratio_test, RatioThreshold};
use super::*;

/// RTKLIB unit-test vectors (test/utest/t_lambda.c, utest1), BSD-2-Clause, (c) T. Takasu.
#[test]
fn rtklib_utest1() {
    let a = DVector::from_vec(vec![
        1585184.171,
        -6716599.430,
        3915742.905,
        7627233.455,
        9565990.879,
        989457273.200,
    ]);
    let (v, c, e) = (0.227134, 0.112202, 0.103473);
    let mut q = DMatrix::from_element(6, 6, c);
    for i in 0..6 {
        q[(i, i)] = v;
        q[(i, 5)] = e;
        q[(5, i)] = e;
    }
    q[(5, 5)] = 0.434339;
    let s = ils(&a, &q, 2).unwrap();
    let f1 = [1585184, -6716599, 3915743, 7627234, 9565991, 989457273];
    let f2 = [1585184, -6716600, 3915743, 7627233, 9565991, 989457273];
    assert_eq!(s.fixed.column(0).as_slice(), &f1);
    assert_eq!(s.fixed.column(1).as_slice(), &f2);
    assert!((s.squared_norms[0] - 3.507984).abs() < 1e-4);
    assert!((s.squared_norms[1] - 3.708456).abs() < 1e-4);
}

/// RTKLIB unit-test vectors (test/utest/t_lambda.c, utest2), BSD-2-Clause, (c) T. Takasu.
#[test]
fn rtklib_utest2() {
    let a = DVector::from_vec(vec![
        -13324172.755747,
        -10668894.713608,
        -7157225.010770,
        -6149367.974367,
        -7454133.571066,
        -5969200.494550,
        8336734.058423,
        6186974.084502,
        -17549093.883655,
        -13970158.922370,
    ]);
    // Blocks s (I + 1 1^T) / 2 with s = 0.446320, 0.572775, 0.735063 (off-diagonal s/2 as printed).
    let (aa, ab, bb) = (
        (0.446320, 0.223160),
        (0.572775, 0.286388),
        (0.735063, 0.367531),
    );
    let q = DMatrix::from_fn(10, 10, |i, j| {
        let (d, o) = match (i < 5, j < 5) {
            (true, true) => aa,
            (false, false) => bb,
            _ => ab,
        };
        if i % 5 == j % 5 {
            d
        } else {
            o
        }
    });
    let s = ils(&a, &q, 2).unwrap();
    let f1 = [
        -13324188, -10668901, -7157236, -6149379, -7454143, -5969220, 8336726, 6186960, -17549108,
        -13970171,
    ];
    let f2 = [
        -13324188, -10668908, -7157236, -6149379, -7454143, -5969220, 8336717, 6186960, -17549108,
        -13970171,
    ];
    assert_eq!(s.fixed.column(0).as_slice(), &f1);
    assert_eq!(s.fixed.column(1).as_slice(), &f2);
    assert!((s.squared_norms[0] - 1506.435789).abs() < 1e-4);
    assert!((s.squared_norms[1] - 1612.811795).abs() < 1e-4);
}

fn random_problem(rng: &mut Lcg, n: usize) -> (DVector<f64>, DMatrix<f64>) {
    let q = random_covariance(rng, n, 1e-3);
    let a = DVector::from_fn(n, |_, _| 200.0 * rng.uniform() - 100.0);
    (a, q)
}

#[test]
fn integer_shift_and_unimodular_transform_carry_over() {
    let mut rng = Lcg(3);
    for n in [1usize, 2, 4, 7, 12, 25] {
        let (a, q) = random_problem(&mut rng, n);
        let base = ils(&a, &q, 2).unwrap();
        let shift = DVector::from_fn(n, |_, _| (2000.0 * rng.uniform()).round() - 1000.0);
        let shifted = ils(&(&a + &shift), &q, 2).unwrap();
        for c in 0..2 {
            let want = base.fixed.column(c).map(|v| v as f64) + &shift;
            assert_eq!(shifted.fixed.column(c).map(|v| v as f64), want);
            assert!((shifted.squared_norms[c] - base.squared_norms[c]).abs() < 1e-7);
        }
        // A unimodular T: the problem (T^T a, T^T Q T) has solutions T^T z.
        let mut t = DMatrix::<f64>::identity(n, n);
        for _ in 0..3 * n {
            let (i, j) = (
                (rng.uniform() * n as f64) as usize,
                (rng.uniform() * n as f64) as usize,
            );
            if i != j {
                let mu = if rng.uniform() < 0.5 { 1.0 } else { -1.0 };
                let col = t.column(i) * mu;
                let mut cj = t.column_mut(j);
                cj += col;
            }
        }
        let moved = ils(&t.tr_mul(&a), &(t.transpose() * &q * &t), 2).unwrap();
        let want = t.tr_mul(&base.fixed.column(0).map(|v| v as f64));
        assert_eq!(moved.fixed.column(0).map(|v| v as f64), want);
        assert!(
            (moved.squared_norms[0] - base.squared_norms[0]).abs()
                < 1e-6 * (1.0 + base.squared_norms[0])
        );
    }
}

#[path = "../../../../benches/lambda_geometry.rs"]
mod geometry;

#[test]
fn realistic_geometries_up_to_64_ambiguities() {
    for n in [6usize, 10, 20, 40, 60, 64] {
        let g = geometry::Geometry::for_ambiguities(n);
        let q = g.float_covariance();
        assert_eq!(q.nrows(), n);
        for a in g.float_draws(&q, 3, n as u64) {
            let s = ils(&a, &q, 3).unwrap();
            assert_eq!(s.fixed.shape(), (n, 3));
            assert!(s.squared_norms.windows(2).all(|w| w[0] <= w[1]));
            // The best is at least as good as the bootstrapped solution's norm bound (chi2 of n dof is
            // ~n; far above would mean a wrong search).
            assert!(s.squared_norms[0] < 5.0 * n as f64);
        }
    }
}

#[test]
fn bad_inputs_are_named() {
    let q = DMatrix::<f64>::identity(3, 3);
    let e = ils(&DVector::zeros(2), &q, 2).unwrap_err().to_string();
    assert!(e.contains("float ambiguities") && e.contains("(2,)"), "{e}");
    let e = ils(&DVector::zeros(3), &q, 0).unwrap_err().to_string();
    assert!(e.contains("candidates"), "{e}");
    let e = ils(&DVector::from_element(3, 1e17), &q, 1)
        .unwrap_err()
        .to_string();
    assert!(e.contains("exceeds"), "{e}");
    let e = ils(&DVector::zeros(0), &DMatrix::zeros(0, 0), 1)
        .unwrap_err()
        .to_string();
    assert!(e.contains("n >= 1"), "{e}");
}

#[test]
fn ratio_test_fixed_threshold() {
    // A precise problem near an integer passes; one half-way between two integers does not.
    let q = DMatrix::from_diagonal(&DVector::from_vec(vec![0.01, 0.02, 0.015]));
    let near = DVector::from_vec(vec![3.05, -2.02, 7.01]);
    let r = ratio_test(&near, &q, RatioThreshold::Fixed(3.0)).unwrap();
    assert!(r.accepted && r.ratio > 3.0);
    assert_eq!(r.fixed.as_slice(), &[3, -2, 7]);
    let half = DVector::from_vec(vec![3.49, -2.02, 7.01]);
    let r = ratio_test(&half, &q, RatioThreshold::Fixed(3.0)).unwrap();
    assert!(!r.accepted && r.ratio < 1.2);
    assert!(ratio_test(&near, &q, RatioThreshold::Fixed(0.5)).is_err());
}

#[test]
fn fixed_failure_rate_threshold_controls_the_failure_rate() {
    // A weak model (bootstrapped failure rate well above P_f): the threshold is > 1, and applying it to
    // independent draws keeps the failure rate near P_f while a threshold of 1 would not.
    let mut rng = Lcg(9);
    let q = random_covariance(&mut rng, 5, 0.02) * 0.25;
    let pf = 0.01;
    let c = fixed_failure_rate_threshold(&q, pf, 20_000, 1).unwrap();
    assert!(c > 1.0, "{c}");
    let again = fixed_failure_rate_threshold(&q, pf, 20_000, 1).unwrap();
    assert_eq!(c, again);
    let p = Problem::new(&DVector::zeros(5), &q).unwrap();
    let chol = q.clone().cholesky().unwrap();
    let (mut wrong_accepted, mut wrong, trials) = (0, 0, 20_000);
    for _ in 0..trials {
        let a = chol.l() * DVector::from_fn(5, |_, _| rng.normal());
        let r = ratio_test(&a, &q, RatioThreshold::Fixed(c)).unwrap();
        let bad = r.fixed.iter().any(|&v| v != 0);
        wrong += bad as usize;
        wrong_accepted += (bad && r.accepted) as usize;
    }
    let rate = wrong_accepted as f64 / trials as f64;
    let sigma = (pf * (1.0 - pf) / trials as f64).sqrt();
    assert!(rate < pf + 5.0 * sigma, "{rate}");
    assert!(wrong as f64 / trials as f64 > 3.0 * pf);
    assert_eq!(p.len(), 5);
}

#[test]
fn partial_fix_drops_the_weak_end() {
    // Two precise ambiguities and one hopeless one, uncorrelated: the precise pair is fixed.
    let q = DMatrix::from_diagonal(&DVector::from_vec(vec![0.001, 4.0, 0.002]));
    let a = DVector::from_vec(vec![1.02, 5.4, -3.01]);
    let pf = partial_fix(&a, &q, RatioThreshold::Fixed(3.0), 0.99).unwrap();
    assert_eq!(pf.fixed_count, 2);
    let fixed_vals = pf.combinations.map(|v| v as f64).tr_mul(&pf.ambiguities);
    for (v, w) in fixed_vals.iter().zip(pf.values.iter()) {
        assert!((v - *w as f64).abs() < 1e-9);
    }
    assert!((pf.ambiguities[0] - 1.0).abs() < 1e-12 && (pf.ambiguities[2] + 3.0).abs() < 1e-12);
    assert!((pf.ambiguities[1] - 5.4).abs() < 1e-12);
    assert!((pf.covariance[(1, 1)] - 4.0).abs() < 1e-12 && pf.covariance[(0, 0)].abs() < 1e-12);
    // All precise: a full fix with zero covariance.
    let q = DMatrix::from_diagonal(&DVector::from_vec(vec![0.001, 0.003, 0.002]));
    let pf = partial_fix(
        &a.map(|v| v.round() + 0.01),
        &q,
        RatioThreshold::Fixed(3.0),
        0.99,
    )
    .unwrap();
    assert_eq!(pf.fixed_count, 3);
    assert_eq!(pf.covariance.amax(), 0.0);
    // Nothing passes: the float solution comes back.
    let q = DMatrix::<f64>::identity(3, 3) * 4.0;
    let pf = partial_fix(&a, &q, RatioThreshold::Fixed(3.0), 0.5).unwrap();
    assert_eq!(pf.fixed_count, 0);
    assert_eq!(pf.ambiguities, a);
}

/// Partial fixing on correlated problems against an independent computation of every subset: the
/// subset of the last k decorrelated ambiguities as a problem of its own (`Z_k^T a`, `Z_k^T Q Z_k`
/// formed here, solved by [`ils`] with its own decorrelation), and the conditioning by explicit inverses.
/// The fast path takes each subset's covariance from one factorisation of the whole `Z^T Q Z`.
#[test]
fn partial_fix_matches_independent_subset_problems() {
    let mut rng = Lcg(29);
    let mut partial = 0;
    for n in [4usize, 8, 15, 24] {
        for _ in 0..6 {
            let q = random_covariance(&mut rng, n, 0.02) * 0.05;
            let a = DVector::from_fn(n, |_, _| {
                (20.0 * rng.uniform()).round() + 0.15 * rng.normal()
            });
            let (gate, c) = (0.5, 2.0);
            let pf = partial_fix(&a, &q, RatioThreshold::Fixed(c), gate).unwrap();
            let p = Problem::new(&a, &q).unwrap();
            let z = p.reduction.z_f64();
            // The first k from n down whose success rate passes the gate and whose ratio passes c.
            let mut want = 0;
            for k in (1..=n).rev() {
                let sr = success_rate(p.reduction.factor.trailing(k).d.as_slice());
                if sr < gate {
                    continue;
                }
                let zk = z.columns(n - k, k).into_owned();
                let qk = zk.transpose() * &q * &zk;
                let qk = (&qk + qk.transpose()) * 0.5;
                let s = ils(&zk.tr_mul(&a), &qk, 2).unwrap();
                let ratio = s.squared_norms[1] / s.squared_norms[0];
                if ratio >= c {
                    want = k;
                    assert!(
                        (pf.ratio - ratio).abs() < 1e-8 * ratio,
                        "{} {ratio}",
                        pf.ratio
                    );
                    assert_eq!(pf.values, s.fixed.column(0).into_owned());
                    if k < n {
                        let qzk = &q * &zk;
                        let qk_inv = qk.clone().try_inverse().unwrap();
                        let r = zk.tr_mul(&a) - s.fixed.column(0).map(|v| v as f64);
                        let amb = &a - &qzk * &qk_inv * r;
                        let cov = &q - &qzk * &qk_inv * qzk.transpose();
                        assert!((&pf.ambiguities - amb).amax() < 1e-8);
                        assert!((&pf.covariance - cov).amax() < 1e-8 * q.amax());
                        partial += 1;
                    }
                    break;
                }
            }
            assert_eq!(pf.fixed_count, want, "n = {n}");
        }
    }
    // The draws exercise the partial branch, not only full fixes and refusals.
    assert!(partial >= 3, "{partial} partial fixes");
}
