//! Double-difference groups of one epoch (one system and frequency slot each, reference = the signal at
//! the highest base elevation) and the exact covariance of their rows, `C = D Sigma_SD D^T`.

use nalgebra::{DMatrix, DVector};

use super::{DdEpoch, SignalPair, MAX_SIGNALS};
use crate::error::{ensure_finite, Error, Result};
use crate::gnss::signal::{System, MAX_FREQUENCIES};

/// Largest accepted |pseudorange|, m (BeiDou GEO ranges are under 4.2e7 m; receivers' clock offsets of
/// up to a second add 3e8 m).
pub const MAX_ABS_CODE_M: f64 = 1e9;

/// Largest accepted |carrier phase|, cycles: its integer rounding stays exact in `f64` and `i64`.
pub const MAX_ABS_PHASE_CYCLES: f64 = 1e13;

/// Signals of one system and slot observed at one epoch, at least two.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    pub system: System,
    pub slot: usize,
    /// Index (in the epoch's signals) of the reference: highest elevation at the base.
    pub reference: usize,
    /// Indices of the other signals, in input order.
    pub members: Vec<usize>,
    /// The wavelengths differ within the group (GLONASS FDMA): the reference's single-difference
    /// ambiguity is estimated ([`super::glonass`]).
    pub fdma: bool,
}

/// Relative wavelength difference above which a group is treated as FDMA (GLONASS channels differ by at
/// least 2.7e-4 relative; rounding of one frequency table stays below 1e-12).
const FDMA_RELATIVE: f64 = 1e-9;

/// Groups of `epoch` with at least two signals, ordered by system then slot.
pub fn groups(epoch: &DdEpoch) -> Vec<Group> {
    let mut out = Vec::new();
    for system in System::ALL {
        for slot in 0..MAX_FREQUENCIES {
            let idx: Vec<usize> = (0..epoch.signals.len())
                .filter(|&i| epoch.signals[i].system == system && epoch.signals[i].slot == slot)
                .collect();
            if idx.len() < 2 {
                continue;
            }
            let reference = idx
                .iter()
                .copied()
                .max_by(|&a, &b| {
                    let (ea, eb) = (
                        epoch.signals[a].base.elevation_rad,
                        epoch.signals[b].base.elevation_rad,
                    );
                    // ties: the lower satellite index, so that the choice does not depend on order
                    ea.total_cmp(&eb)
                        .then(epoch.signals[b].sat.cmp(&epoch.signals[a].sat))
                })
                .unwrap_or(idx[0]);
            let lr = epoch.signals[reference].wavelength_m;
            let fdma = idx
                .iter()
                .any(|&i| (epoch.signals[i].wavelength_m - lr).abs() > FDMA_RELATIVE * lr);
            out.push(Group {
                system,
                slot,
                reference,
                members: idx.into_iter().filter(|&i| i != reference).collect(),
                fdma,
            });
        }
    }
    out
}

/// Row kinds of a group's observation vector, in this order: every member's DD code, every member's DD
/// phase, then (FDMA only) the reference's single-difference phase minus code.
///
/// `D` (rows x 2n) maps the single differences `[P_0..P_n-1, Phi_0..Phi_n-1]` of the group's signals
/// (reference first, then members) to these rows; `Sigma_SD` is diagonal with `2 sigma^2` (base and rover
/// independent, same sigma); the rows' covariance is `D Sigma_SD D^T`, m^2.
pub fn covariance(epoch: &DdEpoch, g: &Group) -> DMatrix<f64> {
    let n = g.members.len() + 1;
    let m = g.members.len();
    let rows = 2 * m + usize::from(g.fdma);
    let mut d = DMatrix::<f64>::zeros(rows, 2 * n);
    for j in 0..m {
        d[(j, j + 1)] = 1.0;
        d[(j, 0)] = -1.0;
        d[(m + j, n + j + 1)] = 1.0;
        d[(m + j, n)] = -1.0;
    }
    if g.fdma {
        d[(2 * m, n)] = 1.0;
        d[(2 * m, 0)] = -1.0;
    }
    let order: Vec<&SignalPair> = std::iter::once(g.reference)
        .chain(g.members.iter().copied())
        .map(|i| &epoch.signals[i])
        .collect();
    let var = DVector::from_fn(2 * n, |i, _| {
        let s = order[i % n];
        let sigma = if i < n {
            s.sigma_code_m
        } else {
            s.sigma_phase_m
        };
        2.0 * sigma * sigma
    });
    let ds = DMatrix::from_fn(rows, 2 * n, |r, c| d[(r, c)] * var[c]);
    ds * d.transpose()
}

/// Checks one epoch: finite positions, at most [`MAX_SIGNALS`] signals, each with a valid slot, a
/// positive wavelength and sigmas, finite observations and geometry, and no (system, slot, satellite) or
/// arc twice.
///
/// # Errors
/// [`Error::OutOfRange`], [`Error::NonFinite`] or [`Error::TooLarge`] naming the field and epoch `k`.
pub fn validate(epoch: &DdEpoch, k: usize) -> Result<()> {
    ensure_finite("base_m", epoch.base_m.iter())?;
    ensure_finite("rover_prior_m", epoch.rover_prior_m.iter())?;
    if epoch.signals.len() > MAX_SIGNALS {
        return Err(Error::too_large(
            "signals",
            epoch.signals.len() as f64,
            MAX_SIGNALS as f64,
            "signals in one epoch",
        ));
    }
    for (i, s) in epoch.signals.iter().enumerate() {
        validate_signal(epoch, s, i, k)?;
    }
    for (i, s) in epoch.signals.iter().enumerate() {
        if let Some(j) = epoch.signals[..i].iter().position(|t| {
            t.arc == s.arc || (t.system == s.system && t.slot == s.slot && t.sat == s.sat)
        }) {
            return Err(Error::out_of_range(
                "signals",
                format!(
                    "epoch {k}: signals {j} and {i} share an arc ({}) or a satellite and slot",
                    s.arc
                ),
            ));
        }
    }
    Ok(())
}

/// Checks signal `i` of epoch `k` on its own: slot, wavelength, sigmas, finite and bounded observations,
/// a satellite away from the antennas.
fn validate_signal(epoch: &DdEpoch, s: &SignalPair, i: usize, k: usize) -> Result<()> {
    let bad = |what: &str| Error::out_of_range("signals", format!("epoch {k}, signal {i}: {what}"));
    if s.slot >= MAX_FREQUENCIES {
        return Err(bad(&format!(
            "expected slot < {MAX_FREQUENCIES}, got {}",
            s.slot
        )));
    }
    if !(s.wavelength_m > 0.0 && s.wavelength_m < 100.0) {
        return Err(bad(&format!(
            "expected a wavelength in (0, 100) m, got {}",
            s.wavelength_m
        )));
    }
    for (name, v) in [
        ("sigma_code_m", s.sigma_code_m),
        ("sigma_phase_m", s.sigma_phase_m),
    ] {
        if !(v > 0.0 && v.is_finite()) {
            return Err(bad(&format!("expected {name} > 0, got {v}")));
        }
    }
    let values = [
        s.base_code_m,
        s.rover_code_m,
        s.base_phase_cycles,
        s.rover_phase_cycles,
        s.base.clock_s,
        s.rover.clock_s,
        s.base.elevation_rad,
    ];
    if values.iter().any(|v| !v.is_finite())
        || s.base.position_m.iter().any(|v| !v.is_finite())
        || s.rover.position_m.iter().any(|v| !v.is_finite())
    {
        return Err(Error::NonFinite {
            name: "signals (observations or satellite geometry)",
            index: i,
        }
        .at_epoch(k));
    }
    if s.base_code_m.abs() > MAX_ABS_CODE_M
        || s.rover_code_m.abs() > MAX_ABS_CODE_M
        || s.base_phase_cycles.abs() > MAX_ABS_PHASE_CYCLES
        || s.rover_phase_cycles.abs() > MAX_ABS_PHASE_CYCLES
    {
        return Err(bad(&format!(
            "expected |code| <= {MAX_ABS_CODE_M:e} m and |phase| <= {MAX_ABS_PHASE_CYCLES:e} cycles, \
             got code {} / {} m, phase {} / {} cycles",
            s.base_code_m, s.rover_code_m, s.base_phase_cycles, s.rover_phase_cycles
        )));
    }
    if (s.base.position_m - epoch.base_m).norm() < 1.0
        || (s.rover.position_m - epoch.rover_prior_m).norm() < 1.0
    {
        return Err(bad("satellite position at the antenna"));
    }
    Ok(())
}
