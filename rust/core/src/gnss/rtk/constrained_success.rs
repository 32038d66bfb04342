//! The simulated success rate of attitude mode's constrained fix ([`super`]'s module documentation):
//! the fix taken as the truth, [`SUCCESS_DRAWS`] seeded draws of every rover's float errors, each draw
//! solved by the same exact search as the epoch (module [`super::search`]); the rate is the share of
//! draws whose best combination is the truth (a draw whose search is incomplete counts as a failure, as
//! in [`super::super::known_length`]).

use nalgebra::{Cholesky, DVector, Matrix3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::search::{rotation_of, search, Candidate, List};
use super::Rover;
use crate::error::{Error, Result};
use crate::lambda::validation::normal;

/// Draws of the simulated constrained success rate (its standard error at 0.95 is 0.015).
pub const SUCCESS_DRAWS: usize = 200;

/// Seed of the simulation: the same epoch gives the same decision in every run.
const SEED: u64 = 2828;

/// What one rover's draws need: the truth's baseline and `Q_b|a`'s Cholesky factor (ENU); the truth's
/// integers are 0 in the draws' shifted decorrelated space.
struct Truth {
    b_enu: Vector3<f64>,
    l_cond: Matrix3<f64>,
}

/// The simulated success rate of the constrained fix `chosen` (one candidate per rover). `to_enu`:
/// ENU <- ECEF at the base.
pub(super) fn success_rate(
    rovers: &[Rover],
    chosen: &[Candidate],
    body: &[Vector3<f64>],
    to_enu: &Matrix3<f64>,
) -> Result<f64> {
    let weights: Vec<f64> = rovers.iter().map(|r| r.weight).collect();
    let fixed_b: Vec<Vector3<f64>> = chosen.iter().map(|c| c.b_enu).collect();
    let rot = rotation_of(&weights, &fixed_b, body)
        .ok_or_else(|| Error::numerical("attitude success rate", "the fix gives no rotation"))?;
    let truths = rovers
        .iter()
        .zip(body)
        .map(|(r, f)| {
            let q = to_enu * r.q_cond * to_enu.transpose();
            let q = (q + q.transpose()) * 0.5;
            let l_cond = Cholesky::new(q + Matrix3::identity() * 1e-12)
                .map(|c| c.l())
                .ok_or_else(|| Error::numerical("attitude success rate", "Q_b|a not positive"))?;
            Ok(Truth {
                b_enu: rot * f,
                l_cond,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let successes = (0..SUCCESS_DRAWS)
        .into_par_iter()
        .map(|t| draw(rovers, &truths, &weights, body, t))
        .try_reduce(|| 0, |a, b| Ok(a + b))?;
    Ok(successes as f64 / SUCCESS_DRAWS as f64)
}

/// Draw `t`: 1 when its exact constrained best is the truth, else 0.
fn draw(
    rovers: &[Rover],
    truths: &[Truth],
    weights: &[f64],
    body: &[Vector3<f64>],
    t: usize,
) -> Result<usize> {
    let mut rng = ChaCha8Rng::seed_from_u64(SEED);
    rng.set_stream(t as u64);
    let mut lists = Vec::with_capacity(rovers.len());
    for (r, truth) in rovers.iter().zip(truths) {
        let e_cond = truth.l_cond * Vector3::from_fn(|_, _| normal(&mut rng));
        match &r.ambiguities {
            None => lists.push(List::single(truth.b_enu + e_cond, r.weight, r.length_m)),
            Some(amb) => {
                // Decorrelated, the truth shifted to 0: zhat = e ~ N(0, L^T D L); b = b* + gain^T e +
                // e_b|a (the float baseline's error correlated with the ambiguities').
                let f = &amb.problem.reduction.factor;
                let w = DVector::from_fn(f.d.len(), |i, _| f.d[i].sqrt() * normal(&mut rng));
                let e = f.l.tr_mul(&w);
                let kb = amb.gain_enu.tr_mul(&e);
                let b = truth.b_enu + Vector3::new(kb[0], kb[1], kb[2]) + e_cond;
                let mut list = List::new(amb, e, b, r.weight, r.length_m)?;
                list.include(DVector::zeros(f.d.len()));
                lists.push(list);
            }
        }
    }
    let out = search(&mut lists, weights, body, false)?;
    let right = out.complete
        && out
            .best
            .is_some_and(|(c, _)| c.iter().all(|c| c.z.iter().all(|&v| v == 0.0)));
    Ok(usize::from(right))
}
