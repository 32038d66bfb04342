//! The exact search against brute force: every integer vector of a box around each rover's float
//! ambiguities, every combination whose norms alone do not already exceed what the box proves (a
//! combination's objective is at least the sum of its norms), the rotation from a textbook SVD. The
//! box covers the whole integer space for the best and second best when the second best is below the
//! box's bound: an integer outside the box is at least `r - 1/2` from the float in some coordinate `k`,
//! so its norm is at least `(r - 1/2)^2 / Q_kk`.

use nalgebra::{DMatrix, DVector, Matrix3, Vector3, SVD};
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::super::super::sim::{normal, random_rotation};
use super::{search, Ambiguities, List};
use crate::lambda::Problem;

/// A random rover: float ambiguities `a` (truth 0), covariance `q`, gain `k` (n x 3, m per cycle), float
/// baseline `b`, weight `1 / sigma^2`, body baseline `f`.
struct Rover {
    a: DVector<f64>,
    q: DMatrix<f64>,
    k: DMatrix<f64>,
    b: Vector3<f64>,
    weight: f64,
    f: Vector3<f64>,
}

/// Random covariance with ambiguity sigmas near `sigma_cycles`, gains of `gain_m` per cycle, a
/// conditioned baseline sigma `sigma_m`; the floats drawn from that covariance around the truth
/// (integers 0, baseline `rot f`).
fn random_rover(
    rng: &mut ChaCha8Rng,
    n: usize,
    sigma_cycles: f64,
    gain_m: f64,
    sigma_m: f64,
    rot: &Matrix3<f64>,
) -> Rover {
    let m = DMatrix::from_fn(n, n, |_, _| normal(rng) * sigma_cycles / (n as f64).sqrt());
    let q = &m * m.transpose() + DMatrix::identity(n, n) * (0.05 * sigma_cycles).powi(2);
    let k = DMatrix::from_fn(n, 3, |_, _| normal(rng) * gain_m);
    let f = Vector3::from_fn(|_, _| normal(rng)).normalize() * (0.8 + rng_unit(rng));
    let l = q.clone().cholesky().unwrap().l();
    let e_a = l * DVector::from_fn(n, |_, _| normal(rng));
    let e_b = Vector3::from_fn(|_, _| normal(rng) * sigma_m);
    let kb = k.tr_mul(&e_a);
    Rover {
        a: e_a,
        q,
        k,
        b: rot * f + Vector3::new(kb[0], kb[1], kb[2]) + e_b,
        weight: 1.0 / (sigma_m * sigma_m),
        f,
    }
}

fn rng_unit(rng: &mut ChaCha8Rng) -> f64 {
    use rand::Rng;
    rng.random::<f64>()
}

/// Every integer of the box of half width `r` around `round(a)`: `(z, norm, b(z))`, norm ascending,
/// and the box's bound on the norm of anything outside.
fn box_candidates(rv: &Rover, r: i64) -> BoxCandidates {
    let n = rv.a.len();
    let qi = rv.q.clone().try_inverse().unwrap();
    let center: Vec<i64> = rv.a.iter().map(|v| v.round() as i64).collect();
    let side = (2 * r + 1) as usize;
    let mut out = Vec::with_capacity(side.pow(n as u32));
    for mut idx in 0..side.pow(n as u32) {
        let z = DVector::from_fn(n, |i, _| {
            let v = center[i] - r + (idx % side) as i64;
            idx /= side;
            let _ = i;
            v
        });
        let d = &rv.a - z.map(|v| v as f64);
        let norm = d.dot(&(&qi * &d));
        let db = rv.k.tr_mul(&d);
        out.push((z, norm, rv.b - Vector3::new(db[0], db[1], db[2])));
    }
    out.sort_by(|x, y| x.1.total_cmp(&y.1));
    let outside = (0..n)
        .map(|i| {
            // Farthest in-box coordinate from a_i is r - |a_i - round(a_i)| >= r - 1/2 away.
            (r as f64 - 0.5).powi(2) / rv.q[(i, i)]
        })
        .fold(f64::INFINITY, f64::min);
    (out, outside)
}

/// The objective of baselines `b` with the rotation of the textbook SVD solution of Wahba's problem.
fn objective(rovers: &[Rover], norms: &[f64], b: &[Vector3<f64>]) -> f64 {
    let h: Matrix3<f64> = rovers
        .iter()
        .zip(b)
        .map(|(r, b)| r.weight * b * r.f.transpose())
        .sum();
    let svd = SVD::new(h, true, true);
    let (u, vt) = (svd.u.unwrap(), svd.v_t.unwrap());
    let d = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, (u * vt).determinant().signum()));
    let rot = u * d * vt;
    rovers
        .iter()
        .zip(norms)
        .zip(b)
        .map(|((r, n), b)| n + r.weight * (b - rot * r.f).norm_squared())
        .sum()
}

/// Each rover's box (candidates, norm ascending, and its outside bound), least norms, the cap.
struct Space<'a> {
    boxes: &'a [BoxCandidates],
    mins: &'a [f64],
    cap: f64,
    rovers: &'a [Rover],
}

type BoxCandidates = (Vec<(DVector<i64>, f64, Vector3<f64>)>, f64);

impl Space<'_> {
    /// Every combination whose norms sum below the cap (the others cost at least the cap).
    fn walk(&self, k: usize, sum: f64, idx: &mut Vec<usize>, found: &mut Vec<(f64, Vec<usize>)>) {
        if k == self.boxes.len() {
            let norms: Vec<f64> = idx.iter().zip(self.boxes).map(|(&i, b)| b.0[i].1).collect();
            let b: Vec<Vector3<f64>> = idx.iter().zip(self.boxes).map(|(&i, b)| b.0[i].2).collect();
            found.push((objective(self.rovers, &norms, &b), idx.clone()));
            return;
        }
        let rest: f64 = self.mins[k + 1..].iter().sum();
        for i in 0..self.boxes[k].0.len() {
            let s = sum + self.boxes[k].0[i].1;
            if s + rest >= self.cap {
                break;
            }
            idx[k] = i;
            self.walk(k + 1, s, idx, found);
        }
    }
}

/// Brute force over boxes of half widths `r` (one per rover): the best combination's integers and
/// objective, the second best's objective, and the second best's integers; `None` when the boxes do not
/// prove them global.
#[allow(clippy::type_complexity)]
fn brute(rovers: &[Rover], r: &[i64]) -> Option<(Vec<DVector<i64>>, f64, f64, Vec<DVector<i64>>)> {
    let boxes: Vec<_> = rovers
        .iter()
        .zip(r)
        .map(|(rv, &r)| box_candidates(rv, r))
        .collect();
    let mins: Vec<f64> = boxes.iter().map(|(c, _)| c[0].1).collect();
    let total_min: f64 = mins.iter().sum();
    let cap = boxes
        .iter()
        .zip(&mins)
        .map(|((_, out), m)| out + total_min - m)
        .fold(f64::INFINITY, f64::min);
    let mut found: Vec<(f64, Vec<usize>)> = Vec::new();
    let mut idx = vec![0usize; rovers.len()];
    let space = Space {
        boxes: &boxes,
        mins: &mins,
        cap,
        rovers,
    };
    space.walk(0, 0.0, &mut idx, &mut found);
    found.sort_by(|x, y| x.0.total_cmp(&y.0));
    if found.len() < 2 || found[1].0 >= cap {
        return None;
    }
    let ints = |c: &[usize]| -> Vec<DVector<i64>> {
        c.iter()
            .zip(&boxes)
            .map(|(&i, b)| b.0[i].0.clone())
            .collect()
    };
    Some((ints(&found[0].1), found[0].0, found[1].0, ints(&found[1].1)))
}

/// The exact search's best, its objective and the second best's, for the same rovers.
fn searched(rovers: &[Rover]) -> (Vec<DVector<i64>>, f64, f64, bool) {
    let amb: Vec<Ambiguities> = rovers
        .iter()
        .map(|rv| {
            let p = Problem::new(&rv.a, &rv.q).unwrap();
            // k is Q_a^-1 Q_ab itself (the frame already ENU).
            Ambiguities::new(p, &rv.k, &Matrix3::identity()).unwrap()
        })
        .collect();
    let mut lists: Vec<List<'_>> = rovers
        .iter()
        .zip(&amb)
        .map(|(rv, a)| List::new(a, a.problem.zhat.clone(), rv.b, rv.weight, rv.f.norm()).unwrap())
        .collect();
    let weights: Vec<f64> = rovers.iter().map(|r| r.weight).collect();
    let body: Vec<Vector3<f64>> = rovers.iter().map(|r| r.f).collect();
    let out = search(&mut lists, &weights, &body, true).unwrap();
    let (chosen, cost) = out.best.clone().unwrap();
    (
        chosen
            .iter()
            .zip(&amb)
            .map(|(c, a)| a.problem.to_original(&c.z).unwrap())
            .collect(),
        cost,
        out.second,
        out.complete,
    )
}

/// Random covariances, two and three rovers of two or three ambiguities, fixed seeds: the search's best
/// integers are brute force's, its best and second-best objectives agree to 1e-9 relative (the same
/// sums in another order, an SVD of another implementation), and it says it is complete.
#[test]
fn the_grown_search_finds_brute_force_best_and_second_best() {
    let mut compared = 0;
    for seed in 0..24u64 {
        let mut rng = ChaCha8Rng::seed_from_u64(4000 + seed);
        let rot = random_rotation(&mut rng);
        let (n_rovers, n, r) = match seed % 3 {
            0 => (2, 2, 6),
            1 => (2, 3, 4),
            _ => (3, 2, 4),
        };
        let rovers: Vec<Rover> = (0..n_rovers)
            .map(|_| random_rover(&mut rng, n, 0.6, 0.06, 0.02, &rot))
            .collect();
        let Some((z_best, best, second, _)) = brute(&rovers, &vec![r; n_rovers]) else {
            continue;
        };
        let (z, cost, sec, complete) = searched(&rovers);
        assert!(complete, "seed {seed}");
        assert_eq!(z, z_best, "seed {seed}");
        assert!(
            (cost - best).abs() <= 1e-9 * best.max(1.0),
            "seed {seed}: {cost} vs {best}"
        );
        assert!(
            (sec - second).abs() <= 1e-9 * second.max(1.0),
            "seed {seed}: {sec} vs {second}"
        );
        compared += 1;
    }
    assert!(
        compared >= 18,
        "{compared} of 24 seeds proved by their boxes"
    );
}

/// One rover with wide float ambiguities (sigma about 1.5 cycles: about 200 integer vectors within a
/// norm of 6) and one with narrow ones, a baseline sigma of 5 cm and gains of a GPS L1 wavelength: the
/// second-best combination has an integer vector of the wide rover ranked beyond its 200 best
/// unconstrained ones (the old `CANDIDATES` list, which could not have seen it), and the grown search
/// still finds it (its best and second best are brute force's).
#[test]
fn the_grown_search_finds_a_second_best_beyond_200_candidates() {
    let (mut beyond, mut compared) = (0, 0);
    for seed in 0..16u64 {
        let mut rng = ChaCha8Rng::seed_from_u64(4100 + seed);
        let rot = random_rotation(&mut rng);
        let rovers = vec![
            random_rover(&mut rng, 3, 2.5, 0.19, 0.02, &rot),
            random_rover(&mut rng, 3, 0.3, 0.19, 0.02, &rot),
        ];
        let Some((_, best, second, z_second)) = brute(&rovers, &[20, 4]) else {
            continue;
        };
        compared += 1;
        let (_, cost, sec, complete) = searched(&rovers);
        assert!(complete, "seed {seed}: {cost} {sec} brute {best} {second}");
        assert!((cost - best).abs() <= 1e-9 * best.max(1.0), "seed {seed}");
        assert!(
            (sec - second).abs() <= 1e-9 * second.max(1.0),
            "seed {seed}"
        );
        // The rank of the second best's integers among the wide rover's unconstrained candidates.
        let (c, _) = box_candidates(&rovers[0], 20);
        let rank = c.iter().position(|(v, _, _)| *v == z_second[0]).unwrap();
        println!("seed {seed}: best {best:.2}, second {second:.2}, rank {rank}");
        beyond += usize::from(rank >= 200);
    }
    assert!(compared >= 4, "{compared} of 8 seeds proved by their boxes");
    assert!(
        beyond >= 1,
        "no second best beyond 200 candidates in {compared}"
    );
}
