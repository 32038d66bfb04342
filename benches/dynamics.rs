//! Criterion benchmarks of the Belokonov et al. rotational dynamics: one 1500 s propagation and the batch
//! objective.
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use gnssatt_core::dynamics::{axis_cost_batch, propagate_axes, Aerodynamics, State, TumbleModel};

fn model() -> TumbleModel {
    TumbleModel {
        inertia_kg_m2: [0.035, 0.008, 0.03],
        orbital_rate_rad_s: 1.1068e-3,
        gravity_gradient: true,
        aero: Aerodynamics {
            density_kg_m3: 5e-13,
            drag_coefficient: 2.2,
            area_m2: 0.03,
            cp_offset_m: [0.002, -0.01, 0.001],
            speed_m_s: 7612.6,
        },
    }
}

fn bench(c: &mut Criterion) {
    let m = model();
    let times: Vec<f64> = (0..1501).map(|k| k as f64).collect();
    let d = 1f64.to_radians();
    let mut group = c.benchmark_group("dynamics/propagate_axes");
    let s = State::from_angles([0.7, 1.1, -2.0], [1.8 * d, -1.5 * d, 1.6 * d]);
    group.bench_function("1500s_h1", |b| {
        b.iter(|| propagate_axes(&m, s, &times, 1.0).unwrap())
    });
    group.finish();

    let measured = propagate_axes(&m, s, &times, 1.0).unwrap();
    let mut group = c.benchmark_group("dynamics/axis_cost_batch");
    group.sample_size(10);
    for n in [1usize, 90] {
        let params: Vec<[f64; 6]> = (0..n)
            .map(|i| {
                let x = i as f64;
                [x * 0.1, 1.0 + 0.01 * x, -x * 0.2, d, -d, 0.5 * d]
            })
            .collect();
        group.bench_with_input(BenchmarkId::new("population", n), &n, |b, _| {
            b.iter(|| axis_cost_batch(&m, &params, &times, &measured, 1.0).unwrap())
        });
        // The fit's global search: 4.84 s steps (0.45 rad at the 3 deg/s box's corner), axes interpolated.
        group.bench_with_input(BenchmarkId::new("population_search_step", n), &n, |b, _| {
            b.iter(|| axis_cost_batch(&m, &params, &times, &measured, 4.84).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
