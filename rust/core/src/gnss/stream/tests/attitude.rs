//! Attitude mode: three antennas with body baselines, by LAMBDA and by the grid.

use nalgebra::Vector3;

use super::simulation::{options, simulate};
use crate::gnss::options::{EngineOptions, Method};
use crate::gnss::session::run;
use crate::likelihood::dcm_enu_from_body;

#[test]
fn lambda_attitude_of_three_antennas_matches_the_truth() {
    // Heading 200, pitch -4, roll 6 degrees; fixed baselines of 1-2 m give the angles to a few
    // hundredths of a degree, so 0.2 degree would already be a wrong fix.
    let m = dcm_enu_from_body(
        (-200f64).to_radians(),
        (-4f64).to_radians(),
        6f64.to_radians(),
    );
    let body = [[2.0, 0.1, 0.0], [0.3, 0.0, -1.5]];
    let enu: Vec<[f64; 3]> = body
        .iter()
        .map(|b| (m * Vector3::from(*b)).into())
        .collect();
    let truth = simulate(6, &enu, 8);
    let opts = EngineOptions {
        body_baselines_m: body.to_vec(),
        ..options()
    };
    let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
    for e in &sol.epochs {
        // The constrained acceptance is rtk's (ratio of the two best combined objectives): not
        // asserted here; a fixed epoch must be right and every epoch close.
        assert!(e.solved && e.method == Method::Lambda);
        let [h, p, r] = [e.angles_deg[0], e.angles_deg[1], e.angles_deg[2]];
        assert!(
            (h - 200.0).abs() < 0.2 && (p + 4.0).abs() < 0.2 && (r - 6.0).abs() < 0.2,
            "{h} {p} {r}"
        );
        // The sigmas are those of baselines of a few millimetres (the engine's elevation-weighted
        // sigmas, larger than the simulated 3 mm) over 1.5-2 m: tenths of a degree at most.
        let bound = if e.fixed { 0.5 } else { 5.0 };
        assert!(
            e.angle_sigmas_deg.iter().all(|s| *s > 1e-4 && *s < bound),
            "{:?}",
            e.angle_sigmas_deg
        );
        for (b, t) in e.baselines_enu_m.iter().zip(&enu) {
            assert!((Vector3::from(*b) - Vector3::from(*t)).norm() < 0.01);
        }
    }
}

#[test]
fn ml_attitude_of_three_antennas_matches_the_truth() {
    // Heading 30, pitch 5, roll -3 degrees (psi = -30): body X nose, Y up, Z right wing.
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
    let truth = simulate(4, &enu, 7);
    let opts = EngineOptions {
        method: Method::Ml,
        body_baselines_m: body.to_vec(),
        ..options()
    };
    let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
    for e in &sol.epochs {
        assert!(e.solved && e.method == Method::Ml);
        let [h, p, r] = [e.angles_deg[0], e.angles_deg[1], e.angles_deg[2]];
        // ~8 single differences of 4.2 mm: about 0.3 degree in heading and 0.5 degree in pitch and
        // roll (vertical components of 1 m baselines); the bounds are 3 sigma.
        assert!((h - 30.0).abs() < 1.0, "heading {h}");
        assert!(
            (p - 5.0).abs() < 1.5 && (r + 3.0).abs() < 1.5,
            "pitch {p} roll {r}"
        );
        let rot = e.rotation_enu_from_body.unwrap();
        assert!((rot[0] - m[(0, 0)]).abs() < 0.02);
    }
}
