use nalgebra::Vector3;

use super::sim::Scenario;
use super::*;
use crate::error::Error;
use crate::gnss::signal::System;

const GATE: FixOptions = FixOptions {
    min_success_rate: 0.999,
    ratio_threshold: 3.0,
    max_failure_rate: 0.0,
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

/// The bootstrapped success rate is a lower bound of the ILS one (Teunissen 1999): with one geometry and
/// fresh noise, the empirical rate of a correct ILS solution over 1000 draws is at least `p` minus 4
/// binomial standard deviations, and (decorrelated bootstrapping being close to ILS) at most `p + 0.1`.
/// GPS L1 only, 9 satellites: `p` is moderate, so both sides can fail.
#[test]
fn success_rate_bounds_the_empirical_ils_rate() {
    let mut sc = Scenario::new(11, &[(System::Gps, 9, &[0])], 15.0);
    sc.code_ab = (0.2, 0.2);
    let truth = Vector3::new(0.3, 0.9, -0.2);
    let n = 1000;
    let (mut correct, mut p) = (0, 0.0);
    for _ in 0..n {
        let e = sc.epoch(&truth, 0.0);
        let fl = float::solve(&[e], &[]).unwrap();
        let na = fl.ambiguities.len();
        let q = fl.covariance.view((3, 3), (na, na)).into_owned();
        let q = (&q + q.transpose()) * 0.5;
        let problem = crate::lambda::Problem::new(&fl.ambiguities_cycles, &q).unwrap();
        p = crate::lambda::bootstrap::success_rate(problem.reduction.factor.d.as_slice());
        let best = problem.solve(1, crate::lambda::DEFAULT_MAX_NODES).unwrap();
        let ok = fl.ambiguities.iter().enumerate().all(|(i, a)| {
            let (k, slot) = Scenario::of_arc(a.arc);
            let (r, _) = Scenario::of_arc(a.reference_arc);
            a.offset + best.fixed[(i, 0)] == sc.dd_integer(k, r, slot)
        });
        correct += usize::from(ok);
    }
    let rate = correct as f64 / n as f64;
    let sd = (p * (1.0 - p) / n as f64).sqrt();
    eprintln!("bootstrapped {p}, empirical ILS {rate}");
    assert!(p > 0.3 && p < 0.97, "{p}");
    assert!(rate >= p - 4.0 * sd, "{rate} {p}");
    assert!(rate <= p + 0.1, "{rate} {p}");
}

/// When the full set misses the gate, a subset is fixed: the integers reported are right, `fixed` is
/// false, and the conditioned baseline is more precise than the float one.
#[test]
fn partial_fixing_fixes_a_correct_subset_when_the_full_set_fails() {
    let (mut partial, mut wrong) = (0, 0);
    for k in 0..100u64 {
        let mut sc = Scenario::new(50_000 + k, &[(System::Gps, 8, &[0, 1])], 15.0);
        let truth = sc.random_baseline(1.0);
        let e = sc.epoch(&truth, 0.0);
        let fl = float::solve(std::slice::from_ref(&e), &[]).unwrap();
        let s = solve_baseline(&[e], &[], &GATE).unwrap();
        if !s.fixed && s.fixed_ambiguities > 0 {
            partial += 1;
            assert!(s.fixed_ambiguities < s.ambiguities);
            assert!(s.success_rate < GATE.min_success_rate || s.ratio >= GATE.ratio_threshold);
            let float_trace = fl.covariance.fixed_view::<3, 3>(0, 0).trace();
            assert!(s.covariance_m2.trace() < float_trace);
            assert!(chi2(&s, &truth) < 16.27);
        }
        wrong += wrong_integers(&sc, &s);
    }
    eprintln!("partially fixed {partial}/100");
    assert!(partial >= 20, "{partial}");
    assert_eq!(wrong, 0);
}

/// GLONASS alone (FDMA G1 + G2): every channel -7..6 occurs over the scenarios, no wrong integer is
/// accepted and most epochs fix.
#[test]
fn glonass_fdma_channels_fix_correctly() {
    let mut seen = std::collections::BTreeSet::new();
    let (mut fixed, mut wrong) = (0, 0);
    for k in 0..150u64 {
        let mut sc = Scenario::new(60_000 + k, &[(System::Glonass, 10, &[0, 1])], 15.0);
        seen.extend(sc.sats.iter().filter_map(|s| s.channel));
        let truth = sc.random_baseline(1.0);
        let e = sc.epoch(&truth, 0.0);
        let s = solve_baseline(&[e], &[], &GATE).unwrap();
        fixed += usize::from(s.fixed);
        wrong += wrong_integers(&sc, &s);
        if s.fixed {
            assert!(chi2(&s, &truth) < 16.27);
        }
    }
    eprintln!("GLONASS: fixed {fixed}/150");
    assert_eq!(seen.len(), 14);
    assert_eq!(wrong, 0);
    assert!(fixed >= 120, "{fixed}");
}

/// A 3 km baseline from a prior 10 m off (per axis): exact ranges iterated; no wrong integer, the
/// baseline consistent with its covariance, and (measured 19 of 20) nearly every epoch fully fixed.
#[test]
fn three_kilometre_baseline_fixes() {
    let mut fixed = 0;
    for k in 0..20u64 {
        let mut sc = Scenario::new(
            70_000 + k,
            &[(System::Gps, 9, &[0, 1]), (System::Galileo, 7, &[0, 2])],
            15.0,
        );
        sc.prior_sigma_m = 10.0;
        let truth = sc.random_baseline(3000.0);
        let e = sc.epoch(&truth, 0.0);
        let s = solve_baseline(&[e], &[], &GATE).unwrap();
        fixed += usize::from(s.fixed);
        assert_eq!(wrong_integers(&sc, &s), 0);
        assert!(chi2(&s, &truth) < 16.27, "{}", chi2(&s, &truth));
    }
    assert!(fixed >= 18, "{fixed}");
}

/// Held integers are exact constraints: holding the integers a free fix found gives the same baseline;
/// holding one of them wrong by a cycle moves it; holding every one fixes without a search.
#[test]
fn held_integers_are_imposed_exactly() {
    let mut sc = Scenario::new(80, &[(System::Gps, 9, &[0, 1])], 15.0);
    let truth = Vector3::new(-0.5, 0.8, 0.3);
    let e1 = sc.epoch(&truth, 0.0);
    let first = solve_baseline(&[e1], &[], &GATE).unwrap();
    assert!(first.fixed);
    let e2 = sc.epoch(&truth, 1.0);
    let free = solve_baseline(std::slice::from_ref(&e2), &[], &GATE).unwrap();
    let held = solve_baseline(std::slice::from_ref(&e2), &first.integers, &GATE).unwrap();
    assert!(free.fixed && held.fixed);
    assert_eq!(held.fixed_ambiguities, held.ambiguities);
    assert_eq!(held.integers.len(), first.integers.len());
    // The free fix conditions the float baseline linearly; the held one re-linearises at the fixed
    // baseline: they differ by the range's curvature over the float error, ~(0.3 m)^2 / 2e7 m = 5e-9 m.
    assert!((free.baseline_m - held.baseline_m).norm() < 1e-6);
    assert!((free.covariance_m2 - held.covariance_m2).norm() < 1e-6 * held.covariance_m2.norm());
    let mut off = first.integers.clone();
    off[0].2 += 1;
    let moved = solve_baseline(&[e2], &off, &GATE).unwrap();
    assert!((moved.baseline_m - held.baseline_m).norm() > 1e-3);
}

/// Static: 30 epochs over 15 minutes with GPS L1 alone and noisy code, where single epochs do not fix,
/// share one baseline and one ambiguity per arc pair: fixed and correct.
#[test]
fn static_session_fixes_what_single_epochs_cannot() {
    let mut sc = Scenario::new(90, &[(System::Gps, 7, &[0])], 15.0);
    sc.code_ab = (1.0, 0.5);
    let truth = Vector3::new(3.0, -4.0, 1.0);
    let epochs: Vec<DdEpoch> = (0..30).map(|k| sc.epoch(&truth, 30.0 * k as f64)).collect();
    let single = solve_baseline(&epochs[..1], &[], &GATE).unwrap();
    assert!(!single.fixed);
    let s = solve_baseline(&epochs, &[], &GATE).unwrap();
    assert!(s.fixed, "{s:?}");
    assert_eq!(wrong_integers(&sc, &s), 0);
    assert!(chi2(&s, &truth) < 16.27);
    assert!((s.baseline_m - truth).norm() < 0.01);
}

#[test]
fn bad_input_is_refused_with_a_named_error() {
    let mut sc = Scenario::new(100, &[(System::Gps, 6, &[0])], 15.0);
    let e = sc.epoch(&Vector3::new(1.0, 0.0, 0.0), 0.0);
    let bad_gate = FixOptions {
        min_success_rate: 1.5,
        ratio_threshold: 3.0,
        max_failure_rate: 0.0,
    };
    assert!(matches!(
        solve_baseline(std::slice::from_ref(&e), &[], &bad_gate),
        Err(Error::OutOfRange {
            name: "--min-success-rate",
            ..
        })
    ));
    assert!(matches!(
        solve_baseline(&[], &[], &GATE),
        Err(Error::Shape { .. })
    ));
    let mut nan = e.clone();
    nan.signals[2].rover_code_m = f64::NAN;
    assert!(matches!(
        solve_baseline(&[nan], &[], &GATE),
        Err(Error::NonFinite { index: 2, .. })
    ));
    let mut dup = e.clone();
    dup.signals[1].arc = dup.signals[0].arc;
    assert!(matches!(
        solve_baseline(&[dup], &[], &GATE),
        Err(Error::OutOfRange { .. })
    ));
    let mut slot = e.clone();
    slot.signals[0].slot = 3;
    assert!(matches!(
        solve_baseline(&[slot], &[], &GATE),
        Err(Error::OutOfRange { .. })
    ));
    let mut few = e.clone();
    few.signals.truncate(2);
    assert!(matches!(
        solve_baseline(&[few], &[], &GATE),
        Err(Error::DegenerateGeometry { .. })
    ));
}

/// Attitude mode, three antennas (base + two rovers at 1.2 m nose and 0.9 m right wing), GPS L1 only,
/// eight satellites: the array constraint fixes at least the epochs the unconstrained fix of both rovers
/// fixes (measured with the gate of `rtk/constrained.rs`: 1 and 0 of 200; the gate's ratio against the
/// 200-candidate lists' cutoff refuses what the lists cannot check, and before it the rule fixed many
/// more, unguarded), no wrong integer is accepted over 200 epochs (wrong-fix rate < 1.5 % at 95 %), and
/// a fixed epoch's baselines agree with their covariances and its rotation with the truth within 4 times
/// the largest baseline sigma over its length.
#[test]
fn attitude_with_three_antennas_fixes_more_and_finds_the_rotation() {
    let body = [[1.2, 0.0, 0.0], [0.0, 0.05, 0.9]];
    let (mut constrained, mut both, mut wrong) = (0, 0, 0);
    for k in 0..200u64 {
        let mut sc = Scenario::new(120_000 + k, &[(System::Gps, 8, &[0])], 15.0);
        let r = super::sim::random_rotation(&mut sc.rng);
        let to_ecef = super::enu_at(&sc.base_m).transpose();
        let truths: Vec<Vector3<f64>> = body
            .iter()
            .map(|f| to_ecef * r * Vector3::from(*f))
            .collect();
        let epochs: Vec<DdEpoch> = truths.iter().map(|b| sc.epoch(b, 0.0)).collect();
        let s = solve_attitude(&epochs, &body, &GATE).unwrap();
        both += usize::from(epochs.iter().all(|e| {
            solve_baseline(std::slice::from_ref(e), &[], &GATE)
                .unwrap()
                .fixed
        }));
        if s.fixed {
            constrained += 1;
            let w = s
                .baselines
                .iter()
                .map(|b| wrong_integers(&sc, b))
                .sum::<usize>();
            wrong += usize::from(w > 0);
            if w == 0 {
                let d = s.rotation_enu_from_body * r.transpose();
                let angle = ((d.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos();
                let mut bound: f64 = 0.0;
                for (i, b) in s.baselines.iter().enumerate() {
                    assert!(chi2(b, &truths[i]) < 16.27);
                    let len = Vector3::from(body[i]).norm();
                    bound = bound.max(4.0 * b.covariance_m2.trace().sqrt() / len);
                }
                assert!(angle < bound, "{angle} {bound}");
            }
        }
    }
    eprintln!(
        "attitude: constrained {constrained}/200, unconstrained both {both}/200, wrong {wrong}"
    );
    assert_eq!(wrong, 0);
    assert!(constrained >= both, "{constrained} {both}");
}

#[test]
fn attitude_bad_input_is_refused_with_a_named_error() {
    let mut sc = Scenario::new(130, &[(System::Gps, 8, &[0])], 15.0);
    let e = sc.epoch(&Vector3::new(1.0, 0.0, 0.0), 0.0);
    let two = [e.clone(), e.clone()];
    assert!(matches!(
        solve_attitude(&two[..1], &[[1.0, 0.0, 0.0]], &GATE),
        Err(Error::Shape { .. })
    ));
    assert!(matches!(
        solve_attitude(&two, &[[1.0, 0.0, 0.0]], &GATE),
        Err(Error::Shape { .. })
    ));
    assert!(matches!(
        solve_attitude(&two, &[[1.0, 0.0, 0.0], [0.0, 0.0, 0.0]], &GATE),
        Err(Error::OutOfRange {
            name: "body baselines",
            ..
        })
    ));
    let mut moved = two.clone();
    moved[1].base_m.x += 1.0;
    assert!(matches!(
        solve_attitude(&moved, &[[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]], &GATE),
        Err(Error::OutOfRange { name: "epochs", .. })
    ));
    let many = vec![e; constrained::MAX_ROVERS + 1];
    let body = vec![[1.0, 0.0, 0.0]; constrained::MAX_ROVERS + 1];
    assert!(matches!(
        solve_attitude(&many, &body, &GATE),
        Err(Error::TooLarge { .. })
    ));
}

/// Static session with a cycle slip: from epoch 15 satellite 2's arcs get new identities and its rover
/// phase jumps by 7 cycles. The new arcs carry their own ambiguities (integer = old + 7), the old ones
/// keep theirs, and everything is fixed right.
#[test]
fn static_session_gives_a_slipped_arc_its_own_ambiguity() {
    let mut sc = Scenario::new(140, &[(System::Gps, 8, &[0, 1])], 15.0);
    sc.code_ab = (1.0, 0.5);
    let truth = Vector3::new(2.0, 1.0, -3.0);
    const NEW: u64 = 3000; // arc offset of the slipped arcs (a multiple of 3 keeps the slot)
    let epochs: Vec<DdEpoch> = (0..30)
        .map(|k| {
            let mut e = sc.epoch(&truth, 20.0 * k as f64);
            if k >= 15 {
                for s in e.signals.iter_mut().filter(|s| s.sat == 2) {
                    s.arc += NEW;
                    s.rover_phase_cycles += 7.0;
                }
            }
            e
        })
        .collect();
    let s = solve_baseline(&epochs, &[], &GATE).unwrap();
    assert!(s.fixed, "{s:?}");
    let mut slipped = 0;
    for &(a, r, n) in &s.integers {
        let jump = |arc: u64| if arc >= NEW { 7 } else { 0 };
        let (k, slot) = Scenario::of_arc(a % NEW);
        let (q, _) = Scenario::of_arc(r % NEW);
        assert_eq!(n, sc.dd_integer(k, q, slot) + jump(a) - jump(r), "{a} {r}");
        slipped += usize::from(a >= NEW || r >= NEW);
    }
    assert!(slipped >= 2, "{slipped}");
    assert!(chi2(&s, &truth) < 16.27);
}
