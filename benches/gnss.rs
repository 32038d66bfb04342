//! Criterion benchmarks of the RTK engine (`gnssatt_core::gnss::rtk`), one epoch per call:
//! - `rtk`: 44 double differences (GPS 8, GLONASS 6, Galileo 6, BeiDou 6 satellites, two slots each),
//!   float solution and LAMBDA fix with the gate (`solve_baseline`), and the attitude mode with two rovers;
//! - `rtk_87dd`: the size of a real all-systems, three-frequency session (GPS 9, GLONASS 7, Galileo 8,
//!   BeiDou 8, QZSS 2 satellites, three slots each: 87 DDs) with the engine's default gate, and its parts:
//!   the float solution, the decorrelation ([`Problem::new`]), the two-candidate search and partial fixing.
//!
//! Epochs are synthetic (seeded): satellites in random directions above 15 degrees at GPS-like ranges,
//! a 1 m baseline, integer ambiguities and Gaussian noise with the model's elevation sigmas.
use criterion::{criterion_group, criterion_main, Criterion};
use gnssatt_core::gnss::geometry::SatGeometry;
use gnssatt_core::gnss::rtk::{
    float, solve_attitude, solve_baseline, DdEpoch, FixOptions, SignalPair,
};
use gnssatt_core::gnss::signal::{carrier_frequency_hz, System, SPEED_OF_LIGHT_M_S};
use gnssatt_core::lambda::validation::{partial_fix, RatioThreshold};
use gnssatt_core::lambda::{Problem, DEFAULT_MAX_NODES};
use nalgebra::{DMatrix, DVector, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const GATE: FixOptions = FixOptions {
    min_success_rate: 0.999,
    ratio_threshold: 3.0,
    max_failure_rate: 0.0,
};

/// The engine's default gate (`gnss::options`).
const DEFAULT_GATE: FixOptions = FixOptions {
    min_success_rate: 0.5,
    ratio_threshold: 3.0,
    max_failure_rate: 0.0,
};

/// Satellites per system of the 44-DD epochs (two slots).
const FOUR_SYSTEMS: [(System, usize); 4] = [
    (System::Gps, 8),
    (System::Glonass, 6),
    (System::Galileo, 6),
    (System::BeiDou, 6),
];

/// Satellites per system of the 87-DD epochs (three slots): 3 x (8 + 6 + 7 + 7 + 1) = 87.
const FIVE_SYSTEMS: [(System, usize); 5] = [
    (System::Gps, 9),
    (System::Glonass, 7),
    (System::Galileo, 8),
    (System::BeiDou, 8),
    (System::Qzss, 2),
];

fn normal(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// Satellite positions (ECEF), systems and GLONASS channels above 15 degrees at a base on the equator
/// (local up = +X, so directions are drawn in that frame directly).
fn satellites(
    rng: &mut ChaCha8Rng,
    base: &Vector3<f64>,
    constellation: &[(System, usize)],
) -> Vec<(Vector3<f64>, System, Option<i8>, f64)> {
    let mut out = Vec::new();
    let mut channel = -7i8;
    for &(system, n) in constellation {
        for _ in 0..n {
            let az = rng.random::<f64>() * std::f64::consts::TAU;
            let smin = 15f64.to_radians().sin();
            let el = (smin + (1.0 - smin) * rng.random::<f64>()).asin();
            let u = Vector3::new(el.sin(), el.cos() * az.sin(), el.cos() * az.cos());
            let r = 26_560e3;
            let bu = base.dot(&u);
            let rho = -bu + (bu * bu - base.norm_squared() + r * r).sqrt();
            let ch = (system == System::Glonass).then(|| {
                // Odd channels -5..5 first, then even ones, all within -7..=6.
                channel = if channel + 2 > 6 {
                    channel - 11
                } else {
                    channel + 2
                };
                channel
            });
            out.push((base + rho * u, system, ch, el));
        }
    }
    out
}

/// One epoch of `constellation` observed on the first `slots` frequency slots.
fn epoch_of(
    rng: &mut ChaCha8Rng,
    baseline: &Vector3<f64>,
    constellation: &[(System, usize)],
    slots: usize,
) -> DdEpoch {
    let base = Vector3::new(6_378_137.0, 0.0, 0.0);
    let rover = base + baseline;
    let mut signals = Vec::new();
    for (i, (pos, system, ch, el)) in satellites(rng, &base, constellation)
        .into_iter()
        .enumerate()
    {
        for slot in 0..slots {
            let lam = SPEED_OF_LIGHT_M_S / carrier_frequency_hz(system, slot, ch).unwrap_or(1.0);
            let sp = 0.003 * (1.0 + 1.0 / el.sin().powi(2)).sqrt();
            let sc = 100.0 * sp;
            let geometry = |rx: &Vector3<f64>| SatGeometry {
                position_m: pos,
                clock_s: 0.0,
                range_m: (pos - rx).norm(),
                los_ecef: (pos - rx).normalize(),
                elevation_rad: el,
                azimuth_rad: 0.0,
            };
            let (rb, rr) = ((pos - base).norm(), (pos - rover).norm());
            let (nb, nr) = (
                rng.random_range(-1000..1000) as f64,
                rng.random_range(-1000..1000) as f64,
            );
            signals.push(SignalPair {
                sat: i,
                system,
                slot,
                wavelength_m: lam,
                base: geometry(&base),
                rover: geometry(&rover),
                base_code_m: rb + sc * normal(rng),
                rover_code_m: rr + sc * normal(rng),
                base_phase_cycles: (rb + sp * normal(rng)) / lam + nb,
                rover_phase_cycles: (rr + sp * normal(rng)) / lam + nr,
                sigma_code_m: sc,
                sigma_phase_m: sp,
                arc: (3 * i + slot) as u64,
            });
        }
    }
    DdEpoch {
        base_m: base,
        rover_prior_m: rover + Vector3::new(1.5, -2.0, 1.0),
        signals,
    }
}

fn epoch(rng: &mut ChaCha8Rng, baseline: &Vector3<f64>) -> DdEpoch {
    epoch_of(rng, baseline, &FOUR_SYSTEMS, 2)
}

/// The float ambiguities (cycles) and their symmetrised covariance (cycles^2) of one epoch.
fn float_ambiguities(e: &DdEpoch) -> (DVector<f64>, DMatrix<f64>) {
    let fl = float::solve(std::slice::from_ref(e), &[]).unwrap();
    let na = fl.ambiguities.len();
    let q = fl.covariance.view((3, 3), (na, na)).into_owned();
    (fl.ambiguities_cycles, (&q + q.transpose()) * 0.5)
}

/// `rtk_87dd`: the whole epoch and its parts at the size of a GRECJ three-frequency session.
fn bench_87dd(c: &mut Criterion) {
    let mut rng = ChaCha8Rng::seed_from_u64(87);
    let epochs: Vec<DdEpoch> = (0..32)
        .map(|_| epoch_of(&mut rng, &Vector3::new(0.6, -0.7, 0.38), &FIVE_SYSTEMS, 3))
        .collect();
    let solved: Vec<_> = epochs
        .iter()
        .map(|e| solve_baseline(std::slice::from_ref(e), &[], &DEFAULT_GATE).unwrap())
        .collect();
    let fixed = solved.iter().filter(|s| s.fixed).count();
    let partial = solved
        .iter()
        .filter(|s| !s.fixed && s.fixed_ambiguities > 0)
        .count();
    println!(
        "rtk_87dd bench: {fixed}/{} epochs fixed, {partial} partially, {} DDs each",
        epochs.len(),
        solved[0].ambiguities
    );
    let floats: Vec<_> = epochs.iter().map(float_ambiguities).collect();
    let problems: Vec<Problem> = floats
        .iter()
        .map(|(a, q)| Problem::new(a, q).unwrap())
        .collect();
    let mut g = c.benchmark_group("rtk_87dd");
    let mut i = 0;
    let mut next = || {
        i = (i + 1) % epochs.len();
        i
    };
    g.bench_function("solve_baseline", |b| {
        b.iter(|| {
            let k = next();
            solve_baseline(std::slice::from_ref(&epochs[k]), &[], &DEFAULT_GATE).unwrap()
        })
    });
    g.bench_function("float", |b| {
        b.iter(|| float::solve(std::slice::from_ref(&epochs[next()]), &[]).unwrap())
    });
    g.bench_function("problem_new", |b| {
        b.iter(|| {
            let (a, q) = &floats[next()];
            Problem::new(a, q).unwrap()
        })
    });
    g.bench_function("search_2", |b| {
        b.iter(|| problems[next()].solve(2, DEFAULT_MAX_NODES).unwrap())
    });
    // Partial fixing with a gate the full sets pass: the cost of one pass over the subsets.
    g.bench_function("partial_fix", |b| {
        b.iter(|| {
            let (a, q) = &floats[next()];
            partial_fix(a, q, RatioThreshold::Fixed(3.0), 0.5).unwrap()
        })
    });
    g.finish();
}

fn bench(c: &mut Criterion) {
    let mut rng = ChaCha8Rng::seed_from_u64(16);
    let epochs: Vec<DdEpoch> = (0..32)
        .map(|_| epoch(&mut rng, &Vector3::new(0.6, -0.7, 0.38)))
        .collect();
    let fixed = epochs
        .iter()
        .filter(|e| {
            solve_baseline(std::slice::from_ref(e), &[], &GATE)
                .unwrap()
                .fixed
        })
        .count();
    println!(
        "rtk bench: {fixed}/{} epochs fixed, 44 DDs each",
        epochs.len()
    );
    let mut g = c.benchmark_group("rtk");
    let mut i = 0;
    g.bench_function("solve_baseline_44dd", |b| {
        b.iter(|| {
            i = (i + 1) % epochs.len();
            solve_baseline(std::slice::from_ref(&epochs[i]), &[], &GATE).unwrap()
        })
    });
    g.bench_function("float_44dd", |b| {
        b.iter(|| {
            i = (i + 1) % epochs.len();
            gnssatt_core::gnss::rtk::float::solve(std::slice::from_ref(&epochs[i]), &[]).unwrap()
        })
    });
    let rovers: Vec<[DdEpoch; 2]> = (0..8)
        .map(|_| {
            [
                epoch(&mut rng, &Vector3::new(0.0, 1.2, 0.0)),
                epoch(&mut rng, &Vector3::new(0.0, 0.0, 0.9)),
            ]
        })
        .collect();
    let body = [[1.2, 0.0, 0.0], [0.0, 0.0, 0.9]];
    let mut j = 0;
    g.bench_function("solve_attitude_2x44dd", |b| {
        b.iter(|| {
            j = (j + 1) % rovers.len();
            solve_attitude(&rovers[j], &body, &GATE).unwrap()
        })
    });
    g.finish();
}

criterion_group!(benches, bench, bench_87dd);
criterion_main!(benches);
