use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::*;
use crate::Error;

const L1: f64 = 0.190_293_672_798_364_9;

fn triangle(l: f64) -> Vec<Vector3<f64>> {
    vec![
        Vector3::new(l, 0.0, 0.0),
        Vector3::new(l / 2.0, 0.0, l * 3f64.sqrt() / 2.0),
    ]
}

pub(super) fn sky(rng: &mut ChaCha8Rng, m: usize) -> Vec<Vector3<f64>> {
    (0..m)
        .map(|_| {
            let az: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let el: f64 = rng.random_range(0.2..1.5);
            Vector3::new(az.sin() * el.cos(), az.cos() * el.cos(), el.sin())
        })
        .collect()
}

/// Wrapped noise-free phases (plus random oscillator phase per baseline) at attitude `angles`.
fn epoch(
    rng: &mut ChaCha8Rng,
    baselines: &[Vector3<f64>],
    los: &[Vector3<f64>],
    lambdas: &[f64],
    angles: [f64; 3],
    noise: f64,
) -> Epoch {
    let r = dcm_enu_from_body(angles[0], angles[1], angles[2]);
    let phase_diffs = baselines
        .iter()
        .map(|b| {
            let osc: f64 = rng.random_range(-3.0..3.0);
            los.iter()
                .zip(lambdas)
                .map(|(s, l)| {
                    let n: f64 = rng.random_range(-1.0..1.0) * noise * 3f64.sqrt();
                    (-std::f64::consts::TAU / l * s.dot(&(r * b)) + osc + n)
                        .rem_euclid(std::f64::consts::TAU)
                })
                .collect()
        })
        .collect();
    Epoch {
        phase_diffs,
        los_enu: los.to_vec(),
        wavelengths: lambdas.to_vec(),
    }
}

#[test]
fn sincos_error_is_bounded() {
    let mut worst = 0.0f64;
    for j in 0..1_000_000 {
        let x = (j as f32 - 500_000.0) * 0.01;
        let (s, c) = sincos_f32(x);
        let xd = x as f64;
        worst = worst
            .max((s as f64 - xd.sin()).abs())
            .max((c as f64 - xd.cos()).abs());
    }
    assert!(worst <= SINCOS_ABS_ERROR as f64, "worst {worst:e}");
}

#[test]
fn enu_matrix_matches_eq5() {
    // Eq. (5): first column of R^T is (cos psi cos theta, sin theta, -sin psi cos theta) in (N, U, E).
    let (psi, theta, phi) = (0.3, -0.2, 0.9);
    let m = dcm_normal_from_body(psi, theta, phi);
    assert!((m[(0, 0)] - psi.cos() * theta.cos()).abs() < 1e-15);
    assert!((m[(1, 0)] - theta.sin()).abs() < 1e-15);
    assert!((m[(2, 0)] + psi.sin() * theta.cos()).abs() < 1e-15);
    assert!((m[(1, 1)] - phi.cos() * theta.cos()).abs() < 1e-15);
    assert!((m[(1, 2)] + theta.cos() * phi.sin()).abs() < 1e-15);
    // Positive psi turns the nose west.
    let e = dcm_enu_from_body(0.5, 0.0, 0.0) * Vector3::x();
    assert!(e.x < 0.0 && e.y > 0.0);
}

#[test]
fn kernel_matches_f64_and_recovers_attitude() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let b = triangle(0.71);
    for stat in [Statistic::AmbiguityFunction, Statistic::DoubleDifference] {
        let los = sky(&mut rng, 8);
        let truth = [1.0, 0.2, -0.4];
        let e = epoch(&mut rng, &b, &los, &[L1; 8], truth, 0.0);
        let model = Model::new(&b, &[e], stat).unwrap();
        let grid = Grid::window(3f64.to_radians(), [(0.8, 1.2), (0.0, 0.4), (-0.6, -0.2)]).unwrap();
        let z = evaluate_grid(&model, &grid).unwrap();
        for (idx, &zk) in z.iter().enumerate() {
            let c = grid.unflatten(idx).map(|i| i as i64);
            let [p, t, f] = grid.angles(c);
            let zr = model.z_f64(p, t, f);
            assert!((zk as f64 - zr).abs() <= 1e-5 * zr.max(1.0), "{zk} vs {zr}");
        }
        let est = estimate(&model, &grid, Search::Exhaustive, Refine::Newton).unwrap();
        for (a, t) in est.angles_rad.iter().zip(truth) {
            assert!((a - t).abs() < 1e-7, "{stat:?} {:?}", est.angles_rad);
        }
    }
}

#[test]
fn branch_and_bound_equals_exhaustive() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    for trial in 0..30 {
        let b = if trial % 2 == 0 {
            triangle(0.71)
        } else {
            vec![
                Vector3::new(0.5, 0.1, 0.0),
                Vector3::new(0.0, 0.05, 0.4),
                Vector3::new(0.3, 0.0, 0.3),
            ]
        };
        let m = 4 + trial % 6;
        let los = sky(&mut rng, m);
        let truth = [
            rng.random_range(-3.0..3.0),
            rng.random_range(-1.4..1.4),
            rng.random_range(-3.0..3.0),
        ];
        let e = epoch(&mut rng, &b, &los, &vec![L1; m], truth, 0.3);
        let stat = [
            Statistic::AmbiguityFunction,
            Statistic::DoubleDifference,
            Statistic::Mean,
        ][trial % 3];
        let model = Model::new(&b, &[e], stat).unwrap();
        let grid = Grid::full(6f64.to_radians()).unwrap();
        let ex = exhaustive_max(&model, &grid).unwrap();
        let (bb, _) = branch_and_bound(&model, &grid).unwrap();
        assert_eq!((ex.index, ex.z), (bb.index, bb.z), "trial {trial}");
    }
}

#[test]
fn bad_input_is_rejected() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let b = triangle(0.71);
    let los = sky(&mut rng, 6);
    let e = epoch(&mut rng, &b, &los, &[L1; 6], [0.0; 3], 0.0);
    let ok = |b: &[Vector3<f64>], e: &Epoch| {
        Model::new(b, std::slice::from_ref(e), Statistic::AmbiguityFunction)
    };
    assert!(ok(&b, &e).is_ok());
    let mut bad = e.clone();
    bad.phase_diffs[0][1] = f64::NAN;
    assert!(matches!(ok(&b, &bad), Err(Error::NonFinite { .. })));
    let mut bad = e.clone();
    bad.wavelengths[2] = 0.0;
    assert!(matches!(ok(&b, &bad), Err(Error::OutOfRange { .. })));
    let mut bad = e.clone();
    bad.los_enu.truncate(2);
    bad.wavelengths.truncate(2);
    bad.phase_diffs.iter_mut().for_each(|r| r.truncate(2));
    assert!(matches!(ok(&b, &bad), Err(Error::OutOfRange { .. })));
    let col = vec![Vector3::new(1.0, 0.0, 0.0), Vector3::new(2.0, 0.0, 0.0)];
    assert!(matches!(
        ok(&col, &e),
        Err(Error::DegenerateGeometry { .. })
    ));
    let zero = vec![Vector3::new(1.0, 0.0, 0.0), Vector3::zeros()];
    assert!(matches!(ok(&zero, &e), Err(Error::OutOfRange { .. })));
    let model = ok(&b, &e).unwrap();
    assert!(exhaustive_max(&model, &Grid::full(20f64.to_radians()).unwrap()).is_err());
    assert!(Grid::window(0.02, [(0.1, 0.105), (0.0, 0.1), (0.0, 0.1)]).is_err());
}

#[test]
fn limits_count_the_work_a_search_does() {
    // 1e-4 deg: 3.6e6 nodes per turn, over the lattice's 2^20.
    let e = Grid::full(1e-4f64.to_radians()).unwrap_err();
    assert!(e.to_string().contains("2^20 nodes per turn"), "{e}");
    // 1e-3 deg: 2.3e16 cells over the whole domain. The grid exists; the exhaustive pass refuses it by
    // its cells, the branch-and-bound by the 6.5e10 rows it would scan, both before any cell is
    // evaluated.
    let step = 1e-3f64.to_radians();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let b = triangle(0.71);
    let los = sky(&mut rng, 6);
    let model = Model::new(
        &b,
        &[epoch(&mut rng, &b, &los, &[L1; 6], [0.0; 3], 0.0)],
        Statistic::AmbiguityFunction,
    )
    .unwrap();
    let grid = Grid::full(step).unwrap();
    assert!(grid.len() > MAX_CELLS);
    let e = exhaustive_max(&model, &grid).unwrap_err().to_string();
    assert!(e.contains("step_deg") && e.contains("over the 2^31"), "{e}");
    let e = branch_and_bound(&model, &grid).unwrap_err().to_string();
    assert!(
        e.contains("step_deg") && e.contains("rows, over its limit"),
        "{e}"
    );
    // A 0.1 deg window per axis holds exactly the lattice nodes inside it: every node in, both outside
    // neighbours out (a 0.1 deg span holds 100 or 101 nodes of step 1e-3 deg).
    let w = 0.05f64.to_radians();
    let centre = [1.0, 0.2, -0.5];
    let check = |axis: &Axis, c: f64| {
        assert!(axis.len == 100 || axis.len == 101, "{}", axis.len);
        let n = axis.len as i64;
        assert!(axis.angle(0) >= c - w && axis.angle(n - 1) <= c + w);
        assert!(axis.angle(-1) < c - w && axis.angle(n) > c + w);
    };
    let r = centre.map(|c| (c - w, c + w));
    let g = Grid::window(step, r).unwrap();
    for (axis, c) in [g.psi, g.theta, g.phi].iter().zip(centre) {
        check(axis, c);
    }
    assert!((g.step() - std::f64::consts::TAU / 360000.0).abs() < 1e-18);
    let g2 = Grid::two_dimensional_window(step, [r[0], r[1]]).unwrap();
    check(&g2.psi, centre[0]);
    check(&g2.theta, centre[1]);
    assert_eq!((g2.phi.len, g2.phi.angle(0)), (1, 0.0));
}

/// GLONASS L1 FDMA wavelength of channel `k` (-7..=6), metres.
pub(super) fn glonass(k: i32) -> f64 {
    299_792_458.0 / (1602e6 + k as f64 * 0.5625e6)
}

/// A random planar-or-not array of `m` antennas (m - 1 baselines) with longest baseline near `l` metres.
pub(super) fn array(rng: &mut ChaCha8Rng, m: usize, l: f64) -> Vec<Vector3<f64>> {
    loop {
        let b: Vec<Vector3<f64>> = (1..m)
            .map(|_| {
                let v = Vector3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-0.3..0.3),
                    rng.random_range(-1.0..1.0),
                );
                v * (l / v.norm()) * rng.random_range(0.4..1.0)
            })
            .collect();
        if b.len() == 1
            || b.iter()
                .any(|x| b.iter().any(|y| x.cross(y).norm() > 0.2 * l * l))
        {
            return b;
        }
    }
}

#[test]
fn direction_parametrisation_follows_the_rotation() {
    // R r = |r| u(psi + beta, e), beta and e from Rz(theta) Rx(phi) r: checked against eq. (5)'s matrix.
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for _ in 0..1000 {
        let r = Vector3::new(
            rng.random_range(-2.0..2.0),
            rng.random_range(-2.0..2.0),
            rng.random_range(-2.0..2.0),
        );
        let (psi, theta, phi) = (
            rng.random_range(-4.0..4.0),
            rng.random_range(-1.6..1.6),
            rng.random_range(-4.0..4.0),
        );
        let w = crate::rotation::elementary(crate::rotation::Axis::Z, theta)
            * crate::rotation::elementary(crate::rotation::Axis::X, phi)
            * r;
        let (beta, e) = super::direction::row_direction(&w, r.norm());
        let v = super::direction::unit(psi + beta, e) * r.norm();
        let want = dcm_normal_from_body(psi, theta, phi) * r;
        assert!((v - want).norm() < 1e-12 * r.norm(), "{v} vs {want}");
    }
}

#[test]
fn kernel_margin_covers_the_float32_error() {
    // The margin is derived, not fitted: check it against the f64 statistic on long arrays (phases of
    // hundreds of radians) where the f32 phase rounding dominates.
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let mut worst_ratio = 0.0f64;
    for trial in 0..20 {
        let l = [0.7, 3.0, 10.0][trial % 3];
        let b = array(&mut rng, 2 + trial % 5, l);
        let m = 5 + trial % 12;
        let los = sky(&mut rng, m);
        let lambdas: Vec<f64> = (0..m).map(|k| glonass(k as i32 % 14 - 7)).collect();
        let e = epoch(&mut rng, &b, &los, &lambdas, [0.3, 0.1, -0.2], 0.1);
        let model = Model::new(&b, &[e], Statistic::AmbiguityFunction).unwrap();
        let margin = super::kernel::kernel_margin(&model).unwrap();
        let grid = Grid::window(model.max_step(), [(0.0, 0.3), (0.0, 0.3), (0.0, 0.3)]).unwrap();
        let z = evaluate_grid(&model, &grid).unwrap();
        for (idx, &zk) in z.iter().enumerate() {
            let [p, t, f] = grid.angles(grid.unflatten(idx).map(|i| i as i64));
            let err = (zk as f64 - model.z_f64(p, t, f)).abs();
            assert!(
                err <= margin,
                "trial {trial}: error {err:e} over margin {margin:e}"
            );
            worst_ratio = worst_ratio.max(err / margin);
        }
    }
    // The margin is a bound, not an estimate: it should not be loose by more than a few thousand.
    assert!(
        worst_ratio > 1e-4,
        "margin loose: worst error / margin {worst_ratio:e}"
    );
}

/// One random scenario of the family and a grid of at most about `max_cells` cells over it: the
/// whole domain when small enough, otherwise a window at a random offset from the truth.
fn random_case(rng: &mut ChaCha8Rng, max_cells: f64) -> (Model, Grid) {
    let antennas = rng.random_range(2..=6usize);
    let l = (rng.random_range(0.3f64.ln()..10f64.ln())).exp();
    let b = array(rng, antennas, l);
    let m = rng.random_range(5..=16usize);
    let los = sky(rng, m);
    let lambdas: Vec<f64> = (0..m).map(|_| glonass(rng.random_range(-7..=6))).collect();
    let truth = [
        rng.random_range(-3.1..3.1),
        rng.random_range(-1.4..1.4),
        rng.random_range(-3.1..3.1),
    ];
    let noise = rng.random_range(0.0..0.2);
    let e = epoch(rng, &b, &los, &lambdas, truth, noise);
    let model = Model::new(&b, &[e], Statistic::AmbiguityFunction).unwrap();
    // Eq. (15)'s step lambda / (10 L) up to lambda / (4 L).
    let step = model.max_step() * rng.random_range(0.2..0.5);
    let two_d = b.len() == 1;
    let full = if two_d {
        Grid::two_dimensional(step)
    } else {
        Grid::full(step)
    };
    if let Ok(g) = full {
        if (g.len() as f64) <= max_cells {
            return (model, g);
        }
    }
    let dims = if two_d { 2.0 } else { 3.0 };
    let half = 0.5 * max_cells.powf(1.0 / dims) * step;
    let off = |rng: &mut ChaCha8Rng| rng.random_range(-0.8..0.8) * half;
    let c = [
        truth[0] + off(rng),
        truth[1] + off(rng),
        truth[2] + off(rng),
    ];
    let grid = if two_d {
        Grid::two_dimensional_window(
            step,
            [(c[0] - half, c[0] + half), (c[1] - half, c[1] + half)],
        )
    } else {
        Grid::window(step, c.map(|x| (x - half, x + half)))
    }
    .unwrap();
    (model, grid)
}

#[test]
fn branch_and_bound_equals_exhaustive_on_500_random_scenarios() {
    // 2-6 antennas, 0.3-10 m, 5-16 satellites on GLONASS FDMA wavelengths, wrapped phases with noise up
    // to 0.2 rad; steps from eq. (15)'s lambda / (10 L) to lambda / (4 L); whole-domain grids where they
    // hold <= 40k cells, windows around the truth elsewhere. The same f32 Z and the same flat index
    // (lowest among equal Z) as the exhaustive pass, compared exactly. Grids this small are below the
    // default work limit's break-even, so the search runs with a fixed limit of 2^16 boxes.
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let (mut fallbacks, mut cells, mut bnb_cells) = (0, 0u64, 0u64);
    for trial in 0..500 {
        let (model, grid) = random_case(&mut rng, 4e4);
        let ex = exhaustive_max(&model, &grid).unwrap();
        let (bb, stats) = super::bnb::branch_and_bound_limited(&model, &grid, 1 << 16).unwrap();
        assert_eq!(
            (ex.index, ex.z),
            (bb.index, bb.z),
            "trial {trial}: {stats:?}"
        );
        fallbacks += stats.fallback as usize;
        if !stats.fallback {
            cells += grid.len() as u64;
            bnb_cells += stats.leaf_cells;
        }
    }
    eprintln!("fallbacks {fallbacks}/500; kernel cells {bnb_cells} of {cells} where it searched");
    // The branch-and-bound itself (not its exhaustive fallback) must carry most of the comparison.
    assert!(fallbacks < 125, "{fallbacks} fallbacks");
}

#[test]
fn long_arrays_are_searched_at_eq15_step_without_a_window() {
    // 5 m and 10 m triangles at eq. (15)'s step lambda / (10 L) (2.2e9 and 1.8e10 cells, more than the
    // exhaustive pass evaluates), 0.1 rad noise: the branch-and-bound searches the whole domain, and its
    // cell is the exhaustive maximum of a window of +-4 steps around it (the window holds the truth).
    let mut rng = ChaCha8Rng::seed_from_u64(15);
    for l in [5.0, 10.0] {
        let b = triangle(l);
        let los = sky(&mut rng, 8);
        let truth = [0.7, 0.05, -0.1];
        let e = epoch(&mut rng, &b, &los, &[L1; 8], truth, 0.1);
        let model = Model::new(&b, &[e], Statistic::AmbiguityFunction).unwrap();
        let step = model.default_step();
        let grid = Grid::full(step).unwrap();
        assert!(grid.len() > MAX_CELLS);
        let (bb, stats) = branch_and_bound(&model, &grid).unwrap();
        assert!(!stats.fallback);
        let at = grid.angles(bb.index.map(|i| i as i64));
        for (a, t) in at.iter().zip(truth) {
            assert!((a - t).abs() < 2.0 * step, "{l} m: {at:?}");
        }
        let w = 4.5 * step;
        let win = Grid::window(step, at.map(|a| (a - w, a + w))).unwrap();
        let ex = exhaustive_max(&model, &win).unwrap();
        assert_eq!(ex.z, bb.z, "{l} m: {stats:?}");
        assert_eq!(win.angles(ex.index.map(|i| i as i64)), at, "{l} m");
    }
}

#[test]
fn direction_sets_hold_every_direction_that_reaches_the_threshold() {
    // Per baseline, random directions (and directions next to the truth, where F_i is near n) with
    // F_i >= tau computed in f64 must lie in a kept box whose bound is at least F_i: 1-5 m baselines,
    // 5-12 satellites, thresholds 0.05-1.5 below n, leaves from a tenth of a degree to a degree.
    use super::direction::{direction_set, top_bins, Budget, Reach};
    let mut rng = ChaCha8Rng::seed_from_u64(29);
    let (mut checked, mut near) = (0, 0);
    for trial in 0..24 {
        let l = rng.random_range(1.0..5.0);
        let b = triangle(l);
        let m = rng.random_range(5..=12);
        let los = sky(&mut rng, m);
        let truth = [rng.random_range(0.0..6.0), rng.random_range(-0.5..0.5), 0.3];
        let e = epoch(&mut rng, &b, &los, &vec![L1; m], truth, 0.1);
        let model = Model::new(&b, &[e], Statistic::AmbiguityFunction).unwrap();
        let n = model.n_terms();
        let r = dcm_enu_from_body(truth[0], truth[1], truth[2]);
        for (i, bi) in model.baselines.iter().enumerate() {
            let tau = n as f64 - rng.random_range(0.05..1.5);
            let h_min = rng.random_range(0.1f64..1.0).to_radians();
            let reach = Reach::new(top_bins(&model, i), true);
            let set = direction_set(&model, i, tau, h_min, &reach, &Budget::new(u64::MAX)).unwrap();
            let f = |a: f64, e: f64| {
                let u = super::direction::unit(a, e);
                let (s, c) = (0..n).fold((0.0, 0.0), |(s, c), k| {
                    let x = model.d[i * n + k] + bi.norm() * model.g[k].dot(&u);
                    (s + x.sin(), c + x.cos())
                });
                s.hypot(c)
            };
            // The truth's direction in the (a, e) parameters (normal frame N, U, E).
            let w = r * b[i] / b[i].norm();
            let (w_n, w_u, w_e) = (w.y, w.z, w.x);
            let (a_t, e_t) = (
                (-w_e).atan2(w_n).rem_euclid(std::f64::consts::TAU),
                w_u.asin(),
            );
            for probe in 0..4000 {
                let (a, e) = if probe % 2 == 0 {
                    (
                        rng.random_range(0.0..std::f64::consts::TAU),
                        rng.random_range(-std::f64::consts::FRAC_PI_2..std::f64::consts::FRAC_PI_2),
                    )
                } else {
                    let a = (a_t + rng.random_range(-0.05..0.05)).rem_euclid(std::f64::consts::TAU);
                    (
                        a,
                        (e_t + rng.random_range(-0.05..0.05))
                            .clamp(-std::f64::consts::FRAC_PI_2, std::f64::consts::FRAC_PI_2),
                    )
                };
                let fv = f(a, e);
                if fv < tau {
                    continue;
                }
                checked += 1;
                near += probe % 2;
                assert!(
                    set.iter().any(|bx| bx.a0 <= a
                        && a <= bx.a1
                        && bx.e0 <= e
                        && e <= bx.e1
                        && bx.bound >= fv - 1e-9),
                    "trial {trial} baseline {i}: F = {fv} >= tau = {tau} at ({a}, {e}) in no box"
                );
            }
        }
    }
    // Probes next to the truth reach the threshold (the test must not pass by checking nothing), and
    // so do some side lobes elsewhere.
    eprintln!("{checked} directions checked, {near} next to the truth");
    assert!(
        near > 5_000 && checked - near > 200,
        "{checked} checked, {near} near"
    );
}

#[test]
fn branch_and_bound_equals_exhaustive_on_coarse_grids_over_many_skies() {
    // Issue 30's case scaled down: the 5 m triangle at 0.45 deg is a grid of 0.41 of the coarsest
    // accepted step lambda / (2 L), where the grid maximum sits 1-3.5 % below m n and the search often
    // needs a second round (its proof at the attained value). A 2 m triangle at 0.35-0.5 of that step
    // has the same phase motion per step (0.8-1.6 rad on 8 satellites at 0.1 rad noise) on whole-domain
    // grids of 1.1e7-2.7e7 cells, small enough for the exhaustive pass as the reference (brute force
    // over every cell). The same f32 Z and flat index, compared exactly; both one-round and later-round
    // proofs must occur.
    let mut rng = ChaCha8Rng::seed_from_u64(30);
    let b = triangle(2.0);
    let (mut rounds, mut fallbacks) = ([0usize; 4], 0);
    for trial in 0..12 {
        let los = sky(&mut rng, 8);
        let truth = [
            rng.random_range(0.0..std::f64::consts::TAU),
            rng.random_range(-0.5..0.5),
            rng.random_range(-0.5..0.5),
        ];
        let e = epoch(&mut rng, &b, &los, &[L1; 8], truth, 0.1);
        let model = Model::new(&b, &[e], Statistic::AmbiguityFunction).unwrap();
        let step = model.max_step() * rng.random_range(0.35..0.5);
        let grid = Grid::full(step).unwrap();
        let ex = exhaustive_max(&model, &grid).unwrap();
        let (bb, stats) = branch_and_bound(&model, &grid).unwrap();
        assert_eq!(
            (ex.index, ex.z),
            (bb.index, bb.z),
            "trial {trial}: {stats:?}"
        );
        if stats.fallback {
            fallbacks += 1;
        } else {
            rounds[(stats.rounds as usize).min(3)] += 1;
        }
    }
    eprintln!("searched trials by rounds (0, 1, 2, 3+): {rounds:?}, {fallbacks} fallbacks");
    // The search itself (not its exhaustive fallback, over its box limit on 3 of these skies) must carry
    // the comparison, in both kinds of proof (3 one-round and 6 two-round skies here).
    assert!(
        2 * fallbacks < 12 && rounds[1] > 0 && rounds[2] + rounds[3] > 0,
        "{rounds:?}, {fallbacks} fallbacks"
    );
}
