//! The code noise scale: estimated from the residuals, and calibrated before a session's first epoch.

use super::simulation::{fixed_error, options, simulate};
use crate::gnss::options::{ElevationSigma, EngineOptions, Motion};
use crate::gnss::session::run;
use crate::gnss::stream::Engine;

#[test]
fn the_code_noise_scale_recovers_the_simulated_noise() {
    // The simulation draws code noise of 0.3 m per receiver; a model of 0.15 m at every elevation is half
    // of it, so the estimated sigma scale is 2 (its relative standard error sqrt(1 / (2 dof)) is about 2 %
    // with the few hundred residual degrees of freedom of 20 epochs: 0.15 is over 3 sigma).
    let truth = simulate(20, &[[0.6, -0.8, 0.05]], 13);
    let opts = EngineOptions {
        code_sigma: ElevationSigma {
            a_m: 0.15,
            b_m: 0.0,
        },
        ..options()
    };
    let sol = run(&truth.obs, &truth.nav, &opts).unwrap();
    let scale = sol.code_sigma_scale[0];
    assert!((scale - 2.0).abs() < 0.15, "{scale}");
    // Static mode estimates nothing.
    let stat = run(
        &truth.obs,
        &truth.nav,
        &EngineOptions {
            motion: Motion::Static,
            ..opts
        },
    )
    .unwrap();
    assert!(stat.code_sigma_scale[0].is_nan());
}

#[test]
fn a_session_gates_its_first_epochs_with_the_calibrated_code_noise() {
    // Receivers twice as noisy as a model of 0.15 m (as above): a streaming engine gates its first epoch
    // with the model's variances, a quarter of the truth, and overstates its success rate; the session
    // calibrates on its first epochs before solving any, so its first epoch is gated as the later ones.
    let truth = simulate(6, &[[0.6, -0.8, 0.05]], 13);
    let opts = EngineOptions {
        code_sigma: ElevationSigma {
            a_m: 0.15,
            b_m: 0.0,
        },
        frequencies: 1,
        ..options()
    };
    let session = run(&truth.obs, &truth.nav, &opts).unwrap();
    let mut engine = Engine::new(
        &truth.nav,
        opts.clone(),
        truth.obs.sats.clone(),
        truth.obs.glonass_channel.clone(),
        2,
    )
    .unwrap();
    let streamed = engine.process(&truth.obs).unwrap();
    let (first_session, first_streamed) = (&session.epochs[0], &streamed[0]);
    assert!(first_session.solved && first_streamed.solved);
    assert!(
        first_session.success_rate < first_streamed.success_rate,
        "{} vs {}",
        first_session.success_rate,
        first_streamed.success_rate
    );
    // Both end with the same estimate of the noise (2, the simulated over the model's sigma), the
    // session's counting its first epochs twice (in the calibration and in the run): within 2.5 %, about
    // the estimate's own standard error with these few hundred degrees of freedom.
    let (s, e) = (session.code_sigma_scale[0], engine.code_sigma_scale()[0]);
    assert!(
        (s - e).abs() < 0.025 * e && (e - 2.0).abs() < 0.15,
        "{s} vs {e}"
    );
    let (err, _) = fixed_error(&truth, &session.epochs);
    assert!(err < 0.05, "a wrong fix: {err} m");
}
