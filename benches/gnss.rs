//! Criterion benchmarks of the RTK engine (`gnssatt_core::gnss::rtk`): one epoch with about 40 double
//! differences (GPS 8, GLONASS 6, Galileo 6, BeiDou 6 satellites, two slots each: 44 DDs), float
//! solution and LAMBDA fix with the gate (`solve_baseline`), and the attitude mode with two rovers.
//! Epochs are synthetic (seeded): satellites in random directions above 15 degrees at GPS-like ranges,
//! a 1 m baseline, integer ambiguities and Gaussian noise with the model's elevation sigmas.
use criterion::{criterion_group, criterion_main, Criterion};
use gnssatt_core::gnss::geometry::SatGeometry;
use gnssatt_core::gnss::rtk::{solve_attitude, solve_baseline, DdEpoch, FixOptions, SignalPair};
use gnssatt_core::gnss::signal::{carrier_frequency_hz, System, SPEED_OF_LIGHT_M_S};
use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const GATE: FixOptions = FixOptions {
    min_success_rate: 0.999,
    ratio_threshold: 3.0,
    max_failure_rate: 0.0,
};

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
) -> Vec<(Vector3<f64>, System, Option<i8>, f64)> {
    let mut out = Vec::new();
    let mut channel = -7i8;
    for (system, n) in [
        (System::Gps, 8),
        (System::Glonass, 6),
        (System::Galileo, 6),
        (System::BeiDou, 6),
    ] {
        for _ in 0..n {
            let az = rng.random::<f64>() * std::f64::consts::TAU;
            let smin = 15f64.to_radians().sin();
            let el = (smin + (1.0 - smin) * rng.random::<f64>()).asin();
            let u = Vector3::new(el.sin(), el.cos() * az.sin(), el.cos() * az.cos());
            let r = 26_560e3;
            let bu = base.dot(&u);
            let rho = -bu + (bu * bu - base.norm_squared() + r * r).sqrt();
            let ch = (system == System::Glonass).then(|| {
                channel += 2;
                channel
            });
            out.push((base + rho * u, system, ch, el));
        }
    }
    out
}

fn epoch(rng: &mut ChaCha8Rng, baseline: &Vector3<f64>) -> DdEpoch {
    let base = Vector3::new(6_378_137.0, 0.0, 0.0);
    let rover = base + baseline;
    let mut signals = Vec::new();
    for (i, (pos, system, ch, el)) in satellites(rng, &base).into_iter().enumerate() {
        for slot in [0usize, 1] {
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
                arc: (2 * i + slot) as u64,
            });
        }
    }
    DdEpoch {
        base_m: base,
        rover_prior_m: rover + Vector3::new(1.5, -2.0, 1.0),
        signals,
    }
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

criterion_group!(benches, bench);
criterion_main!(benches);
