//! Integers imposed on an epoch (baseline mode): with `continuity` those fixed at the previous epoch
//! on the arcs that continue, dropped when the epoch's data disagree; in static mode those of the
//! baseline solved over every epoch seen so far.

use std::collections::BTreeSet;

use super::lambda::{fix_state, RoverEpoch};
use super::{leaves_epoch_unsolved, Engine, Prepared, HELD_RESIDUAL_CYCLES};
use crate::error::Result;
use crate::gnss::rtk::constrained::{chi2_quantile_at, HOLD_Z};
use crate::gnss::rtk::float;
use crate::gnss::rtk::{model::SdRangeModel, BaselineSolution, DdEpoch, FixOptions, SignalPair};

impl Engine {
    /// Static mode: rover `r`'s baseline over every epoch seen so far, those of `prepared` added
    /// (`None`, with a warning, when it has no solution).
    pub(super) fn static_solution(
        &mut self,
        r: usize,
        prepared: &[Prepared],
        fix: &FixOptions,
    ) -> Result<Option<BaselineSolution>> {
        // Epochs without a signal add nothing to the static solution.
        self.static_epochs[r].extend(
            prepared
                .iter()
                .filter_map(|p| p.rovers[r].clone())
                .filter(|d| !d.signals.is_empty()),
        );
        let all = std::mem::take(&mut self.static_epochs[r]);
        let sol = match self.solve(r, &all, &[], fix) {
            Ok(s) => Some(s),
            Err(e) if leaves_epoch_unsolved(&e) => {
                self.warn_once(
                    format!("static {r}"),
                    format!("the static baseline of rover {r} has no solution: {e}"),
                );
                None
            }
            Err(e) => return Err(e),
        };
        self.static_epochs[r] = all;
        Ok(sol)
    }

    /// Rover `r`'s solution at epoch `k` (time `t`, ns GPST) with double differences `dd`, with the
    /// integers of `static_session` (static mode) or those held from the previous epoch (continuity)
    /// imposed, fixed again without them when they do not hold.
    pub(super) fn held_epoch(
        &mut self,
        r: usize,
        k: usize,
        t: i64,
        dd: &DdEpoch,
        static_session: Option<&BaselineSolution>,
        fix: &FixOptions,
    ) -> Result<RoverEpoch> {
        let held = match (static_session, self.opts.continuity) {
            (Some(s), _) => present(&s.integers, dd),
            (None, true) => present(&self.held[r], dd),
            (None, false) => Vec::new(),
        };
        let factor = if self.opts.baseline_lengths_m.is_empty() {
            self.code_scale[r].factor()
        } else {
            self.code_scale[r].known_length_factor()
        };
        let scaled = self.scaled(r, dd, factor);
        let mut result = self.solve(r, std::slice::from_ref(scaled.as_ref()), &held, fix);
        let mut unheld = held.is_empty();
        let holding = !held.is_empty() && static_session.is_none();
        if static_session.is_none() && !held.is_empty() {
            // A known length's held set is also checked against the epoch's float solution (the
            // constrained fix of new arcs leans on it): its chi-square, as attitude mode's.
            let known_length = self.opts.baseline_lengths_m.get(r).is_some();
            let keep = matches!(&result, Ok(s) if s.fixed && held_consistent(dd, s, &held))
                && (!known_length || held_chi2_consistent(scaled.as_ref(), &held));
            if !keep {
                result = self.solve(r, std::slice::from_ref(scaled.as_ref()), &[], fix);
                unheld = true;
            }
        }
        if let (Ok(sol), true, None) = (&result, unheld, static_session) {
            self.code_scale[r].add(sol, factor);
        }
        let Some(mut sol) = self.solved(k, t, result)? else {
            self.held[r].clear();
            return Ok(None);
        };
        if self.opts.continuity && static_session.is_none() {
            self.held[r] = if sol.fixed {
                sol.integers.clone()
            } else {
                Vec::new()
            };
        }
        if let Some(s) = static_session {
            sol.ratio = s.ratio;
            sol.success_rate = s.success_rate;
        }
        self.length[r].add(&sol.baseline_m, &sol.covariance_m2);
        let state = fix_state(sol.fixed, holding && !unheld);
        Ok(Some((sol, state)))
    }
}

/// The held integers whose two arcs both have a signal at this epoch, for every pair of arcs held
/// against one reference: `N(a, b) = N(a, r) - N(b, r)` and `N(r, b) = -N(b, r)`, so that a change of
/// reference satellite (the float solution keys its ambiguities by arc and reference arc) keeps them.
pub(super) fn present(held: &[(u64, u64, i64)], dd: &DdEpoch) -> Vec<(u64, u64, i64)> {
    let arcs: BTreeSet<u64> = dd.signals.iter().map(|s| s.arc).collect();
    let mut by_reference: std::collections::BTreeMap<u64, Vec<(u64, i64)>> = Default::default();
    for &(a, r, n) in held {
        if arcs.contains(&a) && arcs.contains(&r) {
            by_reference.entry(r).or_default().push((a, n));
        }
    }
    let mut out = Vec::new();
    for (r, members) in by_reference {
        let with_reference: Vec<(u64, i64)> = std::iter::once((r, 0)).chain(members).collect();
        for &(a, na) in &with_reference {
            for &(b, nb) in &with_reference {
                if a != b {
                    out.push((a, b, na - nb));
                }
            }
        }
    }
    out
}

/// Whether every held integer agrees with the fixed baseline: the double-difference phase minus the
/// ranges to `base + baseline` minus the integer stays within [`HELD_RESIDUAL_CYCLES`] (GLONASS pairs of
/// different wavelengths, whose receiver clock term does not cancel, are not checked).
fn held_consistent(dd: &DdEpoch, sol: &BaselineSolution, held: &[(u64, u64, i64)]) -> bool {
    let model = SdRangeModel::new(&dd.base_m, &(dd.base_m + sol.baseline_m));
    let sd = |s: &SignalPair| {
        (s.rover_phase_cycles - s.base_phase_cycles) - model.range_m(s) / s.wavelength_m
    };
    held.iter().all(|&(arc, reference, n)| {
        let find = |a: u64| dd.signals.iter().find(|s| s.arc == a);
        match (find(arc), find(reference)) {
            (Some(i), Some(j)) if i.wavelength_m == j.wavelength_m => {
                (sd(i) - sd(j) - n as f64).abs() <= HELD_RESIDUAL_CYCLES
            }
            _ => true,
        }
    })
}

/// Whether `held` agrees with the epoch's float solution: the weighted squared residuals the held
/// integers add (chi-square with them imposed minus without) stay within the
/// [`crate::gnss::rtk::constrained::HOLD_Z`] chi-square quantile of the number imposed.
fn held_chi2_consistent(dd: &DdEpoch, held: &[(u64, u64, i64)]) -> bool {
    let one = std::slice::from_ref(dd);
    let (Ok(free), Ok(with)) = (float::solve(one, &[]), float::solve(one, held)) else {
        return false;
    };
    let n = with.used_held.len();
    n == 0 || with.chi2 - free.chi2 <= chi2_quantile_at(n, HOLD_Z)
}
