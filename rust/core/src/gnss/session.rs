//! One call for a whole session: the streaming [`Engine`] fed every epoch at once.

use super::navdata::NavData;
use super::observations::Observations;
use super::options::{EngineOptions, Method, Motion};
use super::solution::SessionSolution;
use super::stream::Engine;
use crate::error::{Error, Result};

/// Processes every epoch of a session (see [`crate::gnss::stream`] for what happens per epoch).
///
/// # Arguments
/// * `obs` - the session's observations, reference antenna first.
/// * `nav` - broadcast records covering the session.
/// * `opts` - engine settings.
///
/// # Returns
/// One [`crate::gnss::solution::EpochSolution`] per epoch (unsolved ones included: too few satellites
/// at an epoch is not an error), the double differences formed per system and slot, and warnings (a
/// system without ephemerides, a base position far from the code solution, unsolved epochs, ...).
///
/// # Errors
/// The errors of [`Engine::new`] and [`Engine::process`]; [`Error::OutOfRange`] when no epoch has a
/// single usable signal (code and phase at both receivers of a satellite with an ephemeris above the
/// mask), which says the files, systems or navigation data do not fit together.
pub fn run(obs: &Observations, nav: &NavData, opts: &EngineOptions) -> Result<SessionSolution> {
    obs.validate()?;
    let mut engine = Engine::new(
        nav,
        opts.clone(),
        obs.sats.clone(),
        obs.glonass_channel.clone(),
        obs.receivers.len(),
    )?;
    if opts.motion == Motion::Moving {
        calibrate(&mut engine, obs, nav, opts)?;
    }
    let epochs = engine.process(obs)?;
    if engine.usable_signals() == 0 {
        let systems: String = opts.systems.iter().map(|s| s.letter()).collect();
        return Err(Error::out_of_range(
            "observations",
            format!(
                "expected code and phase of satellites of --systems {systems} with an ephemeris and \
                 above the elevation mask at the reference antenna and a rover, got none in {} epochs",
                epochs.len()
            ),
        ));
    }
    let unsolved = epochs.iter().filter(|e| !e.solved).count();
    let mut warnings = engine.warnings().to_vec();
    if unsolved > 0 {
        warnings.push(format!(
            "{unsolved} of {} epochs have no solution (too few common satellites or no code \
             solution)",
            epochs.len()
        ));
    }
    Ok(SessionSolution {
        epochs,
        double_differences: engine.double_differences(),
        warnings,
        code_sigma_scale: engine.code_sigma_scale(),
    })
}

/// Calibrates `engine`'s code noise scale on the first epochs of the session before it processes any.
///
/// A streaming engine learns the receivers' code noise from the epochs it has solved
/// ([`super::stream::CODE_SCALE_MIN_DOF`] residual degrees of freedom: about 17 epochs of GPS L1 with 7
/// satellites), so its first epochs are gated with the uncalibrated model: too pessimistic for a quiet
/// receiver (a known-length fix refused), too optimistic for a noisy one (a success rate overstated). A
/// session has all its epochs at hand: a probe engine (baseline mode, LAMBDA float, no length or array
/// constraint: the float residuals do not depend on them) solves epochs from the first until the
/// estimate stands, and the engine starts from it. Each epoch is still solved from its own observations.
fn calibrate(
    engine: &mut Engine,
    obs: &Observations,
    nav: &NavData,
    opts: &EngineOptions,
) -> Result<()> {
    let probe_opts = EngineOptions {
        method: Method::Lambda,
        continuity: false,
        filter: None,
        rigid: false,
        body_baselines_m: Vec::new(),
        baseline_lengths_m: Vec::new(),
        ..opts.clone()
    };
    let mut probe = Engine::new(
        nav,
        probe_opts,
        obs.sats.clone(),
        obs.glonass_channel.clone(),
        obs.receivers.len(),
    )?;
    // Blocks that grow geometrically: few calls where one epoch has enough residuals (many signals),
    // little work past the point where the estimate stands.
    let (mut start, mut block) = (0, 1);
    while start < obs.n_epochs() && !probe.code_scale_calibrated() {
        let end = (start + block).min(obs.n_epochs());
        probe.process(&obs.epochs(start..end))?;
        (start, block) = (end, block * 2);
    }
    engine.calibrate_code_scale(&probe);
    Ok(())
}
