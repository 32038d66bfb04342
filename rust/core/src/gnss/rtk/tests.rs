use nalgebra::Vector3;

use super::sim::Scenario;
use super::*;
use crate::gnss::signal::System;

const GATE: FixOptions = FixOptions {
    min_success_rate: 0.999,
    ratio_threshold: 3.0,
};

/// Every integer reported equals the truth.
fn wrong_integers(sc: &Scenario, s: &BaselineSolution) -> usize {
    s.integers
        .iter()
        .filter(|&&(a, r, n)| {
            let (k, slot) = Scenario::of_arc(a);
            let (q, _) = Scenario::of_arc(r);
            sc.dd_integer(k, q, slot) != n
        })
        .count()
}

#[test]
fn one_epoch_gps_l1_l2_fixes_a_one_metre_baseline() {
    let mut sc = Scenario::new(1, &[(System::Gps, 9, &[0, 1])], 15.0);
    let truth = Vector3::new(0.6, -0.7, 0.38);
    let e = sc.epoch(&truth, 0.0);
    let s = solve_baseline(&[e], &[], &GATE).unwrap();
    assert!(s.fixed, "{s:?}");
    assert_eq!(wrong_integers(&sc, &s), 0);
    assert_eq!(s.integers.len(), 16);
    // chi-square with 3 degrees of freedom: 16.27 is its 0.999 quantile.
    assert!(chi2(&s, &truth) < 16.27, "{}", chi2(&s, &truth));
}

/// Baseline error normalised by the reported covariance (chi-square with 3 degrees of freedom).
fn chi2(s: &BaselineSolution, truth: &Vector3<f64>) -> f64 {
    let e = s.baseline_m - truth;
    e.dot(&(s.covariance_m2.try_inverse().unwrap() * e))
}

/// Single-epoch fixing over `n` epochs of fresh geometry and baselines of `length_m`: (fixed, wrong
/// integers accepted, partially fixed).
fn fix_rate(
    seed: u64,
    n: usize,
    counts: &[(System, usize, &[usize])],
    length_m: f64,
) -> (usize, usize, usize) {
    let (mut fixed, mut wrong, mut partial) = (0, 0, 0);
    for k in 0..n as u64 {
        let mut sc = Scenario::new(seed * 1000 + k, counts, 15.0);
        let truth = sc.random_baseline(length_m);
        let e = sc.epoch(&truth, 0.0);
        let s = solve_baseline(&[e], &[], &GATE).unwrap();
        fixed += usize::from(s.fixed);
        partial += usize::from(!s.fixed && s.fixed_ambiguities > 0);
        wrong += wrong_integers(&sc, &s);
    }
    (fixed, wrong, partial)
}

/// 300 epochs with no wrong integer accepted bounds the wrong-fix rate below 1 % at 95 % confidence
/// (binomial: (1 - 0.01)^300 = 0.049). Ten GPS satellites above 15 degrees, L1 + L2, gate 0.999 and
/// ratio 3: measured 93 % of epochs fully fixed (the rest mostly partially); the gate binds for fewer
/// satellites (eight: median bootstrapped success rate 0.998, a third fully fixed).
#[test]
fn gps_l1_l2_single_epoch_fix_rate_and_no_wrong_fix() {
    let (fixed, wrong, partial) = fix_rate(2, 300, &[(System::Gps, 10, &[0, 1])], 1.0);
    eprintln!("GPS L1+L2: fixed {fixed}/300, partial {partial}, wrong {wrong}");
    assert_eq!(wrong, 0);
    assert!(fixed >= 255, "{fixed}");
}

#[test]
fn multi_gnss_single_epoch_fix_rate_and_no_wrong_fix() {
    let counts: &[(System, usize, &[usize])] = &[
        (System::Gps, 7, &[0, 1]),
        (System::Glonass, 5, &[0, 1]),
        (System::Galileo, 5, &[0, 2]),
        (System::BeiDou, 5, &[0, 2]),
    ];
    let (fixed, wrong, partial) = fix_rate(3, 300, counts, 1.0);
    eprintln!("GPS+GLO+GAL+BDS: fixed {fixed}/300, partial {partial}, wrong {wrong}");
    assert_eq!(wrong, 0);
    // Measured 281: the bootstrapped success rate is above 0.99998 in 90 % of the epochs, the ratio
    // test at 3 (36 ambiguities) is what rejects the rest, which are then partially fixed.
    assert!(fixed >= 255, "{fixed}");
    assert_eq!(fixed + partial, 300);
}

/// The float baseline is unbiased with the covariance it reports: over 400 epochs the mean of the
/// normalised squared errors (chi-square, 3 dof each) is 3 within 4 standard deviations
/// (sqrt(6 / 400) = 0.12), and each ENU-free ECEF component's mean error is within 4 of its standard error.
#[test]
fn float_solution_is_unbiased_with_its_covariance() {
    let n = 400;
    let mut sum_chi2 = 0.0;
    let mut sum_z = Vector3::zeros();
    for k in 0..n as u64 {
        let mut sc = Scenario::new(40_000 + k, &[(System::Gps, 8, &[0, 1])], 15.0);
        let truth = sc.random_baseline(1.0);
        let e = sc.epoch(&truth, 0.0);
        let fl = float::solve(&[e], &[]).unwrap();
        let cov = fl.covariance.fixed_view::<3, 3>(0, 0).into_owned();
        let err = fl.baseline_m - truth;
        sum_chi2 += err.dot(&(cov.try_inverse().unwrap() * err));
        sum_z += Vector3::from_fn(|i, _| err[i] / cov[(i, i)].sqrt());
    }
    let mean = sum_chi2 / n as f64;
    assert!((mean - 3.0).abs() < 4.0 * (6.0 / n as f64).sqrt(), "{mean}");
    for i in 0..3 {
        assert!(sum_z[i].abs() / (n as f64).sqrt() < 4.0, "{sum_z}");
    }
}
