//! Attitude mode: the baselines of a rigid antenna array fixed together with the array's known body
//! geometry, then the rotation ENU <- body from Wahba's problem.
//!
//! The multivariate constrained ILS problem (Teunissen 2010, J. Geodesy 84:751-762; Giorgi et al. 2012)
//! minimises over the integers `z_i` of every rover `i` and the rotation `R`:
//!
//! `sum_i ||a_i - z_i||^2_{Q_a,i} + sum_i ||b_i(z_i) - R f_i||^2 / sigma_i^2`,
//!
//! with `b_i(z) = b_i - Q_ba Q_aa^-1 (a_i - z)` the conditioned baseline (ENU), `f_i` the body baseline and
//! `sigma_i^2 = tr(Q_b|a,i) / 3` (the conditioned covariance taken as isotropic), `R` from the weighted
//! orthogonal Procrustes problem ([`crate::wahba::svd`]). It is minimised exactly ([`search`]): each
//! rover's list of unconstrained ILS candidates grows (from the [`FIRST_CANDIDATES`] best to every
//! candidate below a radius, at most [`MAX_CANDIDATES`]) until the objective's lower bound (a rover's
//! candidate costs at least `||a - z||^2 + (|b(z)| - |f|)^2 / sigma^2`, which is at least its norm)
//! guarantees that the best and the second-best combinations of the whole integer space are among the
//! lists'. (Until this search, 200 candidates per rover were combined: on the simulated GPS L1 platforms
//! those lists rarely held the true second best, and a ratio against them let wrong fixes through.) The best combination
//! is accepted by the constrained rule of [`crate::lambda::gate`]: the second best's objective is at
//! least `ratio_threshold` times larger (a search that hit its limits gives a lower bound of the
//! ratio: the lists' second best or the bound of what they left out, whichever is smaller), its own
//! objective is plausible (below the `1 - 1e-9` chi-square quantile of its degrees of freedom), and the
//! constrained estimator's simulated success rate on the epoch's own covariance reaches
//! `min_success_rate` or [`MIN_SUCCESS_RATE`], whichever is higher. Rovers are treated as independent
//! (their shared base observations are ignored).
//!
//! **Success rate** ([`success`]). The rovers' unconstrained bootstrapped rates say nothing of the
//! constrained fix (on the simulated car of `docs/rtklib_comparison.md`, GPS L1, wrong fixes passed the
//! ratio and the plausibility). As [`super::known_length`] does for one known length, the rate is
//! simulated ([`SUCCESS_DRAWS`] seeded draws): the accepted combination taken as the truth (its rotation
//! `R`, baselines `R f_i`), each draw adds the float errors of every rover (ambiguities from `Q_a,i`,
//! the baseline's part correlated with them and its part from `Q_b|a,i`) and solves the draw by the
//! same exact search; the rate is the share of draws whose best is the truth (a draw whose search hit
//! its limits is a failure). A wrong fix taken as the truth overstates its own rate: the floor
//! [`MIN_SUCCESS_RATE`] (that of one known length) covers it.
//!
//! [`fix_attitude_filtered`] fixes the float solutions of the rovers' multi-epoch filters
//! ([`super::filter`]) the same way, with the rovers their filters fixed as single candidates.
//!
//! [`solve_attitude_held`] scores integers held from earlier epochs with the same objective on
//! the epoch's float solutions and keeps them while it is plausible (fix-and-hold for arrays).

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::enu_at;
use super::fix::{ambiguity_problem, fix_problem, float_result, validate_input};
use super::float::{self, FloatSolution};
pub use super::known_length::MIN_SUCCESS_RATE;
use super::{AttitudeSolution, BaselineSolution, DdEpoch, FixOptions};
use crate::error::{ensure_finite, Error, Result};
use crate::wahba;

#[path = "constrained_held.rs"]
mod held;
#[path = "constrained_radius.rs"]
mod radius;
#[path = "constrained_search.rs"]
pub mod search;
#[path = "constrained_success.rs"]
pub mod success;

pub use held::{solve_attitude_held, HeldAttitude, HOLD_Z};
use search::{Ambiguities, Candidate, List, Outcome};
pub use search::{EXPANSION, FIRST_CANDIDATES, MAX_CANDIDATES, MAX_COMBINATIONS};
pub use success::SUCCESS_DRAWS;

/// Most rovers in one array.
pub const MAX_ROVERS: usize = 12;

/// Largest body baseline coordinate, m.
pub const MAX_BODY_M: f64 = 1e4;

/// Standard normal quantile of the plausibility check (upper tail 1e-9).
const PLAUSIBLE_Z: f64 = 6.0;

/// An accepted combination: a candidate per rover, and its objective.
type Chosen = (Vec<Candidate>, f64);

/// One rover's float solution and what its candidate lists are searched from.
struct Rover {
    fl: FloatSolution,
    unconstrained: BaselineSolution,
    /// `Q_b|a`, m^2 (ECEF).
    q_cond: Matrix3<f64>,
    /// The objective's weight `1 / sigma^2`, m^-2.
    weight: f64,
    /// The held integers the float solution imposed.
    held_used: Vec<(u64, u64, i64)>,
    /// The free ambiguities (`None`: none, the one candidate is `b_enu`).
    ambiguities: Option<Ambiguities>,
    /// The float baseline, ENU, m (the fixed one when the rover's filter fixed it).
    b_enu: Vector3<f64>,
    /// The body baseline's length, m.
    length_m: f64,
}

impl Rover {
    /// The rover's first candidate list for its own float solution.
    fn list(&self) -> Result<List<'_>> {
        match &self.ambiguities {
            None => Ok(List::single(self.b_enu, self.weight, self.length_m)),
            Some(amb) => List::new(
                amb,
                amb.problem.zhat.clone(),
                self.b_enu,
                self.weight,
                self.length_m,
            ),
        }
    }
}

/// The exact search over the rovers' candidates: the best combination and the second best.
fn search_rovers(rovers: &[Rover], body: &[Vector3<f64>]) -> Result<Outcome> {
    let mut lists = rovers.iter().map(Rover::list).collect::<Result<Vec<_>>>()?;
    let weights: Vec<f64> = rovers.iter().map(|r| r.weight).collect();
    search::search(&mut lists, &weights, body, true)
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
    let rovers = floats
        .iter()
        .zip(fixed)
        .zip(&body)
        .map(|((fl, done), f)| match done {
            Some(sol) => Ok(fixed_rover(fl, sol, f.norm(), &to_enu)),
            None => rover_from_float(fl.clone(), f.norm(), &to_enu, fix, &[]),
        })
        .collect::<Result<Vec<_>>>()?;
    let out = search_rovers(&rovers, &body)?;
    let dof = degrees_of_freedom(&rovers);
    let (accepted, success, ratio) = if fixed.iter().all(Option::is_some) {
        let fits = out
            .best
            .as_ref()
            .is_some_and(|(_, cost)| *cost <= chi2_quantile(dof));
        (out.best.filter(|_| fits), 1.0, f64::INFINITY)
    } else {
        let ratio = out.ratio();
        let (a, s) = decide(
            &rovers,
            &body,
            &to_enu,
            out,
            dof,
            fix,
            Some(MIN_SUCCESS_RATE),
        )?;
        (a, s, ratio)
    };
    let baselines: Vec<BaselineSolution> = match &accepted {
        Some((chosen, _)) => rovers
            .iter()
            .zip(chosen)
            .map(|(r, c)| constrained_solution(r, c, ratio, &to_enu))
            .collect::<Result<_>>()?,
        None => floats.iter().map(|fl| float_result(fl, &[])).collect(),
    };
    Ok(AttitudeSolution {
        rotation_enu_from_body: rotation(&baselines, &body, &to_enu)?,
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
    let rovers = epochs
        .iter()
        .zip(&body)
        .map(|(e, f)| rover(e, f.norm(), &to_enu, fix, &[]))
        .collect::<Result<Vec<_>>>()?;
    let outcome = search_rovers(&rovers, &body)?;
    let ratio = outcome.ratio();
    let dof = degrees_of_freedom(&rovers);
    let (accepted, success) = decide(&rovers, &body, &to_enu, outcome, dof, fix, floor)?;
    let baselines: Vec<BaselineSolution> = match &accepted {
        Some((chosen, _)) => rovers
            .iter()
            .zip(chosen)
            .map(|(r, c)| constrained_solution(r, c, ratio, &to_enu))
            .collect::<Result<_>>()?,
        None => rovers.iter().map(|r| r.unconstrained.clone()).collect(),
    };
    Ok(Fresh {
        solution: AttitudeSolution {
            rotation_enu_from_body: rotation(&baselines, &body, &to_enu)?,
            baselines,
            fixed: accepted.is_some(),
            ratio,
            success_rate: success,
        },
        rovers,
        cost: accepted.map(|(_, c)| c),
    })
}

/// Degrees of freedom of the constrained objective: every free ambiguity, three per baseline, less the
/// rotation's three.
fn degrees_of_freedom(rovers: &[Rover]) -> usize {
    rovers.iter().map(|r| r.fl.ambiguities.len()).sum::<usize>() + 3 * rovers.len() - 3
}

/// The rotation ENU <- body of the solved baselines (Wahba, weights the body baselines' squared lengths).
fn rotation(
    baselines: &[BaselineSolution],
    body: &[Vector3<f64>],
    to_enu: &Matrix3<f64>,
) -> Result<Matrix3<f64>> {
    let enu: Vec<Vector3<f64>> = baselines.iter().map(|b| to_enu * b.baseline_m).collect();
    let weights: Vec<f64> = body.iter().map(|f| f.norm_squared()).collect();
    Ok(wahba::solve(body, &enu, &weights, wahba::Method::Svd)?.dcm_ref_from_body)
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

fn rover(
    epoch: &DdEpoch,
    length: f64,
    to_enu: &Matrix3<f64>,
    fix: &FixOptions,
    held: &[(u64, u64, i64)],
) -> Result<Rover> {
    let fl = float::solve(std::slice::from_ref(epoch), held)?;
    rover_from_float(fl, length, to_enu, fix, held)
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
        b_enu: to_enu * sol.baseline_m,
        fl,
        unconstrained: sol.clone(),
        q_cond: sol.covariance_m2,
        held_used: sol.integers.clone(),
        ambiguities: None,
        length_m: length,
    }
}

fn rover_from_float(
    fl: FloatSolution,
    length: f64,
    to_enu: &Matrix3<f64>,
    fix: &FixOptions,
    held: &[(u64, u64, i64)],
) -> Result<Rover> {
    let held_used: Vec<(u64, u64, i64)> = held
        .iter()
        .copied()
        .filter(|&(a, r, _)| fl.used_held.contains(&(a, r)))
        .collect();
    let b_enu = to_enu * fl.baseline_m;
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
            b_enu,
            fl,
            unconstrained,
            q_cond,
            held_used,
            ambiguities: None,
            length_m: length,
        });
    };
    let unconstrained = fix_problem(&fl, held, fix, &problem, &q_aa)?;
    let na = fl.ambiguities.len();
    let q_ab = fl.covariance.view((3, 0), (na, 3)).into_owned();
    let amb_gain: DMatrix<f64> = nalgebra::Cholesky::new(q_aa.clone())
        .ok_or_else(|| Error::numerical("attitude fix", "float ambiguity covariance not positive"))?
        .solve(&q_ab);
    let q_bb = fl.covariance.fixed_view::<3, 3>(0, 0).into_owned();
    let red = q_ab.transpose() * &amb_gain;
    let q_cond = q_bb - Matrix3::from_fn(|i, j| 0.5 * (red[(i, j)] + red[(j, i)]));
    let ambiguities = Ambiguities::new(problem, &amb_gain, to_enu)?;
    Ok(Rover {
        weight: 3.0 / q_cond.trace(),
        b_enu,
        fl,
        unconstrained,
        q_cond,
        held_used,
        ambiguities: Some(ambiguities),
        length_m: length,
    })
}

/// The constrained rule of the gate for the search's best combination (`dof` degrees of freedom): the
/// accepted candidates and their objective, and the simulated success rate (NaN when the ratio or the
/// plausibility refuse first). `floor`: as [`crate::lambda::gate`]'s.
fn decide(
    rovers: &[Rover],
    body: &[Vector3<f64>],
    to_enu: &Matrix3<f64>,
    out: Outcome,
    dof: usize,
    fix: &FixOptions,
    floor: Option<f64>,
) -> Result<(Option<Chosen>, f64)> {
    // An incomplete search's ratio is a lower bound (below 1 when the bound is below the best, which the
    // lists may then have missed): the ratio test refuses what the search could not check.
    let ratio = out.ratio();
    let Some((chosen, cost)) = out.best else {
        return Ok((None, f64::NAN));
    };
    let d = fix
        .gate()
        .decide_constrained(ratio, cost, chi2_quantile(dof), floor, || {
            success::success_rate(rovers, &chosen, body, to_enu)
        })?;
    Ok((d.accepted.then_some((chosen, cost)), d.success_rate))
}

/// The rover's solution conditioned on candidate `c`.
fn constrained_solution(
    r: &Rover,
    c: &Candidate,
    ratio: f64,
    to_enu: &Matrix3<f64>,
) -> Result<BaselineSolution> {
    let z = match &r.ambiguities {
        Some(amb) => amb.problem.to_original(&c.z)?,
        None => DVector::zeros(0),
    };
    let mut s = r.unconstrained.clone();
    s.baseline_m = to_enu.transpose() * c.b_enu;
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
    Ok(s)
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
