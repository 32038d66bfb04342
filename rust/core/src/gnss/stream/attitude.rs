//! Attitude mode (`body_baselines_m` given): the integers of every rover fixed together under the body
//! baselines ([`crate::gnss::rtk::solve_attitude_held`]), held across epochs with `continuity`; with
//! `filter` each rover's baseline filtered across epochs (its filter knows the body baseline's length and
//! holds its own integers), the filtered floats fixed together under the body baselines
//! ([`crate::gnss::rtk::fix_attitude_filtered`]), and an epoch that stays float fixed on its own as
//! without a filter (the filter never fixes fewer epochs than single epochs).

use nalgebra::{Matrix3, Vector3};

use super::code_scale::scale_code;
use super::held::present;
use super::lambda::fix_state;
use super::output::attitude_sigmas_deg;
use super::{Engine, Estimate, Prepared};
use crate::error::Result;
use crate::gnss::geometry::{enu_from_ecef, geodetic_from_ecef};
use crate::gnss::options::Method;
use crate::gnss::rtk::{
    fix_attitude_filtered, solve_attitude, solve_attitude_held, AttitudeSolution, BaselineSolution,
    DdEpoch, FixOptions, HeldAttitude,
};
use crate::gnss::solution::FixState;
use crate::interrupt;

impl Engine {
    /// Attitude-mode estimates of every epoch of `prepared` (`None`: unsolved); without `continuity`
    /// the epochs are solved in parallel ([`Engine::attitude_single_epochs`]).
    pub(super) fn attitude_epochs(
        &mut self,
        prepared: &[Prepared],
        fix: &FixOptions,
    ) -> Result<Vec<Option<Estimate>>> {
        if !self.opts.continuity && self.opts.filter.is_none() {
            return self.attitude_single_epochs(prepared, fix);
        }
        let mut out = Vec::with_capacity(prepared.len());
        for (k, p) in prepared.iter().enumerate() {
            interrupt::check("GNSS engine")?;
            if self.opts.filter.is_some() {
                out.push(self.attitude_filter_epoch(k, p, fix)?);
                continue;
            }
            let factors = self.attitude_factors();
            let result = self.attitude_solve(p, &factors, fix);
            out.push(self.attitude_apply(k, p, &factors, result)?);
        }
        Ok(out)
    }

    /// The attitude-mode estimate of epoch `k` through the rovers' filters (`None`: a rover without
    /// code solution or filter solution, or unsolved).
    fn attitude_filter_epoch(
        &mut self,
        k: usize,
        p: &Prepared,
        fix: &FixOptions,
    ) -> Result<Option<Estimate>> {
        let Some(dds) = p
            .rovers
            .iter()
            .map(Option::as_ref)
            .collect::<Option<Vec<&DdEpoch>>>()
        else {
            return Ok(None);
        };
        dds.iter().for_each(|d| self.count_double_differences(d));
        let dds: Vec<DdEpoch> = dds
            .into_iter()
            .zip(&self.code_scale)
            .map(|(d, c)| scale_code(d, c.factor()).into_owned())
            .collect();
        let t = p.time_gpst_ns;
        let mut floats = Vec::with_capacity(dds.len());
        let mut fixed: Vec<Option<BaselineSolution>> = Vec::with_capacity(dds.len());
        let mut held = false;
        for (r, dd) in dds.iter().enumerate() {
            let result = self.filters[r].step(dd, t, fix);
            let Some(f) = self.solved(k, t, result)? else {
                return Ok(None);
            };
            if f.hold_rejected {
                self.warn_once(
                    format!("hold rejected {r}"),
                    format!(
                        "rover {}: held integers disagreed with the filter's float ambiguities at \
                         epoch {k} ({t} ns GPST) and were dropped (an undetected slip or a wrong fix); \
                         the filter fixes again",
                        r + 1
                    ),
                );
            }
            held |= f.state == FixState::Held;
            fixed.push((f.state != FixState::Float).then_some(f.solution));
            floats.push(f.float);
        }
        let body = self.opts.body_baselines_m.clone();
        let result = fix_attitude_filtered(&dds, &floats, &fixed, &body, fix);
        let Some(mut a) = self.solved(k, t, result)? else {
            return Ok(None);
        };
        let mut state = fix_state(a.fixed, held);
        if !a.fixed {
            // The epoch on its own (no filter): taken when its gate passes.
            if let Ok(single) = solve_attitude(&dds, &body, fix) {
                if single.fixed {
                    (a, state) = (single, FixState::Fixed);
                }
            }
        }
        Ok(p.base_m.map(|b| self.attitude_estimate(&b, &a, state)))
    }

    /// The code variance factor of every rover's next epoch.
    pub(super) fn attitude_factors(&self) -> Vec<f64> {
        self.code_scale.iter().map(|c| c.factor()).collect()
    }

    /// The constrained fix of epoch `p` with the code variances scaled by `factors` (`None`: a rover
    /// without code solution); reads the held integers, changes nothing.
    pub(super) fn attitude_solve(
        &self,
        p: &Prepared,
        factors: &[f64],
        fix: &FixOptions,
    ) -> Option<Result<HeldAttitude>> {
        let dds = p
            .rovers
            .iter()
            .zip(factors)
            .map(|(d, &f)| Some(scale_code(d.as_ref()?, f).into_owned()))
            .collect::<Option<Vec<DdEpoch>>>()?;
        let held: Vec<Vec<(u64, u64, i64)>> = if self.opts.continuity {
            self.held
                .iter()
                .zip(&dds)
                .map(|(h, d)| present(h, d))
                .collect()
        } else {
            Vec::new()
        };
        Some(solve_attitude_held(
            &dds,
            &self.opts.body_baselines_m,
            fix,
            &held,
        ))
    }

    /// The attitude-mode estimate of epoch `k` from its fix `result` ([`Engine::attitude_solve`] with
    /// `factors`): the counts, code noise scale, warnings and held integers it updates, in epoch order.
    pub(super) fn attitude_apply(
        &mut self,
        k: usize,
        p: &Prepared,
        factors: &[f64],
        result: Option<Result<HeldAttitude>>,
    ) -> Result<Option<Estimate>> {
        let Some(result) = result else {
            return Ok(None);
        };
        for d in p.rovers.iter().flatten() {
            self.count_double_differences(d);
        }
        let Some(h) = self.solved(k, p.time_gpst_ns, result)? else {
            self.held.iter_mut().for_each(Vec::clear);
            return Ok(None);
        };
        for ((c, b), &f) in self
            .code_scale
            .iter_mut()
            .zip(&h.fresh.baselines)
            .zip(factors)
        {
            c.add(b, f);
        }
        if h.rejected {
            self.warn_once(
                "attitude hold rejected".into(),
                format!(
                    "held integers disagreed with the data at epoch {k} ({} ns GPST) \
                     and were dropped (an undetected slip, a wrong fix, or a fresh fix \
                     the data prefer); the epoch is fixed afresh",
                    p.time_gpst_ns
                ),
            );
        }
        let a = h.solution;
        if self.opts.continuity {
            if a.fixed {
                for (held, b) in self.held.iter_mut().zip(&a.baselines) {
                    held.clone_from(&b.integers);
                }
            } else if !h.held {
                self.held.iter_mut().for_each(Vec::clear);
            }
        }
        let state = fix_state(a.fixed, h.held);
        Ok(p.base_m.map(|b| self.attitude_estimate(&b, &a, state)))
    }

    /// Attitude-mode estimate from the constrained fix: baselines and covariances in ENU at the base,
    /// angle sigmas propagated from the rovers' baseline covariances.
    fn attitude_estimate(
        &self,
        base: &Vector3<f64>,
        a: &AttitudeSolution,
        fix_state: FixState,
    ) -> Estimate {
        let (lat, lon, _) = geodetic_from_ecef(base);
        let r = enu_from_ecef(lat, lon);
        let baselines_enu_m: Vec<Vector3<f64>> =
            a.baselines.iter().map(|b| r * b.baseline_m).collect();
        let covariances_enu_m2: Vec<Matrix3<f64>> = a
            .baselines
            .iter()
            .map(|b| r * b.covariance_m2 * r.transpose())
            .collect();
        let sigmas = attitude_sigmas_deg(
            &a.rotation_enu_from_body,
            &baselines_enu_m,
            &covariances_enu_m2,
        );
        Estimate {
            method: Method::Lambda,
            fixed: a.fixed,
            fix_state,
            fixed_ambiguities: a.baselines.iter().map(|b| b.fixed_ambiguities).sum(),
            ambiguities: a.baselines.iter().map(|b| b.ambiguities).sum(),
            ratio: a.ratio,
            success_rate: a.success_rate,
            baselines_enu_m,
            covariances_enu_m2,
            enu_from_body: Some(a.rotation_enu_from_body),
            attitude_sigmas_deg: Some(sigmas),
        }
    }
}
