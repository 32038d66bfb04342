use std::collections::HashMap;

use nalgebra::{DMatrix, DVector, Vector3};

use super::*;
use crate::gnss::rtk::dd::{covariance, groups};
use crate::gnss::rtk::model::SdRangeModel;
use crate::gnss::rtk::rigid::RigidLength;
use crate::gnss::rtk::sim::Scenario;
use crate::gnss::rtk::{BaselineSolution, DdEpoch, FixOptions};
use crate::gnss::signal::System;

const GATE: FixOptions = FixOptions {
    min_success_rate: 0.999,
    ratio_threshold: 3.0,
    max_failure_rate: 0.0,
};

/// Nothing reaches this gate: the filter stays float.
const NO_FIX: FixOptions = FixOptions {
    min_success_rate: 1.0,
    ratio_threshold: 1e300,
    max_failure_rate: 0.0,
};

const SECOND_NS: i64 = 1_000_000_000;

/// Integers of `s` that differ from the scenario's truth (`jump`: cycles added to an arc's rover phase).
fn wrong_integers(sc: &Scenario, s: &BaselineSolution, jump: &HashMap<u64, i64>) -> usize {
    s.integers
        .iter()
        .filter(|&&(a, r, n)| {
            let base = |arc: u64| if arc >= 1000 { arc - 1000 } else { arc };
            let (k, slot) = Scenario::of_arc(base(a));
            let (q, _) = Scenario::of_arc(base(r));
            let truth = sc.dd_integer(k, q, slot) + jump.get(&a).copied().unwrap_or(0)
                - jump.get(&r).copied().unwrap_or(0);
            truth != n
        })
        .count()
}

/// Batch least squares of every epoch with the filter's prior (baseline at the first epoch's code
/// solution, sigma 30 m per axis; each arc's single-difference ambiguity at its first phase minus code,
/// sigma 30 m): unknowns baseline and one single-difference ambiguity per arc, every double difference of
/// code and phase with its exact covariance, Gauss-Newton to convergence. Returns the baseline and its
/// covariance.
fn batch(epochs: &[DdEpoch]) -> (Vector3<f64>, DMatrix<f64>) {
    let BatchPrior {
        arcs,
        x0,
        prior_var,
        offsets,
    } = batch_prior(epochs);
    let n = x0.len();
    let x0 = DVector::from_vec(x0);
    let col = |arc: u64| 3 + arcs.iter().position(|&a| a == arc).unwrap();
    let mut x = x0.clone();
    // The iteration's own rounding floor: updates of a few 1e-8 m (the normal matrix's condition number,
    // about 1e9 between the 30 m priors and the millimetre phases, times 2e-16, times metres).
    for _ in 0..20 {
        let mut normal = DMatrix::from_diagonal(&DVector::from_fn(n, |i, _| 1.0 / prior_var[i]));
        let mut g = DVector::from_fn(n, |i, _| (x0[i] - x[i]) / prior_var[i]);
        let b = Vector3::new(x[0], x[1], x[2]);
        for e in epochs {
            let model = SdRangeModel::new(&e.base_m, &(e.base_m + b));
            for grp in groups(e) {
                let m = grp.members.len();
                let r = &e.signals[grp.reference];
                let (rho_r, u_r) = model.range_and_los(r);
                let mut a = DMatrix::<f64>::zeros(2 * m, n);
                let mut y = DVector::<f64>::zeros(2 * m);
                for (j, &k) in grp.members.iter().enumerate() {
                    let s = &e.signals[k];
                    let (rho_k, u_k) = model.range_and_los(s);
                    let lam_k = if grp.fdma {
                        s.wavelength_m
                    } else {
                        r.wavelength_m
                    };
                    let lam_r = r.wavelength_m;
                    let (ck, cr) = (col(s.arc), col(r.arc));
                    for c in 0..3 {
                        a[(j, c)] = u_r[c] - u_k[c];
                        a[(m + j, c)] = u_r[c] - u_k[c];
                    }
                    a[(m + j, ck)] = lam_k;
                    a[(m + j, cr)] = -lam_r;
                    y[j] = (s.rover_code_m - s.base_code_m)
                        - (r.rover_code_m - r.base_code_m)
                        - (rho_k - rho_r);
                    let phi = |p: &crate::gnss::rtk::SignalPair| {
                        p.rover_phase_cycles - p.base_phase_cycles - offsets[&p.arc]
                    };
                    y[m + j] = lam_k * phi(s)
                        - lam_r * phi(r)
                        - (rho_k - rho_r)
                        - (lam_k * x[ck] - lam_r * x[cr]);
                }
                let c = covariance(e, &grp)
                    .view((0, 0), (2 * m, 2 * m))
                    .into_owned();
                let w = c.try_inverse().unwrap();
                normal += a.transpose() * &w * &a;
                g += a.transpose() * &w * &y;
            }
        }
        let cov = normal.clone().try_inverse().unwrap();
        let dx = &cov * g;
        x += &dx;
        if dx.rows(0, 3).norm() < 1e-7 {
            let cov_b = cov.view((0, 0), (3, 3)).into_owned();
            return (Vector3::new(x[0], x[1], x[2]), cov_b);
        }
    }
    panic!("batch least squares did not converge");
}

/// The prior of [`batch`]: the unknowns' order and prior values and variances, and the integer offset
/// (cycles) taken from each arc's phase.
struct BatchPrior {
    /// The arcs in the order of their ambiguities (unknowns 3, 4, ...).
    arcs: Vec<u64>,
    /// Baseline (m) then single-difference ambiguities (cycles, less the offsets).
    x0: Vec<f64>,
    /// Prior variances of `x0`, m^2 then cycles^2.
    prior_var: Vec<f64>,
    offsets: HashMap<u64, f64>,
}

/// [`batch`]'s prior: the first epoch's code baseline, and each arc's phase minus code at its first
/// epoch.
fn batch_prior(epochs: &[DdEpoch]) -> BatchPrior {
    let mut arcs: Vec<u64> = Vec::new();
    let mut x0: Vec<f64> = Vec::new();
    let mut prior_var: Vec<f64> = vec![INITIAL_BASELINE_SIGMA_M.powi(2); 3];
    let mut offsets: HashMap<u64, f64> = HashMap::new();
    let b0 = epochs[0].rover_prior_m - epochs[0].base_m;
    x0.extend(b0.iter());
    for e in epochs {
        for s in &e.signals {
            if offsets.contains_key(&s.arc) {
                continue;
            }
            let start = (s.rover_phase_cycles - s.base_phase_cycles)
                - (s.rover_code_m - s.base_code_m) / s.wavelength_m;
            // Any integer offset gives the same solution; this one keeps the unknowns small.
            let o = start.round() - 3.0;
            offsets.insert(s.arc, o);
            arcs.push(s.arc);
            x0.push(start - o);
            prior_var.push((INITIAL_AMBIGUITY_SIGMA_M / s.wavelength_m).powi(2));
        }
    }
    BatchPrior {
        arcs,
        x0,
        prior_var,
        offsets,
    }
}

fn epochs(sc: &mut Scenario, truth: &Vector3<f64>, n: usize, step_s: f64) -> Vec<DdEpoch> {
    (0..n).map(|k| sc.epoch(truth, k as f64 * step_s)).collect()
}

#[test]
fn static_filter_float_equals_batch_least_squares() {
    for (seed, counts) in [
        (11, vec![(System::Gps, 8, &[0usize][..])]),
        (
            12,
            vec![
                (System::Gps, 7, &[0, 1][..]),
                (System::Galileo, 5, &[0][..]),
            ],
        ),
        (
            13,
            vec![(System::Glonass, 6, &[0][..]), (System::Gps, 6, &[0][..])],
        ),
    ] {
        let mut sc = Scenario::new(seed, &counts, 15.0);
        sc.prior_sigma_m = 0.5;
        let truth = Vector3::new(0.8, -0.5, 0.3);
        let eps = epochs(&mut sc, &truth, 15, 20.0);
        let mut f = BaselineFilter::new(Dynamics::Static).unwrap();
        let mut last = None;
        for (k, e) in eps.iter().enumerate() {
            last = Some(f.step(e, k as i64 * 20 * SECOND_NS, &NO_FIX).unwrap());
        }
        let last = last.unwrap();
        assert_eq!(last.state, FixState::Float);
        let (b, cov) = batch(&eps);
        // Kalman and batch solutions agree in exact arithmetic; in floating point the covariance form
        // loses about eps x (prior variance / posterior variance) = 2e-16 x 900 / 1e-6 ~ 2e-7 relative,
        // and the linearisation points differ by the filter's predictions (mm), a second-order term of
        // (1e-3)^2 / 2e7 m ~ 1e-13 m.
        let scale = cov.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let dcov = (last.float_covariance_m2 - &cov).abs().max();
        assert!(
            dcov < 2e-6 * scale,
            "seed {seed}: covariance off by {dcov:e} of {scale:e}"
        );
        // The batch's own rounding floor above (1e-7 m): ten times it.
        let db = (last.float_baseline_m - b).norm();
        assert!(db < 1e-6, "seed {seed}: baseline off by {db:e} m");
        // And the batch's baseline is the truth within its covariance (chi-square 3 dof, 0.999: 16.27).
        let e = b - truth;
        let chi2 = e.dot(&(cov.try_inverse().unwrap() * e));
        assert!(chi2 < 16.27, "seed {seed}: {chi2}");
    }
}

#[test]
fn a_wrong_integer_injected_into_the_held_set_is_rejected() {
    let mut sc = Scenario::new(21, &[(System::Gps, 9, &[0, 1])], 15.0);
    sc.prior_sigma_m = 1.0;
    let truth = Vector3::new(0.6, 0.7, -0.2);
    let mut f = BaselineFilter::new(Dynamics::KINEMATIC).unwrap();
    let none = HashMap::new();
    let mut k = 0i64;
    // Until fixed and held for a few epochs.
    let mut fixed = 0;
    while fixed < 3 {
        let e = sc.epoch(&truth, k as f64);
        let out = f.step(&e, k * SECOND_NS, &GATE).unwrap();
        if out.solution.fixed {
            assert_eq!(wrong_integers(&sc, &out.solution, &none), 0);
            fixed += 1;
        }
        k += 1;
        assert!(k < 30, "never fixed");
    }
    let held = f.held_arcs();
    assert!(held.len() >= 10, "{held:?}");
    for (i, &arc) in held.iter().enumerate().take(3) {
        assert!(f.corrupt_held(arc, if i % 2 == 0 { 1 } else { -2 }));
        let e = sc.epoch(&truth, k as f64);
        let out = f.step(&e, k * SECOND_NS, &GATE).unwrap();
        k += 1;
        // Rejected either way: the whole held set dropped (its chi-square against the float), or the
        // arc started again (its phase residual at the held baseline).
        assert!(
            out.hold_rejected || out.restarted_arcs > 0,
            "arc {arc}: the wrong hold was kept"
        );
        assert_eq!(wrong_integers(&sc, &out.solution, &none), 0);
        // The next epochs hold the right integers again.
        let e = sc.epoch(&truth, k as f64);
        let out = f.step(&e, k * SECOND_NS, &GATE).unwrap();
        k += 1;
        assert!(!out.hold_rejected);
        assert_eq!(wrong_integers(&sc, &out.solution, &none), 0);
    }
}

#[test]
fn injected_slips_restart_their_arcs_and_only_those() {
    let mut sc = Scenario::new(31, &[(System::Gps, 8, &[0, 1])], 15.0);
    sc.prior_sigma_m = 1.0;
    let truth = Vector3::new(-0.4, 0.9, 0.1);
    let mut f = BaselineFilter::new(Dynamics::KINEMATIC).unwrap();
    let slips: [(usize, usize, i64); 2] = [(8, 2, 17), (14, 5, -3)]; // epoch, satellite, cycles
    let mut jump: HashMap<u64, i64> = HashMap::new();
    let mut slipped: Vec<usize> = Vec::new();
    for k in 0..20usize {
        let mut e = sc.epoch(&truth, k as f64);
        for &(at, sat, cycles) in &slips {
            if k >= at {
                if k == at {
                    slipped.push(sat);
                }
                // A slip of the rover's slot-0 phase: the arc tracker gives the pair a new arc.
                for s in e.signals.iter_mut().filter(|s| s.sat == sat && s.slot == 0) {
                    s.rover_phase_cycles += cycles as f64;
                    s.arc = Scenario::arc(sat, 0) + 1000;
                    jump.insert(s.arc, cycles);
                }
            }
        }
        let out = f.step(&e, k as i64 * SECOND_NS, &GATE).unwrap();
        let expected = match k {
            0 => e.signals.len(),
            _ if slips.iter().any(|&(at, ..)| at == k) => 1,
            _ => 0,
        };
        assert_eq!(out.new_arcs, expected, "epoch {k}");
        assert_eq!(wrong_integers(&sc, &out.solution, &jump), 0, "epoch {k}");
        if out.solution.fixed {
            // chi-square with 3 degrees of freedom: 16.27 is its 0.999 quantile.
            let err = out.solution.baseline_m - truth;
            let chi2 = err.dot(&(out.solution.covariance_m2.try_inverse().unwrap() * err));
            assert!(chi2 < 16.27, "epoch {k}: {chi2}, {:?}", out.state);
        }
        if k > 2 {
            assert!(out.solution.fixed, "epoch {k}: {:?}", out.state);
        }
    }
    assert_eq!(slipped, vec![2, 5]);
}

#[test]
fn refuses_bad_process_noise_and_time_order() {
    assert!(BaselineFilter::new(Dynamics::RandomWalk { q_m2_s: -1.0 }).is_err());
    assert!(BaselineFilter::new(Dynamics::ConstantVelocity { q_m2_s3: f64::NAN }).is_err());
    let mut sc = Scenario::new(41, &[(System::Gps, 8, &[0])], 15.0);
    let truth = Vector3::new(1.0, 0.0, 0.0);
    let mut f = BaselineFilter::new(Dynamics::VELOCITY).unwrap();
    f.step(&sc.epoch(&truth, 0.0), SECOND_NS, &GATE).unwrap();
    let again = f.step(&sc.epoch(&truth, 0.0), SECOND_NS, &GATE);
    assert!(matches!(again, Err(crate::error::Error::OutOfRange { .. })));
}

#[test]
fn an_epochs_own_fix_agrees_with_the_float_unless_it_is_off_beyond_their_covariance() {
    // GPS L1 + L2, 9 satellites: single epochs fix; the filter, gated shut, stays float.
    let mut sc = Scenario::new(33, &[(System::Gps, 9, &[0, 1])], 15.0);
    let truth = Vector3::new(0.6, 0.7, -0.2);
    let mut f = BaselineFilter::new(Dynamics::KINEMATIC).unwrap();
    for k in 0..5i64 {
        let e = sc.epoch(&truth, k as f64);
        let out = f.step(&e, k * SECOND_NS, &NO_FIX).unwrap();
        assert_eq!(out.state, FixState::Float);
        let single =
            crate::gnss::rtk::solve_baseline(std::slice::from_ref(&e), &[], &GATE).unwrap();
        assert!(single.fixed, "epoch {k}: the single epoch does not fix");
        assert!(out.agrees_with_float(&single), "epoch {k}");
        // The float moved along x to a chi-square of exactly s^2 (the 3-dof quantile at 1e-3 is 16.3).
        let c = out.float_covariance_m2 + single.covariance_m2;
        let dir = Vector3::new(1.0, 0.0, 0.0);
        let ci = c.try_inverse().unwrap();
        let unit = 1.0 / dir.dot(&(ci * dir)).sqrt();
        for (s, agrees) in [(2.0, true), (10.0, false)] {
            let mut moved = single.clone();
            moved.baseline_m = out.float_baseline_m + dir * (s * unit);
            assert_eq!(
                out.agrees_with_float(&moved),
                agrees,
                "epoch {k}, {s} sigmas"
            );
        }
    }
}

/// Steps `f` through `n` epochs of `truth` from epoch `k0` (1 s apart): how many it reported fixed or
/// held, and whether any of them refused a fix for its length.
fn run(
    f: &mut BaselineFilter,
    sc: &mut Scenario,
    truth: &Vector3<f64>,
    k0: i64,
    n: i64,
) -> (usize, bool) {
    let (mut fixed, mut refused) = (0, false);
    for k in k0..k0 + n {
        let out = f
            .step(&sc.epoch(truth, k as f64), k * SECOND_NS, &GATE)
            .unwrap();
        fixed += usize::from(out.state != FixState::Float);
        refused |= out.length_refused;
        if out.state != FixState::Float {
            assert!((out.solution.baseline_m - truth).norm() < 0.05, "epoch {k}");
        }
    }
    (fixed, refused)
}

#[test]
fn a_fix_whose_length_disagrees_with_the_known_length_is_refused() {
    let truth = Vector3::new(0.6, 0.7, -0.2);
    for (length_m, expect_fixes) in [(truth.norm(), true), (truth.norm() + 0.2, false)] {
        let mut sc = Scenario::new(21, &[(System::Gps, 9, &[0, 1])], 15.0);
        sc.prior_sigma_m = 1.0;
        let mut f = BaselineFilter::new(Dynamics::KINEMATIC)
            .unwrap()
            .with_length(RigidLength::known(length_m));
        let (fixed, refused) = run(&mut f, &mut sc, &truth, 0, 10);
        assert_eq!(fixed > 5, expect_fixes, "length {length_m}: {fixed} fixed");
        assert_eq!(refused, !expect_fixes, "length {length_m}");
        if !expect_fixes {
            assert_eq!(fixed, 0);
            assert!(f.held_arcs().is_empty(), "a refused fix was held");
        }
    }
}

#[test]
fn a_rigid_filter_refuses_fixes_of_another_length_after_every_arc_restarted() {
    // The learned length stands after RIGID_MIN_FIXES fixes; then every arc restarts (an outage) and
    // the data show a baseline 0.3 m longer: what a wrong fix looks like to the check. A filter that is
    // not told the pair is rigid fixes it (a rover moving against its base may do that).
    let first = Vector3::new(0.6, 0.7, -0.2);
    let longer = first * (1.0 + 0.3 / first.norm());
    for rigid in [true, false] {
        let mut sc = Scenario::new(21, &[(System::Gps, 9, &[0, 1])], 15.0);
        sc.prior_sigma_m = 1.0;
        let f = BaselineFilter::new(Dynamics::KINEMATIC).unwrap();
        let mut f = if rigid {
            f.with_length(RigidLength::learned())
        } else {
            f
        };
        let (fixed, refused) = run(&mut f, &mut sc, &first, 0, 15);
        assert!(fixed >= super::super::rigid::RIGID_MIN_FIXES, "{fixed}");
        assert!(!refused);
        f.reset();
        let (fixed, refused) = run(&mut f, &mut sc, &longer, 15, 10);
        assert_eq!(refused, rigid);
        assert_eq!(fixed == 0, rigid, "rigid {rigid}: {fixed} fixed");
    }
}

#[test]
fn a_wrong_learned_length_is_learned_again_when_the_later_fixes_agree() {
    // The session's first fixes give a length 0.3 m too long (what a wrong first learned length looks
    // like to the check); after an outage the data show the true one. The first fixes of the true
    // length are refused; once as many agree with each other as made the learned length, it is learned
    // again and the fixes are reported (each checked against the truth by `run`).
    let truth = Vector3::new(0.6, 0.7, -0.2);
    let longer = truth * (1.0 + 0.3 / truth.norm());
    let mut sc = Scenario::new(21, &[(System::Gps, 9, &[0, 1])], 15.0);
    sc.prior_sigma_m = 1.0;
    let mut f = BaselineFilter::new(Dynamics::KINEMATIC)
        .unwrap()
        .with_length(RigidLength::learned());
    let (first_fixes, _) = run(&mut f, &mut sc, &longer, 0, 12);
    assert!(first_fixes >= super::super::rigid::RIGID_MIN_FIXES);
    let (l, _) = f.length().unwrap().reference().unwrap();
    assert!((l - longer.norm()).abs() < 0.01, "{l}");
    f.reset();
    let n = 40;
    let (fixed, refused) = run(&mut f, &mut sc, &truth, 12, n);
    assert!(refused);
    assert!(
        fixed + first_fixes + 2 >= n as usize,
        "{fixed} of {n} fixed"
    );
    let (l, _) = f.length().unwrap().reference().unwrap();
    assert!(
        (l - truth.norm()).abs() < 0.01,
        "{l} against {}",
        truth.norm()
    );
}

#[test]
fn a_fix_without_phase_redundancy_is_not_reported() {
    // GPS L1 only: with 4 satellites (3 double-differenced phases for the 3 baseline unknowns) every
    // integer set fits the phases; with a second frequency (6) they show a wrong one. Static, 30 s
    // apart: the geometry changes and the float converges. The engine's default gate.
    const GATE: FixOptions = FixOptions {
        min_success_rate: 0.5,
        ratio_threshold: 3.0,
        max_failure_rate: 0.0,
    };
    for (slots, expect_fixes) in [(&[0usize][..], false), (&[0, 1][..], true)] {
        let mut sc = Scenario::new(51, &[(System::Gps, 4, slots)], 15.0);
        sc.prior_sigma_m = 1.0;
        let truth = Vector3::new(0.6, 0.7, -0.2);
        let eps = epochs(&mut sc, &truth, 40, 30.0);
        let mut f = BaselineFilter::new(Dynamics::Static).unwrap();
        let mut fixed = 0;
        for (k, e) in eps.iter().enumerate() {
            let out = f.step(e, k as i64 * 30 * SECOND_NS, &GATE).unwrap();
            fixed += usize::from(out.state != FixState::Float);
        }
        assert_eq!(fixed > 0, expect_fixes, "slots {slots:?}: {fixed} fixed");
        if !expect_fixes {
            // The data would fix: the batch solution of the same epochs passes the same gate.
            let batch = crate::gnss::rtk::solve_baseline(&eps, &[], &GATE).unwrap();
            assert!(batch.fixed, "the premise: the epochs fix");
            // The single-epoch fallback's fixes go through the same rule (one epoch: one phase per
            // ambiguity).
            for (phases, accepted) in [(3, false), (4, true)] {
                let one = BaselineSolution {
                    ambiguities: phases,
                    ..batch.clone()
                };
                assert_eq!(f.admit(&one), accepted, "{phases} phases");
            }
        }
    }
}

#[test]
fn a_known_length_fixes_the_filter_earlier_and_right() {
    // GPS L1 only, 7 satellites, kinematic: the first epochs' float is code-wide; the constrained search
    // (the length as a constraint of the integer search: rtk/known_length.rs) on the filter's covariance
    // fixes before the unconstrained gate does, with the right integers.
    let truth = Vector3::new(0.6, 0.7, -0.2);
    let first_fix = |known: bool| {
        let mut sc = Scenario::new(61, &[(System::Gps, 7, &[0])], 15.0);
        sc.prior_sigma_m = 1.0;
        let f = BaselineFilter::new(Dynamics::KINEMATIC).unwrap();
        let mut f = if known {
            f.with_length(RigidLength::known(truth.norm()))
        } else {
            f
        };
        let none = HashMap::new();
        for k in 0..60i64 {
            let out = f
                .step(&sc.epoch(&truth, k as f64), k * SECOND_NS, &GATE)
                .unwrap();
            if out.state != FixState::Float {
                assert_eq!(wrong_integers(&sc, &out.solution, &none), 0, "epoch {k}");
                return Some(k);
            }
        }
        None
    };
    let (with, without) = (first_fix(true), first_fix(false));
    assert!(with.is_some(), "never fixed with the known length");
    assert!(
        without.is_none_or(|w| with.unwrap() < w),
        "{with:?} vs {without:?}"
    );
}
