//! Exhaustive evaluation: the whole `Z` array, or the streamed grid maximum without storing it.

use rayon::prelude::*;

use crate::error::{Error, Result};

use super::grid::Grid;
use super::kernel::{eval_row, heading_tables, RowCoef, LANES};
use super::model::Model;

/// The grid maximum: cell `(p, t, f)` (indices into the grid's axes), its `Z` (float32, as evaluated by
/// the kernel), and how many cells were evaluated to find it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridMax {
    /// Cell indices (heading, pitch, roll).
    pub index: [usize; 3],
    /// `Z` at that cell.
    pub z: f32,
    /// Cells whose `Z` was evaluated.
    pub cells_evaluated: u64,
}

/// Most cells the exhaustive pass (and [`evaluate_grid`]) evaluates: the work it does is one kernel cell
/// per grid cell (2^31 cells of f32 are 8 GiB, about half a minute of the kernel on 2 cores). Larger
/// grids are searched by [`super::branch_and_bound`], whose limit counts the work it does.
pub const MAX_CELLS: usize = 1 << 31;

/// Rejects grids of more than [`MAX_CELLS`] cells for a pass over every cell.
pub(crate) fn check_cells(grid: &Grid) -> Result<()> {
    if grid.len() > MAX_CELLS {
        return Err(Error::out_of_range(
            "step_deg",
            format!(
                "a step of {:.3e} deg gives {:.3e} cells, over the 2^31 a pass over every cell evaluates: \
                 coarsen the step, narrow the window, or search by branch-and-bound (search='auto')",
                grid.step().to_degrees(),
                grid.len() as f64
            ),
        ));
    }
    Ok(())
}

/// Rejects grids whose step is coarser than [`Model::max_step`].
pub(crate) fn check_step(model: &Model, grid: &Grid) -> Result<()> {
    if grid.step() > model.max_step() * (1.0 + 1e-9) {
        return Err(Error::out_of_range(
            "step_deg",
            format!(
                "a step of {:.4} deg is coarser than half the main lobe, lambda / (2 L) = {:.4} deg",
                grid.step().to_degrees(),
                model.max_step().to_degrees()
            ),
        ));
    }
    Ok(())
}

/// `(z, flat index)` ordering shared by every search: larger `z`, then the lower index.
pub(crate) fn better(a: (f32, usize), b: (f32, usize)) -> (f32, usize) {
    if a.0 > b.0 || (a.0 == b.0 && a.1 < b.1) {
        a
    } else {
        b
    }
}

/// The whole `Z` array, float32, flat index `(t * n_phi + f) * n_psi + p`; rows in parallel (rayon: the
/// thread count follows `RAYON_NUM_THREADS`).
///
/// # Arguments
/// * `model` - preprocessed measurements and statistic.
/// * `grid` - the cells (radians).
///
/// # Errors
/// [`Error::OutOfRange`] when the grid step is coarser than [`Model::max_step`] or the grid holds over
/// [`MAX_CELLS`] cells.
pub fn evaluate_grid(model: &Model, grid: &Grid) -> Result<Vec<f32>> {
    check_step(model, grid)?;
    check_cells(grid)?;
    let (cps, sps) = heading_tables((0..grid.psi.len as i64).map(|p| grid.psi.angle(p)));
    let np = grid.psi.len;
    let mut z = vec![0.0f32; grid.len()];
    z.par_chunks_mut(np).enumerate().for_each_init(
        || RowCoef::new(model),
        |coef, (r, out)| {
            let (t, f) = (r / grid.phi.len, r % grid.phi.len);
            coef.fill(model, grid.theta.angle(t as i64), grid.phi.angle(f as i64));
            eval_row(coef, &cps, &sps, out);
        },
    );
    Ok(z)
}

/// The grid maximum by exhaustive evaluation, streamed: rows in parallel, no `Z` array. Ties go to the
/// lowest flat index.
///
/// # Arguments
/// * `model` - preprocessed measurements and statistic.
/// * `grid` - the cells (radians).
///
/// # Errors
/// [`Error::OutOfRange`] when the grid step is coarser than [`Model::max_step`] or the grid holds over
/// [`MAX_CELLS`] cells.
pub fn exhaustive_max(model: &Model, grid: &Grid) -> Result<GridMax> {
    check_step(model, grid)?;
    check_cells(grid)?;
    let (cps, sps) = heading_tables((0..grid.psi.len as i64).map(|p| grid.psi.angle(p)));
    let np = grid.psi.len;
    let rows = grid.theta.len * grid.phi.len;
    let best = (0..rows)
        .into_par_iter()
        .with_min_len(4)
        .map_init(
            || (RowCoef::new(model), vec![0.0f32; np]),
            |(coef, buf), r| {
                let (t, f) = (r / grid.phi.len, r % grid.phi.len);
                coef.fill(model, grid.theta.angle(t as i64), grid.phi.angle(f as i64));
                eval_row(coef, &cps, &sps, buf);
                let mut best = (f32::NEG_INFINITY, usize::MAX);
                for (p, &z) in buf.iter().enumerate() {
                    if z > best.0 {
                        best = (z, p);
                    }
                }
                (best.0, r * np + best.1)
            },
        )
        .reduce(|| (f32::NEG_INFINITY, usize::MAX), better);
    Ok(GridMax {
        index: grid.unflatten(best.1),
        z: best.0,
        cells_evaluated: grid.len() as u64,
    })
}

/// `Z` at lattice cells `(p, t, f)` of `grid` (indices may leave the grid: neighbours), with the same
/// kernel as the full pass.
pub fn evaluate_cells(model: &Model, grid: &Grid, cells: &[[i64; 3]]) -> Vec<f32> {
    let mut coef = RowCoef::new(model);
    cells
        .iter()
        .map(|c| {
            let (cps, sps) = heading_tables(std::iter::once(grid.psi.angle(c[0])));
            coef.fill(model, grid.theta.angle(c[1]), grid.phi.angle(c[2]));
            let mut out = [0.0f32];
            eval_row(&coef, &cps, &sps, &mut out);
            out[0]
        })
        .collect()
}

/// The kernel over chosen heading nodes of one row, with the heading tables of the full pass: each cell's
/// `Z` is bit for bit the value [`exhaustive_max`] sees (the kernel works lane by lane).
pub(crate) struct RowNodes<'a> {
    model: &'a Model,
    grid: &'a Grid,
    cps: &'a [f32],
    sps: &'a [f32],
    coef: RowCoef,
    c: Vec<f32>,
    s: Vec<f32>,
    out: Vec<f32>,
    /// Cells evaluated so far.
    pub cells: u64,
}

impl<'a> RowNodes<'a> {
    /// `cps`, `sps`: [`heading_tables`] of the grid's heading axis.
    pub fn new(model: &'a Model, grid: &'a Grid, cps: &'a [f32], sps: &'a [f32]) -> Self {
        RowNodes {
            model,
            grid,
            cps,
            sps,
            coef: RowCoef::new(model),
            c: vec![],
            s: vec![],
            out: vec![],
            cells: 0,
        }
    }

    /// The best `(z, flat index)` among heading nodes `nodes` (local indices) of row `(t, f)`, by
    /// [`better`]; `(-inf, usize::MAX)` for no node.
    pub fn best(&mut self, t: usize, f: usize, nodes: &[usize]) -> (f32, usize) {
        let mut best = (f32::NEG_INFINITY, usize::MAX);
        if nodes.is_empty() {
            return best;
        }
        let g = self.grid;
        self.coef
            .fill(self.model, g.theta.angle(t as i64), g.phi.angle(f as i64));
        let padded = nodes.len().div_ceil(LANES) * LANES;
        self.c.clear();
        self.s.clear();
        self.c.extend(nodes.iter().map(|&p| self.cps[p]));
        self.s.extend(nodes.iter().map(|&p| self.sps[p]));
        self.c.resize(padded, 1.0);
        self.s.resize(padded, 0.0);
        self.out.resize(nodes.len(), 0.0);
        eval_row(&self.coef, &self.c, &self.s, &mut self.out);
        let base = (t * g.phi.len + f) * g.psi.len;
        for (&p, &z) in nodes.iter().zip(&self.out) {
            best = better(best, (z, base + p));
        }
        self.cells += nodes.len() as u64;
        best
    }
}
