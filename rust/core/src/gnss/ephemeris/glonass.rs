//! GLONASS broadcast states moved to the requested time by fourth-order Runge-Kutta integration of the
//! ICD equations of motion (GLONASS ICD 5.1, A.3.1.2; [`crate::orbit::glonass::GlonassModel`]), with the
//! record's luni-solar acceleration held constant; clock `-tau_n + gamma_n (t - t_b)`.

use nalgebra::{Vector3, Vector6};

use super::super::navdata::GlonassRecord;
use super::super::time::seconds_between;
use crate::orbit::GlonassModel;

/// Longest RK4 step, s (ICD A.3.1.2 uses steps of at most a minute for the simplified algorithm).
pub const MAX_STEP_S: f64 = 60.0;

/// The ICD 5.1 constants (J2 1082625.7e-9, Earth rate 7.292115e-5 rad/s, as RTKLIB and the ICD's worked
/// example use them) with the record's luni-solar acceleration.
fn model(record: &GlonassRecord) -> GlonassModel {
    GlonassModel {
        j2: 1.082_625_7e-3,
        omega_rad_s: 7.292_115e-5,
        lunisolar_m_s2: record.acceleration_m_s2,
        ..GlonassModel::pz90()
    }
}

/// Position (m), velocity (m/s), both Earth-fixed, and clock (s) of `record` at GPST
/// `t_gpst_ns + offset_s`. The caller bounds `|t - t_b|` by the validity interval, so the step count is
/// small (at most 31 for 30 minutes).
pub(crate) fn state(
    record: &GlonassRecord,
    t_gpst_ns: i64,
    offset_s: f64,
) -> (Vector3<f64>, Vector3<f64>, f64) {
    let dt = seconds_between(t_gpst_ns, record.tb_gpst_ns) + offset_s;
    let m = model(record);
    let p = record.position_m;
    let v = record.velocity_m_s;
    let mut x = Vector6::new(p[0], p[1], p[2], v[0], v[1], v[2]);
    let n = (dt.abs() / MAX_STEP_S).ceil().max(1.0) as usize;
    let h = dt / n as f64;
    for _ in 0..n {
        x = m.rk4_step(&x, h);
    }
    let clock = record.clock_bias_s + record.gamma_n * dt;
    (
        x.fixed_rows::<3>(0).into_owned(),
        x.fixed_rows::<3>(3).into_owned(),
        clock,
    )
}
