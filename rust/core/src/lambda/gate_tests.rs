//! The gate against what nobody here wrote: the ratio from a brute-force enumeration of integer vectors,
//! the fixed-failure-rate test's closed-form shortcut (a bootstrapped failure rate already below the
//! allowed one admits every fix), and the rules' definitions.

use nalgebra::{DMatrix, DVector};

use super::*;
use crate::lambda::bootstrap::erf;
use crate::lambda::test_support::{random_covariance, Lcg};
use crate::lambda::DEFAULT_MAX_NODES;

/// The two smallest `(a - z)^T Q^-1 (a - z)` over every integer `z` of a box around `round(a)` wide enough
/// to hold them: `||a - z||^2 <= K` implies `|a_i - z_i| <= sqrt(K q_ii)`, with `K` the second smallest norm
/// of `round(a)` and its `n` unit neighbours (an upper bound of the true second best).
fn brute_force_two_best(a: &DVector<f64>, q: &DMatrix<f64>) -> [f64; 2] {
    let n = a.len();
    let qi = q.clone().try_inverse().unwrap();
    let norm = |z: &DVector<f64>| {
        let r = a - z;
        r.dot(&(&qi * &r))
    };
    let base = a.map(f64::round);
    let mut near: Vec<f64> = (0..n)
        .map(|i| {
            let mut z = base.clone();
            z[i] += if a[i] > base[i] { 1.0 } else { -1.0 };
            norm(&z)
        })
        .chain([norm(&base)])
        .collect();
    near.sort_by(f64::total_cmp);
    let k = near[1];
    let lo: Vec<i64> = (0..n)
        .map(|i| (a[i] - (k * q[(i, i)]).sqrt()).floor() as i64)
        .collect();
    let hi: Vec<i64> = (0..n)
        .map(|i| (a[i] + (k * q[(i, i)]).sqrt()).ceil() as i64)
        .collect();
    let mut best = [f64::INFINITY; 2];
    let mut z: Vec<i64> = lo.clone();
    loop {
        let f = norm(&DVector::from_fn(n, |i, _| z[i] as f64));
        if f < best[0] {
            best = [f, best[0]];
        } else if f < best[1] {
            best[1] = f;
        }
        let Some(i) = (0..n).find(|&i| z[i] < hi[i]) else {
            return best;
        };
        z[i] += 1;
        z[..i].copy_from_slice(&lo[..i]);
    }
}

fn gate(min_success_rate: f64, ratio_threshold: f64, max_failure_rate: f64) -> Gate {
    Gate {
        min_success_rate,
        ratio_threshold,
        max_failure_rate,
    }
}

/// Float ambiguities around integers with a covariance from weak to strong: every outcome of the rule
/// occurs.
fn cases() -> Vec<(DVector<f64>, DMatrix<f64>)> {
    let mut rng = Lcg(19);
    (0..60)
        .map(|k| {
            let n = 2 + k % 3;
            let scale = [0.002, 0.02, 0.08, 0.3][k % 4];
            let q = random_covariance(&mut rng, n, 0.2) * scale;
            let a = DVector::from_fn(n, |_, _| 20.0 * rng.normal() + 0.5 * rng.normal());
            (a, q)
        })
        .collect()
}

#[test]
fn ils_rule_is_ratio_and_success_rate_with_a_brute_force_ratio() {
    let mut reasons = std::collections::HashSet::new();
    for (a, q) in cases() {
        let problem = Problem::new(&a, &q).unwrap();
        let best = problem.solve(2, DEFAULT_MAX_NODES).unwrap();
        let [f1, f2] = brute_force_two_best(&a, &q);
        let ratio = f2 / f1;
        let rate = super::success_rate(problem.reduction.factor.d.as_slice());
        for (min, c) in [
            (0.0, 1.0),
            (0.5, 2.0),
            (0.9, 3.0),
            (0.999, 3.0),
            (0.99, 1.5),
        ] {
            let g = gate(min, c, 0.0);
            let d = g.decide(&problem, &best).unwrap();
            assert!(
                (d.ratio - ratio).abs() <= 1e-9 * ratio,
                "{} vs {ratio}",
                d.ratio
            );
            assert_eq!(d.success_rate, rate);
            // Away from the threshold by more than the norms' rounding, the brute-force ratio decides.
            if (ratio - c).abs() > 1e-9 * c {
                assert_eq!(
                    d.accepted,
                    ratio >= c && rate >= min,
                    "{d:?} {ratio} {rate}"
                );
            }
            let want = if d.ratio < c || d.ratio.is_nan() {
                Reason::LowRatio
            } else if rate >= min {
                Reason::Passed
            } else {
                Reason::LowSuccessRate
            };
            assert_eq!(d.reason, want);
            reasons.insert(format!("{:?}", d.reason));
            // Refusing before the search is refusing after it.
            if let Some(early) = g.before_search(&problem) {
                assert!(!d.accepted && rate < min && early.success_rate == rate);
                assert_eq!((early.ratio, early.accepted), (0.0, false));
            } else {
                assert!(rate >= min);
            }
        }
    }
    assert_eq!(reasons.len(), 3, "{reasons:?}");
}

#[test]
fn failure_rate_test_admits_a_set_whose_bootstrapped_failure_rate_is_below_it() {
    // Three independent ambiguities of sigma 0.15 cycle: success rate erf(0.5 / (0.15 sqrt 2))^3 = 0.99743
    // (a 3.33-sigma interval per ambiguity), so a failure rate of 0.0026 < 0.01 is allowed: accepted whenever the ratio passes, without
    // simulation; with the test off, refused for the gate of 0.9999.
    let q = DMatrix::from_diagonal_element(3, 3, 0.0225);
    let rate = erf(0.5 / (0.15 * 2f64.sqrt())).powi(3);
    assert!((rate - 0.997_43).abs() < 1e-5, "{rate}");
    let mut seen = [0usize; 2];
    for a in [
        [0.1, -0.2, 0.05],
        [0.4, 0.45, -0.3],
        [0.02, 0.01, 0.0],
        [0.3, 0.3, 0.3],
    ] {
        let a = DVector::from_row_slice(&a);
        let problem = Problem::new(&a, &q).unwrap();
        let best = problem.solve(2, DEFAULT_MAX_NODES).unwrap();
        let ffrt = gate(0.9999, 2.0, 0.01);
        assert!(ffrt.before_search(&problem).is_none());
        let d = ffrt.decide(&problem, &best).unwrap();
        assert!((d.success_rate - rate).abs() < 1e-12);
        assert_eq!(d.accepted, d.ratio >= 2.0, "{d:?}");
        seen[usize::from(d.accepted)] += 1;
        let off = gate(0.9999, 2.0, 0.0).decide(&problem, &best).unwrap();
        assert!(!off.accepted);
        assert!(gate(0.9999, 2.0, 0.0).before_search(&problem).is_some());
    }
    assert!(seen[0] > 0 && seen[1] > 0, "{seen:?}");
}

#[test]
fn failure_rate_test_refuses_a_wrong_prone_set_and_stops_beyond_its_dimension() {
    // Sigma 0.4 cycle per ambiguity, n = 4: success rate erf(0.5 / (0.4 sqrt 2))^4 = 0.31; at a ratio just
    // above 1 many wrong draws have a larger ratio, so a 1 % failure rate refuses.
    let q = DMatrix::from_diagonal_element(4, 4, 0.16);
    let a = DVector::from_row_slice(&[0.45, -0.4, 0.3, 0.48]);
    let problem = Problem::new(&a, &q).unwrap();
    let best = problem.solve(2, DEFAULT_MAX_NODES).unwrap();
    let d = gate(0.99, 1.0, 0.01).decide(&problem, &best).unwrap();
    assert!(d.ratio < 1.2, "{d:?}");
    assert_eq!((d.accepted, d.reason), (false, Reason::FailureRate));
    // Beyond FFRT_MAX_AMBIGUITIES the test is not simulated: the success-rate gate alone decides.
    let n = FFRT_MAX_AMBIGUITIES + 1;
    let q = DMatrix::from_diagonal_element(n, n, 0.0225);
    let a = DVector::from_element(n, 0.01);
    let problem = Problem::new(&a, &q).unwrap();
    let g = gate(0.9999, 1.0, 0.1);
    assert!(g.before_search(&problem).is_some());
    let best = problem.solve(2, DEFAULT_MAX_NODES).unwrap();
    let d = g.decide(&problem, &best).unwrap();
    assert_eq!((d.accepted, d.reason), (false, Reason::LowSuccessRate));
}

#[test]
fn constrained_rule_simulates_only_what_passes() {
    let g = gate(0.5, 3.0, 0.0);
    let never = || -> Result<f64> { panic!("simulated a refused fix") };
    let d = g
        .decide_constrained(2.0, 1.0, 10.0, Some(0.95), never)
        .unwrap();
    assert_eq!((d.accepted, d.reason), (false, Reason::LowRatio));
    assert!(d.success_rate.is_nan());
    let d = g
        .decide_constrained(f64::NAN, 1.0, 10.0, None, never)
        .unwrap();
    assert_eq!(d.reason, Reason::LowRatio);
    let d = g.decide_constrained(4.0, 11.0, 10.0, None, never).unwrap();
    assert_eq!((d.accepted, d.reason), (false, Reason::Implausible));
    // The floor applies when above min_success_rate, min_success_rate when above the floor.
    let d = g
        .decide_constrained(4.0, 1.0, 10.0, Some(0.95), || Ok(0.94))
        .unwrap();
    assert_eq!(
        (d.accepted, d.reason, d.success_rate),
        (false, Reason::LowSuccessRate, 0.94)
    );
    let d = g
        .decide_constrained(4.0, 1.0, 10.0, Some(0.95), || Ok(0.95))
        .unwrap();
    assert!(d.accepted);
    let strict = gate(0.99, 3.0, 0.0);
    let d = strict
        .decide_constrained(4.0, 1.0, 10.0, Some(0.95), || Ok(0.97))
        .unwrap();
    assert!(!d.accepted);
    // Without a floor the rate is reported, not gated.
    let d = strict
        .decide_constrained(f64::INFINITY, 0.0, 10.0, None, || Ok(0.1))
        .unwrap();
    assert_eq!(
        (d.accepted, d.reason, d.success_rate),
        (true, Reason::Passed, 0.1)
    );
}

#[test]
fn decide_needs_two_candidates() {
    let q = DMatrix::from_diagonal_element(2, 2, 0.01);
    let problem = Problem::new(&DVector::from_row_slice(&[0.1, 0.2]), &q).unwrap();
    let one = problem.solve(1, DEFAULT_MAX_NODES).unwrap();
    let err = gate(0.0, 1.0, 0.0).decide(&problem, &one).unwrap_err();
    assert!(matches!(err, Error::Shape { .. }), "{err}");
}

#[test]
fn check_names_the_setting_the_range_and_the_value() {
    for (g, names, want) in [
        (
            gate(1.5, 3.0, 0.0),
            Names::PYTHON,
            ["min_success_rate", "[0, 1]", "1.5"],
        ),
        (
            gate(0.9, 0.5, 0.0),
            Names::PYTHON,
            ["ratio_threshold", ">= 1", "0.5"],
        ),
        (
            gate(0.9, f64::INFINITY, 0.0),
            Names::CLI,
            ["--ratio-threshold", ">= 1", "inf"],
        ),
        (
            gate(0.9, 3.0, 0.2),
            Names::CLI,
            ["--max-failure-rate", "[0, 0.1]", "0.2"],
        ),
        (
            gate(f64::NAN, 3.0, 0.0),
            Names::CLI,
            ["--min-success-rate", "[0, 1]", "NaN"],
        ),
        (
            gate(0.9, 3.0, -0.01),
            Names::PYTHON,
            ["max_failure_rate", "[0, 0.1]", "-0.01"],
        ),
    ] {
        let msg = g.check(&names).unwrap_err().to_string();
        for w in want {
            assert!(msg.contains(w), "{msg:?} lacks {w:?}");
        }
    }
    for g in [gate(0.0, 1.0, 0.0), gate(1.0, 1e6, MAX_FAILURE_RATE)] {
        g.check(&Names::CLI).unwrap();
    }
}
