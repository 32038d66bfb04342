//! The right-hand side of Euler's equations (3) and the quaternion kinematics (4).

use nalgebra::{Matrix3, Vector3};

use crate::error::{ensure_finite, Error, Result};
use crate::rotation::euler::YZY;

use super::lanes::Real;

/// Aerodynamic torque parameters: drag `F = -0.5 rho Cd S |V| V` applied at the centre of pressure.
///
/// The spacecraft moves along `+Y0` at `speed_m_s` through a still atmosphere; `area_m2` is held
/// constant (the paper's projected area `S` is attitude dependent; a constant is the usual simplification).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aerodynamics {
    /// Atmospheric density, kg/m^3 (about 5e-13 at 500 km, moderate solar activity).
    pub density_kg_m3: f64,
    /// Drag coefficient `Cx` (dimensionless, about 2.2 for a free-molecular flow).
    pub drag_coefficient: f64,
    /// Reference area `S`, m^2.
    pub area_m2: f64,
    /// Vector from the centre of mass to the centre of pressure in body axes, m.
    pub cp_offset_m: [f64; 3],
    /// Orbital speed, m/s.
    pub speed_m_s: f64,
}

impl Aerodynamics {
    /// No aerodynamic torque.
    pub const NONE: Aerodynamics = Aerodynamics {
        density_kg_m3: 0.0,
        drag_coefficient: 0.0,
        area_m2: 0.0,
        cp_offset_m: [0.0; 3],
        speed_m_s: 0.0,
    };
}

/// Parameters of eqs. (3)-(4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TumbleModel {
    /// Principal moments of inertia `(Ix, Iy, Iz)`, kg m^2. The gravity-gradient motion depends only on
    /// the dimensionless ratios (e.g. `Ix/Iz`, `Iy/Iz`); the absolute scale matters for the aerodynamic
    /// torque.
    pub inertia_kg_m2: [f64; 3],
    /// Orbital rate `w0`, rad/s; the gravity-gradient coefficient is `3 w0^2 = 3 mu / r^3`.
    pub orbital_rate_rad_s: f64,
    /// Whether the gravity-gradient torque acts (the orbital frame turns at `w0` either way).
    pub gravity_gradient: bool,
    /// Aerodynamic torque parameters.
    pub aero: Aerodynamics,
}

/// Quaternion (scalar first, `dcm_orb0_from_body`) and absolute angular velocity (body axes, rad/s); the
/// core's batch propagation holds several states at once in lanes (`V`, crate-internal).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State<V = f64> {
    pub q: [V; 4],
    pub omega: [V; 3],
}

impl TumbleModel {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`Error::NonFinite`]; [`Error::OutOfRange`] for non-positive moments, moments that break the
    /// triangle inequality, a negative rate, density, drag coefficient, area or speed.
    pub fn validate(&self) -> Result<()> {
        let a = &self.aero;
        ensure_finite("inertia_kg_m2", self.inertia_kg_m2.iter())?;
        ensure_finite(
            "model parameters",
            [
                self.orbital_rate_rad_s,
                a.density_kg_m3,
                a.drag_coefficient,
                a.area_m2,
                a.speed_m_s,
            ]
            .iter()
            .chain(a.cp_offset_m.iter()),
        )?;
        let [ix, iy, iz] = self.inertia_kg_m2;
        if ix <= 0.0 || iy <= 0.0 || iz <= 0.0 {
            return Err(Error::out_of_range(
                "inertia_kg_m2",
                format!("expected positive principal moments, got ({ix}, {iy}, {iz})"),
            ));
        }
        let tol = 1e-12 * (ix + iy + iz);
        if ix + iy < iz - tol || iy + iz < ix - tol || iz + ix < iy - tol {
            return Err(Error::out_of_range(
                "inertia_kg_m2",
                format!("principal moments ({ix}, {iy}, {iz}) violate the triangle inequality"),
            ));
        }
        for (name, v) in [
            ("orbital_rate_rad_s", self.orbital_rate_rad_s),
            ("density_kg_m3", a.density_kg_m3),
            ("drag_coefficient", a.drag_coefficient),
            ("area_m2", a.area_m2),
            ("speed_m_s", a.speed_m_s),
        ] {
            if v < 0.0 {
                return Err(Error::out_of_range(name, format!("expected >= 0, got {v}")));
            }
        }
        Ok(())
    }

    /// Time derivative of `(q, omega)`.
    #[inline]
    pub fn derivative(&self, s: &State) -> State {
        Rhs::new(self).derivative(s)
    }

    /// Rotational kinetic energy `0.5 omega . I omega`, J (absolute rates).
    pub fn kinetic_energy(&self, s: &State) -> f64 {
        let i = self.inertia_kg_m2;
        0.5 * (0..3).map(|k| i[k] * s.omega[k] * s.omega[k]).sum::<f64>()
    }

    /// Angular momentum `R I omega` in the paper's orbital axes, kg m^2/s.
    pub fn angular_momentum_orb0(&self, s: &State) -> Vector3<f64> {
        let i = self.inertia_kg_m2;
        s.dcm_orb0_from_body()
            * Vector3::new(i[0] * s.omega[0], i[1] * s.omega[1], i[2] * s.omega[2])
    }
}

/// The right-hand side with the model's constant coefficients worked out once per trajectory (the
/// reciprocal moments, `3 w0^2`, the drag torque factor) instead of at each of the four derivatives of
/// every RK4 step.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Rhs {
    inertia: [f64; 3],
    inv_inertia: [f64; 3],
    w0: f64,
    /// `3 w0^2` with the gravity-gradient torque, else `None`.
    gravity: Option<f64>,
    /// `-k c` with `k = 0.5 rho Cd S |V|^2` and `c` the centre of pressure: the aerodynamic torque is
    /// `c x (-k e_v) = (-k c) x e_v`; `None` without drag.
    drag: Option<[f64; 3]>,
}

impl Rhs {
    pub(crate) fn new(m: &TumbleModel) -> Rhs {
        let a = &m.aero;
        let [ix, iy, iz] = m.inertia_kg_m2;
        let k = 0.5 * a.density_kg_m3 * a.drag_coefficient * a.area_m2 * a.speed_m_s * a.speed_m_s;
        let c = a.cp_offset_m;
        Rhs {
            inertia: m.inertia_kg_m2,
            inv_inertia: [1.0 / ix, 1.0 / iy, 1.0 / iz],
            w0: m.orbital_rate_rad_s,
            gravity: m
                .gravity_gradient
                .then_some(3.0 * m.orbital_rate_rad_s * m.orbital_rate_rad_s),
            drag: (a.density_kg_m3 > 0.0).then_some([-k * c[0], -k * c[1], -k * c[2]]),
        }
    }

    /// Time derivative of `(q, omega)`: Euler's equations (3) and the kinematics (4), per lane.
    #[inline(always)]
    pub(crate) fn derivative<V: Real>(&self, s: &State<V>) -> State<V> {
        let sp = V::splat;
        let (one, two, half) = (sp(1.0), sp(2.0), sp(0.5));
        let [w, x, y, z] = s.q;
        let [ix, iy, iz] = self.inertia;
        let [p, r_, t] = s.omega;
        // Euler: I w' = (I w) x w + M.
        let mut m = [
            sp(iy - iz) * r_ * t,
            sp(iz - ix) * t * p,
            sp(ix - iy) * p * r_,
        ];
        if let Some(g) = self.gravity {
            // Row 0 of dcm_orb0_from_body: X0 (radial) in body axes; M = 3 w0^2 e x (I e).
            let e_r = [
                one - two * (y * y + z * z),
                two * (x * y - w * z),
                two * (x * z + w * y),
            ];
            m[0] = m[0] + sp(g * (iz - iy)) * e_r[1] * e_r[2];
            m[1] = m[1] + sp(g * (ix - iz)) * e_r[2] * e_r[0];
            m[2] = m[2] + sp(g * (iy - ix)) * e_r[0] * e_r[1];
        }
        if let Some(c) = self.drag {
            // Row 1: Y0 (velocity) in body axes; the drag force is -k |V| e_v.
            let e_v = [
                two * (x * y + w * z),
                one - two * (x * x + z * z),
                two * (y * z - w * x),
            ];
            m[0] = m[0] + (sp(c[1]) * e_v[2] - sp(c[2]) * e_v[1]);
            m[1] = m[1] + (sp(c[2]) * e_v[0] - sp(c[0]) * e_v[2]);
            m[2] = m[2] + (sp(c[0]) * e_v[1] - sp(c[1]) * e_v[0]);
        }
        // Relative angular velocity: omega - w0 Z0, Z0 (orbit normal, row 2) in body axes.
        let w0 = sp(self.w0);
        let u = [
            p - w0 * (two * (x * z - w * y)),
            r_ - w0 * (two * (y * z + w * x)),
            t - w0 * (one - two * (x * x + y * y)),
        ];
        // q' = 0.5 q (x) (0, u).
        let dq = [
            half * (-x * u[0] - y * u[1] - z * u[2]),
            half * (w * u[0] + y * u[2] - z * u[1]),
            half * (w * u[1] + z * u[0] - x * u[2]),
            half * (w * u[2] + x * u[1] - y * u[0]),
        ];
        let inv = self.inv_inertia;
        State {
            q: dq,
            omega: [m[0] * sp(inv[0]), m[1] * sp(inv[1]), m[2] * sp(inv[2])],
        }
    }
}

impl State {
    /// State from the paper's angles (precession, attack, spin; intrinsic `YZY` in the paper's orbital
    /// frame, rad) and the absolute angular velocity in body axes (rad/s).
    pub fn from_angles(angles_rad: [f64; 3], omega_rad_s: [f64; 3]) -> State {
        let m = YZY.to_dcm(angles_rad);
        let [x, y, z, w] = crate::rotation::quaternion::from_dcm(&m);
        State {
            q: [w, x, y, z],
            omega: omega_rad_s,
        }
    }

    /// `dcm_orb0_from_body` (paper orbital axes).
    pub fn dcm_orb0_from_body(&self) -> Matrix3<f64> {
        let [w, x, y, z] = self.q;
        Matrix3::new(
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        )
    }
}

impl<V: Real> State<V> {
    /// The antenna (body `Yc`) axis in the library's orbital frame (x along-track, y normal, z radial).
    #[inline(always)]
    pub fn axis_orbital(&self) -> [V; 3] {
        let [w, x, y, z] = self.q;
        let two = V::splat(2.0);
        // Column 1 of dcm_orb0_from_body = (X0, Y0, Z0) components; divided by |q|^2 to stay unit, so
        // an interpolated quaternion needs no normalisation first.
        let inv = (w * w + x * x + y * y + z * z).recip();
        let c0 = two * (x * y - w * z) * inv;
        let c1 = (w * w - x * x + y * y - z * z) * inv;
        let c2 = two * (y * z + w * x) * inv;
        [c1, c2, c0]
    }

    #[inline(always)]
    pub(crate) fn normalized(mut self) -> State<V> {
        let [w, x, y, z] = self.q;
        let inv = (w * w + x * x + y * y + z * z).sqrt().recip();
        for v in &mut self.q {
            *v = *v * inv;
        }
        self
    }
}
