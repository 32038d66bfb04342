//! LAMBDA estimates of a call's epochs (step 4 of the module documentation), one function per mode:
//! attitude mode ([`super::attitude`]), and per rover in baseline mode the single epochs
//! ([`Engine::single_epochs`]), the multi-epoch filter ([`super::filter`]) or integers held from the previous
//! epoch or the static session ([`super::held`]).

use nalgebra::Vector3;

use super::{leaves_epoch_unsolved, Engine, Estimate, Prepared};
use crate::error::Result;
use crate::gnss::geometry::{enu_from_ecef, geodetic_from_ecef};
use crate::gnss::options::{Method, Motion};
use crate::gnss::rtk::{solve_baseline, solve_known_length, BaselineSolution, DdEpoch, FixOptions};
use crate::gnss::solution::FixState;
use crate::interrupt;

/// One rover's solution at one epoch and how its integers were fixed (`None`: unsolved).
pub(super) type RoverEpoch = Option<(BaselineSolution, FixState)>;

impl Engine {
    /// LAMBDA estimates of every epoch (`None`: unsolved), in moving, continuity, filter or static mode.
    pub(super) fn lambda(&mut self, prepared: &[Prepared]) -> Result<Vec<Option<Estimate>>> {
        let fix = self.fix_options();
        if self.attitude_mode() && self.opts.method == Method::Ml {
            // The grid needs nothing from the integer fix when the body baselines are known.
            return Ok(prepared.iter().map(|_| None).collect());
        }
        if self.attitude_mode() {
            return self.attitude_epochs(prepared, &fix);
        }
        let n_rovers = self.n_receivers - 1;
        // Per rover, per epoch.
        let mut solutions: Vec<Vec<RoverEpoch>> = Vec::with_capacity(n_rovers);
        for r in 0..n_rovers {
            solutions.push(self.rover_epochs(r, prepared, &fix)?);
        }
        Ok((0..prepared.len())
            .map(|k| {
                let base = prepared[k].base_m?;
                let sols: Option<Vec<&(BaselineSolution, FixState)>> =
                    solutions.iter().map(|s| s[k].as_ref()).collect();
                let sols = sols?;
                let states: Vec<FixState> = sols.iter().map(|s| s.1).collect();
                let sols: Vec<&BaselineSolution> = sols.iter().map(|s| &s.0).collect();
                Some(baseline_estimate(&base, &sols, &states))
            })
            .collect())
    }

    /// Rover `r`'s solutions at every epoch of `prepared` (baseline mode).
    fn rover_epochs(
        &mut self,
        r: usize,
        prepared: &[Prepared],
        fix: &FixOptions,
    ) -> Result<Vec<RoverEpoch>> {
        let static_session = if self.opts.motion == Motion::Static {
            self.static_solution(r, prepared, fix)?
        } else {
            None
        };
        if self.opts.motion == Motion::Moving && !self.opts.continuity && self.opts.filter.is_none()
        {
            return self.single_epochs(r, prepared, fix);
        }
        let mut per_epoch = Vec::with_capacity(prepared.len());
        for (k, p) in prepared.iter().enumerate() {
            interrupt::check("GNSS engine")?;
            let Some(dd) = &p.rovers[r] else {
                per_epoch.push(None);
                continue;
            };
            self.count_double_differences(dd);
            per_epoch.push(if self.opts.filter.is_some() {
                self.filter_epoch(r, k, p.time_gpst_ns, dd, fix)?
            } else {
                self.held_epoch(r, k, p.time_gpst_ns, dd, static_session.as_ref(), fix)?
            });
        }
        Ok(per_epoch)
    }

    /// Rover `r`'s baseline over `epochs`: with its known length when there is one.
    pub(super) fn solve(
        &self,
        r: usize,
        epochs: &[DdEpoch],
        held: &[(u64, u64, i64)],
        fix: &FixOptions,
    ) -> Result<BaselineSolution> {
        match self.opts.baseline_lengths_m.get(r) {
            Some(&l) => solve_known_length(epochs, held, l, fix),
            None => solve_baseline(epochs, held, fix),
        }
    }

    /// The value of an estimator's `result` at epoch `k` (time `t`, ns GPST); `None` (and a warning)
    /// when its error leaves the epoch unsolved, the error when it stops the session.
    pub(super) fn solved<T>(&mut self, k: usize, t: i64, result: Result<T>) -> Result<Option<T>> {
        match result {
            Ok(v) => Ok(Some(v)),
            Err(e) if leaves_epoch_unsolved(&e) => {
                self.note_unsolved(k, t, &e);
                Ok(None)
            }
            Err(e) => Err(e),
        }
    }
}

/// The fix state of a solution: float unless `fixed`, held when its integers were `held`.
pub(super) fn fix_state(fixed: bool, held: bool) -> FixState {
    match (fixed, held) {
        (false, _) => FixState::Float,
        (true, true) => FixState::Held,
        (true, false) => FixState::Fixed,
    }
}

/// Baseline-mode estimate from one solution per rover, East-North-Up at the base.
fn baseline_estimate(
    base: &Vector3<f64>,
    sols: &[&BaselineSolution],
    states: &[FixState],
) -> Estimate {
    let (lat, lon, _) = geodetic_from_ecef(base);
    let r = enu_from_ecef(lat, lon);
    let first = sols[0];
    let fixed = sols.iter().all(|s| s.fixed);
    Estimate {
        method: Method::Lambda,
        fixed,
        fix_state: if !fixed {
            FixState::Float
        } else if states.contains(&FixState::Held) {
            FixState::Held
        } else {
            FixState::Fixed
        },
        fixed_ambiguities: sols.iter().map(|s| s.fixed_ambiguities).sum(),
        ambiguities: sols.iter().map(|s| s.ambiguities).sum(),
        ratio: first.ratio,
        success_rate: first.success_rate,
        baselines_enu_m: sols.iter().map(|s| r * s.baseline_m).collect(),
        covariances_enu_m2: sols
            .iter()
            .map(|s| r * s.covariance_m2 * r.transpose())
            .collect(),
        enu_from_body: None,
        attitude_sigmas_deg: None,
    }
}
