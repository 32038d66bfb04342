//! The estimate: grid maximum by the chosen search, then the three-point parabolic refinement (16) and,
//! by default, a Newton polish of the continuous maximum of `Z`.

use std::f64::consts::{PI, TAU};

use nalgebra::{Matrix3, SymmetricEigen, Vector3};

use crate::error::Result;

use super::bnb::branch_and_bound;
use super::grid::Grid;
use super::model::{dcm_normal_from_body, Model};
use super::search::{evaluate_cells, exhaustive_max, GridMax, MAX_CELLS};
use crate::rotation::euler::YZX;

/// How the grid maximum is found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Search {
    /// Every cell, in parallel.
    Exhaustive,
    /// Branch-and-bound through per-baseline direction sets ([`branch_and_bound`]): the same grid maximum
    /// from far fewer cells; falls back to the exhaustive pass where it cannot gain.
    BranchAndBound,
    /// Whichever is faster: [`Search::BranchAndBound`] for the ambiguity function on grids of at least
    /// [`AUTO_MIN_CELLS`] cells whose step is at most [`AUTO_MAX_STEP`] times [`Model::max_step`], and on
    /// any grid over [`MAX_CELLS`] (the exhaustive pass refuses those), [`Search::Exhaustive`] otherwise
    /// (same result either way).
    Auto,
}

/// Smallest grid [`Search::Auto`] searches by branch-and-bound. Measured (`benches/likelihood.rs`,
/// `docs/likelihood_search.md`): on the paper's 0.71 m triangle the 1.5 deg grid (7.0e6 cells) is 18-23x
/// faster by branch-and-bound with 0.1 rad noise; below about 10^6 cells its fixed costs (direction
/// search, one pass over the rows) weigh more than the exhaustive pass.
pub const AUTO_MIN_CELLS: usize = 1 << 22;

/// Coarsest step, as a fraction of [`Model::max_step`] (`lambda / (2 L)`), that [`Search::Auto`] searches
/// by branch-and-bound. Coarser grids leave their best cell further from the perfect alignment, which
/// weakens the direction test. Measured: a 5 m triangle at 0.5 deg (0.46 of the coarsest step, 0.1 rad
/// noise) 12x (1 thread) and 27x (2 threads) faster by branch-and-bound; the paper's 1.5 deg grid is 0.2.
/// Steps up to the coarsest accepted one were not measured.
pub const AUTO_MAX_STEP: f64 = 0.5;

/// How the grid maximum is refined between grid nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refine {
    /// The grid node itself.
    None,
    /// Eq. (16): one three-point parabola per axis. The axes of eq. (5) are coupled (the peak of `Z` is
    /// an ellipsoid tilted in (psi, theta, phi)), so per-axis parabolas leave errors of a fraction of a
    /// step even without noise.
    Parabolic,
    /// Eq. (16), then Newton's method on the f64 statistic over the grid's axes with the full Hessian
    /// (finite differences), inside a trust region of one grid step: the continuous maximum of `Z`,
    /// i.e. the maximum-likelihood estimate itself.
    Newton,
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
pub fn parabolic(model: &Model, grid: &Grid, gm: &GridMax) -> ([f64; 3], u64) {
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

/// Finite-difference steps (rad) for the gradient and the Hessian of `Z`: far below the main lobe
/// (`lambda / L`, about 15 deg for the paper's array) and far above f64 rounding of `Z`.
const GRAD_STEP: f64 = 1e-6;
const HESS_STEP: f64 = 1e-4;

/// Newton's method for the local maximum of the f64 statistic from `start` (radians), over the axes the
/// grid searches (a 2-D grid keeps its fixed angle). Directions of non-negative curvature (an unobservable
/// rotation, gimbal lock) are left alone; every accepted step raises `Z`; the result stays within two grid
/// steps of `start` or `start` is returned. Returns the angles and the number of `Z` evaluations.
pub fn polish(model: &Model, grid: &Grid, start: [f64; 3]) -> ([f64; 3], u64) {
    let active: Vec<usize> = [grid.psi, grid.theta, grid.phi]
        .iter()
        .enumerate()
        .filter(|(_, a)| a.len > 1)
        .map(|(i, _)| i)
        .collect();
    let step = grid.step();
    let mut evals = 0u64;
    let mut z = |a: [f64; 3]| {
        evals += 1;
        model.z_f64(a[0], a[1], a[2])
    };
    let shifted = |a: [f64; 3], d: &[(usize, f64)]| {
        let mut b = a;
        for &(i, h) in d {
            b[i] += h;
        }
        b
    };
    let mut a = start;
    let mut za = z(a);
    for _ in 0..30 {
        let (mut g, mut h) = (Vector3::zeros(), Matrix3::from_diagonal_element(-1.0));
        for &i in &active {
            g[i] = (z(shifted(a, &[(i, GRAD_STEP)])) - z(shifted(a, &[(i, -GRAD_STEP)])))
                / (2.0 * GRAD_STEP);
            for &j in active.iter().filter(|&&j| j >= i) {
                let e = HESS_STEP;
                let v = (z(shifted(a, &[(i, e), (j, e)]))
                    - z(shifted(a, &[(i, e), (j, -e)]))
                    - z(shifted(a, &[(i, -e), (j, e)]))
                    + z(shifted(a, &[(i, -e), (j, -e)])))
                    / (4.0 * e * e);
                (h[(i, j)], h[(j, i)]) = (v, v);
            }
        }
        let eig = SymmetricEigen::new(h);
        let scale = eig.eigenvalues.amax();
        let mut d = Vector3::zeros();
        for (k, &l) in eig.eigenvalues.iter().enumerate() {
            if l < -1e-9 * scale {
                let v = eig.eigenvectors.column(k);
                d -= v * (v.dot(&g) / l);
            }
        }
        if d.norm() > step {
            d *= step / d.norm();
        }
        let mut accepted = false;
        for _ in 0..20 {
            let b = [a[0] + d[0], a[1] + d[1], a[2] + d[2]];
            let zb = z(b);
            if zb >= za {
                (a, za, accepted) = (b, zb, true);
                break;
            }
            d *= 0.5;
        }
        if !accepted || d.norm() < 1e-10 {
            break;
        }
    }
    let moved = (0..3)
        .map(|i| wrap_pi(a[i] - start[i]).abs())
        .fold(0.0, f64::max);
    if moved > 2.0 * step {
        return (start, evals);
    }
    // Back through the matrix so that pitch stays in [-90, 90] deg and the others in (-180, 180].
    let e = YZX.from_dcm(&dcm_normal_from_body(a[0], a[1], a[2]));
    ([wrap_pi(e[0]), e[1], wrap_pi(e[2])], evals)
}

/// Grid maximum by `search`, refined as `refine` says.
///
/// # Arguments
/// * `model` - preprocessed measurements and statistic.
/// * `grid` - the cells (radians); its step must not exceed [`Model::max_step`].
/// * `search` - exhaustive, branch-and-bound or the faster of the two (same grid maximum).
/// * `refine` - none, eq. (16), or eq. (16) then Newton.
///
/// # Errors
/// [`crate::Error::OutOfRange`] when the grid step is coarser than [`Model::max_step`].
pub fn estimate(model: &Model, grid: &Grid, search: Search, refine: Refine) -> Result<Estimate> {
    let search = match search {
        Search::Auto
            if model.statistic_splits_by_baseline()
                && (grid.len() > MAX_CELLS
                    || (grid.len() >= AUTO_MIN_CELLS
                        && grid.step() <= AUTO_MAX_STEP * model.max_step())) =>
        {
            Search::BranchAndBound
        }
        Search::Auto => Search::Exhaustive,
        s => s,
    };
    let mut gm = match search {
        Search::BranchAndBound => branch_and_bound(model, grid)?.0,
        _ => exhaustive_max(model, grid)?,
    };
    let g = grid.angles(gm.index.map(|i| i as i64));
    let grid_angles_rad = [wrap_pi(g[0]), g[1], wrap_pi(g[2])];
    let angles_rad = match refine {
        Refine::None => grid_angles_rad,
        Refine::Parabolic | Refine::Newton => {
            let (a, extra) = parabolic(model, grid, &gm);
            gm.cells_evaluated += extra;
            if refine == Refine::Newton {
                polish(model, grid, a).0
            } else {
                a
            }
        }
    };
    Ok(Estimate {
        angles_rad,
        grid_max: gm,
        grid_angles_rad,
        step_rad: grid.step(),
    })
}
