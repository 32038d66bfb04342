//! The code noise scale against simulated receivers whose noise is a known multiple of the model, and the
//! common variance factor's invariances (module documentation of `code_scale`).

use nalgebra::Vector3;

use super::*;
use crate::gnss::rtk::constrained::chi2_quantile_at;
use crate::gnss::rtk::filter::{BaselineFilter, Dynamics};
use crate::gnss::rtk::sim::Scenario;
use crate::gnss::rtk::{solve_baseline, FixOptions};
use crate::gnss::signal::System;
use crate::gnss::solution::FixState;

const GATE: FixOptions = FixOptions {
    min_success_rate: 0.5,
    ratio_threshold: 3.0,
    max_failure_rate: 0.0,
};

const SECOND_NS: i64 = 1_000_000_000;

/// Standard normal quantile of a two-sided `1e-4` interval.
const Z_TWO_SIDED_1E4: f64 = 3.891;

/// `n` epochs, `dt_s` apart, of 8 GPS satellites on `slots` whose code noise is `code_scale` times the
/// model's sigma (`0.3 m + 0.3 m / sin el`, the engine's default) while the epochs carry the model's
/// sigma, as the engine gives them.
fn quiet_receiver(
    seed: u64,
    slots: &[usize],
    code_scale: f64,
    n: usize,
    dt_s: f64,
) -> Vec<DdEpoch> {
    let mut sc = Scenario::new(seed, &[(System::Gps, 8, slots)], 15.0);
    sc.code_ab = (0.3 * code_scale, 0.3 * code_scale);
    let baseline = Vector3::new(3.0, -4.0, 1.5);
    (0..n)
        .map(|k| {
            let mut dd = sc.epoch(&baseline, k as f64 * dt_s);
            dd.signals
                .iter_mut()
                .for_each(|s| s.sigma_code_m /= code_scale);
            dd
        })
        .collect()
}

#[test]
fn the_estimate_recovers_a_known_code_noise_scale_within_its_chi_square_interval() {
    // The float residuals of a single epoch are the code's (each phase has its own ambiguity), so the
    // summed chi-square over the model's variances is s^2 chi2(D): the estimate lies in
    // [s^2 q(D, -z) / D, s^2 q(D, z) / D] but with probability 1e-4.
    for (seed, s) in [(11, 0.5), (12, 0.42), (13, 1.6)] {
        let epochs = quiet_receiver(seed, &[0, 1], s, 40, 5.0);
        let mut unscaled = CodeNoiseScale::default();
        let mut common = CodeNoiseScale::default();
        let f = 0.25;
        for dd in &epochs {
            let one = solve_baseline(std::slice::from_ref(dd), &[], &GATE).unwrap();
            unscaled.add(&one, 1.0);
            let scaled = scale_noise(dd, f);
            let sol = solve_baseline(std::slice::from_ref(scaled.as_ref()), &[], &GATE).unwrap();
            common.add(&sol, f);
        }
        let dof = unscaled.dof as usize;
        assert!(dof >= 300, "dof {dof}");
        let est = unscaled.estimate().unwrap();
        let lo = s * s * chi2_quantile_at(dof, -Z_TWO_SIDED_1E4) / dof as f64;
        let hi = s * s * chi2_quantile_at(dof, Z_TWO_SIDED_1E4) / dof as f64;
        assert!(
            (lo..=hi).contains(&est),
            "scale {s}: estimate {est} outside [{lo}, {hi}] ({dof} dof)"
        );
        // Solving with the common factor and adding with it gives the same estimate.
        let c = common.estimate().unwrap();
        assert!((c - est).abs() <= 1e-6 * est, "{c} vs {est}");
    }
}

#[test]
fn a_common_factor_leaves_the_single_epoch_float_and_ratio_those_of_the_model() {
    // a and b do not depend on a common factor f; every ILS objective is divided by f, so the ratio is
    // the model's; the bootstrapped success rate rises as f falls (each conditional variance times f).
    let epochs = quiet_receiver(21, &[0, 1], 0.42, 6, 30.0);
    let mut code_only_moved = 0;
    for dd in &epochs {
        let model = solve_baseline(std::slice::from_ref(dd), &[], &GATE).unwrap();
        for f in [0.25, 4.0] {
            let scaled = scale_noise(dd, f);
            let sol = solve_baseline(std::slice::from_ref(scaled.as_ref()), &[], &GATE).unwrap();
            assert!((sol.baseline_m - model.baseline_m).norm() < 1e-6);
            assert!(
                (sol.ratio - model.ratio).abs() <= 1e-6 * model.ratio,
                "f {f}: ratio {} vs the model's {}",
                sol.ratio,
                model.ratio
            );
            assert_eq!(sol.fixed, model.fixed);
            if f < 1.0 {
                assert!(sol.success_rate >= model.success_rate);
            } else {
                assert!(sol.success_rate <= model.success_rate);
            }
        }
        // Scaling the code alone changes the covariance's shape, hence the ratio: what the common
        // factor avoids.
        let code = scale_code(dd, 0.25);
        let sol = solve_baseline(std::slice::from_ref(code.as_ref()), &[], &GATE).unwrap();
        if (sol.ratio - model.ratio).abs() > 1e-2 * model.ratio {
            code_only_moved += 1;
        }
    }
    assert!(
        code_only_moved > 0,
        "the code-only scale never moved the ratio"
    );
}

#[test]
fn a_common_factor_leaves_the_filter_float_near_the_model_and_fixes_no_later() {
    // The filter's estimates are least squares with a prior: a common factor f of the measurement
    // variances leaves them unchanged but for the prior's weight, which is not scaled. That weight is
    // at most the DD code variance over the prior's (about 3 m^2 / 30^2 m^2 = 3e-3 at the first epoch,
    // less as epochs add up), times the prior's error (the code solution's, 2 m per axis): a few mm.
    // Single frequency, 1 s epochs: the first fix comes from the epochs accumulated. The ratio is the
    // model's and the success rate higher (the conditional variances times f), so the scaled filter
    // fixes first no later than the model's.
    let epochs = quiet_receiver(31, &[0], 0.42, 40, 1.0);
    let mut model = BaselineFilter::new(Dynamics::KINEMATIC).unwrap();
    let mut common = BaselineFilter::new(Dynamics::KINEMATIC).unwrap();
    let mut first = (None, None);
    for (k, dd) in epochs.iter().enumerate() {
        let t = k as i64 * SECOND_NS;
        let a = model.step(dd, t, &GATE).unwrap();
        let b = common
            .step(scale_noise(dd, 0.25).as_ref(), t, &GATE)
            .unwrap();
        let moved = (a.float_baseline_m - b.float_baseline_m).norm();
        assert!(moved < 0.01, "epoch {k}: float baselines {moved} m apart");
        if a.state != FixState::Float {
            first.0.get_or_insert(k);
        }
        if b.state != FixState::Float {
            first.1.get_or_insert(k);
        }
    }
    let (Some(a), Some(b)) = first else {
        panic!("a filter never fixed: {first:?}");
    };
    assert!(
        b <= a,
        "first fixes at epoch {a} (model) and {b} (factor 0.25)"
    );
}

#[test]
fn scale_noise_scales_code_and_phase_sigmas_by_the_root_of_the_factor() {
    let dd = &quiet_receiver(41, &[0], 1.0, 1, 0.0)[0];
    let scaled = scale_noise(dd, 0.25);
    for (a, b) in dd.signals.iter().zip(&scaled.signals) {
        assert!((b.sigma_code_m - 0.5 * a.sigma_code_m).abs() < 1e-15);
        assert!((b.sigma_phase_m - 0.5 * a.sigma_phase_m).abs() < 1e-15);
    }
    assert!(matches!(scale_noise(dd, 1.0), Cow::Borrowed(_)));
}
