//! The interrupt flag is process-wide: its tests live in this binary of their own, one test function, so
//! that no other test sees the flag set.

use gnssatt_core::dynamics::{propagate_axes, Aerodynamics, State, TumbleModel};
use gnssatt_core::gyro_gnss::kinematics;
use gnssatt_core::interrupt::{check, clear, request, POLL_EVERY};
use gnssatt_core::orbit::{propagate_with_stm, GlonassModel};
use gnssatt_core::Error;
use nalgebra::Vector3;

const ICD_STATE: [f64; 6] = [
    7003.008789e3,
    -12206.626953e3,
    21280.765625e3,
    0.7835417e3,
    2.8042530e3,
    1.3525150e3,
];

#[test]
fn a_requested_interrupt_stops_the_long_loops_until_cleared() {
    let tumble = TumbleModel {
        inertia_kg_m2: [0.035, 0.008, 0.03],
        orbital_rate_rad_s: 1.1e-3,
        gravity_gradient: true,
        aero: Aerodynamics::NONE,
    };
    let s = State::from_angles([0.7, 1.1, -2.0], [0.01, -0.01, 0.01]);
    let glonass = GlonassModel::pz90();
    let n = 4 * POLL_EVERY;
    let t: Vec<f64> = (0..n).map(|k| k as f64).collect();
    let rates = vec![Vector3::new(0.0, 0.0, 0.01); n];

    assert_eq!(check("x"), Ok(()));
    request();
    assert_eq!(check("x"), Err(Error::Interrupted { what: "x" }));
    assert!(matches!(
        propagate_axes(&tumble, s, &[1e4], 1.0),
        Err(Error::Interrupted { .. })
    ));
    assert!(matches!(
        propagate_with_stm(&glonass, &ICD_STATE, 1e4, 1.0),
        Err(Error::Interrupted { .. })
    ));
    assert!(matches!(
        kinematics::propagate([0.0, 0.0, 0.0, 1.0], &t, &rates),
        Err(Error::Interrupted { .. })
    ));
    clear();
    assert_eq!(check("x"), Ok(()));
    assert!(propagate_axes(&tumble, s, &[1e4], 1.0).is_ok());
    assert!(propagate_with_stm(&glonass, &ICD_STATE, 1e4, 1.0).is_ok());
    assert!(kinematics::propagate([0.0, 0.0, 0.0, 1.0], &t, &rates).is_ok());
}
