//! `EngineOptions::systems` selects the signals of every mode: a four-system session solved with GPS
//! alone forms no double difference and counts no satellite of another system.

use nalgebra::Vector3;

use super::simulation::{base_position, options, simulate};
use crate::gnss::options::{EngineOptions, Method, Motion};
use crate::gnss::rtk::filter::Dynamics;
use crate::gnss::session::run;
use crate::gnss::signal::System;
use crate::gnss::solution::SessionSolution;
use crate::likelihood::dcm_enu_from_body;

#[test]
fn gps_alone_uses_no_signal_of_another_system_in_any_mode() {
    // Heading 30, pitch 5, roll -3 degrees; the rovers 1.2 m at the nose and 0.9 m at the right wing.
    let m = dcm_enu_from_body(
        (-30f64).to_radians(),
        5f64.to_radians(),
        (-3f64).to_radians(),
    );
    let body = [[1.2, 0.0, 0.0], [0.0, 0.0, 0.9]];
    let enu: Vec<[f64; 3]> = body
        .iter()
        .map(|b| (m * Vector3::from(*b)).into())
        .collect();
    let truth = simulate(4, &enu, 12);
    let gps = EngineOptions {
        systems: vec![System::Gps],
        ..options()
    };
    for (name, opts) in modes(gps, &body) {
        let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
        assert_gps_alone(name, &opts, &sol);
    }
}

/// Every mode of the engine, each from the options `gps` (`body`: the rovers' body-frame offsets, m).
fn modes(gps: EngineOptions, body: &[[f64; 3]]) -> [(&'static str, EngineOptions); 9] {
    [
        ("single epoch", gps.clone()),
        (
            "surveyed base",
            EngineOptions {
                base_position_m: Some(base_position().into()),
                ..gps.clone()
            },
        ),
        (
            "static",
            EngineOptions {
                motion: Motion::Static,
                ..gps.clone()
            },
        ),
        (
            "continuity",
            EngineOptions {
                continuity: true,
                ..gps.clone()
            },
        ),
        (
            "filter",
            EngineOptions {
                filter: Some(Dynamics::KINEMATIC),
                ..gps.clone()
            },
        ),
        (
            "grid",
            EngineOptions {
                method: Method::Ml,
                baseline_lengths_m: vec![1.2, 0.9],
                ..gps.clone()
            },
        ),
        (
            "attitude",
            EngineOptions {
                body_baselines_m: body.to_vec(),
                ..gps.clone()
            },
        ),
        (
            "attitude filter",
            EngineOptions {
                body_baselines_m: body.to_vec(),
                filter: Some(Dynamics::KINEMATIC),
                ..gps.clone()
            },
        ),
        (
            "attitude grid",
            EngineOptions {
                body_baselines_m: body.to_vec(),
                method: Method::Ml,
                ..gps
            },
        ),
    ]
}

/// `sol`, solved with `opts` (mode `name`), has double differences and satellites of GPS alone, and
/// solves some epoch.
fn assert_gps_alone(name: &str, opts: &EngineOptions, sol: &SessionSolution) {
    let gps_index = System::Gps.index();
    for (system, per_slot) in sol.double_differences.iter().enumerate() {
        let n: u64 = per_slot.iter().sum();
        if system == gps_index {
            // Eight GPS satellites above the mask on two slots, four epochs, two rovers (the grid
            // of attitude mode forms no double difference).
            assert!(
                n > 0 || opts.method == Method::Ml,
                "{name}: no GPS double difference"
            );
        } else {
            assert_eq!(n, 0, "{name}: {n} double differences of system {system}");
        }
    }
    assert!(
        sol.epochs.iter().any(|e| e.solved),
        "{name}: nothing solved"
    );
    for e in sol.epochs.iter().filter(|e| e.solved) {
        for (system, &n) in e.satellites_per_system.iter().enumerate() {
            if system == gps_index {
                assert!(n >= 4, "{name}: {n} GPS satellites");
            } else {
                assert_eq!(n, 0, "{name}: {n} satellites of system {system}");
            }
        }
    }
}
