//! Branch-and-bound time and work, one scenario per line: the paper's 0.71 m array at 1.5 deg and the
//! 5 m array at 0.5 deg on the `bnb_vs_grid` bench's sky, then the 5 m array on `N` random skies and
//! attitudes (8 satellites, 0.1 rad noise); medians of 3 at `RAYON_NUM_THREADS` threads (1 by default),
//! a sum at the end. `check` also runs the exhaustive pass once per scenario and prints the ratio and
//! whether the cell is the same; `eq15` uses eq. (15)'s default step instead (2.3e9 cells on the 5 m
//! array: not with `check`, which the exhaustive pass refuses there).
//!
//! `cargo run --release -p gnssatt-core --example bnb_skies -- [N] [check] [eq15] [step=DEG]` (`step`:
//! the 5 m array's coarse step, 0.5 deg by default)
use std::f64::consts::TAU;
use std::time::Instant;

use gnssatt_core::likelihood::{
    branch_and_bound, dcm_enu_from_body, exhaustive_max, Epoch, Grid, Model, Statistic,
};
use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const L1: f64 = 0.190_293_672_798_364_9;

fn model(
    l: f64,
    los: Vec<Vector3<f64>>,
    r: nalgebra::Matrix3<f64>,
    noise: f64,
    rng: &mut ChaCha8Rng,
) -> Model {
    let b = vec![
        Vector3::new(l, 0.0, 0.0),
        Vector3::new(l / 2.0, 0.0, l * 3f64.sqrt() / 2.0),
    ];
    let pd = b
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
    let m = los.len();
    Model::new(
        &b,
        &[Epoch {
            phase_diffs: pd,
            los_enu: los,
            wavelengths: vec![L1; m],
        }],
        Statistic::AmbiguityFunction,
    )
    .unwrap()
}

fn criterion_sky(l: f64) -> Model {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let los = (0..8)
        .map(|k| {
            let az = k as f64 * 2.4;
            let el = 0.25 + 1.2 * ((k * 7 % 11) as f64 / 11.0);
            Vector3::new(az.sin() * el.cos(), az.cos() * el.cos(), el.sin())
        })
        .collect();
    model(l, los, dcm_enu_from_body(0.7, 0.1, -0.2), 0.1, &mut rng)
}

fn random_sky(l: f64, seed: u64) -> Model {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let los = (0..8)
        .map(|_| {
            let az: f64 = rng.random_range(0.0..TAU);
            let el: f64 = rng.random_range(0.2..1.4);
            Vector3::new(az.sin() * el.cos(), az.cos() * el.cos(), el.sin())
        })
        .collect();
    let (y, p, r) = (
        rng.random_range(0.0..TAU),
        rng.random_range(-0.5..0.5),
        rng.random_range(-0.5..0.5),
    );
    model(l, los, dcm_enu_from_body(y, p, r), 0.1, &mut rng)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n_random: u64 = args.iter().find_map(|s| s.parse().ok()).unwrap_or(10);
    let check = args.iter().any(|s| s == "check");
    let eq15 = args.iter().any(|s| s == "eq15");
    let coarse: f64 = args
        .iter()
        .find_map(|s| s.strip_prefix("step=").and_then(|v| v.parse().ok()))
        .unwrap_or(0.5);
    let threads: usize = std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let mut cases: Vec<(String, Model, f64)> = vec![
        ("paper".into(), criterion_sky(0.71), 1.5),
        ("crit5m".into(), criterion_sky(5.0), coarse),
    ];
    for s in 0..n_random {
        cases.push((format!("rand5m_{s}"), random_sky(5.0, 100 + s), coarse));
    }
    let mut tot = 0.0;
    for (name, m, step) in &cases {
        let step = if eq15 {
            m.default_step().to_degrees()
        } else {
            *step
        };
        let grid = Grid::full(step.to_radians()).unwrap();
        let mut ts = vec![];
        let mut res = None;
        for _ in 0..3 {
            let t = Instant::now();
            let r = pool.install(|| branch_and_bound(m, &grid).unwrap());
            ts.push(t.elapsed().as_secs_f64() * 1e3);
            res = Some(r);
        }
        ts.sort_by(f64::total_cmp);
        let (gm, st) = res.unwrap();
        tot += ts[1];
        let mut line = format!(
            "{name:10} {step:.3} deg {:.2e} cells {:8.1} ms  boxes {:8} cells {:7} rounds {} fb {} z {:.4}",
            grid.len() as f64, ts[1], st.boxes_bounded, st.leaf_cells, st.rounds, st.fallback, gm.z
        );
        if check {
            let t = Instant::now();
            let ex = pool.install(|| exhaustive_max(m, &grid).unwrap());
            let te = t.elapsed().as_secs_f64() * 1e3;
            line += &format!(
                "  ex {te:.0} ms ratio {:.1} same {}",
                te / ts[1],
                (ex.index, ex.z) == (gm.index, gm.z)
            );
        }
        println!("{line}");
    }
    println!("total median bnb {tot:.1} ms");
}
