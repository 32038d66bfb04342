//! The estimate: grid maximum by the chosen search, then the three-point parabolic refinement (16).

use std::f64::consts::{PI, TAU};

use crate::error::Result;

use super::bnb::branch_and_bound;
use super::grid::Grid;
use super::model::Model;
use super::search::{evaluate_cells, exhaustive_max, GridMax};

/// How the grid maximum is found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Search {
    /// Every cell, in parallel.
    Exhaustive,
    /// Best-first branch-and-bound with a proven upper bound of `Z` over boxes of cells: the same grid
    /// maximum from far fewer cells.
    BranchAndBound,
}

/// An attitude estimate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// (psi, theta, phi) of eq. (5), radians, refined when asked; psi and phi in (-pi, pi].
    pub angles_rad: [f64; 3],
    /// The grid maximum.
    pub grid_max: GridMax,
    /// Angles of the grid maximum, radians.
    pub grid_angles_rad: [f64; 3],
    /// Grid step, radians.
    pub step_rad: f64,
}

fn wrap_pi(x: f64) -> f64 {
    let w = (x + PI).rem_euclid(TAU) - PI;
    if w <= -PI {
        w + TAU
    } else {
        w
    }
}

/// Eq. (16): the parabola through the maximum and its two neighbours along each axis, with wrap-around
/// in heading and roll; along pitch the refinement is skipped at +-90 deg. The offset is clamped to half a
/// step (and dropped where the three points are not concave). Returns refined angles (radians) and the
/// number of extra cells evaluated.
pub fn refine(model: &Model, grid: &Grid, gm: &GridMax) -> ([f64; 3], u64) {
    let c = gm.index.map(|i| i as i64);
    let mut angles = grid.angles(c);
    let axes = [grid.psi, grid.theta, grid.phi];
    let mut cells = 0;
    for (a, axis) in axes.iter().enumerate() {
        let g = axis.first + c[a];
        let interior = match axis.period {
            Some(_) => true,
            None => axis.len > 1 && g >= 1 && g < (std::f64::consts::PI / axis.step).round() as i64,
        };
        if !interior || (axis.period.is_none() && axis.len == 1) {
            continue;
        }
        let (mut lo, mut hi) = (c, c);
        lo[a] -= 1;
        hi[a] += 1;
        let z = evaluate_cells(model, grid, &[lo, hi]);
        cells += 2;
        let (zm, z0, zp) = (z[0] as f64, gm.z as f64, z[1] as f64);
        let den = zm - 2.0 * z0 + zp;
        if den < 0.0 {
            let off = (0.5 * (zm - zp) / den).clamp(-0.5, 0.5);
            angles[a] += off * axis.step;
        }
    }
    ([wrap_pi(angles[0]), angles[1], wrap_pi(angles[2])], cells)
}

/// Grid maximum by `search`, refined by eq. (16) when `refine_max`.
///
/// # Arguments
/// * `model` - preprocessed measurements and statistic.
/// * `grid` - the cells (radians); its step must not exceed [`Model::max_step`].
/// * `search` - exhaustive or branch-and-bound (same grid maximum).
/// * `refine_max` - apply eq. (16).
///
/// # Errors
/// [`crate::Error::OutOfRange`] when the grid step is coarser than [`Model::max_step`].
pub fn estimate(model: &Model, grid: &Grid, search: Search, refine_max: bool) -> Result<Estimate> {
    let mut gm = match search {
        Search::Exhaustive => exhaustive_max(model, grid)?,
        Search::BranchAndBound => branch_and_bound(model, grid)?.0,
    };
    let g = grid.angles(gm.index.map(|i| i as i64));
    let grid_angles_rad = [wrap_pi(g[0]), g[1], wrap_pi(g[2])];
    let angles_rad = if refine_max {
        let (a, extra) = refine(model, grid, &gm);
        gm.cells_evaluated += extra;
        a
    } else {
        grid_angles_rad
    };
    Ok(Estimate {
        angles_rad,
        grid_max: gm,
        grid_angles_rad,
        step_rad: grid.step(),
    })
}
