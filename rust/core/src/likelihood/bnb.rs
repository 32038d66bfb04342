//! Exact best-first branch-and-bound over boxes of grid cells.
//!
//! Bound. Over a box with centre node `c` and half-extents `h_a` (radians, a = psi, theta, phi), every
//! phase obeys `|x_ik(chi) - x_ik(c)| <= delta_ik = sum_a |g_k . d_a R(c) r_i| h_a + |g_k| |r_i| (sum_a
//! h_a)^2 / 2` (Taylor with the exact gradient at the centre; every second derivative of `R r_i` has norm
//! at most `|r_i|`, as each factor `Ry`, `Rz`, `Rx` and its derivatives has operator norm <= 1). One
//! modulus `|sum_j exp(j x_j)| = max_w sum_j cos(x_j - w)` is then at most `max_w sum_j h_j(w)`, where
//! `h_j(w) = 1` if `|x_j(c) - w| <= delta_j` (mod 2 pi) and `cos(|x_j(c) - w| - delta_j)` otherwise.
//! Between consecutive breakpoints `x_j(c) +- delta_j`, `x_j(c) + pi` each term is either 1 or
//! `Re(exp(j(x_j(c) -+ delta_j - w)))`, so the sum is `P + Re(exp(-j w) C)` <= `P + |C|`; the bound is
//! the largest `P + |C|` over the segments (and never above the triangle bound
//! `|sum_j exp(j x_j(c))| + sum_j 2 sin(delta_j / 2)` nor the number of terms). A margin covers the
//! float32 kernel's error ([`super::SINCOS_ABS_ERROR`]), so the search returns exactly the grid maximum of
//! the exhaustive pass (same kernel at the leaves, same tie rule). This is the ambiguity-function
//! branch-and-bound idea of Teunissen & Massarweh (2025, J. Geodesy 99:28) on Euler-angle boxes.

use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::f64::consts::{PI, TAU};

use nalgebra::{Matrix3, Vector3};

use crate::error::Result;
use crate::rotation::{elementary, Axis as RotAxis};

use super::grid::Grid;
use super::kernel::{eval_row, heading_tables, RowCoef};
use super::model::{Grouping, Model};
use super::search::{better, check_step, GridMax};

/// Work done by [`branch_and_bound`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BnbStats {
    /// Boxes whose bound was computed (each also evaluates `Z` at its centre node, in f64).
    pub boxes_bounded: u64,
    /// Cells evaluated by the float32 kernel at the leaves.
    pub leaf_cells: u64,
}

/// Boxes with at most this many cells are evaluated cell by cell.
const LEAF_CELLS: usize = 8;

#[derive(Debug, Clone, Copy)]
struct Cube {
    lo: [usize; 3],
    hi: [usize; 3],
    bound: f64,
    split: usize,
}

impl PartialEq for Cube {
    fn eq(&self, o: &Self) -> bool {
        self.bound.total_cmp(&o.bound) == Ordering::Equal
    }
}
impl Eq for Cube {}
impl PartialOrd for Cube {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Cube {
    fn cmp(&self, o: &Self) -> Ordering {
        self.bound.total_cmp(&o.bound)
    }
}

fn dy(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(-s, 0.0, c, 0.0, 0.0, 0.0, -c, 0.0, -s)
}
fn dz(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(-s, -c, 0.0, c, -s, 0.0, 0.0, 0.0, 0.0)
}
fn dx(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(0.0, 0.0, 0.0, 0.0, -s, -c, 0.0, c, -s)
}

fn wrap2pi(x: f64) -> f64 {
    x.rem_euclid(TAU)
}

/// Upper bound of `|sum_j exp(j x_j')|` over `|x_j' - x_j| <= delta_j` (module docs). `scratch` holds
/// the breakpoints, `members` per member `(x, delta, cos(x - delta), sin(x - delta), cos(x + delta),
/// sin(x + delta))`.
pub(crate) fn modulus_bound(
    xs: &[f64],
    deltas: &[f64],
    scratch: &mut Vec<f64>,
    members: &mut Vec<[f64; 6]>,
) -> f64 {
    let n = xs.len() as f64;
    let (mut s, mut c, mut tri) = (0.0, 0.0, 0.0);
    let mut always = 0.0;
    scratch.clear();
    members.clear();
    for (&x, &d) in xs.iter().zip(deltas) {
        let x = x.rem_euclid(TAU);
        let (sx, cx) = x.sin_cos();
        s += sx;
        c += cx;
        tri += 2.0 * (d.min(PI) / 2.0).sin();
        if d >= PI {
            always += 1.0;
        } else {
            let (sm, cm) = (x - d).sin_cos();
            let (sp, cp) = (x + d).sin_cos();
            members.push([x, d, cm, sm, cp, sp]);
            scratch.extend([wrap2pi(x - d), wrap2pi(x + d), wrap2pi(x + PI)]);
        }
    }
    let triangle = s.hypot(c) + tri;
    if scratch.is_empty() || triangle <= always + 1e-12 {
        return n.min(triangle);
    }
    scratch.sort_by(f64::total_cmp);
    let nb = scratch.len();
    let mut sweep: f64 = 0.0;
    for b in 0..nb {
        let (a0, a1) = (
            scratch[b],
            if b + 1 < nb {
                scratch[b + 1]
            } else {
                scratch[0] + TAU
            },
        );
        let w = 0.5 * (a0 + a1);
        let (mut p, mut cs, mut sn) = (always, 0.0, 0.0);
        for m in members.iter() {
            // x - w in (-pi, pi]: both are in [0, 2 pi + pi).
            let mut a = m[0] - w;
            if a > PI {
                a -= TAU;
            } else if a <= -PI {
                a += TAU;
            }
            if a <= -PI {
                a += TAU;
            }
            if a.abs() <= m[1] {
                p += 1.0;
            } else if a > 0.0 {
                cs += m[2];
                sn += m[3];
            } else {
                cs += m[4];
                sn += m[5];
            }
        }
        sweep = sweep.max(p + cs.hypot(sn));
    }
    n.min(triangle).min(sweep)
}

struct Bounder<'a> {
    model: &'a Model,
    grid: &'a Grid,
    margin: f64,
    xs: Vec<f64>,
    ds: Vec<f64>,
    scratch: Vec<f64>,
    members: Vec<[f64; 6]>,
}

impl Bounder<'_> {
    /// (upper bound over the box, `Z` at the centre node in f64, axis to split).
    fn bound(&mut self, lo: [usize; 3], hi: [usize; 3]) -> (f64, f64, usize) {
        let g = self.grid;
        let axes = [g.psi, g.theta, g.phi];
        let mut c = [0i64; 3];
        let mut h = [0.0; 3];
        for a in 0..3 {
            let cc = (lo[a] + hi[a] - 1) / 2;
            c[a] = cc as i64;
            h[a] = (cc - lo[a]).max(hi[a] - 1 - cc) as f64 * axes[a].step;
        }
        let [psi, theta, phi] = g.angles(c);
        let (ry, rz, rx) = (
            elementary(RotAxis::Y, psi),
            elementary(RotAxis::Z, theta),
            elementary(RotAxis::X, phi),
        );
        let mats = [
            ry * rz * rx,
            dy(psi) * rz * rx,
            ry * dz(theta) * rx,
            ry * rz * dx(phi),
        ];
        let hs = h.iter().sum::<f64>();
        let m = self.model;
        let (nb, nt) = (m.n_baselines(), m.n_terms());
        let mut score = [0.0; 3];
        // Phases and deltas per (i, k), stored at i * nt + k.
        self.xs.resize(nb * nt, 0.0);
        self.ds.resize(nb * nt, 0.0);
        for (i, r) in m.baselines.iter().enumerate() {
            let v: [Vector3<f64>; 4] = mats.map(|mm| mm * r);
            for a in 0..3 {
                score[a] += v[a + 1].norm() * h[a];
            }
            let quad = 0.5 * r.norm() * hs * hs;
            for (k, gk) in m.g.iter().enumerate() {
                self.xs[i * nt + k] = m.phase(i, k, &v[0]);
                self.ds[i * nt + k] = gk.dot(&v[1]).abs() * h[0]
                    + gk.dot(&v[2]).abs() * h[1]
                    + gk.dot(&v[3]).abs() * h[2]
                    + gk.norm() * quad;
            }
        }
        let (mut bound, mut zc) = (0.0, 0.0);
        match m.grouping {
            Grouping::PerBaseline => {
                for i in 0..nb {
                    let (x, d) = (
                        &self.xs[i * nt..(i + 1) * nt],
                        &self.ds[i * nt..(i + 1) * nt],
                    );
                    bound += modulus_bound(x, d, &mut self.scratch, &mut self.members);
                    let (s, cc) = x.iter().fold((0.0, 0.0), |(s, c), x| {
                        let (sx, cx) = x.sin_cos();
                        (s + sx, c + cx)
                    });
                    zc += s.hypot(cc);
                }
            }
            Grouping::PerSatellite => {
                let mut x = vec![0.0; nb + 1];
                let mut d = vec![0.0; nb + 1];
                for k in 0..nt {
                    for i in 0..nb {
                        x[i + 1] = self.xs[i * nt + k];
                        d[i + 1] = self.ds[i * nt + k];
                    }
                    bound += modulus_bound(&x, &d, &mut self.scratch, &mut self.members);
                    let (s, cc) = x.iter().fold((0.0, 0.0), |(s, c), x| {
                        let (sx, cx) = x.sin_cos();
                        (s + sx, c + cx)
                    });
                    zc += s.hypot(cc);
                }
            }
        }
        let split = (0..3)
            .filter(|&a| hi[a] - lo[a] > 1)
            .max_by(|&a, &b| score[a].total_cmp(&score[b]))
            .unwrap_or(0);
        (bound + self.margin, zc, split)
    }
}

/// The grid maximum by best-first branch-and-bound: the same cell and `Z` as
/// [`super::exhaustive_max`] (same float32 kernel at the leaves, same tie rule), usually from far fewer
/// cells. Sequential.
///
/// # Arguments
/// * `model` - preprocessed measurements and statistic.
/// * `grid` - the cells (radians).
///
/// # Errors
/// [`crate::Error::OutOfRange`] when the grid step is coarser than [`Model::max_step`].
pub fn branch_and_bound(model: &Model, grid: &Grid) -> Result<(GridMax, BnbStats)> {
    check_step(model, grid)?;
    let xmax = PI
        + model.baselines.iter().map(|r| r.norm()).fold(0.0, f64::max)
            * model.g.iter().map(|g| g.norm()).fold(0.0, f64::max);
    let (groups, members) = model.groups();
    let n_exp = (groups * members) as f64;
    let margin = n_exp * (1e-5 + 1e-6 * xmax);
    let mut b = Bounder {
        model,
        grid,
        margin,
        xs: vec![],
        ds: vec![],
        scratch: vec![],
        members: vec![],
    };
    let mut stats = BnbStats::default();
    let mut lower = f64::NEG_INFINITY;
    let mut best = (f32::NEG_INFINITY, usize::MAX);
    let mut heap = BinaryHeap::new();
    let root_hi = [grid.psi.len, grid.theta.len, grid.phi.len];
    let (bound, zc, split) = b.bound([0; 3], root_hi);
    stats.boxes_bounded += 1;
    lower = lower.max(zc - margin);
    heap.push(Cube {
        lo: [0; 3],
        hi: root_hi,
        bound,
        split,
    });
    let (cps, sps) = heading_tables((0..grid.psi.len as i64).map(|p| grid.psi.angle(p)));
    let mut coef = RowCoef::new(model);
    let mut buf = Vec::new();
    let np = grid.psi.len;
    while let Some(cube) = heap.pop() {
        if cube.bound < lower {
            break;
        }
        let size: usize = (0..3).map(|a| cube.hi[a] - cube.lo[a]).product();
        if size <= LEAF_CELLS {
            let (p0, p1) = (cube.lo[0], cube.hi[0]);
            let (c, s) = (&cps[p0..p1], &sps[p0..p1]);
            let mut cl = c.to_vec();
            let mut sl = s.to_vec();
            let padded = cl.len().div_ceil(super::kernel::LANES) * super::kernel::LANES;
            cl.resize(padded, 1.0);
            sl.resize(padded, 0.0);
            buf.resize(p1 - p0, 0.0);
            for t in cube.lo[1]..cube.hi[1] {
                for f in cube.lo[2]..cube.hi[2] {
                    coef.fill(model, grid.theta.angle(t as i64), grid.phi.angle(f as i64));
                    eval_row(&coef, &cl, &sl, &mut buf);
                    for (j, &z) in buf.iter().enumerate() {
                        best = better(best, (z, (t * grid.phi.len + f) * np + p0 + j));
                    }
                }
            }
            stats.leaf_cells += size as u64;
            lower = lower.max(best.0 as f64);
            continue;
        }
        let a = cube.split;
        let mid = (cube.lo[a] + cube.hi[a]) / 2;
        let (mut hi1, mut lo2) = (cube.hi, cube.lo);
        hi1[a] = mid;
        lo2[a] = mid;
        for (lo, hi) in [(cube.lo, hi1), (lo2, cube.hi)] {
            let (bound, zc, split) = b.bound(lo, hi);
            stats.boxes_bounded += 1;
            lower = lower.max(zc - margin);
            if bound >= lower {
                heap.push(Cube {
                    lo,
                    hi,
                    bound,
                    split,
                });
            }
        }
    }
    Ok((
        GridMax {
            index: grid.unflatten(best.1),
            z: best.0,
            cells_evaluated: stats.boxes_bounded + stats.leaf_cells,
        },
        stats,
    ))
}
