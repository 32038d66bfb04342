//! The engine's work spread over threads where it does not depend on what came before, with results equal
//! bit for bit to one thread's (the order of the arithmetic of every value is unchanged; only independent
//! computations run side by side):
//! - **Code solutions** ([`Engine::code_solutions`]): each receiver's epochs in order (each solution is
//!   seeded with the receiver's previous one), the receivers in parallel, a block of [`BLOCK`] epochs at
//!   a time; with `base_position_m`, the base's geometry at that position with the solution's clocks.
//! - **Single epochs** ([`Engine::single_epochs`], moving mode without `continuity` or `filter`): an
//!   epoch's fix depends on the epochs before only through the code noise scale ([`CodeNoiseScale`]),
//!   which adds the float solutions' residuals in epoch order. The float solutions are computed in that
//!   order, each with the factor the epochs before give, and the integer fixes (decorrelation, search,
//!   gate: most of the work) of the block in parallel. Where the factor cannot move (before the estimate
//!   stands, or clamped at an end of its range: GEONET's and the cssrlib pair's receivers are quieter
//!   than half the model's sigma) the block's float solutions are computed in parallel with that factor
//!   and each kept only where the factor of the ordered pass is the same value. The scale counts an
//!   epoch's residuals only when its fix succeeds; a fix that fails after its float solution (rare: the
//!   search's node cap) takes the scale back and the block again from the next epoch.
//! - **Attitude single epochs** ([`Engine::attitude_single_epochs`], attitude mode without
//!   `continuity`): the same dependence through every rover's code noise scale, but the constrained fix
//!   is one call (float solutions and search together). Where every rover's factor is settled, the
//!   block's fixes are computed in parallel with those factors and each kept only where the factors of
//!   the ordered pass are the same values; an epoch whose factors differ is fixed again in order.

use std::ops::Range;

use nalgebra::Vector3;
use rayon::prelude::*;

use super::code_scale::{scale_code, scale_noise, CodeNoiseScale};
use super::{
    leaves_epoch_unsolved, Engine, Estimate, Prepared, CODE_SCALE_FACTOR_RANGE,
    KNOWN_LENGTH_FACTOR_RANGE,
};
use crate::error::Result;
use crate::gnss::observations::Observations;
use crate::gnss::rtk::fix::{baseline_float, fix_float};
use crate::gnss::rtk::float::FloatSolution;
use crate::gnss::rtk::known_length::{fix_known_length, known_length_float};
use crate::gnss::rtk::{BaselineSolution, DdEpoch, FixOptions};
use crate::gnss::solution::FixState;
use crate::gnss::spp::{observed_geometry, single_point_position, SppSolution};
use crate::interrupt;
use std::borrow::Cow;

/// Epochs handed to the threads at a time: enough work per block for 16 threads, few epochs' solutions
/// held at once.
pub const BLOCK: usize = 64;

/// One epoch of a block after the ordered float pass: the rover's code noise scale before the epoch and
/// its float solution; `None` where the rover has no double differences.
type BlockFloat = Option<(CodeNoiseScale, Result<FloatSolution>)>;

/// [`BlockFloat`] after the fix: the scale before the epoch, whether its float solution succeeded (so
/// counted in the scale), and the fix.
type BlockFix = Option<(CodeNoiseScale, bool, Result<BaselineSolution>)>;

impl Engine {
    /// Code solutions of epochs `epochs` of every receiver, `[epoch][receiver]`; the receivers' priors
    /// advanced past them. With `base_position_m`, the base's geometry is that of the given position
    /// (what [`Engine::prepare`] uses; the code solution's own is not).
    pub(super) fn code_solutions(
        &mut self,
        obs: &Observations,
        epochs: Range<usize>,
    ) -> Vec<Vec<Result<SppSolution>>> {
        let this = &*self;
        let chains: Vec<(_, Vec<_>)> = (0..this.n_receivers)
            .into_par_iter()
            .map(|r| {
                let mut prior = this.spp_prior[r];
                let mut out = Vec::with_capacity(epochs.len());
                for k in epochs.clone() {
                    if let Err(e) = interrupt::check("GNSS engine") {
                        out.push(Err(e));
                        continue;
                    }
                    let (eph, nav, opts) = (&this.eph, &this.nav, &this.opts);
                    let given = (r == 0).then_some(opts.base_position_m).flatten();
                    let mut spp = single_point_position(obs, r, k, eph, nav, opts, prior.as_ref());
                    if let Ok(s) = &mut spp {
                        prior = Some(s.position_m);
                        // The base at its surveyed position: the code solution's own geometry is
                        // not used, so not computed.
                        let at = given.map_or(s.position_m, Vector3::from);
                        s.geometry =
                            observed_geometry(obs, r, k, eph, opts.frequencies, &s.clock_s, &at);
                    }
                    out.push(spp);
                }
                (prior, out)
            })
            .collect();
        let mut per_receiver = Vec::with_capacity(chains.len());
        for (r, (prior, out)) in chains.into_iter().enumerate() {
            self.spp_prior[r] = prior;
            per_receiver.push(out.into_iter());
        }
        epochs
            .map(|_| per_receiver.iter_mut().filter_map(Iterator::next).collect())
            .collect()
    }

    /// The code variance factor of rover `r`'s next epoch (the loop of `Engine::lambda`).
    fn code_factor(&self, r: usize) -> f64 {
        if self.opts.baseline_lengths_m.is_empty() {
            self.code_scale[r].factor()
        } else {
            self.code_scale[r].known_length_factor()
        }
    }

    /// Rover `r`'s epoch `dd` with its variances scaled by `factor` (`Engine::code_factor`): the code and
    /// the phase together in baseline mode, the code alone for a rover with a known length
    /// (`code_scale` module documentation).
    pub(super) fn scaled<'a>(&self, r: usize, dd: &'a DdEpoch, factor: f64) -> Cow<'a, DdEpoch> {
        if self.opts.baseline_lengths_m.get(r).is_some() {
            scale_code(dd, factor)
        } else {
            scale_noise(dd, factor)
        }
    }

    /// Whether rover `r`'s factor stays what it is whatever residuals are added next: 1 before the
    /// estimate stands (the residuals of one block are few against [`super::CODE_SCALE_MIN_DOF`] only
    /// sometimes, which the ordered pass checks), or clamped at an end of its range.
    fn code_factor_settled(&self, r: usize) -> bool {
        let (lo, hi) = if self.opts.baseline_lengths_m.is_empty() {
            CODE_SCALE_FACTOR_RANGE
        } else {
            KNOWN_LENGTH_FACTOR_RANGE
        };
        self.code_scale[r]
            .estimate()
            .is_none_or(|f| f <= lo || f >= hi)
    }

    /// The float solution of rover `r`'s epoch `dd` (already scaled, `Engine::scaled`): `Engine::solve`'s first part.
    fn single_float(&self, r: usize, dd: &DdEpoch, fix: &FixOptions) -> Result<FloatSolution> {
        let one = std::slice::from_ref(dd);
        match self.opts.baseline_lengths_m.get(r) {
            Some(&l) => known_length_float(one, &[], l, fix),
            None => baseline_float(one, &[], fix),
        }
    }

    /// The fix of a float solution of rover `r`: `Engine::solve`'s second part.
    fn single_fix(
        &self,
        r: usize,
        fl: &FloatSolution,
        fix: &FixOptions,
    ) -> Result<BaselineSolution> {
        match self.opts.baseline_lengths_m.get(r) {
            Some(&l) => fix_known_length(fl, &[], l, fix),
            None => fix_float(fl, &[], fix),
        }
    }

    /// Rover `r`'s solution of every epoch of `prepared` in moving mode without `continuity` or
    /// `filter`: the epochs, warnings, double-difference counts, code noise scale and length estimate
    /// the epoch-by-epoch loop of `Engine::lambda` gives, in parallel (module documentation).
    pub(super) fn single_epochs(
        &mut self,
        r: usize,
        prepared: &[Prepared],
        fix: &FixOptions,
    ) -> Result<Vec<Option<(BaselineSolution, FixState)>>> {
        let mut out = Vec::with_capacity(prepared.len());
        let mut start = 0;
        while start < prepared.len() {
            let block = &prepared[start..(start + BLOCK).min(prepared.len())];
            let chain = self.block_floats(r, block, fix)?;
            let this = &*self;
            let fixed: Vec<BlockFix> = chain
                .into_par_iter()
                .map(|c| {
                    c.map(|(before, float)| {
                        let float_ok = float.is_ok();
                        (
                            before,
                            float_ok,
                            float.and_then(|fl| this.single_fix(r, &fl, fix)),
                        )
                    })
                })
                .collect();
            start = self.commit_block(r, start, block, fixed, &mut out)?;
        }
        Ok(out)
    }

    /// Rover `r`'s float solutions of one block, each with the code noise scale before it: computed in
    /// parallel with a guessed factor when the factor is settled, and kept only where the ordered pass
    /// (each epoch with the factor the epochs before it give) finds the same factor; the scale is
    /// updated with every float solution's residuals.
    fn block_floats(
        &mut self,
        r: usize,
        block: &[Prepared],
        fix: &FixOptions,
    ) -> Result<Vec<BlockFloat>> {
        let guess = self.code_factor_settled(r).then(|| self.code_factor(r));
        let this = &*self;
        let speculative: Vec<Option<Result<FloatSolution>>> = match guess {
            Some(f) => block
                .par_iter()
                .map(|p| {
                    let dd = p.rovers[r].as_ref()?;
                    Some(this.single_float(r, this.scaled(r, dd, f).as_ref(), fix))
                })
                .collect(),
            None => block.iter().map(|_| None).collect(),
        };
        // In order: each epoch's float solution with the factor the epochs before it give.
        let mut chain = Vec::with_capacity(block.len());
        for (p, early) in block.iter().zip(speculative) {
            interrupt::check("GNSS engine")?;
            let Some(dd) = &p.rovers[r] else {
                chain.push(None);
                continue;
            };
            let factor = self.code_factor(r);
            let float = match (early, guess) {
                (Some(fl), Some(g)) if g == factor => fl,
                _ => self.single_float(r, self.scaled(r, dd, factor).as_ref(), fix),
            };
            let before = self.code_scale[r];
            if let Ok(fl) = &float {
                self.code_scale[r].add_float(fl.chi2, fl.dof, factor);
            }
            chain.push(Some((before, float)));
        }
        Ok(chain)
    }

    /// Takes rover `r`'s fixes of the block that begins at epoch `start`, in order, into `out`: counts,
    /// length estimate and unsolved notes. Returns where the next block begins: after the block, or
    /// right after the first epoch whose fix failed though its float solution counted in the code
    /// noise scale (the scale is restored to what it was before that epoch, and the later epochs of the
    /// block, solved with it, are solved again).
    fn commit_block(
        &mut self,
        r: usize,
        start: usize,
        block: &[Prepared],
        fixed: Vec<BlockFix>,
        out: &mut Vec<Option<(BaselineSolution, FixState)>>,
    ) -> Result<usize> {
        let mut next = start + block.len();
        for (i, c) in fixed.into_iter().enumerate() {
            let (k, p) = (start + i, &block[i]);
            let (Some(dd), Some((before, float_ok, result))) = (&p.rovers[r], c) else {
                out.push(None);
                continue;
            };
            self.count_double_differences(dd);
            match result {
                Ok(sol) => {
                    self.length[r].add(&sol.baseline_m, &sol.covariance_m2);
                    let state = if sol.fixed {
                        FixState::Fixed
                    } else {
                        FixState::Float
                    };
                    out.push(Some((sol, state)));
                }
                Err(e) if leaves_epoch_unsolved(&e) => {
                    self.note_unsolved(k, p.time_gpst_ns, &e);
                    self.held[r].clear();
                    out.push(None);
                    if float_ok {
                        // The ordered pass counted this epoch's residuals; the epochs after it
                        // were solved with a scale that should not have them.
                        self.code_scale[r] = before;
                        next = k + 1;
                        break;
                    }
                }
                Err(e) => return Err(e),
            }
        }
        Ok(next)
    }

    /// Attitude-mode estimates of every epoch of `prepared` without `continuity`: what the
    /// epoch-by-epoch loop of `Engine::attitude_epochs` gives, in parallel (module documentation).
    pub(super) fn attitude_single_epochs(
        &mut self,
        prepared: &[Prepared],
        fix: &FixOptions,
    ) -> Result<Vec<Option<Estimate>>> {
        let mut out = Vec::with_capacity(prepared.len());
        for (b, block) in prepared.chunks(BLOCK).enumerate() {
            let settled = self.code_scale.iter().all(|c| {
                let (lo, hi) = CODE_SCALE_FACTOR_RANGE;
                c.estimate().is_none_or(|f| f <= lo || f >= hi)
            });
            let guess = settled.then(|| self.attitude_factors());
            let this = &*self;
            let mut speculative: Vec<Option<_>> = match &guess {
                Some(g) => block
                    .par_iter()
                    .map(|p| Some(this.attitude_solve(p, g, fix)))
                    .collect(),
                None => block.iter().map(|_| None).collect(),
            };
            for (i, p) in block.iter().enumerate() {
                interrupt::check("GNSS engine")?;
                let factors = self.attitude_factors();
                let result = match (speculative[i].take(), &guess) {
                    (Some(r), Some(g)) if *g == factors => r,
                    _ => self.attitude_solve(p, &factors, fix),
                };
                out.push(self.attitude_apply(b * BLOCK + i, p, &factors, result)?);
            }
        }
        Ok(out)
    }
}
