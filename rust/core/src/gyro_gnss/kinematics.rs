//! Attitude kinematics of the gyro-driven filter: the quaternion equation `dq/dt = q * [omega / 2, 0]`
//! (equivalently Poisson's equation `dR/dt = R [omega x]`) for the body-to-reference rotation `R`, with
//! `omega` the body angular rate relative to the reference frame, in body axes.
//!
//! Over a step of length `h` with a constant body rate the solution is exact:
//! `q(t + h) = q(t) * exp(omega h / 2)`. A rate whose direction turns within the step leaves the coning
//! error of the one-sample algorithm, `|omega x omega_dot| h^3 / 12` rad per step to leading order.

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

use crate::error::{ensure_finite, Error, Result};
use crate::{guard, interrupt};

/// Most gyro samples of one [`propagate`] call: a sample measured 600 ns through Python on the loaded
/// build machine (32 bytes out), so about 12 s and 640 MB; a day at 200 Hz is 1.7e7.
pub const MAX_SAMPLES: f64 = 2e7;

/// Most rotation of one sample, `|rate| dt`, rad: the step is exact for any angle, but beyond 1e6 rad the
/// angle's phase is lost to rounding (f64 spacing 1e-10 rad there) and a rate held that long is not a
/// gyro measurement; a real gyro turns less than a radian per sample.
pub const MAX_ANGLE_PER_SAMPLE_RAD: f64 = 1e6;

/// `[v x]`, the matrix with `[v x] u = v x u`.
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// One exact step of the kinematic equation for the constant body rate `rate` (rad/s) over `dt` (s).
pub fn step(q: &UnitQuaternion<f64>, rate: &Vector3<f64>, dt: f64) -> UnitQuaternion<f64> {
    q * UnitQuaternion::from_scaled_axis(rate * dt)
}

/// Unit quaternion of a scalar-last `[x, y, z, w]` array (normalised here).
///
/// # Errors
/// [`Error::NonFinite`], or [`Error::OutOfRange`] for a norm below 1e-12.
pub fn unit(name: &'static str, q: [f64; 4]) -> Result<UnitQuaternion<f64>> {
    ensure_finite(name, q.iter())?;
    let quat = Quaternion::new(q[3], q[0], q[1], q[2]);
    let norm = quat.norm();
    if norm < 1e-12 {
        return Err(Error::out_of_range(
            name,
            format!("expected a non-zero quaternion, got norm {norm:.3e}"),
        ));
    }
    Ok(UnitQuaternion::from_quaternion(quat))
}

/// Scalar-last `[x, y, z, w]` with `w >= 0`.
pub fn to_array(q: &UnitQuaternion<f64>) -> [f64; 4] {
    let s = if q.w < 0.0 { -1.0 } else { 1.0 };
    [s * q.i, s * q.j, s * q.k, s * q.w]
}

/// Strictly increasing, finite time stamps (at least `min_len`).
pub fn check_times(name: &'static str, t: &[f64], min_len: usize) -> Result<()> {
    ensure_finite(name, t.iter())?;
    if t.len() < min_len {
        return Err(Error::out_of_range(
            name,
            format!("expected at least {min_len} time stamps, got {}", t.len()),
        ));
    }
    if let Some(k) = t.windows(2).position(|w| w[1] <= w[0]) {
        return Err(Error::out_of_range(
            name,
            format!(
                "expected strictly increasing time stamps, got t[{}] = {} after t[{k}] = {}",
                k + 1,
                t[k + 1],
                t[k]
            ),
        ));
    }
    Ok(())
}

/// Attitude at every gyro time stamp: `rates[k]` (body, rad/s) holds over `[t[k], t[k+1]]`, so the last
/// rate is not used. Returns scalar-last quaternions (body -> reference), `len(t)` of them.
///
/// # Errors
/// Non-finite or non-increasing `t`, non-finite rates, a zero quaternion, or `rates` not as long as `t`;
/// [`Error::OutOfRange`] for a sample turning more than [`MAX_ANGLE_PER_SAMPLE_RAD`];
/// [`Error::TooLarge`] for more than [`MAX_SAMPLES`] samples; [`Error::Interrupted`].
pub fn propagate(q0: [f64; 4], t: &[f64], rates: &[Vector3<f64>]) -> Result<Vec<[f64; 4]>> {
    let mut q = unit("q0", q0)?;
    guard::check_work("t", t.len() as f64, MAX_SAMPLES, "gyro samples")?;
    check_times("t", t, 1)?;
    check_rates("rates", rates, t)?;
    let mut out = Vec::with_capacity(t.len());
    out.push(to_array(&q));
    for k in 1..t.len() {
        interrupt::check_every(k, "gyro propagation")?;
        q = step(&q, &rates[k - 1], t[k] - t[k - 1]);
        out.push(to_array(&q));
    }
    guard::finite_output("gyro propagation", out.iter().flatten(), "rates too large")?;
    Ok(out)
}

/// Finite rates, one per time stamp `t` (checked), none turning more than [`MAX_ANGLE_PER_SAMPLE_RAD`]
/// over its interval; `name` is the parameter.
pub fn check_rates(name: &'static str, rates: &[Vector3<f64>], t: &[f64]) -> Result<()> {
    let n = t.len();
    if rates.len() != n {
        return Err(Error::Shape {
            name,
            expected: format!("({n}, 3), one per time stamp"),
            actual: format!("({}, 3)", rates.len()),
        });
    }
    ensure_finite(name, rates.iter().flat_map(|r| r.iter()))?;
    // hypot: the norm of a rate near the f64 limit stays finite, so that the message gives it.
    let norm = |r: &Vector3<f64>| r.x.hypot(r.y).hypot(r.z);
    for k in 1..n {
        let angle = norm(&rates[k - 1]) * (t[k] - t[k - 1]);
        // NaN cannot come (finite rates, increasing times; hypot does not overflow below 1e308).
        if angle > MAX_ANGLE_PER_SAMPLE_RAD {
            return Err(Error::out_of_range(
                name,
                format!(
                    "{name}[{}] of {:.3e} rad/s held for {:.3e} s turns {angle:.3e} rad, more than \
                     {MAX_ANGLE_PER_SAMPLE_RAD:.0e} rad per sample",
                    k - 1,
                    norm(&rates[k - 1]),
                    t[k] - t[k - 1]
                ),
            ));
        }
    }
    Ok(())
}
