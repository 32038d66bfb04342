//! Bad sessions and options: errors naming the option, warnings, options that would be ignored refused.

use nalgebra::Vector3;

use super::simulation::{base_position, options, simulate};
use crate::gnss::options::{EngineOptions, Motion};
use crate::gnss::session::run;
use crate::gnss::signal::System;
use crate::gnss::stream::Engine;

#[test]
fn bad_sessions_are_errors_or_warnings() {
    let truth = simulate(3, &[[0.6, -0.8, 0.05]], 6);
    // No QZSS satellite observed: no usable signal at all is an error naming what was expected.
    let mut opts = options();
    opts.systems = vec![System::Qzss];
    let err = run(&truth.obs, &truth.nav, &opts).unwrap_err().to_string();
    assert!(err.contains("--systems J"), "{err}");
    // A base position 100 m off the truth: warned once, naming the option.
    let mut opts = options();
    let off = base_position() + Vector3::new(100.0, 0.0, 0.0);
    opts.base_position_m = Some(off.into());
    let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
    assert_eq!(
        sol.warnings
            .iter()
            .filter(|w| w.contains("--base-position"))
            .count(),
        1
    );
    // No Galileo ephemeris: warned.
    let mut nav = truth.nav.clone();
    nav.kepler.retain(|r| r.sat.system != System::Galileo);
    let sol = run(&truth.obs, &nav, &options()).unwrap();
    assert!(sol
        .warnings
        .iter()
        .any(|w| w.contains("--systems includes E")));
    // Mismatched engine and observations.
    let mut engine = Engine::new(
        &truth.nav,
        options(),
        truth.obs.sats[1..].to_vec(),
        truth.obs.glonass_channel[1..].to_vec(),
        2,
    )
    .unwrap();
    assert!(engine.process(&truth.obs).is_err());
    assert!(Engine::new(&truth.nav, options(), truth.obs.sats.clone(), vec![], 2).is_err());
}

#[test]
fn options_that_would_be_ignored_are_refused() {
    // Attitude mode has no static session (one set of integers for a moving array is meaningless): refused
    // by name, not ignored. Holding integers along arcs (continuity) is attitude mode's too.
    let body = vec![[1.0, 0.0, 0.0]];
    let e = EngineOptions {
        motion: Motion::Static,
        body_baselines_m: body.clone(),
        ..options()
    }
    .validate()
    .unwrap_err()
    .to_string();
    assert!(e.contains("--motion") && e.contains("attitude mode"), "{e}");
    EngineOptions {
        continuity: true,
        motion: Motion::Moving,
        body_baselines_m: body,
        ..options()
    }
    .validate()
    .unwrap();
    // Continuity is moving mode's; a static session has one set of integers already.
    let moving = EngineOptions {
        continuity: true,
        motion: Motion::Moving,
        ..options()
    };
    moving.validate().unwrap();
    let e = EngineOptions {
        motion: Motion::Static,
        ..moving
    }
    .validate()
    .unwrap_err()
    .to_string();
    assert!(e.contains("--continuity") && e.contains("static"), "{e}");
}
