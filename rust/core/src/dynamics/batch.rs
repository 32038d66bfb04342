//! Many initial states in parallel (rayon): the antenna axes, or the paper's objective (1) directly.

use rayon::prelude::*;

use crate::error::{ensure_finite, Result};
use crate::guard;

use super::integrate::{check_stable, check_state, check_times, check_work, walk, Plan};
use super::model::{State, TumbleModel};

/// The initial state of a parameter vector `b = (psi, alpha, phi, wx, wy, wz)` (rad, rad/s).
#[inline]
fn state_of(b: &[f64; 6]) -> State {
    State::from_angles([b[0], b[1], b[2]], [b[3], b[4], b[5]])
}

fn check_params(model: &TumbleModel, params: &[[f64; 6]], plan: &Plan) -> Result<()> {
    ensure_finite("params", params.iter().flatten())?;
    for (i, b) in params.iter().enumerate() {
        let s = state_of(b);
        check_state(&s)?;
        check_stable(model, &s, plan, Some(i))?;
    }
    Ok(())
}

/// Axes (library orbital frame) of each parameter vector at each time: `out[i][k]`.
///
/// # Arguments
/// * `params` - `(psi, alpha, phi, wx, wy, wz)` at `t = 0`: the paper's angles (rad, intrinsic `YZY`) and
///   the absolute angular velocity in body axes (rad/s).
/// * `times_s`, `step_s` - as [`super::propagate`].
///
/// Runs on rayon's global pool (set its size with `RAYON_NUM_THREADS`).
///
/// # Errors
/// As [`super::propagate`]: [`crate::Error::NonFinite`] or [`crate::Error::OutOfRange`] for invalid
/// inputs or a step too long for a row's rate; [`crate::Error::TooLarge`] for more than
/// [`super::MAX_RK4_STEPS`] steps over all rows or [`super::MAX_OUTPUT_VALUES`] output values;
/// [`crate::Error::Numerical`] if a row's integration diverges; [`crate::Error::Interrupted`].
pub fn propagate_axes_batch(
    model: &TumbleModel,
    params: &[[f64; 6]],
    times_s: &[f64],
    step_s: f64,
) -> Result<Vec<Vec<[f64; 3]>>> {
    model.validate()?;
    let plan = check_times(times_s, step_s)?;
    check_work(&plan, params.len(), 3 * times_s.len())?;
    check_params(model, params, &plan)?;
    params
        .par_iter()
        .map(|b| {
            let mut out = Vec::with_capacity(times_s.len());
            walk(model, state_of(b), times_s, &plan, |_, s| {
                out.push(s.axis_orbital());
                true
            })?;
            Ok(out)
        })
        .collect()
}

/// The paper's objective (1) for each parameter vector: the sum over times of the squared distance
/// between the modelled axis and the measured one, `sum_k |a(t_k; b) - a_meas_k|^2` (dimensionless).
///
/// # Arguments
/// * `measured` - measured axis directions (library orbital frame), one per time.
///
/// # Errors
/// As [`propagate_axes_batch`] (the output is one value per row); [`crate::Error::Shape`] unless one
/// measurement per time; [`crate::Error::Numerical`] for a cost that overflows.
pub fn axis_cost_batch(
    model: &TumbleModel,
    params: &[[f64; 6]],
    times_s: &[f64],
    measured: &[[f64; 3]],
    step_s: f64,
) -> Result<Vec<f64>> {
    model.validate()?;
    let plan = check_times(times_s, step_s)?;
    check_work(&plan, params.len(), 1)?;
    check_params(model, params, &plan)?;
    if measured.len() != times_s.len() {
        return Err(crate::Error::Shape {
            name: "measured",
            expected: format!("({}, 3)", times_s.len()),
            actual: format!("({}, 3)", measured.len()),
        });
    }
    ensure_finite("measured", measured.iter().flatten())?;
    let cost = params
        .par_iter()
        .map(|b| {
            let mut cost = 0.0;
            walk(model, state_of(b), times_s, &plan, |k, s| {
                let a = s.axis_orbital();
                let m = measured[k];
                cost += (a[0] - m[0]).powi(2) + (a[1] - m[1]).powi(2) + (a[2] - m[2]).powi(2);
                true
            })?;
            Ok(cost)
        })
        .collect::<Result<Vec<f64>>>()?;
    // Unit axes against finite measurements: only measurements near the f64 limit overflow the squares.
    guard::finite_output(
        "tumble objective",
        &cost,
        "the measured axes are expected as unit vectors",
    )?;
    Ok(cost)
}
