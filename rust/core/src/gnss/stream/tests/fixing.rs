//! Integer fixing of single epochs: a short and a long baseline, static against moving, the fix rate over a minute.

use nalgebra::Vector3;

use super::simulation::{base_position, fixed_error, options, simulate};
use crate::gnss::options::{EngineOptions, Motion};
use crate::gnss::session::run;
use crate::gnss::signal::System;

#[test]
fn single_epoch_fixes_a_one_metre_and_a_three_kilometre_baseline() {
    // Four systems on two frequencies (about 30 satellites) give success rates near 1 on both; an
    // error above 5 cm would be a wrong fix (one L1 cycle is 19 cm), the float noise is centimetres.
    for (baseline, tol) in [([0.6, -0.8, 0.05], 0.01), ([1800.0, -2400.0, 12.0], 0.02)] {
        let truth = simulate(10, &[baseline], 1);
        let sol = run(&truth.obs, &truth.nav, &options()).expect("session solves");
        let (err, fixed) = fixed_error(&truth, &sol.epochs);
        assert_eq!(fixed, 10, "every epoch fixed for {baseline:?}");
        assert!(err < tol, "baseline error {err} m for {baseline:?}");
        assert!(sol.epochs.iter().all(|e| e.satellites() >= 20));
        assert!(sol.epochs.iter().all(|e| e.frequency_slots_used == 0b11));
        // Per system: GPS, GLONASS, Galileo, BeiDou all formed double differences on both slots.
        for sys in [
            System::Gps,
            System::Glonass,
            System::Galileo,
            System::BeiDou,
        ] {
            assert!(sol.double_differences[sys.index()]
                .iter()
                .take(2)
                .all(|&n| n > 0));
        }
        // Angles are those of the ENU baseline.
        let e = &sol.epochs[0];
        let [east, north, _] = e.baselines_enu_m[0];
        let az = east.atan2(north).to_degrees().rem_euclid(360.0);
        assert!((e.angles_deg[0] - az).abs() < 1e-9);
        assert!(e.angle_sigmas_deg.iter().all(|s| s.is_finite() && *s > 0.0));
    }
}

#[test]
fn static_and_moving_agree_and_a_surveyed_base_is_used() {
    let truth = simulate(8, &[[0.6, -0.8, 0.05]], 2);
    let moving = run(&truth.obs, &truth.nav, &options()).unwrap();
    let mut opts = options();
    opts.motion = Motion::Static;
    opts.base_position_m = Some(base_position().into());
    let stat = run(&truth.obs, &truth.nav, &opts).unwrap();
    let (err, fixed) = fixed_error(&truth, &stat.epochs);
    assert_eq!(fixed, 8);
    assert!(err < 0.01, "static error {err} m");
    for (a, b) in moving.epochs.iter().zip(&stat.epochs) {
        let d = Vector3::from(a.baselines_enu_m[0]) - Vector3::from(b.baselines_enu_m[0]);
        assert!(d.norm() < 0.01);
        assert_eq!(b.base_position_m, <[f64; 3]>::from(base_position()));
    }
    assert!(stat.warnings.is_empty(), "{:?}", stat.warnings);
}

#[test]
fn fix_rate_and_no_wrong_fix_over_a_minute_of_gps_l1_l2() {
    // GPS alone on L1 + L2, 60 single epochs on 1 m: the gate at 0.999 allows one wrong fix per
    // thousand fixed epochs in expectation, so none is expected here; an error above 5 cm is wrong.
    let truth = simulate(60, &[[0.6, -0.8, 0.05]], 10);
    let opts = EngineOptions {
        systems: vec![System::Gps],
        ..options()
    };
    let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
    let t = Vector3::from(truth.baselines_enu_m[0]);
    let errors: Vec<f64> = sol
        .epochs
        .iter()
        .filter(|e| e.fixed)
        .map(|e| (Vector3::from(e.baselines_enu_m[0]) - t).norm())
        .collect();
    assert!(errors.len() >= 57, "fixed {} of 60", errors.len());
    assert!(errors.iter().all(|&e| e < 0.05), "{errors:?}");
    assert!(sol.epochs.iter().all(|e| e.satellites_per_system[0] >= 6));
}
