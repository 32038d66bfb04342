//! Criterion benchmarks of the seed-001 likelihood grid: exhaustive maximum over grid size, satellites and
//! threads; branch-and-bound; and the per-node-vector variant of eq. (19) that the row kernel replaces.
use std::f64::consts::TAU;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use gnssatt_core::likelihood::{
    branch_and_bound, dcm_enu_from_body, exhaustive_max, Epoch, Grid, Model, Statistic,
};
use nalgebra::Vector3;

const L1: f64 = 0.190_293_672_798_364_9;

fn scenario(m: usize) -> Model {
    let l = 0.71;
    let b = vec![
        Vector3::new(l, 0.0, 0.0),
        Vector3::new(l / 2.0, 0.0, l * 3f64.sqrt() / 2.0),
    ];
    let los: Vec<Vector3<f64>> = (0..m)
        .map(|k| {
            let az = k as f64 * 2.4;
            let el = 0.25 + 1.2 * ((k * 7 % 11) as f64 / 11.0);
            Vector3::new(az.sin() * el.cos(), az.cos() * el.cos(), el.sin())
        })
        .collect();
    let r = dcm_enu_from_body(0.7, 0.1, -0.2);
    let phase_diffs = b
        .iter()
        .map(|bi| {
            los.iter()
                .map(|s| (-TAU / L1 * s.dot(&(r * bi))).rem_euclid(TAU))
                .collect()
        })
        .collect();
    let e = Epoch {
        phase_diffs,
        los_enu: los,
        wavelengths: vec![L1; m],
    };
    Model::new(&b, &[e], Statistic::AmbiguityFunction).unwrap()
}

fn exhaustive(c: &mut Criterion) {
    let mut group = c.benchmark_group("likelihood/exhaustive");
    group.sample_size(10);
    for step in [3.0f64, 1.5] {
        let grid = Grid::full(step.to_radians()).unwrap();
        for m in [4usize, 8, 12] {
            let model = scenario(m);
            let id = BenchmarkId::new(format!("step{step}deg"), format!("M{m}"));
            group.bench_with_input(id, &m, |b, _| {
                b.iter(|| exhaustive_max(&model, &grid).unwrap())
            });
        }
    }
    let grid = Grid::full(1.5f64.to_radians()).unwrap();
    let model = scenario(8);
    for threads in [1usize, 2, 16] {
        if threads > std::thread::available_parallelism().map_or(1, |n| n.get()) {
            continue;
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let id = BenchmarkId::new("step1.5deg_M8", format!("threads{threads}"));
        group.bench_with_input(id, &threads, |b, _| {
            b.iter(|| pool.install(|| exhaustive_max(&model, &grid).unwrap()))
        });
    }
    group.finish();
}

fn bnb(c: &mut Criterion) {
    let mut group = c.benchmark_group("likelihood/branch_and_bound");
    group.sample_size(10);
    for step in [3.0f64, 1.5] {
        let grid = Grid::full(step.to_radians()).unwrap();
        let model = scenario(8);
        let id = BenchmarkId::new(format!("step{step}deg"), "M8");
        group.bench_with_input(id, &step, |b, _| {
            b.iter(|| branch_and_bound(&model, &grid).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, exhaustive, bnb);
criterion_main!(benches);
