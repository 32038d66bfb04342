//! Criterion benchmarks of the Bunyaeva et al. likelihood grid: exhaustive maximum over grid size, satellites
//! and threads; branch-and-bound against the exhaustive pass (`likelihood/bnb_vs_grid`, which also prints the
//! ratio of medians per scenario and thread count; on the 5 m triangle at eq. (15)'s step the exhaustive
//! pass runs once, in two halves, for about 15-30 s per thread count).
//!
//! `cargo bench -p gnssatt-core --bench likelihood -- bnb_vs_grid`
use std::f64::consts::{FRAC_PI_2, TAU};

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use gnssatt_core::likelihood::{
    branch_and_bound, dcm_enu_from_body, exhaustive_max, Epoch, Grid, Model, Statistic,
};
use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const L1: f64 = 0.190_293_672_798_364_9;

/// The bench's attitude (psi, theta, phi), radians.
const ATTITUDE: [f64; 3] = [0.7, 0.1, -0.2];

fn scenario(m: usize) -> Model {
    scenario_sized(0.71, m, 0.0, ATTITUDE)
}

/// The equilateral triangle of side `l` metres, wrapped phases at attitude `euler` (radians) with
/// uniform noise of standard deviation `noise` rad (fixed seed).
fn scenario_sized(l: f64, m: usize, noise: f64, euler: [f64; 3]) -> Model {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
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
    let r = dcm_enu_from_body(euler[0], euler[1], euler[2]);
    let phase_diffs = b
        .iter()
        .map(|bi| {
            los.iter()
                .map(|s| {
                    let n = noise * 3f64.sqrt() * rng.random_range(-1.0..1.0);
                    (-TAU / L1 * s.dot(&(r * bi)) + n).rem_euclid(TAU)
                })
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

/// Rayon pools of 1, 2 and 16 threads, those the machine has.
fn pools() -> Vec<(usize, rayon::ThreadPool)> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    [1usize, 2, 16]
        .into_iter()
        .filter(|&t| t <= cores)
        .map(|t| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .unwrap();
            (t, pool)
        })
        .collect()
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
    for (threads, pool) in pools() {
        let id = BenchmarkId::new("step1.5deg_M8", format!("threads{threads}"));
        group.bench_with_input(id, &threads, |b, _| {
            b.iter(|| pool.install(|| exhaustive_max(&model, &grid).unwrap()))
        });
    }
    group.finish();
}

fn median_ms(mut f: impl FnMut(), reps: usize) -> f64 {
    let mut t: Vec<f64> = (0..reps)
        .map(|_| {
            let s = std::time::Instant::now();
            f();
            s.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[reps / 2]
}

fn bnb_vs_grid(c: &mut Criterion) {
    let mut group = c.benchmark_group("likelihood/bnb_vs_grid");
    group.sample_size(10);
    // The paper's 0.71 m triangle at 1.5 deg (7.0e6 cells), and a 5 m triangle at 0.45 deg (2.6e8 cells,
    // a coarse grid for it: 0.41 of the coarsest accepted step, issue 30's case) and, below, at eq.
    // (15)'s step; 0.1 rad phase noise. At 0.45 deg the bench's attitude ends in one round (grid
    // maximum 0.9 % below m n); a second attitude on the same sky needs two (2.1 % below), as about
    // half of random skies do.
    let cases = [
        ("paper_0.71m_1.5deg", 0.71, 1.5, ATTITUDE),
        ("5m_0.45deg", 5.0, 0.45, ATTITUDE),
        ("5m_0.45deg_two_rounds", 5.0, 0.45, [4.0, -0.2, 0.1]),
    ];
    let mut ratios = vec![];
    for (name, l, step, euler) in cases {
        let model = scenario_sized(l, 8, 0.1, euler);
        let grid = Grid::full(f64::to_radians(step)).unwrap();
        for (threads, pool) in pools() {
            let ex = pool.install(|| exhaustive_max(&model, &grid).unwrap());
            let (bb, stats) = pool.install(|| branch_and_bound(&model, &grid).unwrap());
            assert_eq!(
                (ex.index, ex.z),
                (bb.index, bb.z),
                "{name}: not the grid maximum"
            );
            let id = format!("threads{threads}");
            group.bench_with_input(
                BenchmarkId::new(format!("{name}/exhaustive"), &id),
                &(),
                |b, _| b.iter(|| pool.install(|| exhaustive_max(&model, &grid).unwrap())),
            );
            group.bench_with_input(BenchmarkId::new(format!("{name}/bnb"), &id), &(), |b, _| {
                b.iter(|| pool.install(|| branch_and_bound(&model, &grid).unwrap()))
            });
            let reps = if grid.len() > 50_000_000 { 3 } else { 11 };
            let te = median_ms(
                || drop(pool.install(|| exhaustive_max(&model, &grid))),
                reps,
            );
            let tb = median_ms(
                || drop(pool.install(|| branch_and_bound(&model, &grid))),
                reps,
            );
            ratios.push(format!(
                "{name} threads {threads}: exhaustive {te:.2} ms, branch-and-bound {tb:.2} ms, ratio \
                 {:.1}x ({} boxes, {} kernel cells of {}, {} rounds, fallback {})",
                te / tb,
                stats.boxes_bounded,
                stats.leaf_cells,
                grid.len(),
                stats.rounds,
                stats.fallback
            ));
        }
    }
    // The 5 m triangle at eq. (15)'s step (2.3e9 cells: over the 2^31 the exhaustive pass takes in one
    // call): the exhaustive pass runs as two windows of half the pitch range each (heading and roll
    // whole turns; together every cell once), timed once per thread count (15-30 s).
    let model = scenario_sized(5.0, 8, 0.1, ATTITUDE);
    let step = model.default_step();
    let grid = Grid::full(step).unwrap();
    let mid = -FRAC_PI_2 + (grid.psi.len / 4) as f64 * grid.step() + 0.5 * grid.step();
    let halves = [(-FRAC_PI_2, mid), (mid, FRAC_PI_2)]
        .map(|theta| Grid::window(step, [(-1.0, 7.0), theta, (-4.0, 4.0)]).unwrap());
    assert_eq!(halves.iter().map(Grid::len).sum::<usize>(), grid.len());
    for (threads, pool) in pools() {
        let t = std::time::Instant::now();
        let ex = halves
            .iter()
            .map(|h| {
                let gm = pool.install(|| exhaustive_max(&model, h).unwrap());
                (gm.z, h.angles(gm.index.map(|i| i as i64)))
            })
            // Equal values: the lower pitch comes first in the whole grid's order, as here.
            .reduce(|a, b| if b.0 > a.0 { b } else { a })
            .unwrap();
        let te = t.elapsed().as_secs_f64() * 1e3;
        let (bb, stats) = pool.install(|| branch_and_bound(&model, &grid).unwrap());
        assert_eq!(
            ex,
            (bb.z, grid.angles(bb.index.map(|i| i as i64))),
            "5 m at eq. (15)'s step: not the grid maximum"
        );
        let id = format!("threads{threads}");
        group.bench_with_input(BenchmarkId::new("5m_eq15/bnb", &id), &(), |b, _| {
            b.iter(|| pool.install(|| branch_and_bound(&model, &grid).unwrap()))
        });
        let tb = median_ms(
            || drop(pool.install(|| branch_and_bound(&model, &grid))),
            11,
        );
        ratios.push(format!(
            "5m_eq15 ({:.3} deg) threads {threads}: exhaustive in two halves {te:.0} ms (once), \
             branch-and-bound {tb:.2} ms, ratio {:.1}x ({} units of work, {} kernel cells of {}, \
             {} rounds)",
            step.to_degrees(),
            te / tb,
            stats.boxes_bounded,
            stats.leaf_cells,
            grid.len(),
            stats.rounds
        ));
    }
    group.finish();
    for r in ratios {
        println!("{r}");
    }
}

criterion_group!(benches, exhaustive, bnb_vs_grid);
criterion_main!(benches);
