//! Criterion benchmarks of the Ryzhkov-Oliinyk matrix method.
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use gnssatt_core::matrix_method::{solve, Method};
use gnssatt_core::rotation::euler::ZYX;
use nalgebra::{DMatrix, Vector3};

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("matrix_method/solve");
    let s3 = 3f64.sqrt() / 2.0;
    let baselines = vec![Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.5, s3, 0.0)];
    let a = ZYX.to_dcm([3.0, 0.1, -0.2]).transpose();
    for n in [3usize, 8, 16] {
        let los: Vec<_> = (0..n)
            .map(|j| {
                let t = j as f64 * 2.4;
                Vector3::new(t.cos(), t.sin(), 0.5 + 0.05 * j as f64).normalize()
            })
            .collect();
        let r = DMatrix::from_fn(2, n, |i, j| baselines[i].dot(&(a * los[j])));
        group.bench_with_input(BenchmarkId::new("svd", n), &n, |bench, _| {
            bench.iter(|| solve(&baselines, &los, &r, Method::Svd).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
