//! Batches over epochs, in parallel with rayon (thread count: `RAYON_NUM_THREADS` or rayon's global pool).
//! Errors name the first failing epoch.

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::wahba::profile::{solve, Method, Solution};
use crate::wahba::triad::{triad, TriadSolution};

/// Wahba's problem for `body.len() / pairs` epochs of `pairs` vector pairs each, stored epoch-major.
///
/// # Arguments
/// * `body`, `reference` - `epochs * pairs` vectors; epoch `k` owns `[k * pairs, (k + 1) * pairs)`.
/// * `weights` - `epochs * pairs` weights, laid out the same way.
/// * `pairs` - vector pairs per epoch (at least 2).
///
/// # Errors
/// [`Error::Shape`] for inconsistent lengths or fewer than 2 pairs; otherwise those of [`solve`], with the
/// epoch index in the message.
pub fn solve_batch(
    body: &[Vector3<f64>],
    reference: &[Vector3<f64>],
    weights: &[f64],
    pairs: usize,
    method: Method,
) -> Result<Vec<Solution>> {
    if pairs < 2
        || !body.len().is_multiple_of(pairs)
        || reference.len() != body.len()
        || weights.len() != body.len()
    {
        return Err(Error::Shape {
            name: "vector pairs",
            expected: "epochs x pairs (pairs >= 2) body vectors, reference vectors and weights"
                .into(),
            actual: format!(
                "{} body, {} reference, {} weights, {pairs} pairs per epoch",
                body.len(),
                reference.len(),
                weights.len()
            ),
        });
    }
    body.par_chunks(pairs)
        .zip(reference.par_chunks(pairs))
        .zip(weights.par_chunks(pairs))
        .enumerate()
        .map(|(k, ((b, r), w))| solve(b, r, w, method).map_err(|e| e.at_epoch(k)))
        .collect()
}

/// TRIAD for each epoch `k` of equally long slices.
///
/// # Errors
/// [`Error::Shape`] for unequal lengths; otherwise those of [`triad`], with the epoch index.
pub fn triad_batch(
    b1: &[Vector3<f64>],
    b2: &[Vector3<f64>],
    r1: &[Vector3<f64>],
    r2: &[Vector3<f64>],
) -> Result<Vec<TriadSolution>> {
    let n = b1.len();
    if b2.len() != n || r1.len() != n || r2.len() != n {
        return Err(Error::Shape {
            name: "TRIAD vectors",
            expected: format!("{n} of each of b1, b2, r1, r2"),
            actual: format!("{}, {}, {}, {}", n, b2.len(), r1.len(), r2.len()),
        });
    }
    (0..n)
        .into_par_iter()
        .map(|k| triad(&b1[k], &b2[k], &r1[k], &r2[k]).map_err(|e| e.at_epoch(k)))
        .collect()
}
