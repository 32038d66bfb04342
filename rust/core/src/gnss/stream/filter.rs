//! Filter mode (`EngineOptions::filter`): one rover's epoch through its multi-epoch filter, checked
//! against the epoch's own fix.

use super::lambda::RoverEpoch;
use super::Engine;
use crate::error::Result;
use crate::gnss::rtk::{DdEpoch, FixOptions};
use crate::gnss::solution::FixState;

impl Engine {
    /// Rover `r`'s solution at epoch `k` (time `t`, ns GPST) with double differences `dd`, from its
    /// filter (or the epoch's own fix where the filter leaves it float).
    pub(super) fn filter_epoch(
        &mut self,
        r: usize,
        k: usize,
        t: i64,
        dd: &DdEpoch,
        fix: &FixOptions,
    ) -> Result<RoverEpoch> {
        let factor = self.code_scale[r].factor();
        let scaled = self.scaled(r, dd, factor);
        let result = self.filters[r].step(scaled.as_ref(), t, fix);
        let Some(f) = self.solved(k, t, result)? else {
            return Ok(None);
        };
        if f.hold_rejected {
            self.warn_once(
                format!("hold rejected {r}"),
                format!(
                    "rover {}: held integers disagreed with the filter's float \
                     ambiguities at epoch {k} ({} ns GPST) and were dropped (an \
                     undetected slip or a wrong fix); the filter fixes again",
                    r + 1,
                    t
                ),
            );
        }
        if f.length_refused {
            self.warn_once(
                format!("length refused {r}"),
                format!(
                    "rover {}: a fix at epoch {k} ({} ns GPST) whose length \
                     disagreed with the pair's (known or learned from earlier \
                     fixes) was refused",
                    r + 1,
                    t
                ),
            );
        }
        // An epoch the filter leaves float is solved on its own too (through the filter's checks of a
        // fix, which learn the length from it): the filter never fixes fewer epochs than single epochs.
        // It is scaled as the filter's epoch and single epochs are (code and phase together: the model's
        // ratio test, `code_scale` module documentation).
        let single = match f.state {
            FixState::Float => self
                .solve(r, std::slice::from_ref(scaled.as_ref()), &[], fix)
                .ok()
                .filter(|s| s.fixed),
            _ => None,
        }
        .filter(|s| self.filters[r].admit(s));
        if single.as_ref().is_some_and(|s| !f.agrees_with_float(s)) {
            self.warn_once(
                format!("filter float biased {r}"),
                format!(
                    "rover {}: the epoch's own fix at epoch {k} ({} ns GPST) \
                     disagrees with the filter's float baseline beyond its \
                     covariance (errors correlated in time, such as code biases \
                     or the ionosphere, bias the float); the single-epoch fix, \
                     which passed the gate, is reported",
                    r + 1,
                    t
                ),
            );
        }
        let (solution, state) = match single {
            Some(s) => (s, FixState::Fixed),
            None => (f.solution, f.state),
        };
        self.length[r].add(&solution.baseline_m, &solution.covariance_m2);
        Ok(Some((solution, state)))
    }
}
