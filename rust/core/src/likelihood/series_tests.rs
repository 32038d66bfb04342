//! The batch calls against the single-epoch search run epoch by epoch (exhaustive pass, so the grid
//! maximum of the batch's `Search::Auto` is checked against every cell), and against the truth.

use std::f64::consts::TAU;

use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::tests::{array, glonass, sky};
use super::*;
use crate::Error;

/// An epoch at attitude `truth` (eq. (5) angles): wrapped phases with an oscillator phase per rover and
/// uniform noise of standard deviation `noise` rad.
fn ml_epoch(
    rng: &mut ChaCha8Rng,
    baselines: &[Vector3<f64>],
    los: &[Vector3<f64>],
    lambdas: &[f64],
    truth: [f64; 3],
    noise: f64,
) -> MlEpoch {
    let r = dcm_enu_from_body(truth[0], truth[1], truth[2]);
    let mut sd = Vec::new();
    for b in baselines {
        let osc: f64 = rng.random_range(-3.0..3.0);
        for (s, l) in los.iter().zip(lambdas) {
            let n: f64 = rng.random_range(-1.0..1.0) * noise * 3f64.sqrt();
            sd.push((-TAU / l * s.dot(&(r * b)) + osc + n).rem_euclid(TAU));
        }
    }
    MlEpoch {
        sd_phase_rad: sd,
        los_enu: los.iter().map(|v| [v.x, v.y, v.z]).collect(),
        wavelength_m: lambdas.to_vec(),
    }
}

/// Epoch by epoch through `Model` / `Grid` / `estimate` with the exhaustive pass: signals with a NaN at
/// any rover dropped, the window around the previous solved epoch. `(angles, z)` or `None` (unsolved).
fn reference(
    epochs: &[MlEpoch],
    b: &[Vector3<f64>],
    two_d: bool,
    step: f64,
    window: Option<f64>,
) -> Vec<Option<([f64; 3], f64)>> {
    let mut out: Vec<Option<([f64; 3], f64)>> = vec![];
    for e in epochs {
        let n = e.los_enu.len();
        let mut ep = Epoch {
            phase_diffs: vec![vec![]; b.len()],
            los_enu: vec![],
            wavelengths: vec![],
        };
        for k in 0..n {
            if (0..b.len()).any(|i| e.sd_phase_rad[i * n + k].is_nan()) {
                continue;
            }
            for i in 0..b.len() {
                ep.phase_diffs[i].push(e.sd_phase_rad[i * n + k]);
            }
            ep.los_enu.push(Vector3::from(e.los_enu[k]));
            ep.wavelengths.push(e.wavelength_m[k]);
        }
        if ep.los_enu.len() < 3 {
            out.push(None);
            continue;
        }
        let model = Model::new(b, &[ep], Statistic::AmbiguityFunction).unwrap();
        let prev = out.last().copied().flatten();
        let grid = match (window.zip(prev), two_d) {
            (None, false) => Grid::full(step),
            (None, true) => Grid::two_dimensional(step),
            (Some((w, (a, _))), false) => Grid::window(step, a.map(|x| (x - w, x + w))),
            (Some((w, (a, _))), true) => {
                Grid::two_dimensional_window(step, [(a[0] - w, a[0] + w), (a[1] - w, a[1] + w)])
            }
        }
        .unwrap();
        let est = estimate(&model, &grid, Search::Exhaustive, Refine::Newton).unwrap();
        out.push(Some((est.angles_rad, est.grid_max.z as f64)));
    }
    out
}

/// A random batch: `n_ep` epochs of a slowly turning platform, 5-12 signals on GLONASS wavelengths (or
/// GPS L1/L2 mixed), some signals absent at one rover (NaN), one epoch with too few complete signals.
fn batch(rng: &mut ChaCha8Rng, b: &[Vector3<f64>], n_ep: usize, step: f64) -> Vec<MlEpoch> {
    let m = rng.random_range(5..=12usize);
    let lambdas: Vec<f64> = (0..m)
        .map(|k| match k % 3 {
            0 => glonass(rng.random_range(-7..=6)),
            1 => 0.190_293_672_798_364_9,
            _ => 0.244_210_213_424_568_2,
        })
        .collect();
    let mut truth = [
        rng.random_range(-3.0..3.0),
        rng.random_range(-1.2..1.2),
        rng.random_range(-3.0..3.0),
    ];
    let unsolved = rng.random_range(1..n_ep);
    (0..n_ep)
        .map(|k| {
            for a in &mut truth {
                *a += rng.random_range(-1.0..1.0) * step;
            }
            let los = sky(rng, m);
            let noise = rng.random_range(0.0..0.1);
            let mut e = ml_epoch(rng, b, &los, &lambdas, truth, noise);
            let keep = if k == unsolved { 2 } else { m - 2 };
            for s in keep..m {
                let i = rng.random_range(0..b.len());
                e.sd_phase_rad[i * m + s] = f64::NAN;
            }
            e
        })
        .collect()
}

fn check(got: &[MlSolution], want: &[Option<([f64; 3], f64)>], two_d: bool, case: usize) {
    assert_eq!(got.len(), want.len());
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        match w {
            None => {
                assert!(!g.solved, "case {case} epoch {k}");
                assert!(g.value.is_nan() && g.euler_gost_rad.iter().all(|a| a.is_nan()));
            }
            Some((a, z)) => {
                assert!(g.solved, "case {case} epoch {k}");
                assert_eq!(
                    (g.euler_gost_rad, g.value),
                    (*a, *z),
                    "case {case} epoch {k}"
                );
                if two_d {
                    // Compass azimuth of the baseline = -psi (module docs of `crate::likelihood`).
                    let az = (-a[0]).rem_euclid(TAU);
                    assert!((g.direction_rad[0] - az).abs() < 1e-12);
                    assert!((g.direction_rad[1] - a[1]).abs() < 1e-12);
                }
            }
        }
    }
}

#[test]
fn attitude_series_equals_the_single_epoch_search() {
    let mut rng = ChaCha8Rng::seed_from_u64(170);
    for case in 0..12 {
        let antennas = rng.random_range(3..=4usize);
        let l = rng.random_range(0.3..1.2);
        let b = array(&mut rng, antennas, l);
        let l = b.iter().map(|x| x.norm()).fold(l, f64::max);
        // Every wavelength is at least 0.18 m: a step of at most 0.25 lambda / (2 L).
        let step = rng.random_range(0.1..0.25) * 0.18 / (2.0 * l);
        let epochs = batch(&mut rng, &b, 5, step);
        let body: Vec<[f64; 3]> = b.iter().map(|v| [v.x, v.y, v.z]).collect();
        for window in [None, Some(rng.random_range(2.0..6.0) * step)] {
            let got = ml_attitude_series(&epochs, &body, Some(step), window).unwrap();
            check(
                &got,
                &reference(&epochs, &b, false, step, window),
                false,
                case,
            );
        }
    }
}

#[test]
fn attitude_series_by_branch_and_bound_equals_the_exhaustive_pass() {
    // A grid of 2^22 cells or more at a step of 0.5 lambda / (2 L) or finer: `Search::Auto` takes the
    // branch-and-bound there, so the batch's cell must match the exhaustive pass's.
    let mut rng = ChaCha8Rng::seed_from_u64(171);
    let b = vec![
        Vector3::new(0.71, 0.0, 0.0),
        Vector3::new(0.355, 0.0, 0.615),
    ];
    let step = 0.2 * 0.18 / (2.0 * 0.71);
    assert!(Grid::full(step).unwrap().len() >= AUTO_MIN_CELLS);
    let epochs = batch(&mut rng, &b, 3, step);
    let body: Vec<[f64; 3]> = b.iter().map(|v| [v.x, v.y, v.z]).collect();
    let got = ml_attitude_series(&epochs, &body, Some(step), None).unwrap();
    check(&got, &reference(&epochs, &b, false, step, None), false, 0);
}

#[test]
fn baseline_series_equals_the_single_epoch_search() {
    let mut rng = ChaCha8Rng::seed_from_u64(172);
    for case in 0..12 {
        let len = rng.random_range(0.3..3.0);
        let b = [Vector3::new(len, 0.0, 0.0)];
        let step = rng.random_range(0.1..0.4) * 0.18 / (2.0 * len);
        // Roll about the single baseline (body X) leaves it in place: the batch's roll is harmless.
        let epochs = batch(&mut rng, &b, 6, step);
        for window in [None, Some(rng.random_range(2.0..6.0) * step)] {
            let got = ml_baseline_series(&epochs, len, Some(step), window).unwrap();
            check(
                &got,
                &reference(&epochs, &b, true, step, window),
                true,
                case,
            );
        }
    }
}

#[test]
fn series_recovers_the_truth() {
    // Noise-free phases, default step (eq. (15)): the refined angles are the truth (to the Newton
    // polish's tolerance), and the baseline direction is that of the rotated first baseline.
    let mut rng = ChaCha8Rng::seed_from_u64(173);
    let b = vec![Vector3::new(0.5, 0.0, 0.0), Vector3::new(0.0, 0.0, 0.4)];
    let body: Vec<[f64; 3]> = b.iter().map(|v| [v.x, v.y, v.z]).collect();
    let truths = [[0.4, 0.1, -0.2], [0.42, 0.11, -0.19], [0.45, 0.1, -0.17]];
    let epochs: Vec<MlEpoch> = truths
        .iter()
        .map(|t| {
            let los = sky(&mut rng, 8);
            ml_epoch(&mut rng, &b, &los, &[0.19; 8], *t, 0.0)
        })
        .collect();
    for window in [None, Some(0.1)] {
        let got = ml_attitude_series(&epochs, &body, None, window).unwrap();
        for (g, t) in got.iter().zip(&truths) {
            for (a, x) in g.euler_gost_rad.iter().zip(t) {
                assert!((a - x).abs() < 1e-7, "{:?} vs {t:?}", g.euler_gost_rad);
            }
            // The grid cell lies within sqrt(3) / 2 steps of the truth: each phase is off by at most
            // 2 pi L / lambda x sqrt(3) lambda / (20 L) = 0.54 rad, so each of the 16 terms is >= cos 0.54.
            assert!(
                g.value <= 16.0 + 1e-4 && g.value >= 16.0 * 0.54f64.cos(),
                "{}",
                g.value
            );
            let v = dcm_enu_from_body(t[0], t[1], t[2]) * b[0];
            let az = v.x.atan2(v.y).rem_euclid(TAU);
            assert!((g.direction_rad[0] - az).abs() < 1e-7);
            assert!((g.direction_rad[1] - (v.z / v.norm()).asin()).abs() < 1e-7);
        }
    }
    // Baseline mode: heading 30 deg east of north (psi = -30 deg), elevation 10 deg.
    let (psi, theta) = (-30f64.to_radians(), 10f64.to_radians());
    let one = [Vector3::new(1.5, 0.0, 0.0)];
    let los = sky(&mut rng, 7);
    let e = ml_epoch(&mut rng, &one, &los, &[0.19; 7], [psi, theta, 0.0], 0.0);
    let got = ml_baseline_series(&[e], 1.5, None, None).unwrap();
    assert!((got[0].direction_rad[0] - 30f64.to_radians()).abs() < 1e-7);
    assert!((got[0].direction_rad[1] - theta).abs() < 1e-7);
}

#[test]
fn bad_input_is_rejected() {
    let mut rng = ChaCha8Rng::seed_from_u64(174);
    let b = vec![Vector3::new(0.5, 0.0, 0.0), Vector3::new(0.0, 0.0, 0.4)];
    let body = [[0.5, 0.0, 0.0], [0.0, 0.0, 0.4]];
    let los = sky(&mut rng, 6);
    let good = ml_epoch(&mut rng, &b, &los, &[0.19; 6], [0.0; 3], 0.0);
    let step = Some(0.05);
    let one = std::slice::from_ref(&good);
    assert_eq!(ml_attitude_series(&[], &body, step, None), Ok(vec![]));
    let mut short = good.clone();
    short.sd_phase_rad.pop();
    let err = ml_attitude_series(&[good.clone(), short], &body, step, None);
    assert!(matches!(err, Err(Error::Shape { ref expected, .. }) if expected.contains("epoch 1")));
    let mut inf = good.clone();
    inf.sd_phase_rad[3] = f64::INFINITY;
    let err = ml_attitude_series(&[inf], &body, step, None);
    assert!(
        matches!(err, Err(Error::OutOfRange { name: "sd_phase_rad", ref detail })
            if detail.contains("epoch 0") && detail.contains("(0, 3)")),
        "{err:?}"
    );
    let mut bad_los = good.clone();
    bad_los.los_enu[0] = [0.0, 0.0, 2.0];
    let err = ml_attitude_series(&[good.clone(), bad_los], &body, step, None);
    assert!(
        matches!(err, Err(Error::OutOfRange { name: "los", ref detail }) if detail.contains("epoch 1"))
    );
    for s in [0.0, -1.0, f64::NAN, 4.0] {
        let err = ml_attitude_series(one, &body, Some(s), None);
        assert!(
            matches!(
                err,
                Err(Error::OutOfRange {
                    name: "step_deg",
                    ..
                })
            ),
            "{s}"
        );
    }
    for w in [0.0, f64::INFINITY, 7.0] {
        let err = ml_attitude_series(one, &body, step, Some(w));
        assert!(
            matches!(
                err,
                Err(Error::OutOfRange {
                    name: "window_deg",
                    ..
                })
            ),
            "{w}"
        );
    }
    // A window narrower than the step could hold no node: refused at the first windowed epoch.
    let err = ml_attitude_series(&[good.clone(), good.clone()], &body, step, Some(0.01));
    assert!(
        matches!(err, Err(Error::OutOfRange { name: "window_deg", ref detail }) if detail.contains("epoch 1"))
    );
    // Coarser than half the main lobe (0.19 / (2 x 0.5) = 0.19 rad).
    let err = ml_attitude_series(one, &body, Some(0.3), None);
    assert!(matches!(err, Err(Error::OutOfRange { .. })));
    let err = ml_attitude_series(one, &[[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]], step, None);
    assert!(matches!(err, Err(Error::DegenerateGeometry { .. })));
    for len in [0.0, -1.0, f64::NAN] {
        let err = ml_baseline_series(one, len, step, None);
        assert!(matches!(
            err,
            Err(Error::OutOfRange {
                name: "baseline_length_m",
                ..
            })
        ));
    }
}

#[test]
fn a_batch_over_the_work_limit_is_refused_before_any_search() {
    use crate::likelihood::{series_work, MAX_SERIES_WORK};
    // 1 m triangle, 6 signals, step 3 deg: an exhaustive pass over 120 x 61 x 120 cells an epoch.
    let per_epoch = series_work(1, 2, 6, Some(3f64.to_radians()), 0.19, 1.0, None, false);
    assert_eq!(per_epoch, ((120 * 61 * 120 + 8192) * 12) as f64);
    let n = (MAX_SERIES_WORK / per_epoch) as usize + 1;
    let epoch = MlEpoch {
        sd_phase_rad: vec![0.0; 12],
        los_enu: vec![
            [0.0, 0.6, 0.8],
            [0.6, 0.0, 0.8],
            [0.0, 0.0, 1.0],
            [0.8, 0.0, 0.6],
            [0.0, 0.8, 0.6],
            [-0.6, 0.0, 0.8],
        ],
        wavelength_m: vec![0.19; 6],
    };
    let epochs = vec![epoch; n];
    let b = [[1.0, 0.0, 0.0], [0.5, 0.0, 0.866_025_403_784_438_6]];
    match ml_attitude_series(&epochs, &b, Some(3f64.to_radians()), None) {
        Err(Error::TooLarge {
            name,
            requested,
            limit,
            ..
        }) => {
            assert_eq!(name, "sd_phase");
            assert_eq!(limit, MAX_SERIES_WORK);
            assert_eq!(requested, n as f64 * per_epoch);
        }
        other => panic!("expected TooLarge, got {other:?}"),
    }
}
