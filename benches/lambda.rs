//! Criterion benchmarks of LAMBDA on float solutions of a realistic geometry (`lambda_geometry.rs`):
//! n = 6, 10 (one frequency) and 20, 40 (two frequencies) DD ambiguities. Each timed call cycles through
//! 64 seeded float vectors, so search times average over typical draws. The mean number of search nodes
//! visited is printed per n and written to `target/criterion/lambda_nodes.csv`.
//!
//! `lambda/vs_rtklib` times `ils` (two candidates) and the same problems through one reused
//! `Workspace` (`gnssatt_workspace`, the per-problem path of a batch) at every n from 4 to 40 on 32 draws
//! each; with
//! `RTKLIB_SRC` set to an RTKLIB 2.4.3 folder (e.g. `../shared/peers/rtklib-2.4.3`) it also times RTKLIB's C
//! `lambda()` on the same problems: `src/lambda.c` and `src/rtkcmn.c` are compiled with `cc -O3` into the
//! timing program `RTKLIB_HARNESS` (written here; RTKLIB's code is only compiled), which criterion runs
//! through `iter_custom` with the number of calls to time, and whose integers are checked against `ils`'s.
//! `RTKLIB_SRC=../shared/peers/rtklib-2.4.3 cargo bench --bench lambda -- vs_rtklib` runs only that group.
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use gnssatt_core::lambda::validation::{partial_fix, ratio_test, RatioThreshold};
use gnssatt_core::lambda::{
    bootstrap_success_rate, ils, ldl::ltdl, node_budget, reduce, search, Problem, Workspace,
    DEFAULT_MAX_NODES,
};
use nalgebra::{DMatrix, DVector};

mod lambda_geometry;
use lambda_geometry::Geometry;

const SIZES: [usize; 4] = [6, 10, 20, 40];
const DRAWS: usize = 64;
/// Draws per n of `lambda/vs_rtklib` (as `benches/python/lambda_rtklib.py --draws 32`).
const RTKLIB_DRAWS: usize = 32;

/// Our timing program around RTKLIB's `lambda()`: `harness FILE 0` prints the best integers of every
/// problem, `harness FILE CALLS` makes CALLS calls cycling through the problems and prints their wall
/// time in seconds (the clock criterion uses for the Rust side). FILE: n, k (int32), Q (n x n
/// column-major), then k float vectors (float64).
const RTKLIB_HARNESS: &str = r#"
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
int lambda(int n, int m, const double *a, const double *Q, double *F, double *s);
int main(int argc, char **argv) {
    FILE *f = fopen(argv[1], "rb"); long calls = atol(argv[2]); int n, k;
    if (!f || fread(&n, sizeof n, 1, f) != 1 || fread(&k, sizeof k, 1, f) != 1) return 2;
    double *Q = malloc(sizeof(double) * n * n), *a = malloc(sizeof(double) * n * k);
    double *F = malloc(sizeof(double) * n * 2), s[2];
    if (fread(Q, sizeof(double), n * n, f) != (size_t)(n * n)) return 2;
    if (fread(a, sizeof(double), n * k, f) != (size_t)(n * k)) return 2;
    if (calls == 0) {
        for (int i = 0; i < k; i++) {
            if (lambda(n, 2, a + n * i, Q, F, s)) return 3;
            for (int j = 0; j < n; j++) printf("%.0f ", F[j]);
            printf("\n");
        }
        return 0;
    }
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (long c = 0; c < calls; c++)
        if (lambda(n, 2, a + n * (c % k), Q, F, s)) return 3;
    clock_gettime(CLOCK_MONOTONIC, &t1);
    printf("%.9f\n", (t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec));
    return 0;
}
"#;

/// The covariance of `n` ambiguities as `benches/python/lambda_rtklib.py` builds it: one frequency up to
/// n = 10 and for odd n, two above.
fn rtklib_setting(n: usize) -> (DMatrix<f64>, Vec<DVector<f64>>) {
    let frequencies = if n > 10 && n.is_multiple_of(2) { 2 } else { 1 };
    let g = Geometry {
        satellites: n / frequencies + 1,
        frequencies,
        ..Geometry::for_ambiguities(4)
    };
    let q = g.float_covariance();
    let draws = g.float_draws(&q, RTKLIB_DRAWS, 42 + n as u64);
    (q, draws)
}

/// Compiles the RTKLIB harness from `src` into `dir`.
fn build_rtklib_harness(src: &Path, dir: &Path) -> PathBuf {
    std::fs::create_dir_all(dir).expect("harness folder");
    let c = dir.join("lambda_harness.c");
    std::fs::write(&c, RTKLIB_HARNESS).expect("harness source");
    let exe = dir.join("lambda_harness");
    let s = src.join("src");
    let status = Command::new("cc")
        .args([
            "-O3",
            "-std=gnu99",
            "-w",
            "-DENAGLO",
            "-DENAQZS",
            "-DENAGAL",
            "-DENACMP",
        ])
        .arg("-DNFREQ=3")
        .arg(format!("-I{}", s.display()))
        .arg("-o")
        .arg(&exe)
        .arg(&c)
        .arg(s.join("lambda.c"))
        .arg(s.join("rtkcmn.c"))
        .arg("-lm")
        .status()
        .expect("cc runs");
    assert!(status.success(), "compiling RTKLIB's lambda.c failed");
    exe
}

fn write_problems(path: &Path, q: &DMatrix<f64>, draws: &[DVector<f64>]) {
    let mut bytes = Vec::new();
    bytes.extend((q.nrows() as i32).to_le_bytes());
    bytes.extend((draws.len() as i32).to_le_bytes());
    for v in q.iter().chain(draws.iter().flat_map(|a| a.iter())) {
        bytes.extend(v.to_le_bytes());
    }
    std::fs::write(path, bytes).expect("problem file");
}

fn run_harness(exe: &Path, problems: &Path, calls: u64) -> String {
    let out = Command::new(exe)
        .arg(problems)
        .arg(calls.to_string())
        .output()
        .expect("harness runs");
    assert!(out.status.success(), "RTKLIB's lambda() failed");
    String::from_utf8(out.stdout).expect("utf-8")
}

fn bench_vs_rtklib(c: &mut Criterion) {
    let rtklib = std::env::var_os("RTKLIB_SRC").map(PathBuf::from);
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/criterion/lambda_rtklib");
    let exe = rtklib.as_deref().map(|src| build_rtklib_harness(src, &dir));
    if exe.is_none() {
        println!("lambda/vs_rtklib: RTKLIB_SRC not set, timing gnssatt only");
    }
    let mut group = c.benchmark_group("lambda/vs_rtklib");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    for n in 4..=40 {
        let (q, draws) = rtklib_setting(n);
        let mut i = 0;
        group.bench_function(BenchmarkId::new("gnssatt", n), |b| {
            b.iter(|| ils(cycle(&draws, &mut i), &q, 2).unwrap())
        });
        // The same problems through one reused workspace (what a batch does per problem): no allocation.
        let mut ws = Workspace::new();
        let (mut fixed, mut norms) = (vec![0i64; 2 * n], [0.0; 2]);
        group.bench_function(BenchmarkId::new("gnssatt_workspace", n), |b| {
            b.iter(|| {
                let a = cycle(&draws, &mut i).as_slice();
                ws.solve(a, &q, 2, node_budget(n), &mut fixed, &mut norms)
                    .unwrap()
            })
        });
        let Some(exe) = &exe else { continue };
        let problems = dir.join(format!("problems_{n}.bin"));
        write_problems(&problems, &q, &draws);
        // Both are exact ILS: the best integers must agree on every draw.
        let theirs = run_harness(exe, &problems, 0);
        for (d, (a, line)) in draws.iter().zip(theirs.lines()).enumerate() {
            let ours = ils(a, &q, 2).unwrap();
            let want: Vec<i64> = line
                .split_whitespace()
                .map(|v| v.parse().unwrap())
                .collect();
            assert_eq!(ours.fixed.column(0).as_slice(), want, "n = {n}, draw {d}");
        }
        group.bench_function(BenchmarkId::new("rtklib", n), |b| {
            b.iter_custom(|calls| {
                let s: f64 = run_harness(exe, &problems, calls).trim().parse().unwrap();
                Duration::from_secs_f64(s)
            })
        });
    }
    group.finish();
}

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

criterion_group!(benches, bench, bench_vs_rtklib);
criterion_main!(benches);
