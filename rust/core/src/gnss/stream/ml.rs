//! Single differences for the ambiguity-function grid ([`crate::likelihood::series`]).
//!
//! The grid's model has one oscillator phase per baseline, shared by every satellite. Receivers add an
//! unknown phase bias per system and per carrier, so one epoch's grid input uses a single system and
//! slot 0 (L1, G1, E1, B1I): the system with the most slot-0 signals common to every rover (ties: the
//! order of [`crate::gnss::signal::System::ALL`]). GLONASS FDMA wavelengths differ by under 0.5 %, which
//! the grid takes per satellite.
//!
//! Each rover's phase is moved to the base's reception instant. With receiver clocks `dt` (from the
//! code solutions), phase in cycles `phi = (rho(T) + c dt) / lambda + N` at the true reception time
//! `T = label - dt`, and range rate `rho_dot`:
//! `phi_r - phi_b + (rho_dot - c) (dt_r - dt_b) / lambda = (rho_r(T_b) - rho_b(T_b)) / lambda + N`,
//! the single difference at one instant that the grid's model assumes (receiver clocks of a millisecond
//! move a satellite 3 m along its orbit, so this matters).

use nalgebra::Vector3;

use super::Prepared;
use crate::gnss::ephemeris::Ephemerides;
use crate::gnss::geometry::{enu_from_ecef, geodetic_from_ecef};
use crate::gnss::rtk::DdEpoch;
use crate::gnss::signal::{SatId, System, SPEED_OF_LIGHT_M_S};
use crate::likelihood::MlEpoch;

/// Smallest number of satellites the grid is given (three lines of sight fix a direction).
pub(crate) const MIN_SIGNALS: usize = 3;

/// The system with the most slot-0 signals common to every rover's double differences `dds` (ties: the
/// earlier in [`System::ALL`]) and those signals' satellite indices, in the first rover's order.
fn choose_signals(sats: &[SatId], dds: &[&DdEpoch]) -> Option<(System, Vec<usize>)> {
    let first = dds.first()?;
    let common = |sat: usize| {
        dds.iter()
            .all(|d| d.signals.iter().any(|s| s.sat == sat && s.slot == 0))
    };
    let candidates: Vec<usize> = first
        .signals
        .iter()
        .filter(|s| s.slot == 0 && common(s.sat))
        .map(|s| s.sat)
        .collect();
    let system = System::ALL.into_iter().max_by_key(|&sys| {
        let n = candidates
            .iter()
            .filter(|&&s| sats[s].system == sys)
            .count();
        // Ties go to the earlier system: a larger key for a smaller index.
        (n, std::cmp::Reverse(sys.index()))
    })?;
    let chosen: Vec<usize> = candidates
        .into_iter()
        .filter(|&s| sats[s].system == system)
        .collect();
    Some((system, chosen))
}

/// Receiver `r`'s clock (0: the base) from its code solution, s: its clock of `system`, else its first
/// finite clock of another system.
fn receiver_clock_s(p: &Prepared, r: usize, system: System) -> Option<f64> {
    let c = p.clocks_s[r];
    let own = c[system.index()];
    if own.is_finite() {
        Some(own)
    } else {
        c.iter().copied().find(|x| x.is_finite())
    }
}

/// The grid input of one prepared epoch with `n_rovers` rovers, or `None` when fewer than
/// [`MIN_SIGNALS`] slot-0 signals of one system are common to every rover.
pub(crate) fn epoch(
    eph: &Ephemerides,
    sats: &[SatId],
    p: &Prepared,
    n_rovers: usize,
) -> Option<MlEpoch> {
    let base = p.base_m?;
    let dds: Vec<_> = p
        .rovers
        .iter()
        .take(n_rovers)
        .map(Option::as_ref)
        .collect::<Option<Vec<_>>>()?;
    let first = dds.first()?;
    let (system, chosen) = choose_signals(sats, &dds)?;
    if chosen.len() < MIN_SIGNALS {
        return None;
    }
    let clock = |r: usize| receiver_clock_s(p, r, system);
    let dt_b = clock(0)?;
    let (lat, lon, _) = geodetic_from_ecef(&base);
    let enu = enu_from_ecef(lat, lon);
    let n_sig = chosen.len();
    let mut sd_phase_rad = vec![0.0; n_rovers * n_sig];
    let mut los_enu = Vec::with_capacity(n_sig);
    let mut wavelength_m = Vec::with_capacity(n_sig);
    for (j, &sat) in chosen.iter().enumerate() {
        let pick = |d: &DdEpoch| {
            d.signals
                .iter()
                .find(|s| s.sat == sat && s.slot == 0)
                .cloned()
        };
        let s0 = pick(first)?;
        let offset = -dt_b - s0.base.range_m / SPEED_OF_LIGHT_M_S;
        let velocity: Vector3<f64> = eph.state(sats[sat], p.time_gpst_ns, offset)?.velocity_m_s;
        let range_rate = s0.base.los_ecef.dot(&velocity);
        let l = enu * s0.base.los_ecef;
        los_enu.push([l.x, l.y, l.z]);
        wavelength_m.push(s0.wavelength_m);
        for (r, d) in dds.iter().enumerate() {
            let s = pick(d)?;
            let dt_r = clock(r + 1)?;
            let cycles = s.rover_phase_cycles - s.base_phase_cycles
                + (range_rate - SPEED_OF_LIGHT_M_S) * (dt_r - dt_b) / s.wavelength_m;
            sd_phase_rad[r * n_sig + j] = std::f64::consts::TAU * cycles.rem_euclid(1.0);
        }
    }
    Some(MlEpoch {
        sd_phase_rad,
        los_enu,
        wavelength_m,
    })
}
