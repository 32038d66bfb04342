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
//! [`crate::lambda::gate`]: the second best's objective is at least `ratio_threshold` times larger and
//! its own objective is plausible (below the `1 - 1e-9` chi-square quantile of its degrees of freedom,
//! which refuses a best that is only the least wrong of a list that missed the truth). Rovers are treated as independent (their shared base observations are ignored).
//!
//! [`solve_attitude_held`] scores integers held from earlier epochs with the same objective on the
//! epoch's float solutions and keeps them while it is plausible (fix-and-hold for arrays).

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::enu_at;
use super::fix::{ambiguity_problem, fix_problem, float_result, validate_input};
use super::float::{self, FloatSolution};
use super::{AttitudeSolution, BaselineSolution, DdEpoch, FixOptions};
use crate::error::{ensure_finite, Error, Result};
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

/// One rover's float solution and its candidates.
struct Rover {
    fl: FloatSolution,
    unconstrained: BaselineSolution,
    /// `Q_b|a`, m^2 (ECEF).
    q_cond: Matrix3<f64>,
    /// `(integers, ||a - z||^2, conditioned baseline ENU)`, best screening cost first.
    candidates: Vec<(DVector<i64>, f64, Vector3<f64>)>,
    weight: f64,
    /// The held integers the float solution imposed.
    held_used: Vec<(u64, u64, i64)>,
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
    Ok(fresh(epochs, body_m, fix)?.solution)
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
    let fresh_fix = fresh(epochs, body_m, fix)?;
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
    let keep = keep_per_rover(epochs.len());
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

/// The fresh constrained fix of one epoch, its rovers and the accepted combination's objective.
struct Fresh {
    solution: AttitudeSolution,
    rovers: Vec<Rover>,
    cost: Option<f64>,
}

fn fresh(epochs: &[DdEpoch], body_m: &[[f64; 3]], fix: &FixOptions) -> Result<Fresh> {
    validate_attitude(epochs, body_m)?;
    validate_input(epochs, fix)?;
    let body: Vec<Vector3<f64>> = body_m.iter().map(|f| Vector3::from(*f)).collect();
    let to_enu = enu_at(&epochs[0].base_m);
    let keep = keep_per_rover(epochs.len());
    let rovers = epochs
        .iter()
        .zip(&body)
        .map(|(e, f)| rover(e, f.norm(), &to_enu, fix, keep, &[]))
        .collect::<Result<Vec<_>>>()?;
    let success: f64 = rovers
        .iter()
        .map(|r| r.unconstrained.success_rate)
        .product();
    let (best, ratio) = best_combination(&rovers, &body);
    let dof: usize =
        rovers.iter().map(|r| r.fl.ambiguities.len()).sum::<usize>() + 3 * rovers.len() - 3;
    // The constrained rule of the gate, its success rate reported (the rovers' unconstrained product),
    // not gated.
    let accepted = match &best {
        Some((choice, cost)) => fix
            .gate()
            .decide_constrained(ratio, *cost, chi2_quantile(dof), None, || Ok(success))?
            .accepted
            .then(|| (choice.clone(), *cost)),
        None => None,
    };
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

/// Candidates kept per rover so that all combinations stay within [`MAX_COMBINATIONS`].
fn keep_per_rover(n: usize) -> usize {
    let mut k = 2usize;
    while (k + 1)
        .checked_pow(n as u32)
        .is_some_and(|c| c <= MAX_COMBINATIONS)
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
            candidates: vec![(DVector::zeros(0), 0.0, to_enu * fl.baseline_m)],
            fl,
            unconstrained,
            q_cond,
            held_used,
        });
    };
    let unconstrained = fix_problem(&fl, held, fix, &problem, &q_aa)?;
    let na = fl.ambiguities.len();
    let a = &fl.ambiguities_cycles;
    let q_ab = fl.covariance.view((3, 0), (na, 3)).into_owned();
    let k: DMatrix<f64> = nalgebra::Cholesky::new(q_aa.clone())
        .ok_or_else(|| Error::numerical("attitude fix", "float ambiguity covariance not positive"))?
        .solve(&q_ab);
    let q_bb = fl.covariance.fixed_view::<3, 3>(0, 0).into_owned();
    let red = q_ab.transpose() * &k;
    let q_cond = q_bb - Matrix3::from_fn(|i, j| 0.5 * (red[(i, j)] + red[(j, i)]));
    let found = problem.solve(CANDIDATES, DEFAULT_MAX_NODES)?;
    let mut candidates: Vec<(DVector<i64>, f64, Vector3<f64>, f64)> = (0..found.fixed.ncols())
        .map(|c| {
            let z = found.fixed.column(c).into_owned();
            let d = a - z.map(|v| v as f64);
            let db = k.tr_mul(&d);
            let b = fl.baseline_m - Vector3::new(db[0], db[1], db[2]);
            let u = b / b.norm().max(f64::MIN_POSITIVE);
            let dl = b.norm() - length;
            let screen = found.squared_norms[c] + dl * dl / u.dot(&(q_cond * u));
            (z, found.squared_norms[c], to_enu * b, screen)
        })
        .collect();
    candidates.sort_by(|x, y| x.3.total_cmp(&y.3));
    candidates.truncate(keep);
    Ok(Rover {
        weight: 3.0 / q_cond.trace(),
        fl,
        unconstrained,
        q_cond,
        held_used,
        candidates: candidates
            .into_iter()
            .map(|(z, f, b, _)| (z, f, b))
            .collect(),
    })
}

/// The best combination (candidate index per rover) with its objective, and second-best over best.
fn best_combination(rovers: &[Rover], body: &[Vector3<f64>]) -> (Option<(Vec<usize>, f64)>, f64) {
    let sizes: Vec<usize> = rovers.iter().map(|r| r.candidates.len()).collect();
    let total: usize = sizes.iter().product();
    let mut best: Option<(Vec<usize>, f64)> = None;
    let mut second = f64::INFINITY;
    let mut choice = vec![0usize; rovers.len()];
    for mut index in 0..total {
        for (i, &n) in sizes.iter().enumerate() {
            choice[i] = index % n;
            index /= n;
        }
        let h: Matrix3<f64> = rovers
            .iter()
            .zip(&choice)
            .zip(body)
            .map(|((r, &c), f)| r.weight * r.candidates[c].2 * f.transpose())
            .sum();
        let Ok(rot) = wahba::svd::solve(&h) else {
            continue; // a candidate set with parallel baselines fixes no rotation: not a solution
        };
        let cost: f64 = rovers
            .iter()
            .zip(&choice)
            .zip(body)
            .map(|((r, &c), f)| {
                let (_, fa, b) = &r.candidates[c];
                fa + r.weight * (b - rot * f).norm_squared()
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
    let (z, _, b_enu) = &r.candidates[c];
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
