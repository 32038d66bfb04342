//! Circular Keplerian orbit mapped orbital -> inertial -> Earth-fixed (the Dzhepe Ali reference orbit).
//!
//! Frames as in `docs/conventions.md`: ECI without precession or nutation; ECEF = ECI rotated about z by
//! `theta(t) = theta0 + omega_E t`; velocities in ECEF are relative to the rotating Earth,
//! `v_ecef = R(theta) (v_eci - omega_E x r_eci)`.

use nalgebra::{Matrix3, Vector3};

use crate::error::{ensure_finite, Error, Result};

/// A circular orbit: radius, inclination, right ascension of the ascending node (ECI) and argument of
/// latitude at `t = 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CircularOrbit {
    pub radius_m: f64,
    pub inclination_rad: f64,
    pub raan_rad: f64,
    pub arg_latitude0_rad: f64,
    pub gm_m3_s2: f64,
}

impl CircularOrbit {
    /// Checks finiteness and positive radius and GM.
    pub fn validate(&self) -> Result<()> {
        ensure_finite(
            "circular orbit elements",
            [
                &self.radius_m,
                &self.inclination_rad,
                &self.raan_rad,
                &self.arg_latitude0_rad,
                &self.gm_m3_s2,
            ],
        )?;
        if self.radius_m <= 0.0 || self.gm_m3_s2 <= 0.0 {
            return Err(Error::out_of_range(
                "circular orbit elements",
                format!(
                    "expected radius > 0 and GM > 0, got {} m and {} m^3/s^2",
                    self.radius_m, self.gm_m3_s2
                ),
            ));
        }
        Ok(())
    }

    /// Mean motion `sqrt(GM / r^3)`, rad/s.
    pub fn mean_motion_rad_s(&self) -> f64 {
        (self.gm_m3_s2 / self.radius_m.powi(3)).sqrt()
    }

    /// Rotation orbital -> ECI at argument of latitude `u`; orbital axes x along-track, y orbit normal,
    /// z radial (zenith).
    pub fn dcm_eci_from_orbital(&self, u: f64) -> Matrix3<f64> {
        let (so, co) = self.raan_rad.sin_cos();
        let (si, ci) = self.inclination_rad.sin_cos();
        let (su, cu) = u.sin_cos();
        // Radial, along-track and normal unit vectors of Rz(raan) Rx(i) Rz(u).
        let radial = Vector3::new(co * cu - so * ci * su, so * cu + co * ci * su, si * su);
        let along = Vector3::new(-co * su - so * ci * cu, -so * su + co * ci * cu, si * cu);
        let normal = Vector3::new(so * si, -co * si, ci);
        Matrix3::from_columns(&[along, normal, radial])
    }

    /// Position (m) and velocity (m/s) in ECI at `t` seconds.
    pub fn state_eci(&self, t: f64) -> (Vector3<f64>, Vector3<f64>) {
        let n = self.mean_motion_rad_s();
        let dcm = self.dcm_eci_from_orbital(self.arg_latitude0_rad + n * t);
        let r = dcm * Vector3::new(0.0, 0.0, self.radius_m);
        let v = dcm * Vector3::new(n * self.radius_m, 0.0, 0.0);
        (r, v)
    }

    /// Position (m) and velocity relative to the rotating Earth (m/s) in ECEF at `t` seconds, Earth rotation
    /// angle `theta0_rad + omega_rad_s t`.
    pub fn state_ecef(
        &self,
        t: f64,
        theta0_rad: f64,
        omega_rad_s: f64,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let (r, v) = self.state_eci(t);
        let (s, c) = (theta0_rad + omega_rad_s * t).sin_cos();
        let ecef_from_eci = Matrix3::new(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0);
        let w = Vector3::new(0.0, 0.0, omega_rad_s);
        (ecef_from_eci * r, ecef_from_eci * (v - w.cross(&r)))
    }
}
