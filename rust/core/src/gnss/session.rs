//! One call for a whole session: the streaming [`Engine`] fed every epoch at once.

use super::navdata::NavData;
use super::observations::Observations;
use super::options::EngineOptions;
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
