//! Every integer vector within a radius of a float vector, in the metric of a decorrelated covariance
//! `Q = L^T D L`: the enumeration of [`crate::lambda::search`] (same conditional estimates, same zig-zag
//! order, Schnorr-Euchner) with a fixed radius and no list of the `m` best. The exact attitude search
//! needs every candidate below a bound ([`super::search`]); a fixed radius visits only the tree's nodes
//! below it, where an `m`-best search keeps a heap of `m` and shrinks from an infinite radius.

use nalgebra::{DMatrix, DVector};

use crate::error::{Error, Result};
use crate::lambda::ldl::Ltdl;

/// Calls `leaf` with every integer vector `z` with `(zhat - z)^T Q^-1 (zhat - z) <= radius` and its
/// squared norm, in the order found, and returns their count; `None` when there are more than `cap`
/// (the caller's list stops growing).
///
/// # Errors
/// [`Error::Convergence`] past `max_nodes` nodes.
pub(super) fn within(
    factor: &Ltdl,
    zhat: &DVector<f64>,
    radius: f64,
    cap: usize,
    max_nodes: u64,
    leaf: &mut dyn FnMut(&[f64], f64),
) -> Result<Option<usize>> {
    let Ltdl { l, d } = factor;
    let n = d.len();
    let mut acc = DMatrix::<f64>::zeros(n, n);
    let mut dist = vec![0.0; n];
    let mut zb = vec![0.0; n];
    let mut z = vec![0.0; n];
    let mut step = vec![0.0; n];
    let mut count = 0usize;
    let mut nodes = 0u64;
    let start = |k: usize, zb: &mut [f64], z: &mut [f64], step: &mut [f64], value: f64| -> f64 {
        zb[k] = value;
        z[k] = value.round();
        let y = value - z[k];
        step[k] = if y <= 0.0 { -1.0 } else { 1.0 };
        y
    };
    let next = |k: usize, zb: &[f64], z: &mut [f64], step: &mut [f64]| -> f64 {
        z[k] += step[k];
        step[k] = -step[k] - step[k].signum();
        zb[k] - z[k]
    };
    let mut k = n - 1;
    let mut y = start(k, &mut zb, &mut z, &mut step, zhat[k]);
    loop {
        nodes += 1;
        if nodes > max_nodes {
            return Err(Error::Convergence {
                what: "attitude candidate enumeration (node cap reached)",
                iterations: max_nodes as usize,
            });
        }
        let newdist = dist[k] + y * y / d[k];
        if newdist <= radius {
            if k > 0 {
                let e = z[k] - zb[k];
                for j in 0..k {
                    acc[(k - 1, j)] = acc[(k, j)] + e * l[(k, j)];
                }
                k -= 1;
                dist[k] = newdist;
                let value = zhat[k] + acc[(k, k)];
                y = start(k, &mut zb, &mut z, &mut step, value);
            } else {
                if count == cap {
                    return Ok(None);
                }
                count += 1;
                leaf(&z, newdist);
                y = next(0, &zb, &mut z, &mut step);
            }
        } else {
            if k == n - 1 {
                break;
            }
            k += 1;
            y = next(k, &zb, &mut z, &mut step);
        }
    }
    Ok(Some(count))
}
