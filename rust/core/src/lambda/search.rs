//! Exact integer least-squares search for the `m` best integer vectors: depth-first over the conditional
//! estimates, last ambiguity first, with Schnorr-Euchner enumeration (values in order of distance from
//! the conditional estimate) and an ellipsoid that shrinks to the m-th best norm found so far.
//! Chang, Yang & Zhou (2005), "MLAMBDA", J. Geodesy 79:552-565, section 4; de Jonge & Tiberius (1996),
//! LGR-12, section 4.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use nalgebra::{DMatrix, DVector};

use super::ldl::Ltdl;
use crate::error::{Error, Result};
use crate::interrupt;

/// Cap on the nodes one search may visit (see [`search`]): measured at about 16 million nodes a second
/// on one core at n = 40, so 1e8 nodes bound one search to about 6 s. The best candidate of a float
/// vector drawn from its covariance needs about 2n nodes; the second best (the ratio test) grows
/// roughly binomially with n where the decorrelated variances are flat (1e5 to beyond 1e8 nodes at
/// n = 40 to 64). Past the cap the search stops with [`Error::Convergence`]. The public entry points
/// give a problem of n ambiguities [`node_budget`]`(n)`, which reaches this cap at n = 200.
pub const DEFAULT_MAX_NODES: u64 = 100_000_000;

/// Nodes per ambiguity of [`node_budget`]: 500,000, so that n = 64 gets 3.2e7 nodes, about 3 s (issue
/// 31's second-best searches at n = 64 visited 1e8 nodes in 8.8 s on a shared machine), inside the
/// robustness promise of an answer or a refusal in about 10 s; the budget reaches [`DEFAULT_MAX_NODES`]
/// at n = 200.
pub const NODES_PER_AMBIGUITY: u64 = 500_000;

/// The node budget of one search over `n` ambiguities: `NODES_PER_AMBIGUITY n`, at most
/// [`DEFAULT_MAX_NODES`]. A search tree has at least 2n nodes and its work per node grows with n, so a
/// budget proportional to n refuses a hopeless small problem in milliseconds instead of seconds, while
/// the larger problems, whose legitimate searches are the longer ones, get the most.
pub fn node_budget(n: usize) -> u64 {
    NODES_PER_AMBIGUITY
        .saturating_mul(n as u64)
        .min(DEFAULT_MAX_NODES)
}

/// Nodes between two polls of [`crate::interrupt`] (2^20: about 60 ms of search).
const POLL_NODES: u64 = 1 << 20;

/// Largest number of candidates one search may be asked for: they are held in memory (n x m values)
/// and each costs at least one node.
pub const MAX_CANDIDATES: usize = 10_000;

/// Checks a number of candidates: 1 ..= [`MAX_CANDIDATES`], before anything is allocated.
///
/// # Errors
/// [`Error::OutOfRange`] for 0, [`Error::TooLarge`] beyond the limit.
pub fn check_candidates(m: usize) -> Result<()> {
    if m == 0 {
        return Err(Error::out_of_range(
            "candidates",
            "expected at least 1, got 0",
        ));
    }
    if m > MAX_CANDIDATES {
        return Err(Error::too_large(
            "candidates",
            m as f64,
            MAX_CANDIDATES as f64,
            "integer vectors",
        ));
    }
    Ok(())
}

/// A candidate kept by the search: its squared norm and its slot in the candidate store, ordered by the
/// norm (a max-heap keeps the worst on top).
struct Kept(f64, usize);

impl PartialEq for Kept {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Kept {}
impl PartialOrd for Kept {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Kept {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// The best integer vectors of one search, in the space where it ran.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidates {
    /// Integer vectors (stored as `f64`), one per column (n x m), best first.
    pub z: DMatrix<f64>,
    /// `(zhat - z)^T Q^-1 (zhat - z)` of each column, ascending.
    pub squared_norms: Vec<f64>,
    /// Nodes visited: integer values tried at any level of the tree, i.e. partial norms evaluated.
    pub nodes_visited: u64,
}

/// Finds the `m` integer vectors closest to `zhat` in the metric of `Q = L^T D L`.
///
/// # Arguments
/// * `factor` - `L` and `d` of the (preferably decorrelated) covariance, cycles^2.
/// * `zhat` - the float ambiguities in the same space, cycles.
/// * `m` - number of candidates, 1 ..= [`MAX_CANDIDATES`].
/// * `max_nodes` - give up after visiting this many nodes.
///
/// # Errors
/// [`Error::Shape`] when `zhat` does not match `factor`, those of [`check_candidates`],
/// [`Error::Convergence`] when the node cap is reached (a badly conditioned, undecorrelated problem),
/// [`Error::Numerical`] when fewer than `m` candidates have a finite norm (norms beyond the `f64` range:
/// a covariance tiny compared with the distances to the integers); [`Error::Interrupted`] on
/// [`crate::interrupt::request`] (polled every 2^20 nodes).
pub fn search(factor: &Ltdl, zhat: &DVector<f64>, m: usize, max_nodes: u64) -> Result<Candidates> {
    let n = factor.d.len();
    let mut b = SearchBuffers::default();
    let mut z = DMatrix::zeros(n, m.min(MAX_CANDIDATES));
    let mut squared_norms = Vec::new();
    let nodes_visited = search_into(
        factor,
        zhat.as_slice(),
        m,
        max_nodes,
        &mut b,
        z.as_mut_slice(),
        &mut squared_norms,
    )?;
    Ok(Candidates {
        z,
        squared_norms,
        nodes_visited,
    })
}

/// The scratch of [`search_into`], kept between searches: none of it is allocated again once it has held
/// a search of the same n and m.
#[derive(Default)]
pub(crate) struct SearchBuffers {
    acc: Vec<f64>,
    dist: Vec<f64>,
    zb: Vec<f64>,
    z: Vec<f64>,
    step: Vec<f64>,
    store: Vec<f64>,
    best: BinaryHeap<Kept>,
}

/// [`search`] through the buffers `b`: the candidates go into `out` (n m values, column after column,
/// best first), their norms into `norms` (cleared first); returns the nodes visited.
///
/// # Errors
/// Those of [`search`].
pub(crate) fn search_into(
    factor: &Ltdl,
    zhat: &[f64],
    m: usize,
    max_nodes: u64,
    b: &mut SearchBuffers,
    out: &mut [f64],
    norms: &mut Vec<f64>,
) -> Result<u64> {
    check_search_input(factor, zhat, m)?;
    let Ltdl { l, d } = factor;
    let n = d.len();
    b.reset(n, m);
    // acc[(k, j)], j <= k: sum over i > k of (z_i - zb_i) L_ij, so that zb_k = zhat_k + acc[(k, k)].
    // (Column-major n x n: acc[(k, j)] at j n + k.) Everything is borrowed as plain slices, which the
    // optimiser knows do not alias one another, unlike the vectors behind `b`.
    let acc = &mut b.acc[..];
    let (dist, zb, z, step) = (
        &mut b.dist[..],
        &mut b.zb[..],
        &mut b.z[..],
        &mut b.step[..],
    );
    let store = &mut b.store[..];
    let best = &mut b.best;
    let mut radius = f64::INFINITY;
    let mut nodes = 0u64;

    let mut k = n - 1;
    let mut y = start(k, zb, z, step, zhat[k]);
    loop {
        nodes += 1;
        if nodes > max_nodes {
            return Err(Error::Convergence {
                what: "integer least-squares search (node cap reached)",
                iterations: max_nodes as usize,
            });
        }
        if nodes.is_multiple_of(POLL_NODES) {
            interrupt::check("integer least-squares search")?;
        }
        let newdist = dist[k] + y * y / d[k];
        if newdist < radius {
            if k > 0 {
                let e = z[k] - zb[k];
                for j in 0..k {
                    acc[j * n + k - 1] = acc[j * n + k] + e * l[(k, j)];
                }
                k -= 1;
                dist[k] = newdist;
                let value = zhat[k] + acc[k * n + k];
                y = start(k, zb, z, step, value);
            } else {
                let slot = if best.len() == m {
                    best.pop().map_or(0, |w| w.1)
                } else {
                    best.len()
                };
                store[slot * n..(slot + 1) * n].copy_from_slice(z);
                best.push(Kept(newdist, slot));
                if best.len() == m {
                    radius = best.peek().map_or(f64::INFINITY, |w| w.0);
                }
                y = next(0, zb, z, step);
            }
        } else {
            if k == n - 1 {
                break;
            }
            k += 1;
            y = next(k, zb, z, step);
        }
    }
    // Only an overflow of the partial norms (inf is never < inf) leaves fewer than m candidates.
    if best.len() < m {
        return Err(too_few_finite(best.len(), m, d));
    }
    hand_out_sorted(best, store, n, out, norms);
    Ok(nodes)
}

/// Level `k`'s first value: the conditional estimate `value` (cycles) rounded, with the direction of the
/// next nearest integer in `step[k]`; returns the residual `value - z[k]`.
#[inline(always)]
fn start(k: usize, zb: &mut [f64], z: &mut [f64], step: &mut [f64], value: f64) -> f64 {
    zb[k] = value;
    z[k] = value.round();
    let y = value - z[k];
    step[k] = if y <= 0.0 { -1.0 } else { 1.0 };
    y
}

/// Level `k`'s next value in Schnorr-Euchner order (alternating sides, ever farther from `zb[k]`);
/// returns the new residual `zb[k] - z[k]`, cycles.
#[inline(always)]
fn next(k: usize, zb: &[f64], z: &mut [f64], step: &mut [f64]) -> f64 {
    z[k] += step[k];
    step[k] = -step[k] - step[k].signum();
    zb[k] - z[k]
}

/// The error of a search that kept only `found` of `m` candidates, `d` the conditional variances.
fn too_few_finite(found: usize, m: usize, d: &DVector<f64>) -> Error {
    Error::numerical(
        "integer least-squares search",
        format!(
            "only {found} of {m} candidates have a finite squared norm (dimension {}, smallest \
             conditional variance {:.3e}): the norms exceed the f64 range",
            d.len(),
            d.min()
        ),
    )
}

/// The input checks of [`search_into`]: `zhat` and `L` of the factor's dimension, and
/// [`check_candidates`].
fn check_search_input(factor: &Ltdl, zhat: &[f64], m: usize) -> Result<()> {
    let n = factor.d.len();
    if zhat.len() != n || factor.l.shape() != (n, n) {
        return Err(Error::Shape {
            name: "float ambiguities",
            expected: format!("({n},)"),
            actual: format!("({},)", zhat.len()),
        });
    }
    check_candidates(m)
}

impl SearchBuffers {
    /// Zeroes the scratch for a search of `n` ambiguities and `m` candidates, reusing what is allocated.
    fn reset(&mut self, n: usize, m: usize) {
        for v in [
            &mut self.acc,
            &mut self.dist,
            &mut self.zb,
            &mut self.z,
            &mut self.step,
        ] {
            v.clear();
        }
        self.acc.resize(n * n, 0.0);
        for v in [&mut self.dist, &mut self.zb, &mut self.z, &mut self.step] {
            v.resize(n, 0.0);
        }
        // The m candidates live in one n x m store (a leaf overwrites the slot of the worst it
        // replaces): no allocation inside the search.
        self.store.clear();
        self.store.resize(n * m, 0.0);
        self.best.clear();
        self.best.reserve(m);
    }
}

/// Copies the kept candidates from `store` into `out` best first (n values each, column after column)
/// and their squared norms into `norms`, leaving `best` empty.
fn hand_out_sorted(
    best: &mut BinaryHeap<Kept>,
    store: &[f64],
    n: usize,
    out: &mut [f64],
    norms: &mut Vec<f64>,
) {
    // The heap's own storage, sorted ascending, and handed back empty: no allocation.
    let sorted = std::mem::take(best).into_sorted_vec();
    norms.clear();
    for (c, &Kept(v, slot)) in sorted.iter().enumerate() {
        out[c * n..(c + 1) * n].copy_from_slice(&store[slot * n..(slot + 1) * n]);
        norms.push(v);
    }
    let mut sorted = sorted;
    sorted.clear();
    *best = BinaryHeap::from(sorted);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lambda::ldl::ltdl;
    use crate::lambda::test_support::{random_covariance, Lcg};

    fn norm(q_inv: &DMatrix<f64>, a: &DVector<f64>, z: &[f64]) -> f64 {
        let r = a - DVector::from_column_slice(z);
        (r.transpose() * q_inv * &r)[0]
    }

    /// Every integer vector in a box that holds the m best, sorted by norm.
    fn brute_force(q: &DMatrix<f64>, a: &DVector<f64>, m: usize) -> Vec<f64> {
        let n = a.len();
        let q_inv = q.clone().try_inverse().unwrap();
        // The rounded vector and its unit neighbours give an upper bound chi2 on the m-th best norm;
        // the ellipsoid of that size lies in the box |a_i - z_i| <= sqrt(chi2 Q_ii).
        let r: Vec<f64> = a.iter().map(|v| v.round()).collect();
        let mut seeds = vec![norm(&q_inv, a, &r)];
        for i in 0..n {
            for s in [-1.0, 1.0] {
                let mut v = r.clone();
                v[i] += s;
                seeds.push(norm(&q_inv, a, &v));
            }
        }
        seeds.sort_by(f64::total_cmp);
        let chi2 = seeds[m - 1];
        let lo: Vec<i64> = (0..n)
            .map(|i| (a[i] - (chi2 * q[(i, i)]).sqrt()).floor() as i64)
            .collect();
        let hi: Vec<i64> = (0..n)
            .map(|i| (a[i] + (chi2 * q[(i, i)]).sqrt()).ceil() as i64)
            .collect();
        let mut norms = Vec::new();
        let mut cur = lo.clone();
        loop {
            let v: Vec<f64> = cur.iter().map(|&c| c as f64).collect();
            norms.push(norm(&q_inv, a, &v));
            let mut i = 0;
            while i < n {
                cur[i] += 1;
                if cur[i] <= hi[i] {
                    break;
                }
                cur[i] = lo[i];
                i += 1;
            }
            if i == n {
                break;
            }
        }
        norms.sort_by(f64::total_cmp);
        norms.truncate(m);
        norms
    }

    #[test]
    fn matches_brute_force_without_decorrelation() {
        let mut rng = Lcg(11);
        for n in 1..=4 {
            for _ in 0..30 {
                let q = random_covariance(&mut rng, n, 0.05);
                let a = DVector::from_fn(n, |_, _| 10.0 * rng.uniform() - 5.0);
                let f = ltdl(&q).unwrap();
                let got = search(&f, &a, 3, DEFAULT_MAX_NODES).unwrap();
                let want = brute_force(&q, &a, 3);
                let q_inv = q.clone().try_inverse().unwrap();
                for (c, w) in want.iter().enumerate() {
                    let zc: Vec<f64> = got.z.column(c).iter().copied().collect();
                    assert!((norm(&q_inv, &a, &zc) - got.squared_norms[c]).abs() < 1e-8);
                    assert!((got.squared_norms[c] - w).abs() < 1e-8 * (1.0 + w));
                }
            }
        }
    }

    #[test]
    fn rejects_zero_candidates_and_caps_nodes() {
        let f = ltdl(&DMatrix::identity(2, 2)).unwrap();
        let a = DVector::from_vec(vec![0.2, 0.4]);
        assert!(matches!(
            search(&f, &a, 0, 10),
            Err(Error::OutOfRange { .. })
        ));
        assert!(matches!(
            search(&f, &a, 50, 10),
            Err(Error::Convergence { .. })
        ));
        // Refused before allocating (2^58 used to panic, 1e11 to abort on allocation failure).
        for m in [MAX_CANDIDATES + 1, 100_000_000_000, 1 << 58, usize::MAX] {
            assert!(matches!(search(&f, &a, m, 10), Err(Error::TooLarge { .. })));
        }
        // Norms beyond the f64 range: refused, not an empty or short answer.
        // d = 1e-307: (0.4 + 4)^2 / d = 1.9e308 overflows.
        let tiny = ltdl(&(DMatrix::identity(1, 1) * 1e-307)).unwrap();
        let far = DVector::from_vec(vec![0.4]);
        assert!(search(&tiny, &far, 2, 10).is_ok());
        let e = search(&tiny, &far, 20, 100_000).unwrap_err();
        assert!(matches!(e, Error::Numerical { .. }), "{e:?}");
        let b = DVector::from_vec(vec![0.2]);
        assert!(matches!(search(&f, &b, 1, 10), Err(Error::Shape { .. })));
    }
}
