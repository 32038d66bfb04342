//! Classical fixed-step fourth-order Runge-Kutta integration of [`TumbleModel::derivative`].

use crate::error::{ensure_finite, Error, Result};
use crate::{guard, interrupt};

use super::model::{State, TumbleModel};

#[inline]
fn axpy(s: &State, h: f64, d: &State) -> State {
    State {
        q: [
            s.q[0] + h * d.q[0],
            s.q[1] + h * d.q[1],
            s.q[2] + h * d.q[2],
            s.q[3] + h * d.q[3],
        ],
        omega: [
            s.omega[0] + h * d.omega[0],
            s.omega[1] + h * d.omega[1],
            s.omega[2] + h * d.omega[2],
        ],
    }
}

/// One RK4 step of length `h` seconds; the quaternion is renormalised afterwards.
#[inline]
pub fn rk4_step(model: &TumbleModel, s: &State, h: f64) -> State {
    let k1 = model.derivative(s);
    let k2 = model.derivative(&axpy(s, 0.5 * h, &k1));
    let k3 = model.derivative(&axpy(s, 0.5 * h, &k2));
    let k4 = model.derivative(&axpy(s, h, &k3));
    let mut out = *s;
    for i in 0..4 {
        out.q[i] += h / 6.0 * (k1.q[i] + 2.0 * k2.q[i] + 2.0 * k3.q[i] + k4.q[i]);
    }
    for i in 0..3 {
        out.omega[i] +=
            h / 6.0 * (k1.omega[i] + 2.0 * k2.omega[i] + 2.0 * k3.omega[i] + k4.omega[i]);
    }
    out.normalized()
}

/// Most RK4 steps of one call, summed over every initial state of a batch: about 10 s on a loaded core
/// (a step measured 320 ns through Python on the shared 2-core build machine); the paper's fits need
/// 1.4e5 per call (a population of 90 over 1500 s at 1 s).
pub const MAX_RK4_STEPS: f64 = 3e7;

/// Most output values (`states x times x 3` axes, or `times x 7` state components) of one call: 800 MB.
pub const MAX_OUTPUT_VALUES: f64 = 1e8;

/// Most rotation per RK4 step, `h (|omega| + 2 w0)` in rad: RK4 is stable on rotations up to `2 sqrt(2)`
/// rad per step and accurate to ~1e-3 rad per step at 1 rad (local error `(omega h)^5 / 120`); legitimate
/// steps turn 0.05 rad (3 deg/s, 1 s). Beyond it the integration is refused, or stopped if the rate grows
/// there during the run.
pub const MAX_ROTATION_PER_STEP_RAD: f64 = 1.0;

/// The sub-steps of a run: `steps` RK4 steps per initial state, none longer than `longest_s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Plan {
    pub steps: f64,
    pub longest_s: f64,
}

/// Number of equal sub-steps of a `span_s` interval with steps no longer than `step_s`.
#[inline]
fn substeps(span_s: f64, step_s: f64) -> f64 {
    (span_s / step_s - 1e-9).ceil().max(1.0)
}

/// Checks output times (seconds from the initial epoch: finite, >= 0, non-decreasing) and the step, and
/// counts the RK4 steps of one trajectory.
pub(crate) fn check_times(times_s: &[f64], step_s: f64) -> Result<Plan> {
    ensure_finite("t", times_s.iter())?;
    if !(step_s.is_finite() && step_s > 0.0) {
        return Err(Error::out_of_range(
            "step_s",
            format!("expected a positive finite step, got {step_s}"),
        ));
    }
    if let Some(&t) = times_s.first() {
        if t < 0.0 {
            return Err(Error::out_of_range(
                "t",
                format!("expected times >= 0 s from the initial epoch, got {t}"),
            ));
        }
    }
    if let Some(i) = times_s.windows(2).position(|w| w[1] < w[0]) {
        return Err(Error::out_of_range(
            "t",
            format!(
                "expected non-decreasing times, got {} after {} at index {}",
                times_s[i + 1],
                times_s[i],
                i + 1
            ),
        ));
    }
    let mut plan = Plan {
        steps: 0.0,
        longest_s: 0.0,
    };
    let mut t = 0.0;
    for &target in times_s {
        let span = target - t;
        if span > 0.0 {
            let n = substeps(span, step_s);
            plan.steps += n;
            plan.longest_s = plan.longest_s.max(span / n);
            t = target;
        }
    }
    Ok(plan)
}

/// Refuses a batch of `states` trajectories of `plan` and `values_per_state` output values each above
/// [`MAX_RK4_STEPS`] or [`MAX_OUTPUT_VALUES`].
pub(crate) fn check_work(plan: &Plan, states: usize, values_per_state: usize) -> Result<()> {
    let n = states as f64;
    guard::check_work(
        "step_s",
        plan.steps * n,
        MAX_RK4_STEPS,
        "RK4 steps (over all initial states)",
    )?;
    guard::check_work(
        "t",
        values_per_state as f64 * n,
        MAX_OUTPUT_VALUES,
        "output values",
    )
}

/// The rate that sets the RK4 step limit: the body rate plus the orbital frame's turn and the
/// gravity-gradient libration (`sqrt(3) w0` at most), rad/s.
#[inline]
fn rate_bound(model: &TumbleModel, s: &State) -> f64 {
    let w = s.omega;
    (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt() + 2.0 * model.orbital_rate_rad_s
}

/// Refuses an initial state that turns more than [`MAX_ROTATION_PER_STEP_RAD`] per step of `plan`;
/// `row` names the parameter row of a batch.
pub(crate) fn check_stable(
    model: &TumbleModel,
    s: &State,
    plan: &Plan,
    row: Option<usize>,
) -> Result<()> {
    let rate = rate_bound(model, s);
    let turn = rate * plan.longest_s;
    if turn <= MAX_ROTATION_PER_STEP_RAD {
        return Ok(());
    }
    let of = row.map_or(String::new(), |i| format!(" (params row {i})"));
    Err(Error::out_of_range(
        "step_s",
        format!(
            "|omega| + 2 w0 = {rate:.3e} rad/s{of} turns {turn:.3e} rad per RK4 step of {:.3e} s, more \
             than the stable {MAX_ROTATION_PER_STEP_RAD} rad; use step_s <= {:.3e} s",
            plan.longest_s,
            MAX_ROTATION_PER_STEP_RAD / rate
        ),
    ))
}

/// Calls `visit(k, state)` at every output time `times_s[k]` (inputs checked by the caller), polling for
/// interruption and stopping with [`Error::Numerical`] if the state stops being finite or its rate grows
/// beyond [`MAX_ROTATION_PER_STEP_RAD`] per step.
#[inline]
pub(crate) fn walk(
    model: &TumbleModel,
    initial: State,
    times_s: &[f64],
    step_s: f64,
    mut visit: impl FnMut(usize, &State),
) -> Result<()> {
    let mut s = initial.normalized();
    let mut t = 0.0;
    let mut done = 0usize;
    for (k, &target) in times_s.iter().enumerate() {
        let span = target - t;
        if span > 0.0 {
            let n = substeps(span, step_s) as usize;
            let h = span / n as f64;
            for i in 0..n {
                interrupt::check_every(done, "tumble propagation")?;
                done += 1;
                s = rk4_step(model, &s, h);
                let turn = rate_bound(model, &s) * h;
                // NaN fails both comparisons: a non-finite quaternion or rate stops here too.
                if !(turn <= MAX_ROTATION_PER_STEP_RAD && s.q.iter().all(|v| v.is_finite())) {
                    return Err(Error::numerical(
                        "tumble propagation",
                        format!(
                            "diverged at t = {:.6e} s: the state turns {turn:.3e} rad per step of {h:.3e} s \
                             (stable up to {MAX_ROTATION_PER_STEP_RAD}); the torques spin the body up \
                             beyond what step_s resolves",
                            t + (i + 1) as f64 * h
                        ),
                    ));
                }
            }
            t = target;
        }
        visit(k, &s);
    }
    Ok(())
}

/// The state at each output time.
///
/// # Arguments
/// * `initial` - state at `t = 0`.
/// * `times_s` - output times, s from the initial epoch, non-decreasing, >= 0.
/// * `step_s` - the longest RK4 step, s.
///
/// # Errors
/// [`Error::NonFinite`] or [`Error::OutOfRange`] for invalid parameters, state, times or step, and for a
/// step that turns the body more than [`MAX_ROTATION_PER_STEP_RAD`]; [`Error::TooLarge`] for more than
/// [`MAX_RK4_STEPS`] steps or [`MAX_OUTPUT_VALUES`] values; [`Error::Numerical`] if the integration
/// diverges; [`Error::Interrupted`] on [`crate::interrupt::request`].
pub fn propagate(
    model: &TumbleModel,
    initial: State,
    times_s: &[f64],
    step_s: f64,
) -> Result<Vec<State>> {
    model.validate()?;
    check_state(&initial)?;
    let plan = check_times(times_s, step_s)?;
    check_work(&plan, 1, 7 * times_s.len())?;
    check_stable(model, &initial, &plan, None)?;
    let mut out = Vec::with_capacity(times_s.len());
    walk(model, initial, times_s, step_s, |_, s| out.push(*s))?;
    Ok(out)
}

/// The antenna (body `Yc`) axis in the library's orbital frame at each output time; see [`propagate`].
///
/// # Errors
/// As [`propagate`].
pub fn propagate_axes(
    model: &TumbleModel,
    initial: State,
    times_s: &[f64],
    step_s: f64,
) -> Result<Vec<[f64; 3]>> {
    model.validate()?;
    check_state(&initial)?;
    let plan = check_times(times_s, step_s)?;
    check_work(&plan, 1, 3 * times_s.len())?;
    check_stable(model, &initial, &plan, None)?;
    let mut out = Vec::with_capacity(times_s.len());
    walk(model, initial, times_s, step_s, |_, s| {
        out.push(s.axis_orbital())
    })?;
    Ok(out)
}

pub(crate) fn check_state(s: &State) -> Result<()> {
    ensure_finite("state", s.q.iter().chain(s.omega.iter()))?;
    let n = s.q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if n < 1e-12 {
        return Err(Error::out_of_range(
            "state",
            format!("expected a non-zero quaternion, got norm {n:.3e}"),
        ));
    }
    Ok(())
}
