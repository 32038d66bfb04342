//! Attitude mode: the baselines of a rigid antenna array fixed together with the array's known body
//! geometry, then the rotation ENU <- body from Wahba's problem.
//!
//! The multivariate constrained ILS problem (Teunissen 2010, J. Geodesy 84:751-762; Giorgi et al. 2012)
//! minimises over the integers `z_i` of every rover `i` and the rotation `R`:
//!
//! `sum_i ||a_i - z_i||^2_{Q_a,i} + sum_i ||b_i(z_i) - R f_i||^2 / sigma_i^2`,
//!
//! with `b_i(z) = b_i - Q_ba Q_aa^-1 (a_i - z)` the conditioned baseline (ENU), `f_i` the body baseline and
//! `sigma_i^2 = tr(Q_b|a,i) / 3` (the conditioned covariance taken as isotropic). It is evaluated here on
//! candidate lists rather than by a bounded search: each rover's [`CANDIDATES`] best unconstrained ILS
//! candidates are ranked by `||a - z||^2 + (|b(z)| - |f|)^2 / (u^T Q_b|a u)` (the length constraint to
//! first order, `u = b(z) / |b(z)|`), the best of each are combined (at most [`MAX_COMBINATIONS`]) and
//! scored with the full objective, `R` from the weighted orthogonal Procrustes problem
//! ([`crate::wahba::svd`]). The best combination is accepted by the constrained rule of
//! [`crate::lambda::gate`]: the second best's objective is at least `ratio_threshold` times larger, its
//! own objective is plausible (below the `1 - 1e-9` chi-square quantile of its degrees of freedom,
//! which refuses a best that is only the least wrong of a list that missed the truth), and the
//! constrained estimator's simulated success rate on the epoch's own covariance reaches
//! `min_success_rate` or [`MIN_SUCCESS_RATE`], whichever is higher. Rovers are treated as independent
//! (their shared base observations are ignored).
//!
//! **Success rate.** The rovers' unconstrained bootstrapped rates say nothing of the constrained fix (on
//! the simulated car of `docs/rtklib_comparison.md`, GPS L1, wrong fixes passed the ratio and the
//! plausibility). As [`super::known_length`] does for one known length, the rate is simulated
//! ([`SUCCESS_DRAWS`] seeded draws): the accepted combination taken as the truth (its rotation `R`,
//! baselines `R f_i`), each draw adds the float errors of every rover (ambiguities from `Q_a,i`, the
//! baseline's part not explained by them from `Q_b|a,i`), ranks the rover's searched candidates by the
//! same screening cost, keeps the best of each (at most [`SIMULATED_COMBINATIONS`] combinations) and
//! scores them with the full objective; the rate is the share of draws whose best is the truth. The
//! draws' competitors are the integer sets the epoch's own search found around its float (those near
//! the truth when the fix is right), and a wrong fix taken as the truth overstates its own rate: the
//! floor [`MIN_SUCCESS_RATE`] (that of one known length) covers both.
//!
//! [`fix_attitude_filtered`] fixes the float solutions of the rovers' multi-epoch filters
//! ([`super::filter`]) the same way, with the rovers their filters fixed as single candidates.
//!
//! [`solve_attitude_held`] scores integers held from earlier epochs with the same objective on the
//! epoch's float solutions and keeps them while it is plausible (fix-and-hold for arrays).

use nalgebra::{Cholesky, DMatrix, DVector, Dyn, Matrix3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::enu_at;
use super::fix::{ambiguity_problem, fix_problem, float_result, validate_input};
use super::float::{self, FloatSolution};
pub use super::known_length::MIN_SUCCESS_RATE;
use super::{AttitudeSolution, BaselineSolution, DdEpoch, FixOptions};
use crate::error::{ensure_finite, Error, Result};
use crate::lambda::validation::normal;
use crate::lambda::DEFAULT_MAX_NODES;
use crate::wahba;

/// ILS candidates searched per rover.
pub const CANDIDATES: usize = 200;

/// Most combinations of candidates scored with the full objective (per rover: the `n_rover`-th root).
pub const MAX_COMBINATIONS: usize = 4096;

/// Most rovers in one array (two candidates each already give 2^12 = [`MAX_COMBINATIONS`]).
pub const MAX_ROVERS: usize = 12;

/// Largest body baseline coordinate, m.
pub const MAX_BODY_M: f64 = 1e4;

/// Standard normal quantile of the plausibility check (upper tail 1e-9).
const PLAUSIBLE_Z: f64 = 6.0;

/// Draws of the simulated constrained success rate (its standard error at 0.95 is 0.015).
pub const SUCCESS_DRAWS: usize = 200;

/// Most combinations of candidates one draw of the simulation scores (per rover: the `n_rover`-th root).
pub const SIMULATED_COMBINATIONS: usize = 64;

/// Seed of the simulation: the same epoch gives the same decision in every run.
const SEED: u64 = 2828;

/// A combination (candidate index per rover) and its objective.
type Choice = (Vec<usize>, f64);

/// One rover's float solution and its candidates.
struct Rover {
    fl: FloatSolution,
    unconstrained: BaselineSolution,
    /// `Q_b|a`, m^2 (ECEF).
    q_cond: Matrix3<f64>,
    /// Integers of the kept candidates, best screening cost first.
    integers: Vec<DVector<i64>>,
    /// `(||a - z||^2, conditioned baseline ENU)` of each kept candidate.
    scored: Vec<(f64, Vector3<f64>)>,
    weight: f64,
    /// The held integers the float solution imposed.
    held_used: Vec<(u64, u64, i64)>,
    /// What the simulated success rate needs (`None`: no free ambiguity).
    search: Option<Search>,
    /// The body baseline's length, m.
    length_m: f64,
    /// The smallest screening cost of a candidate not in the list (searched and dropped, or beyond the
    /// search: the largest searched norm): every combination with one has an objective at least this
    /// (infinite: none).
    cutoff: f64,
}

/// A rover's integer search, kept for the simulated success rate.
struct Search {
    /// Every candidate the search found (the kept ones among them).
    found: Vec<DVector<i64>>,
    /// Cholesky factor of `Q_a`.
    chol: Cholesky<f64, Dyn>,
    /// `Q_a^-1 Q_ab` (n x 3): `b(z) = b - K^T (a - z)`, ECEF.
    gain: DMatrix<f64>,
}

/// Attitude mode, one epoch: each rover's [`DdEpoch`] (same base), the body baselines (one per rover,
/// body frame of Bunyaeva et al.: X nose, Y up, Z right wing, m), fixed with the array geometry, then Wahba.
///
/// # Errors
/// [`Error::Shape`] for fewer than two rovers or mismatched lengths, [`Error::TooLarge`] beyond
/// [`MAX_ROVERS`]; [`Error::OutOfRange`] for a body
/// baseline shorter than 1 cm or beyond [`MAX_BODY_M`], epochs with different bases, or the errors of
/// [`super::solve_baseline`]; [`Error::DegenerateGeometry`] when the baselines do not fix a rotation.
pub fn solve_attitude(
    epochs: &[DdEpoch],
    body_m: &[[f64; 3]],
    fix: &FixOptions,
) -> Result<AttitudeSolution> {
    Ok(fresh(epochs, body_m, fix, Some(MIN_SUCCESS_RATE))?.solution)
}

/// Upper-tail standard normal quantile of the held integers' chi-square test (tail 1e-3): a false
/// alarm only costs a fresh fix, a wrong integer kept costs every later epoch.
pub const HOLD_Z: f64 = 3.09;

/// What [`solve_attitude_held`] made of the held integers.
#[derive(Debug, Clone)]
pub struct HeldAttitude {
    /// The epoch's solution: the held integers' (new arcs fixed on them) when `held`, else the fresh fix
    /// (or float) of [`solve_attitude`].
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
/// Those of [`solve_attitude`].
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
    let keep = keep_per_rover(epochs.len(), MAX_COMBINATIONS);
    let rovers = epochs
        .iter()
        .zip(&body)
        .zip(held)
        .map(|((e, f), h)| rover(e, f.norm(), &to_enu, fix, keep, h))
        .collect::<Result<Vec<_>>>()?;
    let (best, ratio) = best_combination(&rovers, &body);
    let Some((choice, extension_cost)) = best else {
        return Ok(fresh_out(true, fresh_fix));
    };
    let imposed: f64 = rovers
        .iter()
        .zip(&fresh_fix.rovers)
        .map(|(h, f)| h.fl.chi2 - f.fl.chi2)
        .sum();
    let cost = imposed.max(0.0) + extension_cost;
    let dof: usize = fresh_fix
        .rovers
        .iter()
        .map(|r| r.fl.ambiguities.len())
        .sum::<usize>()
        + 3 * rovers.len()
        - 3;
    if cost > chi2_quantile_at(dof, HOLD_Z) {
        return Ok(fresh_out(true, fresh_fix));
    }
    let remaining = rovers.iter().any(|r| !r.fl.ambiguities.is_empty());
    let extended = !remaining || ratio >= fix.ratio_threshold;
    let baselines: Vec<BaselineSolution> = if extended {
        rovers
            .iter()
            .zip(&choice)
            .map(|(r, &c)| constrained_solution(r, c, ratio, &to_enu))
            .collect()
    } else {
        rovers.iter().map(|r| r.unconstrained.clone()).collect()
    };
    if let (true, Some(fresh_cost)) = (fresh_fix.solution.fixed, fresh_fix.cost) {
        let differ = fresh_fix
            .solution
            .baselines
            .iter()
            .zip(&baselines)
            .any(|(f, h)| {
                let mut a = f.integers.clone();
                let mut b = h.integers.clone();
                a.sort_unstable();
                b.sort_unstable();
                a != b
            });
        if differ && (!extended || cost > fix.ratio_threshold * fresh_cost) {
            return Ok(fresh_out(true, fresh_fix));
        }
    }
    let enu: Vec<Vector3<f64>> = baselines.iter().map(|b| to_enu * b.baseline_m).collect();
    let weights: Vec<f64> = body.iter().map(|f| f.norm_squared()).collect();
    let rotation = wahba::solve(&body, &enu, &weights, wahba::Method::Svd)?.dcm_ref_from_body;
    let solution = AttitudeSolution {
        rotation_enu_from_body: rotation,
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

/// Attitude mode on the rovers' multi-epoch filters (`--filter`): `floats[i]` is rover `i`'s filtered
/// float solution of the epoch ([`super::filter::FilterEpoch::float`]), `fixed[i]` its filter's fix or
/// hold when it has one. `epochs` (the epoch's double differences) are checked as [`solve_attitude`]'s.
///
/// A rover its filter fixed is one candidate, its fixed baseline; the others' candidates come from
/// their filtered floats, and the combination is accepted by [`solve_attitude`]'s gate (ratio,
/// plausibility, simulated success rate) on the filters' covariances. When every filter has fixed its
/// rover, the fixed baselines must still fit the body baselines: their objective within the
/// plausibility quantile of `3 m - 3` degrees of freedom (a wrong integer set moves a baseline by a
/// good part of a wavelength, tens of its millimetre sigmas), else the epoch is float.
///
/// # Errors
/// Those of [`solve_attitude`]; [`Error::Shape`] when `floats` or `fixed` do not have one entry per
/// rover.
pub fn fix_attitude_filtered(
    epochs: &[DdEpoch],
    floats: &[FloatSolution],
    fixed: &[Option<BaselineSolution>],
    body_m: &[[f64; 3]],
    fix: &FixOptions,
) -> Result<AttitudeSolution> {
    validate_attitude(epochs, body_m)?;
    validate_input(epochs, fix)?;
    if floats.len() != epochs.len() || fixed.len() != epochs.len() {
        return Err(Error::Shape {
            name: "filtered floats",
            expected: "one float solution and one fix (or none) per rover".into(),
            actual: format!(
                "{} floats and {} fixes for {} rovers",
                floats.len(),
                fixed.len(),
                epochs.len()
            ),
        });
    }
    let body: Vec<Vector3<f64>> = body_m.iter().map(|f| Vector3::from(*f)).collect();
    let to_enu = enu_at(&epochs[0].base_m);
    let keep = keep_per_rover(epochs.len(), MAX_COMBINATIONS);
    let rovers = floats
        .iter()
        .zip(fixed)
        .zip(&body)
        .map(|((fl, done), f)| match done {
            Some(sol) => Ok(fixed_rover(fl, sol, f.norm(), &to_enu)),
            None => rover_from_float(fl.clone(), f.norm(), &to_enu, fix, keep, &[]),
        })
        .collect::<Result<Vec<_>>>()?;
    let (best, ratio) = best_combination(&rovers, &body);
    let dof: usize =
        rovers.iter().map(|r| r.fl.ambiguities.len()).sum::<usize>() + 3 * rovers.len() - 3;
    let (accepted, success, ratio) = if fixed.iter().all(Option::is_some) {
        let fits = best
            .as_ref()
            .is_some_and(|(_, cost)| *cost <= chi2_quantile(dof));
        (best.filter(|_| fits), 1.0, f64::INFINITY)
    } else {
        let (a, s) = decide(
            &rovers,
            &body,
            &to_enu,
            best,
            ratio,
            dof,
            fix,
            Some(MIN_SUCCESS_RATE),
        )?;
        (a, s, ratio)
    };
    let baselines: Vec<BaselineSolution> = match &accepted {
        Some((choice, _)) => rovers
            .iter()
            .zip(choice)
            .map(|(r, &c)| constrained_solution(r, c, ratio, &to_enu))
            .collect(),
        None => floats.iter().map(|fl| float_result(fl, &[])).collect(),
    };
    let enu: Vec<Vector3<f64>> = baselines.iter().map(|b| to_enu * b.baseline_m).collect();
    let weights: Vec<f64> = body.iter().map(|f| f.norm_squared()).collect();
    let rotation = wahba::solve(&body, &enu, &weights, wahba::Method::Svd)?.dcm_ref_from_body;
    Ok(AttitudeSolution {
        rotation_enu_from_body: rotation,
        baselines,
        fixed: accepted.is_some(),
        ratio,
        success_rate: success,
    })
}

/// The fresh constrained fix of one epoch, its rovers and the accepted combination's objective.
struct Fresh {
    solution: AttitudeSolution,
    rovers: Vec<Rover>,
    cost: Option<f64>,
}

/// The fresh fix; `floor`: the success-rate floor of the gate (`None`: the rate reported, not gated).
fn fresh(
    epochs: &[DdEpoch],
    body_m: &[[f64; 3]],
    fix: &FixOptions,
    floor: Option<f64>,
) -> Result<Fresh> {
    validate_attitude(epochs, body_m)?;
    validate_input(epochs, fix)?;
    let body: Vec<Vector3<f64>> = body_m.iter().map(|f| Vector3::from(*f)).collect();
    let to_enu = enu_at(&epochs[0].base_m);
    let keep = keep_per_rover(epochs.len(), MAX_COMBINATIONS);
    let rovers = epochs
        .iter()
        .zip(&body)
        .map(|(e, f)| rover(e, f.norm(), &to_enu, fix, keep, &[]))
        .collect::<Result<Vec<_>>>()?;
    let (best, ratio) = best_combination(&rovers, &body);
    let dof: usize =
        rovers.iter().map(|r| r.fl.ambiguities.len()).sum::<usize>() + 3 * rovers.len() - 3;
    let (accepted, success) = decide(&rovers, &body, &to_enu, best, ratio, dof, fix, floor)?;
    let baselines: Vec<BaselineSolution> = match &accepted {
        Some((choice, _)) => rovers
            .iter()
            .zip(choice)
            .map(|(r, &c)| constrained_solution(r, c, ratio, &to_enu))
            .collect(),
        None => rovers.iter().map(|r| r.unconstrained.clone()).collect(),
    };
    let enu: Vec<Vector3<f64>> = baselines.iter().map(|b| to_enu * b.baseline_m).collect();
    let weights: Vec<f64> = body.iter().map(|f| f.norm_squared()).collect();
    let rotation = wahba::solve(&body, &enu, &weights, wahba::Method::Svd)?.dcm_ref_from_body;
    Ok(Fresh {
        solution: AttitudeSolution {
            rotation_enu_from_body: rotation,
            baselines,
            fixed: accepted.is_some(),
            ratio,
            success_rate: success,
        },
        rovers,
        cost: accepted.map(|(_, c)| c),
    })
}

fn validate_attitude(epochs: &[DdEpoch], body_m: &[[f64; 3]]) -> Result<()> {
    if epochs.len() < 2 || body_m.len() != epochs.len() {
        return Err(Error::Shape {
            name: "body baselines",
            expected: "one per rover, at least two rovers (as many as epochs)".into(),
            actual: format!(
                "{} body baselines for {} rovers",
                body_m.len(),
                epochs.len()
            ),
        });
    }
    if epochs.len() > MAX_ROVERS {
        return Err(Error::too_large(
            "body baselines",
            epochs.len() as f64,
            MAX_ROVERS as f64,
            "rovers",
        ));
    }
    ensure_finite("body baselines", body_m.iter().flatten())?;
    for (i, f) in body_m.iter().enumerate() {
        let n = Vector3::from(*f).norm();
        if !(0.01..=MAX_BODY_M).contains(&n) || f.iter().any(|v| v.abs() > MAX_BODY_M) {
            return Err(Error::out_of_range(
                "body baselines",
                format!("expected a length in [0.01, {MAX_BODY_M}] m, got {n} m for rover {i}"),
            ));
        }
    }
    if let Some(i) = epochs
        .iter()
        .position(|e| (e.base_m - epochs[0].base_m).norm() > 1e-3)
    {
        return Err(Error::out_of_range(
            "epochs",
            format!("expected one base for every rover, rover {i}'s base differs from rover 0's"),
        ));
    }
    Ok(())
}

/// Candidates kept per rover of `n` so that all combinations stay within `max_combinations`.
fn keep_per_rover(n: usize, max_combinations: usize) -> usize {
    let mut k = 2usize;
    while (k + 1)
        .checked_pow(n as u32)
        .is_some_and(|c| c <= max_combinations)
    {
        k += 1;
    }
    k.min(CANDIDATES)
}

fn rover(
    epoch: &DdEpoch,
    length: f64,
    to_enu: &Matrix3<f64>,
    fix: &FixOptions,
    keep: usize,
    held: &[(u64, u64, i64)],
) -> Result<Rover> {
    let fl = float::solve(std::slice::from_ref(epoch), held)?;
    rover_from_float(fl, length, to_enu, fix, keep, held)
}

/// A rover whose baseline is fixed already (by its filter): one candidate, that baseline.
fn fixed_rover(
    fl: &FloatSolution,
    sol: &BaselineSolution,
    length: f64,
    to_enu: &Matrix3<f64>,
) -> Rover {
    let mut fl = fl.clone();
    fl.ambiguities.clear();
    fl.ambiguities_cycles = DVector::zeros(0);
    Rover {
        weight: 3.0 / sol.covariance_m2.trace(),
        integers: vec![DVector::zeros(0)],
        scored: vec![(0.0, to_enu * sol.baseline_m)],
        fl,
        unconstrained: sol.clone(),
        q_cond: sol.covariance_m2,
        held_used: sol.integers.clone(),
        search: None,
        length_m: length,
        cutoff: f64::INFINITY,
    }
}

fn rover_from_float(
    fl: FloatSolution,
    length: f64,
    to_enu: &Matrix3<f64>,
    fix: &FixOptions,
    keep: usize,
    held: &[(u64, u64, i64)],
) -> Result<Rover> {
    let held_used: Vec<(u64, u64, i64)> = held
        .iter()
        .copied()
        .filter(|&(a, r, _)| fl.used_held.contains(&(a, r)))
        .collect();
    // One decorrelation serves the unconstrained fix and the candidate search.
    let Some((problem, q_aa)) = ambiguity_problem(&fl)? else {
        if held.is_empty() {
            return Err(Error::Shape {
                name: "epochs",
                expected: "float ambiguities in every rover's epoch".into(),
                actual: "none".into(),
            });
        }
        // Every ambiguity held: one candidate, the held baseline.
        let unconstrained = float_result(&fl, held);
        let q_cond = unconstrained.covariance_m2;
        return Ok(Rover {
            weight: 3.0 / q_cond.trace(),
            integers: vec![DVector::zeros(0)],
            scored: vec![(0.0, to_enu * fl.baseline_m)],
            fl,
            unconstrained,
            q_cond,
            held_used,
            search: None,
            length_m: length,
            cutoff: f64::INFINITY,
        });
    };
    let unconstrained = fix_problem(&fl, held, fix, &problem, &q_aa)?;
    let na = fl.ambiguities.len();
    let a = &fl.ambiguities_cycles;
    let q_ab = fl.covariance.view((3, 0), (na, 3)).into_owned();
    let chol = Cholesky::new(q_aa.clone()).ok_or_else(|| {
        Error::numerical("attitude fix", "float ambiguity covariance not positive")
    })?;
    let k: DMatrix<f64> = chol.solve(&q_ab);
    let q_bb = fl.covariance.fixed_view::<3, 3>(0, 0).into_owned();
    let red = q_ab.transpose() * &k;
    let q_cond = q_bb - Matrix3::from_fn(|i, j| 0.5 * (red[(i, j)] + red[(j, i)]));
    let weight = 3.0 / q_cond.trace();
    let found = problem.solve(CANDIDATES, DEFAULT_MAX_NODES)?;
    let all: Vec<DVector<i64>> = (0..found.fixed.ncols())
        .map(|c| found.fixed.column(c).into_owned())
        .collect();
    let mut candidates: Vec<(usize, f64, Vector3<f64>, f64)> = all
        .iter()
        .enumerate()
        .map(|(c, z)| {
            let d = a - z.map(|v| v as f64);
            let db = k.tr_mul(&d);
            let b = fl.baseline_m - Vector3::new(db[0], db[1], db[2]);
            let screen = screening_cost(found.squared_norms[c], &b, length, weight);
            (c, found.squared_norms[c], to_enu * b, screen)
        })
        .collect();
    candidates.sort_by(|x, y| x.3.total_cmp(&y.3));
    let searched = found.squared_norms.last().copied().unwrap_or(f64::INFINITY);
    let cutoff = candidates
        .iter()
        .skip(keep)
        .map(|c| c.3)
        .fold(searched, f64::min);
    candidates.truncate(keep);
    Ok(Rover {
        weight,
        integers: candidates.iter().map(|c| all[c.0].clone()).collect(),
        scored: candidates.iter().map(|c| (c.1, c.2)).collect(),
        fl,
        unconstrained,
        q_cond,
        held_used,
        search: Some(Search {
            found: all,
            chol,
            gain: k,
        }),
        length_m: length,
        cutoff,
    })
}

/// The candidate ranking `||a - z||^2 + w (|b(z)| - |f|)^2`, with the objective's weight `w`: a lower
/// bound of the candidate's term of the objective (`|b - R f| >= ||b| - |f||`), so that a candidate
/// ranked out of the list bounds every combination that has it.
fn screening_cost(norm: f64, b: &Vector3<f64>, length: f64, weight: f64) -> f64 {
    let dl = b.norm() - length;
    norm + weight * dl * dl
}

/// The constrained rule of the gate for the best combination `best` (objective, ratio `ratio`, `dof`
/// degrees of freedom): the accepted choice and its objective, and the simulated success rate (NaN when
/// the ratio or the plausibility refuse first). `floor`: as [`crate::lambda::gate`]'s.
#[allow(clippy::too_many_arguments)]
fn decide(
    rovers: &[Rover],
    body: &[Vector3<f64>],
    to_enu: &Matrix3<f64>,
    best: Option<Choice>,
    ratio: f64,
    dof: usize,
    fix: &FixOptions,
    floor: Option<f64>,
) -> Result<(Option<Choice>, f64)> {
    let Some((choice, cost)) = best else {
        return Ok((None, f64::NAN));
    };
    // A combination outside the lists has an objective of at least the cutoff: the ratio against the
    // problem's second best is at least the lists' second best or the cutoff over the best (the lists
    // may have missed the truth when the cutoff is below the best).
    let cutoff = rovers
        .iter()
        .map(|r| r.cutoff)
        .fold(f64::INFINITY, f64::min);
    let ratio = ratio.min(cutoff / cost);
    let d = fix
        .gate()
        .decide_constrained(ratio, cost, chi2_quantile(dof), floor, || {
            success_rate(rovers, &choice, body, to_enu)
        })?;
    Ok((d.accepted.then_some((choice, cost)), d.success_rate))
}

/// The weighted rotation of the candidates `choice` (`None`: their baselines fix no rotation).
fn rotation_of(
    weights: &[f64],
    lists: &[&[(f64, Vector3<f64>)]],
    choice: &[usize],
    body: &[Vector3<f64>],
) -> Option<Matrix3<f64>> {
    let h: Matrix3<f64> = weights
        .iter()
        .zip(lists)
        .zip(choice)
        .zip(body)
        .map(|(((w, l), &c), f)| *w * l[c].1 * f.transpose())
        .sum();
    wahba::svd::solve(&h).ok()
}

/// The simulated success rate of the constrained fix `choice` (module documentation): the share of
/// [`SUCCESS_DRAWS`] draws around it whose constrained best is it (the estimator's success: no ratio
/// test in the draws). `to_enu`: ENU <- ECEF at the base.
fn success_rate(
    rovers: &[Rover],
    choice: &[usize],
    body: &[Vector3<f64>],
    to_enu: &Matrix3<f64>,
) -> Result<f64> {
    let weights: Vec<f64> = rovers.iter().map(|r| r.weight).collect();
    let lists: Vec<&[(f64, Vector3<f64>)]> = rovers.iter().map(|r| r.scored.as_slice()).collect();
    let rot = rotation_of(&weights, &lists, choice, body)
        .ok_or_else(|| Error::numerical("attitude success rate", "the fix gives no rotation"))?;
    let keep = keep_per_rover(rovers.len(), SIMULATED_COMBINATIONS);
    // Per rover: the truth's baseline (ENU), the Cholesky factor of Q_b|a (ENU), and per searched
    // candidate z: L^-1 (z* - z) (the ambiguity residual of a draw is g + that, g standard normal) and
    // K^T (z - z*) (ENU: the conditioned baseline of a draw is the truth's plus the draw's Q_b|a error
    // plus that), truth first.
    struct Pre {
        truth_b: Vector3<f64>,
        l_cond: Matrix3<f64>,
        n: usize,
        shifts: Vec<(DVector<f64>, Vector3<f64>)>,
    }
    let pre: Vec<Pre> = rovers
        .iter()
        .zip(choice)
        .zip(body)
        .map(|((r, &c), f)| {
            let q_cond = to_enu * r.q_cond * to_enu.transpose();
            let q_cond = (q_cond + q_cond.transpose()) * 0.5;
            let l_cond = Cholesky::new(q_cond + Matrix3::identity() * 1e-12)
                .map(|c| c.l())
                .ok_or_else(|| Error::numerical("attitude success rate", "Q_b|a not positive"))?;
            let truth_b = rot * f;
            let shifts = match &r.search {
                None => vec![(DVector::zeros(0), Vector3::zeros())],
                Some(s) => {
                    let truth = &r.integers[c];
                    let truth_first =
                        std::iter::once(truth).chain(s.found.iter().filter(|z| *z != truth));
                    truth_first
                        .map(|z| {
                            let dz = (truth - z).map(|v| v as f64);
                            let d = s.chol.l().solve_lower_triangular(&dz).unwrap_or(dz);
                            let db = s.gain.tr_mul(&(-(truth - z).map(|v| v as f64)));
                            (d, to_enu * Vector3::new(db[0], db[1], db[2]))
                        })
                        .collect()
                }
            };
            Ok(Pre {
                truth_b,
                l_cond,
                n: r.fl.ambiguities.len(),
                shifts,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let successes: usize = (0..SUCCESS_DRAWS)
        .into_par_iter()
        .map(|t| {
            let mut rng = ChaCha8Rng::seed_from_u64(SEED);
            rng.set_stream(t as u64);
            // Per rover: the kept candidates' (index, norm, baseline ENU), index 0 the truth.
            let drawn: Vec<Vec<(usize, f64, Vector3<f64>)>> = pre
                .iter()
                .zip(rovers)
                .map(|(p, r)| {
                    let g = DVector::from_fn(p.n, |_, _| normal(&mut rng));
                    let e = p.l_cond * Vector3::from_fn(|_, _| normal(&mut rng));
                    let mut c: Vec<(usize, f64, Vector3<f64>, f64)> = p
                        .shifts
                        .iter()
                        .enumerate()
                        .map(|(j, (d, db))| {
                            let norm = (&g + d).norm_squared();
                            let b = p.truth_b + e + db;
                            (j, norm, b, screening_cost(norm, &b, r.length_m, r.weight))
                        })
                        .collect();
                    c.sort_by(|x, y| x.3.total_cmp(&y.3));
                    c.truncate(keep);
                    c.into_iter().map(|(j, n, b, _)| (j, n, b)).collect()
                })
                .collect();
            let lists: Vec<Vec<(f64, Vector3<f64>)>> = drawn
                .iter()
                .map(|d| d.iter().map(|&(_, n, b)| (n, b)).collect())
                .collect();
            let views: Vec<&[(f64, Vector3<f64>)]> = lists.iter().map(Vec::as_slice).collect();
            let (best, _) = best_of(&weights, &views, body);
            usize::from(best.is_some_and(|(c, _)| c.iter().zip(&drawn).all(|(&i, d)| d[i].0 == 0)))
        })
        .sum();
    Ok(successes as f64 / SUCCESS_DRAWS as f64)
}

/// The best combination (candidate index per rover) with its objective, and second-best over best.
fn best_combination(rovers: &[Rover], body: &[Vector3<f64>]) -> (Option<Choice>, f64) {
    let weights: Vec<f64> = rovers.iter().map(|r| r.weight).collect();
    let lists: Vec<&[(f64, Vector3<f64>)]> = rovers.iter().map(|r| r.scored.as_slice()).collect();
    best_of(&weights, &lists, body)
}

/// [`best_combination`] over candidate lists `(||a - z||^2, conditioned baseline ENU)` with the rovers'
/// weights.
fn best_of(
    weights: &[f64],
    lists: &[&[(f64, Vector3<f64>)]],
    body: &[Vector3<f64>],
) -> (Option<Choice>, f64) {
    let sizes: Vec<usize> = lists.iter().map(|l| l.len()).collect();
    let total: usize = sizes.iter().product();
    let mut best: Option<Choice> = None;
    let mut second = f64::INFINITY;
    let mut choice = vec![0usize; lists.len()];
    for mut index in 0..total {
        for (i, &n) in sizes.iter().enumerate() {
            choice[i] = index % n;
            index /= n;
        }
        let Some(rot) = rotation_of(weights, lists, &choice, body) else {
            continue; // a candidate set with parallel baselines fixes no rotation: not a solution
        };
        let cost: f64 = weights
            .iter()
            .zip(lists)
            .zip(&choice)
            .zip(body)
            .map(|(((w, l), &c), f)| {
                let (fa, b) = &l[c];
                fa + w * (b - rot * f).norm_squared()
            })
            .sum();
        match &best {
            Some((_, b)) if cost >= *b => second = second.min(cost),
            _ => {
                if let Some((_, b)) = &best {
                    second = second.min(*b);
                }
                best = Some((choice.clone(), cost));
            }
        }
    }
    let ratio = match &best {
        Some((_, b)) if *b > 0.0 => second / b,
        Some(_) => f64::INFINITY,
        None => f64::NAN,
    };
    (best, ratio)
}

/// The rover's solution conditioned on candidate `c`.
fn constrained_solution(
    r: &Rover,
    c: usize,
    ratio: f64,
    to_enu: &Matrix3<f64>,
) -> BaselineSolution {
    let (z, b_enu) = (&r.integers[c], r.scored[c].1);
    let mut s = r.unconstrained.clone();
    s.baseline_m = to_enu.transpose() * b_enu;
    s.covariance_m2 = r.q_cond;
    s.fixed = true;
    s.fixed_ambiguities = r.fl.ambiguities.len() + r.held_used.len();
    s.ratio = ratio;
    s.integers = r.held_used.clone();
    s.integers.extend(
        r.fl.ambiguities
            .iter()
            .zip(z.iter())
            .map(|(a, &v)| (a.arc, a.reference_arc, a.offset + v)),
    );
    s
}

/// Wilson-Hilferty approximation of the chi-square quantile with `dof` degrees of freedom at the
/// standard normal quantile [`PLAUSIBLE_Z`] (relative error under 1 % for dof >= 3).
pub(super) fn chi2_quantile(dof: usize) -> f64 {
    chi2_quantile_at(dof, PLAUSIBLE_Z)
}

/// Wilson-Hilferty chi-square quantile of `dof` degrees of freedom at the standard normal quantile `z`.
pub(crate) fn chi2_quantile_at(dof: usize, z: f64) -> f64 {
    let k = dof.max(1) as f64;
    let c = 2.0 / (9.0 * k);
    k * (1.0 - c + z * c.sqrt()).powi(3)
}

#[cfg(test)]
#[path = "constrained_tests.rs"]
mod tests;
