//! The likelihood grid (`Method::Ml`, `Method::Auto`) in baseline mode, and the baseline length it needs.

use nalgebra::Vector3;

use super::simulation::{options, simulate};
use crate::error::Error;
use crate::gnss::options::{EngineOptions, Method};
use crate::gnss::session::run;
use crate::gnss::signal::{System, MAX_FREQUENCIES};
use crate::gnss::stream::Engine;

#[test]
fn ml_agrees_with_lambda_on_a_one_metre_baseline() {
    let truth = simulate(5, &[[0.6, -0.8, 0.05]], 5);
    let lambda = run(&truth.obs, &truth.nav, &options()).unwrap();
    let mut opts = options();
    opts.method = Method::Ml;
    let ml = run(&truth.obs, &truth.nav, &opts).unwrap();
    for (a, b) in lambda.epochs.iter().zip(&ml.epochs) {
        assert_eq!(b.method, Method::Ml);
        assert!(b.solved);
        // The grid's direction from ~8 L1 phases of 3 mm noise on 1 m: a few tenths of a degree.
        let daz = (a.angles_deg[0] - b.angles_deg[0] + 180.0).rem_euclid(360.0) - 180.0;
        assert!(
            daz.abs() < 1.5,
            "azimuth {} vs {}",
            a.angles_deg[0],
            b.angles_deg[0]
        );
        assert!((a.angles_deg[1] - b.angles_deg[1]).abs() < 1.5);
        // And the truth, azimuth 143.13 and elevation 2.86 degrees: one system's ~8 L1 single
        // differences of 4.2 mm give about 0.25 degree (horizontal) and 0.45 degree (vertical) on 1 m;
        // the bounds are 3-4 sigma.
        let truth_az = 0.6f64.atan2(-0.8).to_degrees();
        let truth_el = 0.05f64.atan2(1.0).to_degrees();
        assert!(
            (b.angles_deg[0] - truth_az).abs() < 1.0,
            "{}",
            b.angles_deg[0]
        );
        assert!(
            (b.angles_deg[1] - truth_el).abs() < 1.5,
            "{}",
            b.angles_deg[1]
        );
    }
}

#[test]
fn auto_keeps_the_integer_fix_and_falls_back_to_the_grid_when_the_gate_refuses() {
    // With four systems on two slots every epoch is fixed and Auto is Lambda.
    let mut truth = simulate(8, &[[0.6, -0.8, 0.05]], 9);
    let auto = EngineOptions {
        method: Method::Auto,
        ..options()
    };
    let all = run(&truth.obs, &truth.nav, &auto).unwrap();
    assert!(all
        .epochs
        .iter()
        .all(|e| e.fixed && e.method == Method::Lambda));
    // GPS alone (eight satellites), L1 + L2 for three epochs, then L1 alone (L2 lost at the rover):
    // the default gate fixes the L1 + L2 epochs (success rate 0.996 of 14 ambiguities) and refuses the
    // L1 epochs (0.30 of 7), which go to the grid with the length the fixed epochs give.
    let ns = truth.obs.n_sats();
    for k in 3..8 {
        for s in 0..ns {
            truth.obs.receivers[1].phase_cycles[(k * ns + s) * MAX_FREQUENCIES + 1] = f64::NAN;
        }
    }
    let gps = EngineOptions {
        systems: vec![System::Gps],
        ..auto
    };
    let sol = run(&truth.obs, &truth.nav, &gps).unwrap();
    let az = 0.6f64.atan2(-0.8).to_degrees();
    for (k, e) in sol.epochs.iter().enumerate() {
        assert!(e.solved);
        assert_eq!(
            e.satellites(),
            e.satellites_per_system[System::Gps.index()].into()
        );
        assert_eq!(
            (e.fixed, e.method == Method::Lambda),
            (k < 3, k < 3),
            "epoch {k}"
        );
        // 8 L1 single differences on 1 m: 0.25 degree of azimuth noise; 1 degree is 4 sigma.
        assert!((e.angles_deg[0] - az).abs() < 1.0, "{}", e.angles_deg[0]);
    }
}

#[test]
fn ml_without_a_known_length_keeps_the_double_difference_solution() {
    // GPS L1 alone with a gate nothing passes: each float length has decimetres of sigma on 1 m, far from
    // the 1 % the grid needs, so the grid is not run and a warning says why.
    let truth = simulate(3, &[[0.6, -0.8, 0.05]], 11);
    let opts = EngineOptions {
        systems: vec![System::Gps],
        frequencies: 1,
        method: Method::Ml,
        min_success_rate: 0.99999,
        ..EngineOptions::default()
    };
    let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
    assert!(sol
        .epochs
        .iter()
        .all(|e| e.solved && !e.fixed && e.method == Method::Lambda));
    assert!(
        sol.warnings
            .iter()
            .any(|w| w.contains("needs the baseline length")),
        "{:?}",
        sol.warnings
    );
}

#[test]
fn a_known_length_gives_the_grid_its_length_at_once_and_is_checked() {
    // As above (GPS L1, a gate nothing passes), with the length given: the grid runs from the first epoch
    // and returns the baseline at that length, within the grid's direction error (a few degrees: 5 cm).
    let b = [0.6, -0.8, 0.05];
    let truth = simulate(3, &[b], 11);
    let length = Vector3::from(b).norm();
    let opts = EngineOptions {
        systems: vec![System::Gps],
        frequencies: 1,
        method: Method::Ml,
        min_success_rate: 0.99999,
        baseline_lengths_m: vec![length],
        ..EngineOptions::default()
    };
    let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
    for e in &sol.epochs {
        assert!(e.solved && e.method == Method::Ml, "{e:?}");
        let got = Vector3::from(e.baselines_enu_m[0]);
        assert!((got.norm() - length).abs() < 1e-9);
        assert!((got - Vector3::from(b)).norm() < 0.05, "{got}");
    }
    // One length per rover, and not with body baselines.
    let two = EngineOptions {
        baseline_lengths_m: vec![1.0, 2.0],
        ..options()
    };
    let e = Engine::new(
        &truth.nav,
        two,
        truth.obs.sats.clone(),
        truth.obs.glonass_channel.clone(),
        2,
    );
    assert!(matches!(
        e,
        Err(Error::OutOfRange {
            name: "--baseline-length",
            ..
        })
    ));
    let both = EngineOptions {
        baseline_lengths_m: vec![1.0],
        body_baselines_m: vec![[1.0, 0.0, 0.0]],
        ..options()
    };
    assert!(matches!(
        both.validate(),
        Err(Error::OutOfRange {
            name: "--baseline-length",
            ..
        })
    ));
    let short = EngineOptions {
        baseline_lengths_m: vec![0.001],
        ..options()
    };
    assert!(matches!(
        short.validate(),
        Err(Error::OutOfRange {
            name: "--baseline-length",
            ..
        })
    ));
}
