//! Classical fixed-step fourth-order Runge-Kutta integration of [`TumbleModel::derivative`].

use crate::error::{ensure_finite, Error, Result};

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

/// Checks output times (seconds from the initial epoch: finite, >= 0, non-decreasing) and the step.
pub(crate) fn check_times(times_s: &[f64], step_s: f64) -> Result<()> {
    ensure_finite("times", times_s.iter())?;
    if !(step_s.is_finite() && step_s > 0.0) {
        return Err(Error::out_of_range(
            "step_s",
            format!("expected a positive finite step, got {step_s}"),
        ));
    }
    if let Some(&t) = times_s.first() {
        if t < 0.0 {
            return Err(Error::out_of_range(
                "times",
                format!("expected times >= 0 s from the initial epoch, got {t}"),
            ));
        }
    }
    if let Some(i) = times_s.windows(2).position(|w| w[1] < w[0]) {
        return Err(Error::out_of_range(
            "times",
            format!(
                "expected non-decreasing times, got {} after {} at index {}",
                times_s[i + 1],
                times_s[i],
                i + 1
            ),
        ));
    }
    Ok(())
}

/// Calls `visit(k, state)` at every output time `times_s[k]` (unchecked inputs).
#[inline]
pub(crate) fn walk(
    model: &TumbleModel,
    initial: State,
    times_s: &[f64],
    step_s: f64,
    mut visit: impl FnMut(usize, &State),
) {
    let mut s = initial.normalized();
    let mut t = 0.0;
    for (k, &target) in times_s.iter().enumerate() {
        let span = target - t;
        if span > 0.0 {
            let n = (span / step_s - 1e-9).ceil().max(1.0) as usize;
            let h = span / n as f64;
            for _ in 0..n {
                s = rk4_step(model, &s, h);
            }
            t = target;
        }
        visit(k, &s);
    }
}

/// The state at each output time.
///
/// # Arguments
/// * `initial` - state at `t = 0`.
/// * `times_s` - output times, s from the initial epoch, non-decreasing, >= 0.
/// * `step_s` - the longest RK4 step, s.
///
/// # Errors
/// [`Error::NonFinite`] or [`Error::OutOfRange`] for invalid parameters, state, times or step.
pub fn propagate(
    model: &TumbleModel,
    initial: State,
    times_s: &[f64],
    step_s: f64,
) -> Result<Vec<State>> {
    model.validate()?;
    check_state(&initial)?;
    check_times(times_s, step_s)?;
    let mut out = Vec::with_capacity(times_s.len());
    walk(model, initial, times_s, step_s, |_, s| out.push(*s));
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
    check_times(times_s, step_s)?;
    let mut out = Vec::with_capacity(times_s.len());
    walk(model, initial, times_s, step_s, |_, s| {
        out.push(s.axis_orbital())
    });
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
