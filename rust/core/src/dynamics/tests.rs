use super::*;
use crate::Error;

const MU: f64 = 3.986_004_418e14;

fn w0_500km() -> f64 {
    (MU / 6_878_137f64.powi(3)).sqrt()
}

fn model(inertia: [f64; 3], w0: f64, gg: bool) -> TumbleModel {
    TumbleModel {
        inertia_kg_m2: inertia,
        orbital_rate_rad_s: w0,
        gravity_gradient: gg,
        aero: Aerodynamics::NONE,
    }
}

fn times(n: usize, dt: f64) -> Vec<f64> {
    (0..n).map(|k| k as f64 * dt).collect()
}

fn angle(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    d.clamp(-1.0, 1.0).acos()
}

fn tumbling_state() -> State {
    let d = 3f64.to_radians();
    State::from_angles([0.7, 1.1, -2.0], [0.6 * d, -0.5 * d, 0.55 * d])
}

/// Largest relative drift of energy and |L| (orbital axes, inertial when w0 = 0) over 1500 s.
fn torque_free_drift(step: f64) -> (f64, f64) {
    let m = model([0.035, 0.008, 0.03], 0.0, false);
    let s0 = tumbling_state();
    let out = propagate(&m, s0, &times(1501, 1.0), step).unwrap();
    let (e0, l0) = (m.kinetic_energy(&s0), m.angular_momentum_orb0(&s0));
    let de = out
        .iter()
        .map(|s| ((m.kinetic_energy(s) - e0) / e0).abs())
        .fold(0.0, f64::max);
    let dl = out
        .iter()
        .map(|s| (m.angular_momentum_orb0(s) - l0).norm() / l0.norm())
        .fold(0.0, f64::max);
    (de, dl)
}

#[test]
fn torque_free_motion_conserves_energy_and_momentum_to_rk4_order() {
    let (de1, dl1) = torque_free_drift(1.0);
    let (de2, dl2) = torque_free_drift(0.5);
    // |omega| h ~ 0.05 rad per step: RK4's O(h^4) global error gives ~1e-8 relative drift over 1500 s.
    assert!(de1 < 1e-7 && dl1 < 1e-7, "drift {de1:e} {dl1:e}");
    // Halving the step divides the error by 2^4 = 16 or more (order 4; the energy error here is nearer
    // 2^5 because its leading term averages out over a tumble period).
    assert!(
        de1 / de2 > 12.0 && de1 / de2 < 40.0,
        "energy ratio {}",
        de1 / de2
    );
    assert!(
        dl1 / dl2 > 12.0 && dl1 / dl2 < 40.0,
        "momentum ratio {}",
        dl1 / dl2
    );
}

#[test]
fn axis_with_one_second_step_matches_a_fine_step() {
    let mut m = model([0.035, 0.008, 0.03], w0_500km(), true);
    m.aero = paper_aero();
    let t = times(151, 10.0);
    let coarse = propagate_axes(&m, tumbling_state(), &t, 1.0).unwrap();
    let fine = propagate_axes(&m, tumbling_state(), &t, 0.125).unwrap();
    let worst = coarse
        .iter()
        .zip(&fine)
        .map(|(a, b)| angle(*a, *b))
        .fold(0.0, f64::max);
    assert!(worst < 1e-6, "axis error {worst:e} rad");
}

fn paper_aero() -> Aerodynamics {
    Aerodynamics {
        density_kg_m3: 5e-13,
        drag_coefficient: 2.2,
        area_m2: 0.03,
        cp_offset_m: [0.002, -0.01, 0.001],
        speed_m_s: 7612.6,
    }
}

/// Largest angle (rad) between body axes and the paper's orbital axes over `orbits` orbits, starting
/// near the orbital frame turning with it.
fn max_libration(inertia: [f64; 3], orbits: f64) -> f64 {
    let w0 = w0_500km();
    let m = model(inertia, w0, true);
    let s0 = State::from_angles([0.01, 0.01, 0.0], [0.01 * w0, -0.01 * w0, 1.01 * w0]);
    let period = 2.0 * std::f64::consts::PI / w0;
    let t = times((orbits * 100.0) as usize + 1, period / 100.0);
    propagate(&m, s0, &t, 10.0)
        .unwrap()
        .iter()
        .map(|s| 2.0 * s.q[0].abs().clamp(0.0, 1.0).acos())
        .fold(0.0, f64::max)
}

#[test]
fn gravity_gradient_lagrange_equilibrium_is_stable() {
    // Least inertia radial (Xc), greatest along the orbit normal (Zc): small librations stay small.
    let worst = max_libration([1.0, 2.0, 3.0], 5.0);
    assert!(worst < 0.05, "libration grew to {worst} rad");
}

#[test]
fn gravity_gradient_pitch_instability_diverges() {
    // Radial inertia above along-track inertia: negative pitch stiffness 3 w0^2 (Iy - Ix) / Iz.
    let worst = max_libration([2.0, 1.0, 3.0], 5.0);
    assert!(worst > 1.0, "libration stayed at {worst} rad");
}

#[test]
fn aerodynamic_torque_is_cp_offset_cross_drag() {
    let mut m = model([0.035, 0.008, 0.03], 0.0, false);
    m.aero = paper_aero();
    let s = State::from_angles([0.0; 3], [0.0; 3]);
    let d = m.derivative(&s);
    let a = paper_aero();
    let k = 0.5 * a.density_kg_m3 * a.drag_coefficient * a.area_m2 * a.speed_m_s.powi(2);
    // Body = orbital: velocity along +Yc, drag F = (0, -k, 0), M = r x F = (r_z k, 0, -r_x k).
    let c = a.cp_offset_m;
    let expect = [c[2] * k / 0.035, 0.0, -c[0] * k / 0.03];
    for i in 0..3 {
        assert!(
            (d.omega[i] - expect[i]).abs() < 1e-18,
            "{:?} {:?}",
            d.omega,
            expect
        );
    }
}

#[test]
fn initial_axis_follows_the_yzy_angles() {
    let (psi, alpha) = (0.4_f64, 1.2_f64);
    let s = State::from_angles([psi, alpha, 2.5], [0.0; 3]);
    let a = s.axis_orbital();
    // R_y(psi) R_z(alpha) e_y = (-sin a cos p, cos a, sin a sin p) in (X0, Y0, Z0); library = (Y0, Z0, X0).
    let expect = [
        alpha.cos(),
        alpha.sin() * psi.sin(),
        -alpha.sin() * psi.cos(),
    ];
    for i in 0..3 {
        assert!((a[i] - expect[i]).abs() < 1e-14);
    }
}

#[test]
fn batch_matches_single_propagation_and_cost_vanishes_at_truth() {
    let mut m = model([0.035, 0.008, 0.03], w0_500km(), true);
    m.aero = paper_aero();
    let t = times(31, 50.0);
    let d = 1f64.to_radians();
    // Six rows: a full pack of four lanes and a partial one; each row's axes are the single
    // propagation's to the last bit, whatever rows share its pack.
    let params = [
        [0.7, 1.1, -2.0, 0.6 * d, -0.5 * d, 0.55 * d],
        [3.0, 0.3, 1.0, -2.0 * d, 0.1 * d, 1.0 * d],
        [5.0, 2.9, 0.2, 2.9 * d, 0.3 * d, -0.4 * d],
        [1.5, 1.6, 4.0, 0.0, 0.0, 0.0],
        [0.1, 0.01, 6.0, -d, 1.7 * d, 0.2 * d],
        [2.2, 3.1, 3.3, 0.4 * d, -2.5 * d, 1.5 * d],
    ];
    let batch = propagate_axes_batch(&m, &params, &t, 1.0).unwrap();
    assert_eq!(batch.len(), params.len());
    for (b, axes) in params.iter().zip(&batch) {
        let s = State::from_angles([b[0], b[1], b[2]], [b[3], b[4], b[5]]);
        assert_eq!(&propagate_axes(&m, s, &t, 1.0).unwrap(), axes);
    }
    let cost = axis_cost_batch(&m, &params, &t, &batch[0], 1.0).unwrap();
    assert_eq!(cost[0], 0.0);
    assert!(cost[1..].iter().all(|&c| c > 1.0), "{cost:?}");
    // Each row's objective is its own sum over the single propagation.
    for (c, axes) in cost.iter().zip(&batch) {
        let sum: f64 = axes
            .iter()
            .zip(&batch[0])
            .map(|(a, b)| (0..3).map(|i| (a[i] - b[i]) * (a[i] - b[i])).sum::<f64>())
            .sum();
        assert!((c - sum).abs() <= 1e-12 * sum, "{c} vs {sum}");
    }
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let m = model([0.035, 0.008, 0.03], w0_500km(), true);
    let s = tumbling_state();
    assert!(matches!(
        propagate(&m, s, &[0.0, 2.0, 1.0], 1.0),
        Err(Error::OutOfRange { name: "t", .. })
    ));
    assert!(matches!(
        propagate(&m, s, &[-1.0], 1.0),
        Err(Error::OutOfRange { .. })
    ));
    assert!(matches!(
        propagate(&m, s, &[1.0], 0.0),
        Err(Error::OutOfRange { name: "step_s", .. })
    ));
    assert!(matches!(
        propagate(&m, s, &[f64::NAN], 1.0),
        Err(Error::NonFinite { .. })
    ));
    let bad = model([1.0, 1.0, 3.0], 0.001, true);
    assert!(matches!(
        propagate(&bad, s, &[1.0], 1.0),
        Err(Error::OutOfRange {
            name: "inertia_kg_m2",
            ..
        })
    ));
    let t = [0.0, 1.0];
    assert!(matches!(
        axis_cost_batch(&m, &[[0.0; 6]], &t, &[[1.0, 0.0, 0.0]], 1.0),
        Err(Error::Shape { .. })
    ));
    assert!(matches!(
        propagate_axes_batch(&m, &[[0.0, f64::INFINITY, 0.0, 0.0, 0.0, 0.0]], &t, 1.0),
        Err(Error::NonFinite { .. })
    ));
}

#[test]
fn work_beyond_the_limits_is_refused_before_it_starts() {
    let m = model([0.035, 0.008, 0.03], w0_500km(), true);
    let s = tumbling_state();
    // 1 s in steps of 1e-300 s: 1e300 steps (the call used to run forever).
    match propagate_axes(&m, s, &[1.0], 1e-300) {
        Err(Error::TooLarge {
            name: "step_s",
            requested,
            limit,
            ..
        }) => assert!(requested >= 1e299 && limit == MAX_RK4_STEPS),
        other => panic!("{other:?}"),
    }
    // 1e4 initial states x 1e5 steps each: 1e9 steps over the batch.
    let d = 1f64.to_radians();
    let params = vec![[0.7, 1.1, -2.0, d, -d, d]; 10_000];
    assert!(matches!(
        axis_cost_batch(&m, &params, &[1e5], &[[1.0, 0.0, 0.0]], 1.0),
        Err(Error::TooLarge { name: "step_s", .. })
    ));
    // Exactly at the limit is allowed: the steps are counted, not refused (not run here).
    let plan = super::integrate::check_times(&[MAX_RK4_STEPS], 1.0).unwrap();
    assert_eq!(plan.steps, MAX_RK4_STEPS);
    // Output values: 1e5 states x 1e3 times x 3.
    let params = vec![[0.7, 1.1, -2.0, d, -d, d]; 100_000];
    let t = times(1000, 0.0);
    assert!(matches!(
        propagate_axes_batch(&m, &params, &t, 1.0),
        Err(Error::TooLarge { name: "t", .. })
    ));
}

#[test]
fn a_rate_too_fast_for_the_step_is_refused_with_the_step_that_works() {
    let m = model([0.035, 0.008, 0.03], w0_500km(), true);
    // 10 rad/s with 1 s steps: 10 rad per step (RK4 returned NaN here before).
    let fast = State::from_angles([0.7, 1.1, -2.0], [6.0, -8.0, 0.0]);
    let e = propagate_axes(&m, fast, &times(11, 1.0), 1.0).unwrap_err();
    match &e {
        Error::OutOfRange {
            name: "step_s",
            detail,
        } => assert!(detail.contains("use step_s <= 9.99"), "{detail}"),
        other => panic!("{other:?}"),
    }
    // A step within the limit works: torque-free, energy and |L| are conserved to RK4 accuracy
    // (0.5 rad per step: local error (0.5)^5 / 120 ~ 3e-4 relative, far less in the invariants).
    let free = model([0.035, 0.008, 0.03], 0.0, false);
    let out = propagate(&free, fast, &times(11, 1.0), 0.05).unwrap();
    let (e0, l0) = (
        free.kinetic_energy(&fast),
        free.angular_momentum_orb0(&fast).norm(),
    );
    for s in &out {
        assert!(((free.kinetic_energy(s) - e0) / e0).abs() < 1e-3);
        assert!(((free.angular_momentum_orb0(s).norm() - l0) / l0).abs() < 1e-3);
    }
    // In a batch the error names the row.
    let rows = [[0.0; 6], [0.7, 1.1, -2.0, 6.0, -8.0, 0.0]];
    match propagate_axes_batch(&m, &rows, &[1.0], 1.0) {
        Err(Error::OutOfRange { detail, .. }) => {
            assert!(detail.contains("params row 1"), "{detail}")
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_torque_that_spins_the_body_up_stops_the_run_instead_of_returning_nan() {
    let mut m = model([0.035, 0.008, 0.03], 0.0, false);
    // 1e11 N of drag 1 m from the centre of mass: 3e12 rad/s^2, so the rate leaves the stable range
    // within the first second although it starts at rest.
    m.aero = Aerodynamics {
        density_kg_m3: 1e3,
        drag_coefficient: 2.0,
        area_m2: 1.0,
        cp_offset_m: [1.0, 0.0, 1.0],
        speed_m_s: 1e4,
    };
    let rest = State::from_angles([0.1, 0.2, 0.3], [0.0; 3]);
    match propagate_axes(&m, rest, &times(100, 1.0), 1.0) {
        Err(Error::Numerical { detail, .. }) => assert!(detail.contains("diverged"), "{detail}"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn outputs_between_grid_points_are_interpolated_to_rk4_accuracy() {
    let mut m = model([0.035, 0.008, 0.03], w0_500km(), true);
    m.aero = paper_aero();
    // 3 deg/s about a skew axis: 0.16 rad per 3 s step, 0.26 rad per 5 s step.
    let d = 3f64.to_radians() / 3f64.sqrt();
    let s = State::from_angles([0.7, 1.1, -2.0], [d, -d, d]);
    let t = times(1501, 1.0);
    let fine = propagate_axes(&m, s, &t, 0.125).unwrap();
    let worst = |step: f64| {
        let out = propagate_axes(&m, s, &t, step).unwrap();
        out.iter()
            .zip(&fine)
            .map(|(a, b)| angle(*a, *b))
            .fold(0.0, f64::max)
    };
    // RK4's O(h^4) global error over 1500 s: measured 3.9e-5 rad at 3 s and 3.8e-4 rad at 5 s
    // ((5/3)^4 = 7.7; the interpolation adds far less).
    let (e3, e5) = (worst(3.0), worst(5.0));
    assert!(e3 < 1e-4 && e5 < 1e-3, "{e3:e} {e5:e}");
    assert!(e5 / e3 > 4.0, "error ratio {} for steps 5/3", e5 / e3);
    // Times on the grid are the grid's states exactly, whatever other times are asked for.
    let dense = propagate_axes(&m, s, &t, 3.0).unwrap();
    let sparse = propagate_axes(&m, s, &times(501, 3.0), 3.0).unwrap();
    for (k, a) in sparse.iter().enumerate() {
        assert_eq!(*a, dense[3 * k]);
    }
    // A step longer than the last time is cut to it; the state there is RK4's.
    let one = propagate(&m, s, &[0.4, 2.0], 5.0).unwrap();
    assert_eq!(one[1], rk4_step(&m, &s, 2.0));
}

#[test]
fn batch_results_do_not_depend_on_the_pool_or_the_pack_path() {
    // A one-thread pool and a single pack run on the calling thread, a larger pool on rayon: the same
    // rows give the same bits either way.
    let mut m = model([0.035, 0.008, 0.03], w0_500km(), true);
    m.aero = paper_aero();
    let t = times(41, 7.5);
    let d = 1f64.to_radians();
    let params: Vec<[f64; 6]> = (0..11)
        .map(|i| {
            let x = i as f64;
            [
                0.5 * x,
                0.1 + 0.25 * x,
                6.0 - 0.5 * x,
                (x - 5.0) * 0.5 * d,
                0.3 * d,
                -0.2 * x * d,
            ]
        })
        .collect();
    let meas = propagate_axes_batch(&m, &params[..1], &t, 2.5)
        .unwrap()
        .remove(0);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            (
                axis_cost_batch(&m, &params, &t, &meas, 2.5).unwrap(),
                propagate_axes_batch(&m, &params, &t, 2.5).unwrap(),
            )
        })
    };
    let (one, three) = (run(1), run(3));
    assert_eq!(one, three);
    for (i, b) in params.iter().enumerate() {
        let single = axis_cost_batch(&m, &[*b], &t, &meas, 2.5).unwrap();
        assert_eq!(single[0], one.0[i]);
    }
}
