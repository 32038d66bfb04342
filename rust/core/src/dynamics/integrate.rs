//! Classical fixed-step fourth-order Runge-Kutta integration of [`TumbleModel::derivative`].

use crate::error::{ensure_finite, Error, Result};
use crate::{guard, interrupt};

use super::lanes::Real;
use super::model::{Rhs, State, TumbleModel};

#[inline(always)]
fn axpy<V: Real>(s: &State<V>, h: f64, d: &State<V>) -> State<V> {
    let h = V::splat(h);
    State {
        q: std::array::from_fn(|i| s.q[i] + h * d.q[i]),
        omega: std::array::from_fn(|i| s.omega[i] + h * d.omega[i]),
    }
}

/// One RK4 step of length `h` seconds; the quaternion is renormalised afterwards.
#[inline]
pub fn rk4_step(model: &TumbleModel, s: &State, h: f64) -> State {
    let rhs = Rhs::new(model);
    rk4_from(&rhs, s, &rhs.derivative(s), h)
}

/// One RK4 step from `s` whose derivative `k1 = model.derivative(s)` is already known (the previous
/// step's end point, also needed by the interpolation).
#[inline(always)]
fn rk4_from<V: Real>(rhs: &Rhs, s: &State<V>, k1: &State<V>, h: f64) -> State<V> {
    let k2 = rhs.derivative(&axpy(s, 0.5 * h, k1));
    let k3 = rhs.derivative(&axpy(s, 0.5 * h, &k2));
    let k4 = rhs.derivative(&axpy(s, h, &k3));
    let (h6, two) = (V::splat(h / 6.0), V::splat(2.0));
    let mut out = *s;
    for i in 0..4 {
        out.q[i] = out.q[i] + h6 * (k1.q[i] + two * k2.q[i] + two * k3.q[i] + k4.q[i]);
    }
    for i in 0..3 {
        out.omega[i] =
            out.omega[i] + h6 * (k1.omega[i] + two * k2.omega[i] + two * k3.omega[i] + k4.omega[i]);
    }
    out.normalized()
}

/// Cubic Hermite interpolation at `theta` in `[0, 1]` of a step of length `h` from `(s0, d0)` to
/// `(s1, d1)` (states and their derivatives); the quaternion is left unnormalised (its norm is within
/// the interpolation error of 1, and [`State::axis_orbital`] divides by it). The error, `h^4 / 384`
/// times the fourth derivative, is of RK4's own order: for a body turning `omega h` rad per step the
/// quaternion's fourth derivative is `(omega / 2)^4`, so 0.16 rad per step (3 s at 3 deg/s)
/// interpolates to 1e-7. `theta = 0` and `1` return `s0` and `s1` exactly.
#[inline(always)]
fn hermite<V: Real>(
    s0: &State<V>,
    d0: &State<V>,
    s1: &State<V>,
    d1: &State<V>,
    h: f64,
    theta: f64,
) -> State<V> {
    let t2 = theta * theta;
    let t3 = t2 * theta;
    let a0 = V::splat(2.0 * t3 - 3.0 * t2 + 1.0);
    let a1 = V::splat(-2.0 * t3 + 3.0 * t2);
    let b0 = V::splat(h * (t3 - 2.0 * t2 + theta));
    let b1 = V::splat(h * (t3 - t2));
    State {
        q: std::array::from_fn(|i| a0 * s0.q[i] + a1 * s1.q[i] + b0 * d0.q[i] + b1 * d1.q[i]),
        omega: std::array::from_fn(|i| {
            a0 * s0.omega[i] + a1 * s1.omega[i] + b0 * d0.omega[i] + b1 * d1.omega[i]
        }),
    }
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

/// The RK4 grid of a run: `steps` equal steps of `longest_s` seconds from 0 to the last output time,
/// per initial state.
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
/// plans the RK4 grid of one trajectory: equal steps no longer than `step_s` from 0 to the last time
/// (output times between grid points are interpolated, see [`walk`]).
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
    let end = times_s.last().copied().unwrap_or(0.0);
    if end > 0.0 {
        let steps = substeps(end, step_s);
        Ok(Plan {
            steps,
            longest_s: end / steps,
        })
    } else {
        Ok(Plan {
            steps: 0.0,
            longest_s: 0.0,
        })
    }
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
/// gravity-gradient libration (`sqrt(3) w0` at most), rad/s, from the squared body rate `|omega|^2`.
#[inline(always)]
fn rate_bound(model: &TumbleModel, omega2: f64) -> f64 {
    omega2.sqrt() + 2.0 * model.orbital_rate_rad_s
}

/// Refuses an initial state that turns more than [`MAX_ROTATION_PER_STEP_RAD`] per step of `plan`;
/// `row` names the parameter row of a batch.
pub(crate) fn check_stable(
    model: &TumbleModel,
    s: &State,
    plan: &Plan,
    row: Option<usize>,
) -> Result<()> {
    let w = s.omega;
    let rate = rate_bound(model, w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
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

/// The RK4 grid of [`Plan`] walked forward, holding the states and derivatives at grid point `j` and,
/// once an output time falls inside step `j`, those at `j + 1`.
struct Grid<'a, V> {
    model: &'a TumbleModel,
    rhs: Rhs,
    h: f64,
    steps: usize,
    end: f64,
    j: usize,
    at: (State<V>, State<V>),
    ahead: Option<(State<V>, State<V>)>,
}

impl<V: Real> Grid<'_, V> {
    /// Time of grid point `j`; the last one is the last output time exactly.
    #[inline(always)]
    fn time(&self, j: usize) -> f64 {
        if j >= self.steps {
            self.end
        } else {
            j as f64 * self.h
        }
    }

    /// The states and derivatives at grid point `j + 1`, integrated once and kept.
    #[inline(always)]
    fn next(&mut self) -> Result<(State<V>, State<V>)> {
        if let Some(p) = self.ahead {
            return Ok(p);
        }
        interrupt::check_every(self.j, "tumble propagation")?;
        let (s0, d0) = &self.at;
        let s = rk4_from(&self.rhs, s0, d0, self.h);
        let [p, r, t] = s.omega;
        let rate2 = p * p + r * r + t * t;
        for l in 0..V::LANES {
            let turn = rate_bound(self.model, rate2.lane(l)) * self.h;
            // NaN fails both comparisons: a non-finite quaternion or rate stops here too.
            if !(turn <= MAX_ROTATION_PER_STEP_RAD && s.q.iter().all(|v| v.lane(l).is_finite())) {
                return Err(Error::numerical(
                    "tumble propagation",
                    format!(
                        "diverged at t = {:.6e} s: the state turns {turn:.3e} rad per step of {:.3e} s \
                         (stable up to {MAX_ROTATION_PER_STEP_RAD}); the torques spin the body up \
                         beyond what step_s resolves",
                        self.time(self.j + 1),
                        self.h
                    ),
                ));
            }
        }
        let p = (s, self.rhs.derivative(&s));
        self.ahead = Some(p);
        Ok(p)
    }

    /// The states at `t`, no earlier than the previous call's: the grid point itself where `t` is one,
    /// else the cubic Hermite interpolant of the step that holds it (quaternion not renormalised).
    #[inline(always)]
    fn state_at(&mut self, t: f64) -> Result<State<V>> {
        while self.j < self.steps && t >= self.time(self.j + 1) {
            self.at = self.next()?;
            self.ahead = None;
            self.j += 1;
        }
        let tj = self.time(self.j);
        if t <= tj || self.j >= self.steps {
            return Ok(self.at.0);
        }
        let (s1, d1) = self.next()?;
        let (s0, d0) = &self.at;
        Ok(hermite(s0, d0, &s1, &d1, self.h, (t - tj) / self.h))
    }
}

/// Calls `visit(k, states)` at every output time `times_s[k]` (inputs checked by the caller) until it
/// returns `false`; `V` holds one state or a pack of them (`super::lanes`), all on the same grid.
///
/// The RK4 steps are those of `plan` from [`check_times`]: equal steps no longer than `step_s` from 0
/// to the last time. A time between grid points gets the cubic Hermite interpolant of its step (the
/// quaternion not renormalised), so outputs denser than the step cost a few operations each, not a step
/// each. Polls for interruption and stops with [`Error::Numerical`] if a state stops being finite or its
/// rate grows beyond [`MAX_ROTATION_PER_STEP_RAD`] per step.
#[inline(always)]
pub(crate) fn walk<V: Real>(
    model: &TumbleModel,
    initial: State<V>,
    times_s: &[f64],
    plan: &Plan,
    mut visit: impl FnMut(usize, &State<V>) -> bool,
) -> Result<()> {
    let s = initial.normalized();
    let rhs = Rhs::new(model);
    let mut grid = Grid {
        model,
        rhs,
        h: plan.longest_s,
        steps: plan.steps as usize,
        end: times_s.last().copied().unwrap_or(0.0),
        j: 0,
        at: (s, rhs.derivative(&s)),
        ahead: None,
    };
    for (k, &t) in times_s.iter().enumerate() {
        let s = grid.state_at(t)?;
        if !visit(k, &s) {
            break;
        }
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
    walk(model, initial, times_s, &plan, |_, s| {
        out.push(s.normalized());
        true
    })?;
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
    walk(model, initial, times_s, &plan, |_, s| {
        out.push(s.axis_orbital());
        true
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
