//! Exact branch-and-bound for the grid maximum of the ambiguity function, through per-baseline
//! direction sets.
//!
//! With the per-baseline grouping `Z(R) = sum_i F_i(R r_i)`, each `F_i` a modulus of `n` unit terms, so
//! `F_i <= n`. A cell can only match an incumbent `Z*` if, for every baseline, `F_i(R r_i) >= tau_i =
//! Z* - margin - (m - 1) n` (the `m - 1` other moduli give at most `n` each; `margin` is the float32
//! kernel's error, [`super::kernel::kernel_margin`]). Near the maximum `Z*` is close to `m n`, so `tau_i`
//! is close to `n`: each baseline must point almost exactly where all its terms align, a set of tiny
//! spots on its sphere. The search:
//! 1. incumbent, coarse to fine: the kernel on every `c`-th node of each axis (`c` steps span about
//!    half the main lobe, `lambda / (2 L)`), then a hill climb on the fine grid from the best coarse
//!    cells; the incumbent is a real cell with its kernel value;
//! 2. per baseline and in parallel, [`direction_set`]: a 2-D branch-and-bound over direction parameters
//!    that keeps every direction where `F_i` may reach `tau_i` (bound in the module docs there);
//! 3. rows `(theta, phi)` in parallel blocks: a block is dropped when some baseline's elevation range
//!    over it (the centre's elevation +- the block's half-extents in pitch and roll, since each rotation
//!    moves a direction by at most its angle) meets none of that baseline's boxes; in the remaining rows
//!    each box maps to a few heading nodes (`psi = a - beta`), the nodes every baseline allows are
//!    evaluated by the kernel with the full pass's tables.
//!
//! Every cell with kernel `Z >= Z*` is evaluated, by the same kernel code with the same inputs as the
//! exhaustive pass, so the result is the exhaustive maximum bit for bit: the same float32 `Z` and, among
//! equal values, the lowest flat index ([`super::search::better`]). No tolerance enters the comparison.
//!
//! Falls back to [`exhaustive_max`] (same result, [`BnbStats::fallback`]) for the per-satellite
//! statistics (no per-baseline decomposition), when the incumbent leaves the direction test powerless
//! (`n - tau_i >= 2`, i.e. `Z*` more than about 2 below `m n`: very noisy phases), when a phase may
//! exceed the kernel's checked range, or when the direction search tests more than
//! [`box_limit`] boxes.
//!
//! Compared with Teunissen & Massarweh (2025, J. Geodesy 99:28), whose globally convergent ambiguity
//! function algorithm (from the abstract: branch-and-bound with a convex relaxation of the multimodal
//! ambiguity function, bounds obtained by projected gradient descent) bounds the whole function over a
//! region of the unknowns, the bound here is per baseline and combinatorial (an arc-intersection test,
//! then a relaxed modulus with each phase free in its arc), needs no inner optimisation, and is tied to
//! the float32 grid so that the answer is the grid's maximum cell rather than a continuous optimum.

use rayon::prelude::*;

use crate::error::Result;
use crate::rotation::{elementary, Axis as RotAxis};

use super::direction::{direction_set, row_direction, top_bins, Budget, DirBox, Reach};
use super::grid::{Axis, Grid};
use super::kernel::{heading_tables, kernel_margin};
use super::model::{Grouping, Model};
use super::search::{better, check_step, exhaustive_max, GridMax, RowNodes};

/// Work done by [`branch_and_bound`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BnbStats {
    /// Direction boxes tested plus row blocks tested.
    pub boxes_bounded: u64,
    /// Cells evaluated by the float32 kernel (coarse pass, hill climb, candidates).
    pub leaf_cells: u64,
    /// Whether the search fell back to the exhaustive pass (module docs say when).
    pub fallback: bool,
}

/// Rows per side of a block in step 3.
const BLOCK: usize = 8;
/// Coarse stride of the incumbent pass, in units of the coarsest accepted step (half the main lobe).
/// Coarser strides were tried: at 3x the incumbent of a 5 m array landed in a side lobe and the search
/// fell back.
const STRIDE: f64 = 1.5;
/// Coarse cells the hill climb starts from.
const STARTS: usize = 8;

/// Most direction boxes [`branch_and_bound`] tests before it falls back to the exhaustive pass: one per
/// 256 cells. A box costs about as much as 10 to 150 kernel cells (arc test or relaxed bound), so the
/// bounding work stays under about half the exhaustive pass; small grids (under about 10^6 cells
/// for the paper's array) are searched exhaustively.
pub fn box_limit(grid: &Grid) -> u64 {
    grid.len() as u64 / 256
}

/// Local indices of the nodes next to `j` (and `j`) on `axis`, wrapping when it is a full turn.
fn around(axis: &Axis, j: usize) -> Vec<usize> {
    let full = axis.period == Some(axis.len);
    let mut v: Vec<usize> = [-1i64, 0, 1]
        .iter()
        .filter_map(|d| {
            let k = j as i64 + d;
            if full {
                Some(k.rem_euclid(axis.len as i64) as usize)
            } else {
                (0..axis.len as i64).contains(&k).then_some(k as usize)
            }
        })
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// Steepest ascent over the 26 neighbours on the fine grid.
fn climb(rn: &mut RowNodes, grid: &Grid, start: (f32, usize)) -> (f32, usize) {
    let mut cur = start;
    // Each move raises (z, -index) strictly, so the climb ends; the cap only bounds pathological plateaus.
    for _ in 0..grid.len().min(1 << 16) {
        let [p, t, f] = grid.unflatten(cur.1);
        let ps = around(&grid.psi, p);
        let mut best = cur;
        for t2 in around(&grid.theta, t) {
            for &f2 in &around(&grid.phi, f) {
                best = better(best, rn.best(t2, f2, &ps));
            }
        }
        if best == cur {
            break;
        }
        cur = best;
    }
    cur
}

/// Step 1 of the module docs: the incumbent `(z, flat index)` and the cells it cost.
fn incumbent(model: &Model, grid: &Grid, cps: &[f32], sps: &[f32]) -> ((f32, usize), u64) {
    let c = ((STRIDE * model.max_step() / grid.step()).floor() as usize).max(2);
    let ps: Vec<usize> = (0..grid.psi.len).step_by(c).collect();
    let rows: Vec<(usize, usize)> = (0..grid.theta.len)
        .step_by(c)
        .flat_map(|t| (0..grid.phi.len).step_by(c).map(move |f| (t, f)))
        .collect();
    let mut coarse: Vec<((f32, usize), u64)> = rows
        .par_iter()
        .map_init(
            || RowNodes::new(model, grid, cps, sps),
            |rn, &(t, f)| (rn.best(t, f, &ps), ps.len() as u64),
        )
        .collect();
    let mut cells: u64 = coarse.iter().map(|r| r.1).sum();
    coarse.sort_by(|a, b| b.0 .0.total_cmp(&a.0 .0).then(a.0 .1.cmp(&b.0 .1)));
    let climbed: Vec<((f32, usize), u64)> = coarse
        .iter()
        .take(STARTS)
        .collect::<Vec<_>>()
        .par_iter()
        .map(|s| {
            let mut rn = RowNodes::new(model, grid, cps, sps);
            let best = climb(&mut rn, grid, s.0);
            (best, rn.cells)
        })
        .collect();
    let mut best = (f32::NEG_INFINITY, usize::MAX);
    for (b, n) in climbed {
        best = better(best, b);
        cells += n;
    }
    (best, cells)
}

/// Per-thread state of step 3: a node marker that needs no clearing between rows, and per node the
/// bound of the current baseline and the summed deficit `sum_i (n - U_i)` so far.
struct Scan {
    level: Vec<u64>,
    base: u64,
    u: Vec<f64>,
    deficit: Vec<f64>,
    nodes: Vec<usize>,
}

impl Scan {
    fn new(len: usize) -> Self {
        Scan {
            level: vec![0; len],
            base: 0,
            u: vec![0.0; len],
            deficit: vec![0.0; len],
            nodes: vec![],
        }
    }

    /// Heading nodes whose baseline-`i` direction falls in one of `boxes`, among those the previous
    /// baselines of the row kept (`i = 0` starts a row), and whose summed deficit stays within `slack`:
    /// `Z <= sum_i U_i` must reach `Z*`, i.e. `sum_i (n - U_i) <= m n - Z*`. A node may be marked by a
    /// box that only its one-node rounding slack reaches; the largest bound of its boxes is used, which
    /// is at least the bound of the box that holds it.
    #[allow(clippy::too_many_arguments)]
    fn mark(
        &mut self,
        psi: &Axis,
        (i, nb): (usize, usize),
        beta: f64,
        e: f64,
        boxes: &[DirBox],
        n: f64,
        slack: f64,
    ) {
        if i == 0 {
            self.base += nb as u64 + 1;
        }
        let (want, set) = (self.base + i as u64, self.base + i as u64 + 1);
        let mut kept = std::mem::take(&mut self.nodes);
        let prev = kept.len();
        for b in boxes {
            if e < b.e0 - 1e-9 || e > b.e1 + 1e-9 {
                continue;
            }
            // Node g (global) has heading origin + g step; floor and ceil keep one node of slack for
            // rounding (an extra cell is evaluated, never one missed).
            let g0 = ((b.a0 - beta - psi.origin) / psi.step).floor() as i64;
            let g1 = ((b.a1 - beta - psi.origin) / psi.step).ceil() as i64;
            let span = (g1 - g0 + 1).min(psi.period.unwrap_or(usize::MAX) as i64);
            for g in g0..g0 + span {
                let j = g - psi.first;
                let j = match psi.period {
                    Some(p) => j.rem_euclid(p as i64),
                    None => j,
                };
                if !(0..psi.len as i64).contains(&j) {
                    continue;
                }
                let j = j as usize;
                if self.level[j] == set {
                    self.u[j] = self.u[j].max(b.bound);
                } else if (i == 0) || self.level[j] == want {
                    self.level[j] = set;
                    self.u[j] = b.bound;
                    if i == 0 {
                        self.deficit[j] = 0.0;
                        kept.push(j);
                    }
                }
            }
        }
        // For i > 0 the candidates are the previous baselines' nodes that this one marked too.
        let start = if i == 0 { prev } else { 0 };
        let mut out = Vec::with_capacity(kept.len());
        for &j in &kept[start..] {
            if self.level[j] != set {
                continue;
            }
            self.deficit[j] += n - self.u[j];
            if self.deficit[j] <= slack {
                out.push(j);
            } else {
                self.level[j] = 0;
            }
        }
        self.nodes = out;
    }
}

/// Centre row of a block and how far (radians) any baseline direction of its rows can be from the
/// centre's: each rotation moves a direction by at most its angle.
fn block_centre(grid: &Grid, tr: (usize, usize), fr: (usize, usize)) -> (usize, usize, f64) {
    let tc = (tr.0 + tr.1 - 1) / 2;
    let fc = (fr.0 + fr.1 - 1) / 2;
    let ht = (tc - tr.0).max(tr.1 - 1 - tc) as f64 * grid.theta.step;
    let hf = (fc - fr.0).max(fr.1 - 1 - fc) as f64 * grid.phi.step;
    (tc, fc, ht + hf + 1e-9)
}

/// `Rz(theta) Rx(phi)` of row `(t, f)`, as the kernel's row coefficients build it.
fn row_rotation(grid: &Grid, t: usize, f: usize) -> nalgebra::Matrix3<f64> {
    elementary(RotAxis::Z, grid.theta.angle(t as i64))
        * elementary(RotAxis::X, grid.phi.angle(f as i64))
}

/// Per baseline, the top direction boxes some cell of the grid points it into: around each block's
/// centre direction, elevation +- the block's reach and azimuth +- reach / cos(latitude bound), over
/// the headings of the grid.
fn reaches(model: &Model, grid: &Grid, blocks: &[Block]) -> Vec<Reach> {
    let psi = &grid.psi;
    let full = psi.period == Some(psi.len);
    let (p_lo, p_hi) = (psi.angle(0), psi.angle(psi.len as i64 - 1));
    let whole = full
        && grid.phi.period == Some(grid.phi.len)
        && grid.theta.angle(0) <= -std::f64::consts::FRAC_PI_2 + 1e-12
        && grid.theta.angle(grid.theta.len as i64 - 1) >= std::f64::consts::FRAC_PI_2 - 1e-12;
    let mut out: Vec<Reach> = (0..model.n_baselines())
        .map(|i| Reach::new(top_bins(model, i), whole))
        .collect();
    if whole {
        return out;
    }
    for &(tr, fr) in blocks {
        let (tc, fc, reach) = block_centre(grid, tr, fr);
        let m = row_rotation(grid, tc, fc);
        for (r, set) in model.baselines.iter().zip(out.iter_mut()) {
            let (beta, e) = row_direction(&(m * r), r.norm());
            let lat = e.abs() + reach;
            let (a_lo, a_hi) = if full || lat >= std::f64::consts::FRAC_PI_2 - 1e-6 {
                (0.0, std::f64::consts::TAU)
            } else {
                let ra = reach / lat.cos();
                (p_lo + beta - ra, p_hi + beta + ra)
            };
            set.add(a_lo, a_hi, e - reach, e + reach);
        }
    }
    out
}

/// Pitch and roll index ranges of a block of rows.
type Block = ((usize, usize), (usize, usize));

/// Step 3 over one block of rows: the best candidate cell and the cells evaluated.
#[allow(clippy::too_many_arguments)]
fn scan_block(
    model: &Model,
    grid: &Grid,
    sets: &[Vec<DirBox>],
    slack: f64,
    rn: &mut RowNodes,
    scan: &mut Scan,
    t_range: (usize, usize),
    f_range: (usize, usize),
) -> (f32, usize) {
    let mut best = (f32::NEG_INFINITY, usize::MAX);
    let (tc, fc, reach) = block_centre(grid, t_range, f_range);
    let mc = row_rotation(grid, tc, fc);
    let mut local: Vec<Vec<DirBox>> = Vec::with_capacity(sets.len());
    for (r, set) in model.baselines.iter().zip(sets) {
        let (_, ec) = row_direction(&(mc * r), r.norm());
        let near: Vec<DirBox> = set
            .iter()
            .filter(|b| b.e1 >= ec - reach && b.e0 <= ec + reach)
            .copied()
            .collect();
        if near.is_empty() {
            return best;
        }
        local.push(near);
    }
    for t in t_range.0..t_range.1 {
        for f in f_range.0..f_range.1 {
            let m = row_rotation(grid, t, f);
            for (i, (r, near)) in model.baselines.iter().zip(&local).enumerate() {
                let (beta, e) = row_direction(&(m * r), r.norm());
                let n = model.n_terms() as f64;
                scan.mark(&grid.psi, (i, local.len()), beta, e, near, n, slack);
                if scan.nodes.is_empty() {
                    break;
                }
            }
            if !scan.nodes.is_empty() {
                scan.nodes.sort_unstable();
                best = better(best, rn.best(t, f, &scan.nodes));
            }
        }
    }
    best
}

/// The grid maximum by branch-and-bound (module docs): the same cell and `Z` as [`exhaustive_max`],
/// bit for bit, from far fewer cells. Parallel (rayon: the thread count follows `RAYON_NUM_THREADS`).
///
/// # Arguments
/// * `model` - preprocessed measurements and statistic.
/// * `grid` - the cells (radians).
///
/// # Errors
/// [`crate::Error::OutOfRange`] when the grid step is coarser than [`Model::max_step`].
pub fn branch_and_bound(model: &Model, grid: &Grid) -> Result<(GridMax, BnbStats)> {
    branch_and_bound_limited(model, grid, box_limit(grid))
}

/// [`branch_and_bound`] with at most `limit` direction boxes before the exhaustive fallback.
pub(crate) fn branch_and_bound_limited(
    model: &Model,
    grid: &Grid,
    limit: u64,
) -> Result<(GridMax, BnbStats)> {
    check_step(model, grid)?;
    let exhaustive = |boxes: u64, cells: u64| -> Result<(GridMax, BnbStats)> {
        let gm = exhaustive_max(model, grid)?;
        let stats = BnbStats {
            boxes_bounded: boxes,
            leaf_cells: cells + gm.cells_evaluated,
            fallback: true,
        };
        Ok((
            GridMax {
                cells_evaluated: stats.boxes_bounded + stats.leaf_cells,
                ..gm
            },
            stats,
        ))
    };
    let margin = match (model.grouping, kernel_margin(model)) {
        (Grouping::PerBaseline, Some(m)) => m,
        _ => return exhaustive(0, 0),
    };
    let (cps, sps) = heading_tables((0..grid.psi.len as i64).map(|p| grid.psi.angle(p)));
    let (inc, mut cells) = incumbent(model, grid, &cps, &sps);
    let (nb, n) = (model.n_baselines(), model.n_terms() as f64);
    // 1e-6: f64 rounding of the direction of a node (|dF| <= n |g| |r| 1e-15) with room to spare.
    let tau = inc.0 as f64 - margin - (nb - 1) as f64 * n - 1e-6;
    let slack = n - tau;
    let blocks: Vec<Block> = (0..grid.theta.len)
        .step_by(BLOCK)
        .flat_map(|t| {
            (0..grid.phi.len).step_by(BLOCK).map(move |f| {
                (
                    (t, (t + BLOCK).min(grid.theta.len)),
                    (f, (f + BLOCK).min(grid.phi.len)),
                )
            })
        })
        .collect();
    let reach = reaches(model, grid, &blocks);
    let budget = Budget::new(limit);
    let h_min = 0.5 * grid.step();
    let mut sets = Vec::with_capacity(nb);
    for (i, r) in reach.iter().enumerate() {
        match direction_set(model, i, tau, h_min, r, &budget) {
            Some(s) => sets.push(s),
            None => return exhaustive(budget.used(), cells),
        }
    }
    let (best, leaf) = blocks
        .par_iter()
        .map_init(
            || {
                (
                    RowNodes::new(model, grid, &cps, &sps),
                    Scan::new(grid.psi.len),
                )
            },
            |(rn, scan), &(tr, fr)| {
                let before = rn.cells;
                let b = scan_block(model, grid, &sets, slack, rn, scan, tr, fr);
                (b, rn.cells - before)
            },
        )
        .reduce(
            || ((f32::NEG_INFINITY, usize::MAX), 0),
            |a, b| (better(a.0, b.0), a.1 + b.1),
        );
    cells += leaf;
    let best = better(best, inc);
    let stats = BnbStats {
        boxes_bounded: budget.used() + blocks.len() as u64,
        leaf_cells: cells,
        fallback: false,
    };
    Ok((
        GridMax {
            index: grid.unflatten(best.1),
            z: best.0,
            cells_evaluated: stats.boxes_bounded + stats.leaf_cells,
        },
        stats,
    ))
}
