//! Attitude mode with integers held from earlier epochs (fix-and-hold for arrays): the held integers
//! scored with the constrained objective of [`super`]'s module documentation on the epoch's float
//! solutions, kept while plausible.

use nalgebra::Vector3;

use super::super::enu_at;
use super::super::{AttitudeSolution, BaselineSolution, DdEpoch, FixOptions};
use super::{
    chi2_quantile_at, constrained_solution, degrees_of_freedom, fresh, rotation, rover,
    search_rovers, Fresh, MIN_SUCCESS_RATE,
};
use crate::error::Result;

/// Upper-tail standard normal quantile of the held integers' chi-square test (tail 1e-3): a false
/// alarm only costs a fresh fix, a wrong integer kept costs every later epoch.
pub const HOLD_Z: f64 = 3.09;

/// What [`solve_attitude_held`] made of the held integers.
#[derive(Debug, Clone)]
pub struct HeldAttitude {
    /// The epoch's solution: the held integers' (new arcs fixed on them) when `held`, else the fresh fix
    /// (or float) of [`super::solve_attitude`].
    pub solution: AttitudeSolution,
    /// The solution comes from the held integers.
    pub held: bool,
    /// The held integers were dropped: their chi-square on this epoch's float solution exceeded its
    /// [`HOLD_Z`] quantile, or a fresh validated fix the data prefer replaced them.
    pub rejected: bool,
    /// The epoch's fresh solution (its float residuals feed the code noise estimate).
    pub fresh: AttitudeSolution,
}

/// Attitude mode with integers held from earlier epochs: `held[i]` is rover `i`'s
/// `(arc, reference arc, integer)` triples present at this epoch (possibly none).
///
/// The held integers (and, for the arcs they do not cover, the best constrained candidates conditioned
/// on them) are scored with the objective of the module documentation on this epoch's unheld float
/// solutions: `sum_i chi2(held_i) - chi2(free_i)` (the ambiguity residuals' quadratic form) plus the
/// constrained search's cost of what remains. They are kept while that cost is below the [`HOLD_Z`]
/// chi-square quantile of `sum n_i + 3 m - 3` degrees of freedom (the fresh fix's), and while a fresh
/// validated fix with other integers does not have a cost `ratio_threshold` times smaller (the data must
/// prefer it as the ratio test prefers a best candidate to its second: no heading jump from a marginal
/// fresh fix). Arcs the held integers do not cover are fixed on them when their constrained ratio passes
/// `ratio_threshold`; otherwise the epoch is float on the held integers (kept for the next epoch).
///
/// # Errors
/// Those of [`super::solve_attitude`].
pub fn solve_attitude_held(
    epochs: &[DdEpoch],
    body_m: &[[f64; 3]],
    fix: &FixOptions,
    held: &[Vec<(u64, u64, i64)>],
) -> Result<HeldAttitude> {
    let fresh_fix = fresh(epochs, body_m, fix, Some(MIN_SUCCESS_RATE))?;
    let fresh_out = |rejected: bool, f: Fresh| HeldAttitude {
        solution: f.solution.clone(),
        held: false,
        rejected,
        fresh: f.solution,
    };
    if held.len() != epochs.len() || held.iter().all(Vec::is_empty) {
        return Ok(fresh_out(false, fresh_fix));
    }
    let body: Vec<Vector3<f64>> = body_m.iter().map(|f| Vector3::from(*f)).collect();
    let to_enu = enu_at(&epochs[0].base_m);
    let rovers = epochs
        .iter()
        .zip(&body)
        .zip(held)
        .map(|((e, f), h)| rover(e, f.norm(), &to_enu, fix, h))
        .collect::<Result<Vec<_>>>()?;
    let out = search_rovers(&rovers, &body)?;
    // Incomplete: the best found is an upper bound of the extension's cost and the ratio a lower bound
    // of its ratio, both on the side of refusing.
    let ratio = out.ratio();
    let Some((chosen, extension_cost)) = out.best else {
        return Ok(fresh_out(true, fresh_fix));
    };
    let imposed: f64 = rovers
        .iter()
        .zip(&fresh_fix.rovers)
        .map(|(h, f)| h.fl.chi2 - f.fl.chi2)
        .sum();
    let cost = imposed.max(0.0) + extension_cost;
    let dof = degrees_of_freedom(&fresh_fix.rovers);
    if cost > chi2_quantile_at(dof, HOLD_Z) {
        return Ok(fresh_out(true, fresh_fix));
    }
    let remaining = rovers.iter().any(|r| !r.fl.ambiguities.is_empty());
    let extended = !remaining || ratio >= fix.ratio_threshold;
    let baselines: Vec<BaselineSolution> = if extended {
        rovers
            .iter()
            .zip(&chosen)
            .map(|(r, c)| constrained_solution(r, c, ratio, &to_enu))
            .collect::<Result<_>>()?
    } else {
        rovers.iter().map(|r| r.unconstrained.clone()).collect()
    };
    if let (true, Some(fresh_cost)) = (fresh_fix.solution.fixed, fresh_fix.cost) {
        if other_integers(&fresh_fix.solution.baselines, &baselines)
            && (!extended || cost > fix.ratio_threshold * fresh_cost)
        {
            return Ok(fresh_out(true, fresh_fix));
        }
    }
    let solution = AttitudeSolution {
        rotation_enu_from_body: rotation(&baselines, &body, &to_enu)?,
        baselines,
        fixed: extended,
        ratio: if remaining { ratio } else { f64::INFINITY },
        success_rate: fresh_fix.solution.success_rate,
    };
    Ok(HeldAttitude {
        solution,
        held: true,
        rejected: false,
        fresh: fresh_fix.solution,
    })
}

/// Whether the fresh fix's integers differ from the held solution's on some rover.
fn other_integers(fresh: &[BaselineSolution], held: &[BaselineSolution]) -> bool {
    fresh.iter().zip(held).any(|(f, h)| {
        let mut a = f.integers.clone();
        let mut b = h.integers.clone();
        a.sort_unstable();
        b.sort_unstable();
        a != b
    })
}
