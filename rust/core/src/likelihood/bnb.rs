//! Exact branch-and-bound for the grid maximum of the ambiguity function, through per-baseline
//! direction sets.
//!
//! With the per-baseline grouping `Z(R) = sum_i F_i(R r_i)`, each `F_i` a modulus of `n` unit terms, so
//! `F_i <= n`. The search works towards a target `T`: it evaluates every cell whose kernel `Z` may reach
//! `T`, so if the best of them reaches `T` it is the grid maximum (every cell at or above it, ties
//! included, was evaluated); otherwise `T` is lowered and the search repeated. A cell can only reach `T`
//! if, for every baseline, `F_i(R r_i) >= tau = T - margin - (m - 1) n` (the `m - 1` other moduli give
//! at most `n` each; `margin` is the float32 kernel's error, [`super::kernel::kernel_margin`]), and in
//! fact if `sum_i U_i >= T - margin` for upper bounds `U_i` of the `F_i`. Near the maximum `T` is close
//! to `m n`, so `tau` is close to `n`: each baseline must point almost exactly where all its terms align,
//! a set of small spots on its sphere. One round:
//! 1. per baseline and in parallel, [`direction_set`]: a 2-D branch-and-bound over direction parameters
//!    that keeps every direction where `F_i` may reach `tau` (bound in the module docs there), as boxes
//!    with their bounds `U_i`, rasterised on bins of the grid's step ([`DirMap`]);
//! 2. rows `(theta, phi)` in parallel: each baseline's elevation picks one raster row (a row where some
//!    baseline's raster row is empty is skipped); the heading nodes of the sparsest baseline's bins are
//!    looked up in the other baselines' rows (`psi = a - beta`), and the nodes with `sum_i U_i >= T -
//!    margin` are evaluated by the kernel with the full pass's tables.
//!
//! The first target is `m n (1 - FIRST_DEFICIT)`; a round that finds nothing at `T` multiplies the
//! deficit `m n - T` by `GROWTH` (or stops at the best value it found, which the next round then
//! certainly reaches). No coarse pass is needed for a first incumbent, and no side lobe can mislead one.
//!
//! Every cell with kernel `Z >= T` is evaluated, by the same kernel code with the same inputs as the
//! exhaustive pass, so the result is the exhaustive maximum bit for bit: the same float32 `Z` and, among
//! equal values, the lowest flat index ([`super::search::better`]). No tolerance enters the comparison.
//!
//! Falls back to [`exhaustive_max`] (same result, [`BnbStats::fallback`]) for the per-satellite
//! statistics (no per-baseline decomposition), when a phase may exceed the kernel's checked range, when
//! the target falls to 0, or when the direction searches test more than [`box_limit`] boxes.
//!
//! Compared with Teunissen & Massarweh (2025, J. Geodesy 99:28), whose globally convergent ambiguity
//! function algorithm (from the abstract: branch-and-bound with a convex relaxation of the multimodal
//! ambiguity function, bounds obtained by projected gradient descent) bounds the whole function over a
//! region of the unknowns, the bound here is per baseline and combinatorial (an arc-intersection test,
//! then a relaxed modulus with each phase free in its arc), needs no inner optimisation, and is tied to
//! the float32 grid so that the answer is the grid's maximum cell rather than a continuous optimum.

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::rotation::{elementary, Axis as RotAxis};

use super::direction::{direction_set, floor, row_direction, top_bins, top_rows, Budget, Reach};
use super::dirmap::{lookup, DirMap};
use super::grid::{Axis, Grid};
use super::kernel::{heading_tables, kernel_margin};
use super::model::{Grouping, Model};
use super::search::{better, check_step, exhaustive_max, GridMax, RowNodes, MAX_CELLS};

/// Work done by [`branch_and_bound`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BnbStats {
    /// Direction boxes tested.
    pub boxes_bounded: u64,
    /// Cells evaluated by the float32 kernel.
    pub leaf_cells: u64,
    /// Rounds of the search (targets tried).
    pub rounds: u32,
    /// Whether the search fell back to the exhaustive pass (module docs say when).
    pub fallback: bool,
}

/// First target's deficit as a fraction of `m n`. Measured grid maxima sit 0.3 % (2 mm phase noise, 1 m
/// array at eq. (15)'s step) to 2 % (0.17 rad noise, 5 m array at 0.5 deg) below `m n`; a round at a
/// target that is too high costs less than the one that succeeds.
const FIRST_DEFICIT: f64 = 0.01;

/// Factor on the deficit `m n - T` after a round that found nothing at `T`.
const GROWTH: f64 = 4.0;

/// Most work [`branch_and_bound`] does on a grid the exhaustive pass cannot take over (over
/// [`MAX_CELLS`] cells): direction boxes tested plus rows scanned, each costing well under a
/// microsecond, so about a minute on one core at most. Checked before the search (on such a grid
/// every top box is tested and every row scanned) and as it goes; over it, the search stops with
/// [`Error::OutOfRange`].
pub const MAX_WORK: u64 = 1 << 28;

/// Rows per side of a block when a window's reachable directions are gathered.
const BLOCK: usize = 8;

/// Most direction boxes [`branch_and_bound`] tests before it falls back to the exhaustive pass: one per
/// 128 cells. A box costs about as much as 10 to 150 kernel cells (arc test or relaxed bound; 27
/// measured on the 5 m array of the `bnb_vs_grid` bench), so the bounding work stays under about the
/// exhaustive pass; small grids (under about 10^6 cells for the paper's array) are searched
/// exhaustively.
pub fn box_limit(grid: &Grid) -> u64 {
    grid.len() as u64 / 128
}

/// Half-width (radians) of baseline `i`'s leaf boxes in the direction search. Leaves of half a step (one
/// bin of the raster) leave each phase free over `+- g |r_i| step / 2`; where a step moves a phase by
/// more than `FINE_LEAF` rad (5 m array at 0.5 deg: 1.44 rad) the relaxed bound then keeps most bins it
/// is asked about, and leaves of a quarter step keep 3.5x fewer bins and evaluate 18x fewer kernel
/// cells for 17 % more boxes (measured on the `bnb_vs_grid` bench's 5 m array; an eighth of a step
/// costs 25 % more boxes again). Below it (the paper's array at 1.5 deg: 0.61 rad) quarter-step leaves
/// cost 13 % more boxes for no gain in time, and more searches of small grids hit their box limit.
fn leaf_half_width(model: &Model, i: usize, step: f64) -> f64 {
    let g_max = model.g.iter().map(|g| g.norm()).fold(0.0, f64::max);
    if g_max * model.baselines[i].norm() * step > FINE_LEAF {
        0.25 * step
    } else {
        0.5 * step
    }
}

/// Phase motion per grid step (rad) above which the direction search uses quarter-step leaves
/// ([`leaf_half_width`]).
const FINE_LEAF: f64 = 1.0;

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

/// Pitch and roll index ranges of a block of rows.
type Block = ((usize, usize), (usize, usize));

/// Per baseline, the top direction boxes some cell of the grid points it into: around each block's
/// centre direction, elevation +- the block's reach and azimuth +- reach / cos(latitude bound), over
/// the headings of the grid. Every top box for the whole domain.
fn reaches(model: &Model, grid: &Grid) -> Vec<Reach> {
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
    for (tr, fr) in blocks {
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

/// Per-thread state of the row scan.
struct Scan<'a> {
    rn: RowNodes<'a>,
    /// Per baseline: `(beta, raster row)` of the current row.
    dirs: Vec<(f64, &'a [(u32, f32)])>,
    /// Baseline lengths, metres.
    lens: Vec<f64>,
    nodes: Vec<usize>,
}

/// Heading nodes (local indices) whose azimuth `a = psi + beta` may fall in azimuth bin `bin` of
/// `width` radians: global indices `g` with `psi = origin + g step`, the bin's start minus `beta`, one
/// node either side for rounding; the caller checks each by its own bin.
fn bin_nodes(psi: &Axis, width: f64, bin: u32, beta: f64) -> impl Iterator<Item = usize> + '_ {
    let v = (f64::from(bin) * width - beta - psi.origin) / psi.step;
    let g_mid = floor(v) as i64;
    // Nodes in the bin have g in [v, v + 1): g_mid + 1 (and g_mid when v is an integer); the outer
    // two only when rounding of v may have moved it across an integer.
    let frac = v - floor(v);
    let edge = !(1e-6..=1.0 - 1e-6).contains(&frac);
    let (lo, hi) = if edge {
        (g_mid - 1, g_mid + 2)
    } else {
        (g_mid + 1, g_mid + 1)
    };
    (lo..=hi).filter_map(move |g| {
        let j = g - psi.first;
        let j = match psi.period {
            Some(p) => j.rem_euclid(p as i64),
            None => j,
        };
        (0..psi.len as i64).contains(&j).then_some(j as usize)
    })
}

/// Step 2 of the module docs for row `(t, f)`: the best cell among the nodes whose summed bounds reach
/// `need`. `(ct, st)` are `cos theta`, `sin theta` of the row and `v[i]` is `Rx(phi) r_i`, so `w = Rz(theta)
/// v` is the baseline's direction before the heading turn; every elevation is looked up before any
/// azimuth is computed (most rows stop at an empty raster row).
fn scan_row<'a>(
    psi: &Axis,
    maps: &'a [DirMap],
    need: f64,
    scan: &mut Scan<'a>,
    (t, f, (ct, st), v): (usize, usize, (f64, f64), &[Vector3<f64>]),
) -> (f32, usize) {
    let none = (f32::NEG_INFINITY, usize::MAX);
    scan.dirs.clear();
    let mut sparsest = 0;
    for (i, ((vi, map), len)) in v.iter().zip(maps).zip(&scan.lens).enumerate() {
        let y = st * vi.x + ct * vi.y;
        let row = map.row((y / len).clamp(-1.0, 1.0).asin());
        if row.is_empty() {
            return none;
        }
        if row.len() < scan.dirs.get(sparsest).map_or(usize::MAX, |d| d.1.len()) {
            sparsest = i;
        }
        // The azimuth follows once every row is known to be occupied.
        scan.dirs.push((0.0, row));
    }
    for (d, vi) in scan.dirs.iter_mut().zip(v) {
        d.0 = (-vi.z).atan2(ct * vi.x - st * vi.y);
    }
    scan.nodes.clear();
    let map0 = &maps[sparsest];
    let (beta0, row0) = scan.dirs[sparsest];
    for &(bin, u0) in row0 {
        for j in bin_nodes(psi, map0.width(), bin, beta0) {
            let a = psi.angle(j as i64);
            if map0.bin(a + beta0) != bin {
                continue;
            }
            let mut sum = f64::from(u0);
            for (i, &(beta, row)) in scan.dirs.iter().enumerate() {
                if i == sparsest {
                    continue;
                }
                match lookup(row, maps[i].bin(a + beta)) {
                    Some(u) => sum += f64::from(u),
                    None => {
                        sum = f64::NEG_INFINITY;
                        break;
                    }
                }
            }
            if sum >= need {
                scan.nodes.push(j);
            }
        }
    }
    if scan.nodes.is_empty() {
        return none;
    }
    scan.nodes.sort_unstable();
    scan.nodes.dedup();
    scan.rn.best(t, f, &scan.nodes)
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

/// The exhaustive pass in place of the branch-and-bound (`why` it gave up), with the work done so far;
/// where the grid is over [`MAX_CELLS`] cells (not `feasible`), the error naming `step_deg` instead.
fn fall_back(
    model: &Model,
    grid: &Grid,
    feasible: bool,
    mut stats: BnbStats,
    why: &str,
) -> Result<(GridMax, BnbStats)> {
    if !feasible {
        return Err(Error::out_of_range(
            "step_deg",
            format!(
                "a step of {:.3e} deg gives {:.3e} cells, over the 2^31 the exhaustive pass \
                 evaluates, and the branch-and-bound cannot search them: {why}; coarsen the step \
                 or narrow the window",
                grid.step().to_degrees(),
                grid.len() as f64
            ),
        ));
    }
    let gm = exhaustive_max(model, grid)?;
    stats.leaf_cells += gm.cells_evaluated;
    stats.fallback = true;
    Ok((
        GridMax {
            cells_evaluated: stats.boxes_bounded + stats.leaf_cells,
            ..gm
        },
        stats,
    ))
}

/// What the row scan of every round reads: the heading tables of the full pass, `(cos, sin)` of each
/// pitch node, and per roll node `Rx(phi) r_i` for every baseline (flat, `nb` per node).
struct RowTables {
    cps: Vec<f32>,
    sps: Vec<f32>,
    trig: Vec<(f64, f64)>,
    rolled: Vec<Vector3<f64>>,
}

impl RowTables {
    fn new(model: &Model, grid: &Grid) -> Self {
        let (cps, sps) = heading_tables((0..grid.psi.len as i64).map(|p| grid.psi.angle(p)));
        let trig = (0..grid.theta.len)
            .map(|t| {
                let (s, c) = grid.theta.angle(t as i64).sin_cos();
                (c, s)
            })
            .collect();
        let rolled = (0..grid.phi.len)
            .flat_map(|f| {
                let rx = elementary(RotAxis::X, grid.phi.angle(f as i64));
                model.baselines.iter().map(move |r| rx * r)
            })
            .collect();
        RowTables {
            cps,
            sps,
            trig,
            rolled,
        }
    }
}

/// Step 2 of the module docs over every row, in parallel: the best `(z, flat index)` among the nodes
/// whose summed bounds reach `need`, and the number of kernel cells evaluated.
fn scan_rows(
    model: &Model,
    grid: &Grid,
    tables: &RowTables,
    maps: &[DirMap],
    need: f64,
) -> ((f32, usize), u64) {
    let nb = model.n_baselines();
    (0..grid.theta.len * grid.phi.len)
        .into_par_iter()
        .with_min_len(64)
        .map_init(
            || Scan {
                rn: RowNodes::new(model, grid, &tables.cps, &tables.sps),
                dirs: Vec::with_capacity(nb),
                lens: model.baselines.iter().map(|r| r.norm()).collect(),
                nodes: vec![],
            },
            |scan, r| {
                let (t, f) = (r / grid.phi.len, r % grid.phi.len);
                let v = &tables.rolled[f * nb..(f + 1) * nb];
                let before = scan.rn.cells;
                let b = scan_row(&grid.psi, maps, need, scan, (t, f, tables.trig[t], v));
                (b, scan.rn.cells - before)
            },
        )
        .reduce(
            || ((f32::NEG_INFINITY, usize::MAX), 0),
            |a, b| (better(a.0, b.0), a.1 + b.1),
        )
}

/// The kernel's margin ([`kernel_margin`]) where the search can run, or why it cannot: a statistic that
/// does not split by baseline, phases beyond the kernel's checked range, or (on a grid the exhaustive
/// pass cannot take over, not `feasible`) more than `limit` units of work before any pruning.
fn preflight(
    model: &Model,
    grid: &Grid,
    feasible: bool,
    limit: u64,
) -> std::result::Result<f64, String> {
    let margin = match (model.grouping, kernel_margin(model)) {
        (Grouping::PerBaseline, Some(m)) => m,
        (Grouping::PerBaseline, None) => {
            return Err("phases beyond the kernel's checked range".into())
        }
        _ => return Err("the statistic does not split by baseline".into()),
    };
    let rows = (grid.theta.len * grid.phi.len) as f64;
    let tops: f64 = (0..model.n_baselines())
        .map(|i| 2.0 * top_rows(model, i).powi(2))
        .sum();
    // Where the exhaustive pass can take over, the budget decides (a window's search tests only the
    // top boxes it reaches).
    if !feasible && tops + rows > limit as f64 {
        return Err(format!(
            "it would test at least {tops:.3e} direction boxes and scan {rows:.3e} rows, over its \
             limit of {limit:.3e}"
        ));
    }
    Ok(margin)
}

/// [`branch_and_bound`] with at most `limit` direction boxes before the exhaustive fallback (where the
/// grid holds at most [`MAX_CELLS`] cells; [`MAX_WORK`] otherwise).
pub(crate) fn branch_and_bound_limited(
    model: &Model,
    grid: &Grid,
    limit: u64,
) -> Result<(GridMax, BnbStats)> {
    check_step(model, grid)?;
    let mut stats = BnbStats::default();
    let feasible = grid.len() <= MAX_CELLS;
    let limit = if feasible { limit } else { MAX_WORK };
    let exhaustive = |stats: BnbStats, why: &str| fall_back(model, grid, feasible, stats, why);
    let margin = match preflight(model, grid, feasible, limit) {
        Ok(m) => m,
        Err(why) => return exhaustive(stats, &why),
    };
    let rows = grid.theta.len * grid.phi.len;
    let (nb, n, top) = (model.n_baselines(), model.n_terms() as f64, model.z_upper());
    let reach = reaches(model, grid);
    let budget = Budget::new(limit);
    let per_turn = (std::f64::consts::TAU / grid.step()).round() as usize;
    let tables = RowTables::new(model, grid);
    let mut deficit = FIRST_DEFICIT * top;
    let mut target = top - deficit;
    loop {
        stats.rounds += 1;
        if target <= 0.0 {
            return exhaustive(stats, "no cell reaches the lowest target");
        }
        // 1e-6: f64 rounding of the direction of a node (|dF| <= n |g| |r| 1e-15) with room to spare.
        let need = target - margin - 1e-6;
        let tau = need - (nb - 1) as f64 * n;
        let mut maps = Vec::with_capacity(nb);
        for (i, r) in reach.iter().enumerate() {
            let h_min = leaf_half_width(model, i, grid.step());
            match direction_set(model, i, tau, h_min, r, &budget) {
                Some(s) => maps.push(DirMap::new(&s, grid.step(), per_turn)),
                None => {
                    stats.boxes_bounded = budget.used();
                    let why = format!("its direction search passed its work limit of {limit:.3e}");
                    return exhaustive(stats, &why);
                }
            }
        }
        if !feasible && !budget.spend(rows as u64) {
            stats.boxes_bounded = budget.used();
            let why = format!("its rows and direction boxes passed its work limit of {limit:.3e}");
            return exhaustive(stats, &why);
        }
        let (best, leaf) = scan_rows(model, grid, &tables, &maps, need);
        stats.leaf_cells += leaf;
        stats.boxes_bounded = budget.used();
        if f64::from(best.0) >= target {
            return Ok((
                GridMax {
                    index: grid.unflatten(best.1),
                    z: best.0,
                    cells_evaluated: stats.boxes_bounded + stats.leaf_cells,
                },
                stats,
            ));
        }
        // Nothing reached the target. A round at the best value found certainly ends the search (that
        // cell is evaluated again); it is taken unless it lies below the next step of the schedule.
        deficit *= GROWTH;
        target = (top - deficit).max(f64::from(best.0));
    }
}
