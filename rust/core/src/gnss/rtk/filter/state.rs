//! Steps 1-2 of [`super::BaselineFilter::step`]: the prediction of the baseline (and velocity) over the
//! time since the previous epoch, and the ambiguity states of the arcs that start, end or restart; the
//! reference of each group.

use std::collections::BTreeSet;

use nalgebra::{DMatrix, DVector};

use super::{
    ArcState, BaselineFilter, Dynamics, INITIAL_AMBIGUITY_SIGMA_M, INITIAL_BASELINE_SIGMA_M,
    INITIAL_VELOCITY_SIGMA_M_S,
};
use crate::error::{Error, Result};
use crate::gnss::rtk::dd::{groups, Group};
use crate::gnss::rtk::{DdEpoch, SignalPair};

impl BaselineFilter {
    /// Step 1: the baseline (and velocity) propagated to `t`; the first epoch starts the state.
    pub(super) fn predict(&mut self, epoch: &DdEpoch, t: i64) -> Result<()> {
        let nk = self.nk();
        let Some(t0) = self.time_ns else {
            self.x = DVector::zeros(nk);
            self.p = DMatrix::zeros(nk, nk);
            let b0 = epoch.rover_prior_m - epoch.base_m;
            for i in 0..3 {
                self.x[i] = b0[i];
                self.p[(i, i)] = INITIAL_BASELINE_SIGMA_M.powi(2);
                if nk == 6 {
                    self.p[(3 + i, 3 + i)] = INITIAL_VELOCITY_SIGMA_M_S.powi(2);
                }
            }
            self.time_ns = Some(t);
            return Ok(());
        };
        if t <= t0 {
            return Err(Error::out_of_range(
                "time_gpst_ns",
                format!("expected an epoch after the filter's last one ({t0} ns), got {t} ns"),
            ));
        }
        let dt = (t - t0) as f64 * 1e-9;
        self.time_ns = Some(t);
        match self.dynamics {
            Dynamics::Static => {}
            Dynamics::RandomWalk { q_m2_s } => {
                for i in 0..3 {
                    self.p[(i, i)] += q_m2_s * dt;
                }
            }
            Dynamics::ConstantVelocity { q_m2_s3 } => {
                let n = self.x.len();
                let mut f = DMatrix::<f64>::identity(n, n);
                for i in 0..3 {
                    f[(i, 3 + i)] = dt;
                }
                self.x = &f * &self.x;
                self.p = &f * &self.p * f.transpose();
                // Integrated white acceleration: [dt^3/3, dt^2/2; dt^2/2, dt] q per axis.
                for i in 0..3 {
                    self.p[(i, i)] += q_m2_s3 * dt.powi(3) / 3.0;
                    self.p[(i, 3 + i)] += q_m2_s3 * dt * dt / 2.0;
                    self.p[(3 + i, i)] += q_m2_s3 * dt * dt / 2.0;
                    self.p[(3 + i, 3 + i)] += q_m2_s3 * dt;
                }
            }
        }
        Ok(())
    }

    /// Step 2: states of arcs not observed removed (and their held integers), new arcs started; returns
    /// the number started.
    pub(super) fn update_arcs(&mut self, epoch: &DdEpoch) -> usize {
        let nk = self.nk();
        let present: BTreeSet<u64> = epoch.signals.iter().map(|s| s.arc).collect();
        let keep: Vec<usize> = (0..nk)
            .chain(
                self.arcs
                    .iter()
                    .enumerate()
                    .filter(|(_, a)| present.contains(&a.arc))
                    .map(|(i, _)| nk + i),
            )
            .collect();
        if keep.len() != self.x.len() {
            self.x = DVector::from_fn(keep.len(), |i, _| self.x[keep[i]]);
            self.p = DMatrix::from_fn(keep.len(), keep.len(), |i, j| self.p[(keep[i], keep[j])]);
            self.arcs.retain(|a| present.contains(&a.arc));
            self.held.retain(|a, _| present.contains(a));
        }
        let known: BTreeSet<u64> = self.arcs.iter().map(|a| a.arc).collect();
        let mut started = 0;
        for s in &epoch.signals {
            if known.contains(&s.arc) {
                continue;
            }
            let start = (s.rover_phase_cycles - s.base_phase_cycles)
                - (s.rover_code_m - s.base_code_m) / s.wavelength_m;
            let offset = start.round() as i64; // |phase| <= 1e13, |code| <= 1e9 (validated): exact
            let n = self.x.len();
            self.x = self.x.clone().insert_row(n, start - offset as f64);
            let mut p = DMatrix::zeros(n + 1, n + 1);
            p.view_mut((0, 0), (n, n)).copy_from(&self.p);
            p[(n, n)] = (INITIAL_AMBIGUITY_SIGMA_M / s.wavelength_m).powi(2);
            self.p = p;
            self.arcs.push(ArcState { arc: s.arc, offset });
            started += 1;
        }
        started
    }

    /// Starts the ambiguity state of `s`'s arc again (its phase minus code, uncorrelated, the initial
    /// sigma) and forgets its held integer.
    pub(super) fn restart_arc(&mut self, s: &SignalPair) {
        let i = self.state_of(s.arc);
        let start = (s.rover_phase_cycles - s.base_phase_cycles)
            - (s.rover_code_m - s.base_code_m) / s.wavelength_m;
        let offset = start.round() as i64;
        let nk = self.nk();
        self.arcs[i - nk].offset = offset;
        self.x[i] = start - offset as f64;
        self.p.row_mut(i).fill(0.0);
        self.p.column_mut(i).fill(0.0);
        self.p[(i, i)] = (INITIAL_AMBIGUITY_SIGMA_M / s.wavelength_m).powi(2);
        self.held.remove(&s.arc);
    }

    /// The epoch's groups, each with its reference: the held arc of highest elevation where the group has
    /// held arcs (so that the hold carries over a change of the highest satellite), else the signal of
    /// highest elevation at the base.
    pub(super) fn groups(&self, epoch: &DdEpoch) -> Vec<Group> {
        groups(epoch)
            .into_iter()
            .map(|mut g| {
                let all: Vec<usize> = std::iter::once(g.reference)
                    .chain(g.members.iter().copied())
                    .collect();
                let held_best = all
                    .iter()
                    .copied()
                    .filter(|&i| self.held.contains_key(&epoch.signals[i].arc))
                    .max_by(|&a, &b| {
                        let (sa, sb) = (&epoch.signals[a], &epoch.signals[b]);
                        sa.base
                            .elevation_rad
                            .total_cmp(&sb.base.elevation_rad)
                            .then(sb.sat.cmp(&sa.sat))
                    });
                if let Some(r) = held_best {
                    if r != g.reference {
                        g.members = all.into_iter().filter(|&i| i != r).collect();
                        g.reference = r;
                    }
                }
                g
            })
            .collect()
    }

    pub(super) fn state_of(&self, arc: u64) -> usize {
        // Every signal's arc has a state after `update_arcs`.
        self.nk()
            + self
                .arcs
                .iter()
                .position(|a| a.arc == arc)
                .unwrap_or_default()
    }
}
