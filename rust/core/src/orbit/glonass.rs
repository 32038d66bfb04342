//! The GLONASS ICD equations of motion in Earth-fixed (PZ-90) axes: central gravity, the J2 zonal term,
//! centrifugal and Coriolis accelerations of the rotating frame and an optional constant luni-solar
//! acceleration; fourth-order Runge-Kutta integration of the state and of its variational equations.
//!
//! Source: GLONASS ICD, edition 5.1 (2008), A.3.1.2, and the CDMA general description (2016), appendix J.2
//! ("simplified algorithm"); constants of the 2016 edition.

use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

use crate::error::{ensure_finite, Error, Result};
use crate::{guard, interrupt};

/// Most RK4 steps of one call: a step with the
/// state-transition matrix measured 1.5 us on the loaded build machine, so about 8 s; a day in 1 s steps
/// is 86 400.
pub const MAX_RK4_STEPS: f64 = 5e6;

/// Lowest radius a trajectory may have, as a fraction of the model's equatorial radius: below the Earth's
/// surface (the polar radius is 0.9966 of the equatorial one) the model no longer describes the motion.
pub const MIN_RADIUS_FRACTION: f64 = 0.99;

/// Highest speed of an initial state, in escape speeds `sqrt(2 GM / r)` at its radius, on top of the
/// rotating axes' own speed `omega r`: anything faster leaves the Earth at once and is not an orbit.
pub const MAX_ESCAPE_SPEEDS: f64 = 2.0;

/// PZ-90 constants and the constant perturbing acceleration of the ICD model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlonassModel {
    /// Earth's gravitational parameter, m^3/s^2 (ICD: 398600.4418e9).
    pub gm_m3_s2: f64,
    /// Second zonal harmonic J2 (ICD: 1082625.75e-9); 0 for a central field.
    pub j2: f64,
    /// Equatorial radius that scales J2, m (ICD: 6378136).
    pub equatorial_radius_m: f64,
    /// Earth rotation rate of the Earth-fixed axes, rad/s (ICD 2016: 7.2921151467e-5); 0 for inertial axes.
    pub omega_rad_s: f64,
    /// Constant luni-solar (or any other) acceleration in Earth-fixed axes, m/s^2.
    pub lunisolar_m_s2: [f64; 3],
}

impl Default for GlonassModel {
    fn default() -> Self {
        Self::pz90()
    }
}

impl GlonassModel {
    /// The ICD's PZ-90 constants without luni-solar acceleration.
    pub const fn pz90() -> Self {
        GlonassModel {
            gm_m3_s2: 398_600.441_8e9,
            j2: 1_082_625.75e-9,
            equatorial_radius_m: 6_378_136.0,
            omega_rad_s: 7.292_115_146_7e-5,
            lunisolar_m_s2: [0.0; 3],
        }
    }

    /// Checks that the constants are finite and `GM`, the radius are positive.
    pub fn validate(&self) -> Result<()> {
        ensure_finite(
            "orbit model constants",
            [
                &self.gm_m3_s2,
                &self.j2,
                &self.equatorial_radius_m,
                &self.omega_rad_s,
            ],
        )?;
        ensure_finite("lunisolar_m_s2", &self.lunisolar_m_s2)?;
        if self.gm_m3_s2 <= 0.0 || self.equatorial_radius_m <= 0.0 {
            return Err(Error::out_of_range(
                "orbit model constants",
                format!(
                    "expected GM > 0 and equatorial radius > 0, got {} m^3/s^2 and {} m",
                    self.gm_m3_s2, self.equatorial_radius_m
                ),
            ));
        }
        Ok(())
    }

    /// Acceleration (m/s^2, Earth-fixed axes) at position `r` (m) moving with velocity `v` (m/s) relative to
    /// the rotating axes.
    pub fn acceleration(&self, r: &Vector3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
        let r2 = r.norm_squared();
        let rn = r2.sqrt();
        let a = -self.gm_m3_s2 / (r2 * rn);
        let b = 1.5 * self.j2 * self.gm_m3_s2 * self.equatorial_radius_m.powi(2) / (r2 * r2 * rn);
        let z2 = 5.0 * r.z * r.z / r2;
        let w = self.omega_rad_s;
        let ls = &self.lunisolar_m_s2;
        Vector3::new(
            (a - b * (1.0 - z2) + w * w) * r.x + 2.0 * w * v.y + ls[0],
            (a - b * (1.0 - z2) + w * w) * r.y - 2.0 * w * v.x + ls[1],
            (a - b * (3.0 - z2)) * r.z + ls[2],
        )
    }

    /// Jacobian `F = d(dx/dt)/dx` (6 x 6) of the state `x = (r, v)`: `[[0, I], [da/dr, da/dv]]`.
    pub fn jacobian(&self, r: &Vector3<f64>) -> Matrix6<f64> {
        let r2 = r.norm_squared();
        let rn = r2.sqrt();
        let (r5, r7, r9) = (r2 * r2 * rn, r2 * r2 * r2 * rn, r2 * r2 * r2 * r2 * rn);
        let mu = self.gm_m3_s2;
        // Central term: -mu/r^3 (I - 3 r r^T / r^2).
        let mut dadr = (Matrix3::identity() - r * r.transpose() * (3.0 / r2)) * (-mu / (r2 * rn));
        // J2 term a = -k (x g1, y g1, z g3) with g1 = r^-5 - 5 z^2 r^-7, g3 = 3 r^-5 - 5 z^2 r^-7.
        let k = 1.5 * self.j2 * mu * self.equatorial_radius_m.powi(2);
        let z = r.z;
        let g1 = 1.0 / r5 - 5.0 * z * z / r7;
        let g3 = 3.0 / r5 - 5.0 * z * z / r7;
        let ez = Vector3::z();
        let dg1 = r * (-5.0 / r7 + 35.0 * z * z / r9) - ez * (10.0 * z / r7);
        let dg3 = r * (-15.0 / r7 + 35.0 * z * z / r9) - ez * (10.0 * z / r7);
        for j in 0..3 {
            dadr[(0, j)] -= k * (if j == 0 { g1 } else { 0.0 } + r.x * dg1[j]);
            dadr[(1, j)] -= k * (if j == 1 { g1 } else { 0.0 } + r.y * dg1[j]);
            dadr[(2, j)] -= k * (if j == 2 { g3 } else { 0.0 } + z * dg3[j]);
        }
        let w = self.omega_rad_s;
        dadr[(0, 0)] += w * w;
        dadr[(1, 1)] += w * w;
        let mut f = Matrix6::zeros();
        f.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&Matrix3::identity());
        f.fixed_view_mut::<3, 3>(3, 0).copy_from(&dadr);
        f[(3, 4)] = 2.0 * w;
        f[(4, 3)] = -2.0 * w;
        f
    }

    fn derivative(&self, x: &Vector6<f64>) -> Vector6<f64> {
        let r = x.fixed_rows::<3>(0).into_owned();
        let v = x.fixed_rows::<3>(3).into_owned();
        let a = self.acceleration(&r, &v);
        Vector6::new(v.x, v.y, v.z, a.x, a.y, a.z)
    }

    /// One RK4 step of length `h` (s, either sign).
    pub fn rk4_step(&self, x: &Vector6<f64>, h: f64) -> Vector6<f64> {
        let k1 = self.derivative(x);
        let k2 = self.derivative(&(x + k1 * (0.5 * h)));
        let k3 = self.derivative(&(x + k2 * (0.5 * h)));
        let k4 = self.derivative(&(x + k3 * h));
        x + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0)
    }

    /// One RK4 step of the state and of the variational equations `dPhi/dt = F(x(t)) Phi`, starting from
    /// `Phi = I`: returns the new state and the state-transition matrix of the step.
    pub fn rk4_step_with_stm(&self, x: &Vector6<f64>, h: f64) -> (Vector6<f64>, Matrix6<f64>) {
        let f_at = |x: &Vector6<f64>| self.jacobian(&x.fixed_rows::<3>(0).into_owned());
        let phi0 = Matrix6::<f64>::identity();
        let k1 = self.derivative(x);
        let p1 = f_at(x) * phi0;
        let x2 = x + k1 * (0.5 * h);
        let k2 = self.derivative(&x2);
        let p2 = f_at(&x2) * (phi0 + p1 * (0.5 * h));
        let x3 = x + k2 * (0.5 * h);
        let k3 = self.derivative(&x3);
        let p3 = f_at(&x3) * (phi0 + p2 * (0.5 * h));
        let x4 = x + k3 * h;
        let k4 = self.derivative(&x4);
        let p4 = f_at(&x4) * (phi0 + p3 * h);
        (
            x + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0),
            phi0 + (p1 + p2 * 2.0 + p3 * 2.0 + p4) * (h / 6.0),
        )
    }
}

/// Number of equal RK4 steps for `duration_s` with steps no longer than `step_s`, after checking both
/// (`step_name` names the step parameter in errors).
fn steps_for(duration_s: f64, step_s: f64, step_name: &'static str) -> Result<f64> {
    ensure_finite("duration_s", [&duration_s])?;
    ensure_finite(step_name, [&step_s])?;
    if duration_s < 0.0 {
        return Err(Error::out_of_range(
            "duration_s",
            format!("expected a duration >= 0 s (forward propagation), got {duration_s}"),
        ));
    }
    if step_s <= 0.0 {
        return Err(Error::out_of_range(
            step_name,
            format!("expected a step > 0 s, got {step_s}"),
        ));
    }
    if duration_s == 0.0 {
        return Ok(0.0);
    }
    if step_s > duration_s {
        return Err(Error::out_of_range(
            step_name,
            format!("expected a step no longer than the duration {duration_s} s, got {step_s} s"),
        ));
    }
    Ok((duration_s / step_s).ceil())
}

/// The lowest radius the model accepts, m.
fn min_radius(model: &GlonassModel) -> f64 {
    MIN_RADIUS_FRACTION * model.equatorial_radius_m
}

/// A finite initial state above the surface and below [`MAX_ESCAPE_SPEEDS`]; `name` is the parameter.
fn checked_state(
    model: &GlonassModel,
    name: &'static str,
    state: &[f64; 6],
) -> Result<Vector6<f64>> {
    ensure_finite(name, state)?;
    let x = Vector6::from_column_slice(state);
    let r = x.fixed_rows::<3>(0).norm();
    let r_min = min_radius(model);
    if !r.is_finite() || r < r_min {
        return Err(Error::out_of_range(
            "position_m",
            format!(
                "expected a position away from the Earth's centre, at least {r_min:.0} m \
                 ({MIN_RADIUS_FRACTION} equatorial radius), got |r| = {r:.6e} m"
            ),
        ));
    }
    let v = x.fixed_rows::<3>(3).norm();
    let v_max = MAX_ESCAPE_SPEEDS * (2.0 * model.gm_m3_s2 / r).sqrt() + model.omega_rad_s.abs() * r;
    if v.is_nan() || v > v_max {
        return Err(Error::out_of_range(
            "velocity_m_s",
            format!(
                "expected a bound orbit: |v| = {v:.6e} m/s at |r| = {r:.6e} m exceeds {MAX_ESCAPE_SPEEDS} \
                 escape speeds plus the axes' rotation, {v_max:.6e} m/s"
            ),
        ));
    }
    Ok(x)
}

/// After step `k` (of length `h`): polls for interruption and stops a trajectory that left the finite
/// numbers or went below the surface (a step far too long for the orbit, or a plunging state).
#[inline]
fn check_step(model: &GlonassModel, x: &Vector6<f64>, k: usize, h: f64) -> Result<()> {
    interrupt::check_every(k, "GLONASS propagation")?;
    let r = x.fixed_rows::<3>(0).norm();
    // NaN fails the comparison: a non-finite state stops here too.
    if !(r >= min_radius(model) && x.iter().all(|v| v.is_finite())) {
        return Err(Error::numerical(
            "GLONASS propagation",
            format!(
                "diverged at t = {:.6e} s: |r| = {r:.6e} m, below the Earth's surface ({:.0} m) or not \
                 finite; the step {h:.3e} s is too long for this orbit, or the orbit meets the Earth",
                (k + 1) as f64 * h,
                min_radius(model)
            ),
        ));
    }
    Ok(())
}

/// Propagates `state = (x, y, z, vx, vy, vz)` (m, m/s, Earth-fixed) forward by `duration_s` with
/// `ceil(duration / step_s)` equal RK4 steps.
///
/// # Errors
/// [`Error::NonFinite`] or [`Error::OutOfRange`] for a non-finite state or model, a negative duration, a
/// step <= 0 or longer than a non-zero duration, a position below [`MIN_RADIUS_FRACTION`] of the
/// equatorial radius or a speed above [`MAX_ESCAPE_SPEEDS`]; [`Error::TooLarge`] for more than
/// [`MAX_RK4_STEPS`] steps; [`Error::Numerical`] if the trajectory leaves the finite numbers or goes
/// below the surface; [`Error::Interrupted`] on [`crate::interrupt::request`].
pub fn propagate(
    model: &GlonassModel,
    state: &[f64; 6],
    duration_s: f64,
    step_s: f64,
) -> Result<[f64; 6]> {
    model.validate()?;
    let mut x = checked_state(model, "state", state)?;
    let n = steps_for(duration_s, step_s, "step_s")?;
    guard::check_work("step_s", n, MAX_RK4_STEPS, "RK4 steps")?;
    let n = n as usize;
    let h = if n > 0 { duration_s / n as f64 } else { 0.0 };
    for k in 0..n {
        x = model.rk4_step(&x, h);
        check_step(model, &x, k, h)?;
    }
    Ok(x.into())
}

/// As [`propagate`], also returning the 6 x 6 state-transition matrix `d x(t + duration) / d x(t)` (row-major
/// rows) integrated from the variational equations.
///
/// # Errors
/// As [`propagate`]; [`Error::Numerical`] also for a state-transition matrix that overflows.
pub fn propagate_with_stm(
    model: &GlonassModel,
    state: &[f64; 6],
    duration_s: f64,
    step_s: f64,
) -> Result<([f64; 6], Matrix6<f64>)> {
    model.validate()?;
    let mut x = checked_state(model, "state", state)?;
    let n = steps_for(duration_s, step_s, "step_s")?;
    guard::check_work("step_s", n, MAX_RK4_STEPS, "RK4 steps")?;
    let n = n as usize;
    let h = if n > 0 { duration_s / n as f64 } else { 0.0 };
    let mut phi = Matrix6::identity();
    for k in 0..n {
        let (xn, step_phi) = model.rk4_step_with_stm(&x, h);
        x = xn;
        phi = step_phi * phi;
        check_step(model, &x, k, h)?;
    }
    guard::finite_output(
        "GLONASS state-transition matrix",
        phi.iter(),
        "the propagation is too long for its sensitivities to stay representable",
    )?;
    Ok((x.into(), phi))
}
