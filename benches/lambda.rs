//! Criterion benchmarks of LAMBDA on float solutions of a realistic geometry (`lambda_geometry.rs`):
//! n = 6, 10 (one frequency) and 20, 40 (two frequencies) DD ambiguities. Each timed call cycles through
//! 64 seeded float vectors, so search times average over typical draws. The mean number of search nodes
//! visited is printed per n and written to `target/criterion/lambda_nodes.csv`.
use std::fmt::Write as _;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use gnssatt_core::lambda::validation::{partial_fix, ratio_test, RatioThreshold};
use gnssatt_core::lambda::{
    bootstrap_success_rate, ils, ldl::ltdl, reduce, search, Problem, DEFAULT_MAX_NODES,
};
use nalgebra::{DMatrix, DVector};

mod lambda_geometry;
use lambda_geometry::Geometry;

const SIZES: [usize; 4] = [6, 10, 20, 40];
const DRAWS: usize = 64;

fn setting(n: usize) -> (DMatrix<f64>, Vec<DVector<f64>>) {
    let g = Geometry::for_ambiguities(n);
    let q = g.float_covariance();
    let draws = g.float_draws(&q, DRAWS, 42 + n as u64);
    (q, draws)
}

fn cycle<'a>(draws: &'a [DVector<f64>], i: &mut usize) -> &'a DVector<f64> {
    *i = (*i + 1) % draws.len();
    &draws[*i]
}

fn record_nodes() {
    let mut csv = String::from("n,mean_nodes,max_nodes,bootstrap_success_rate\n");
    for n in SIZES {
        let (q, draws) = setting(n);
        let nodes: Vec<u64> = draws
            .iter()
            .map(|a| ils(a, &q, 2).unwrap().nodes_visited)
            .collect();
        let mean = nodes.iter().sum::<u64>() as f64 / nodes.len() as f64;
        let max = nodes.iter().max().copied().unwrap_or(0);
        let ps = bootstrap_success_rate(&q).unwrap();
        println!(
            "lambda/search n={n}: mean {mean:.1} nodes, max {max} (2 candidates), P_boot = {ps:.6}"
        );
        writeln!(csv, "{n},{mean:.1},{max},{ps:.6}").unwrap();
    }
    // Benches run in the package folder; the workspace target folder is two levels up.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/criterion");
    let _ = std::fs::create_dir_all(&dir)
        .and_then(|_| std::fs::write(dir.join("lambda_nodes.csv"), csv));
}

fn bench(c: &mut Criterion) {
    record_nodes();
    let settings: Vec<_> = SIZES.iter().map(|&n| (n, setting(n))).collect();

    let mut group = c.benchmark_group("lambda/ldl");
    for (n, (q, _)) in &settings {
        group.bench_with_input(BenchmarkId::from_parameter(n), q, |b, q| {
            b.iter(|| ltdl(q).unwrap())
        });
    }
    group.finish();

    let mut group = c.benchmark_group("lambda/reduce");
    for (n, (q, _)) in &settings {
        group.bench_with_input(BenchmarkId::from_parameter(n), q, |b, q| {
            b.iter(|| reduce(q).unwrap())
        });
    }
    group.finish();

    let mut group = c.benchmark_group("lambda/search");
    for (n, (q, draws)) in &settings {
        let problems: Vec<Problem> = draws.iter().map(|a| Problem::new(a, q).unwrap()).collect();
        let mut i = 0;
        group.bench_function(BenchmarkId::from_parameter(n), |b| {
            b.iter(|| {
                i = (i + 1) % problems.len();
                let p = &problems[i];
                search(&p.reduction.factor, &p.zhat, 2, DEFAULT_MAX_NODES).unwrap()
            })
        });
    }
    group.finish();

    let mut group = c.benchmark_group("lambda/ils");
    for (n, (q, draws)) in &settings {
        let mut i = 0;
        group.bench_function(BenchmarkId::from_parameter(n), |b| {
            b.iter(|| ils(cycle(draws, &mut i), q, 2).unwrap())
        });
    }
    group.finish();

    let mut group = c.benchmark_group("lambda/bootstrap_success_rate");
    for (n, (q, _)) in &settings {
        group.bench_with_input(BenchmarkId::from_parameter(n), q, |b, q| {
            b.iter(|| bootstrap_success_rate(q).unwrap())
        });
    }
    group.finish();

    let mut group = c.benchmark_group("lambda/ratio_test");
    for (n, (q, draws)) in &settings {
        let mut i = 0;
        group.bench_function(BenchmarkId::from_parameter(n), |b| {
            b.iter(|| ratio_test(cycle(draws, &mut i), q, RatioThreshold::Fixed(3.0)).unwrap())
        });
    }
    group.finish();

    let mut group = c.benchmark_group("lambda/partial_fix");
    for (n, (q, draws)) in &settings {
        let mut i = 0;
        group.bench_function(BenchmarkId::from_parameter(n), |b| {
            b.iter(|| {
                partial_fix(cycle(draws, &mut i), q, RatioThreshold::Fixed(3.0), 0.99).unwrap()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
