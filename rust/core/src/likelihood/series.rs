//! Per-epoch maximum-likelihood attitude or baseline direction over a batch of epochs, in one call.
//!
//! Each epoch is its own problem (the receivers' oscillator phases are free per epoch, unlike the static
//! batch of [`Model::new`], which sums epochs inside the modulus): the ambiguity function on the epoch's
//! single-difference phases, its grid maximum by [`Search::Auto`] (branch-and-bound where it is faster,
//! the same cell either way) and the Newton refinement ([`Refine::Newton`]), exactly what
//! [`estimate`] gives for that epoch alone.
//!
//! Without a window the epochs are independent and run in parallel (rayon over epochs, each search
//! itself parallel inside; `benches/python/ml_series_speed.py` measures the choice). With a window each
//! epoch searches `+- window_rad` on every axis around the previous epoch's refined solution, a
//! sequential chain; the whole domain is searched where the previous epoch is unsolved (the first one,
//! or one with fewer than 3 complete signals).
//!
//! The work of the whole call is counted before any epoch is searched ([`series_work`], refused above
//! [`MAX_SERIES_WORK`]): each epoch is charged the cells its search evaluates (its grid for the exhaustive
//! pass, [`AUTO_MIN_CELLS`] for a branch-and-bound search, [`super::MAX_WORK`] beyond [`MAX_CELLS`]) plus
//! [`EPOCH_OVERHEAD_CELLS`] for its refinement, times its signals and rovers. Each search also stays
//! within its own limit; the loop polls [`crate::interrupt`] between epochs.

use std::f64::consts::{PI, TAU};

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::guard::check_work;
use crate::interrupt;

use super::bnb::MAX_WORK;
use super::grid::Grid;
use super::model::{dcm_enu_from_body, Epoch, Model, Statistic};
use super::refine::{estimate, Refine, Search, AUTO_MAX_STEP, AUTO_MIN_CELLS};
use super::search::MAX_CELLS;

/// Most work one series call accepts, in cell evaluations times signals times rovers (the kernel terms
/// of [`series_work`]): 2^33. Measured on the shared 2-core build machine under a load of about 10
/// (`benches/python/ml_series_speed.py`-style timing, step 3 deg exhaustive and the default step by
/// branch-and-bound): 2.9 ns a term, so the limit is about 25 s there and a few seconds on a free machine.
/// A day of 1 Hz epochs tracked in a window (2 rovers, 6 signals) is 8.8e9: split it in two calls.
pub const MAX_SERIES_WORK: f64 = 8_589_934_592.0;

/// Cells charged to each solved epoch for what its search does besides the cells (the refinement's
/// evaluations, the model): measured as the cost of a windowed epoch, about 10^4 cells.
pub const EPOCH_OVERHEAD_CELLS: f64 = 8192.0;

/// What an epoch's search is charged, in cells (module docs): `cells` of its grid, searched by
/// [`Search::Auto`] at `step_rad` with a coarsest accepted step `max_step_rad`.
fn charged_cells(cells: usize, step_rad: f64, max_step_rad: f64) -> f64 {
    let bnb =
        cells > MAX_CELLS || (cells >= AUTO_MIN_CELLS && step_rad <= AUTO_MAX_STEP * max_step_rad);
    let searched = if cells > MAX_CELLS {
        MAX_WORK as f64
    } else if bnb {
        AUTO_MIN_CELLS as f64
    } else {
        cells as f64
    };
    searched + EPOCH_OVERHEAD_CELLS
}

/// The work [`ml_attitude_series`] (`two_dimensional` false) or [`ml_baseline_series`] charges a call of
/// `n_epochs` epochs with `n_rover` rovers and `n_sig` signals each at wavelength `wavelength_m`, the
/// longest baseline `longest_baseline_m`: the kernel terms of module docs, every epoch solved, the first
/// on the whole domain and the others on the window when there is one. With per-epoch signals the call
/// counts each epoch's own (fewer signals, a finer step); this is the count from the shapes alone that a
/// binding can check before it copies the measurements.
///
/// # Errors
/// None; steps and windows the search refuses are charged nothing here (the search names them).
#[allow(clippy::too_many_arguments)]
pub fn series_work(
    n_epochs: usize,
    n_rover: usize,
    n_sig: usize,
    step_rad: Option<f64>,
    wavelength_m: f64,
    longest_baseline_m: f64,
    window_rad: Option<f64>,
    two_dimensional: bool,
) -> f64 {
    let mode = if two_dimensional {
        Mode::Baseline
    } else {
        Mode::Attitude
    };
    if n_epochs == 0 || n_sig < 3 {
        return 0.0;
    }
    let terms = (n_rover * n_sig) as f64;
    let max_step = wavelength_m / (2.0 * longest_baseline_m);
    let step = step_rad.unwrap_or(wavelength_m / (10.0 * longest_baseline_m));
    let first = epoch_charge(step, max_step, mode, None);
    let rest = window_rad.map_or(first, |w| epoch_charge(step, max_step, mode, Some(w)));
    terms * (first + rest * (n_epochs - 1) as f64)
}

/// [`charged_cells`] of one epoch's grid, the window centred where it holds the most cells (zero pitch);
/// nothing for a grid the search refuses.
fn epoch_charge(step: f64, max_step: f64, mode: Mode, window: Option<f64>) -> f64 {
    match epoch_grid(step, mode, window.map(|w| ([0.0; 3], w))) {
        Ok(g) => charged_cells(g.len(), g.step(), max_step),
        Err(_) => 0.0,
    }
}

/// [`series_work`] from the epochs themselves: each epoch's complete signals, smallest wavelength and
/// window (the whole domain after an unsolved epoch), refused above [`MAX_SERIES_WORK`] before any search.
fn check_series_work(
    epochs: &[MlEpoch],
    baselines: &[Vector3<f64>],
    mode: Mode,
    step_rad: Option<f64>,
    window_rad: Option<f64>,
) -> Result<()> {
    let n_rover = baselines.len();
    let longest = baselines.iter().map(|b| b.norm()).fold(0.0, f64::max);
    let mut total = 0.0;
    let mut previous_solved = false;
    for e in epochs {
        let n_sig = e.los_enu.len();
        let mut used = 0usize;
        let mut lambda_min = f64::INFINITY;
        for k in 0..n_sig {
            let complete = (0..n_rover).all(|i| {
                e.sd_phase_rad
                    .get(i * n_sig + k)
                    .is_some_and(|p| !p.is_nan())
            });
            if complete {
                used += 1;
                lambda_min = lambda_min.min(e.wavelength_m.get(k).copied().unwrap_or(f64::NAN));
            }
        }
        let solved = used >= 3;
        if solved {
            let max_step = lambda_min / (2.0 * longest);
            let step = step_rad.unwrap_or(lambda_min / (10.0 * longest));
            let window = window_rad.filter(|_| previous_solved);
            total += (n_rover * used) as f64 * epoch_charge(step, max_step, mode, window);
        }
        previous_solved = solved;
    }
    check_work(
        "sd_phase",
        total,
        MAX_SERIES_WORK,
        "kernel terms (epochs x grid cells searched x signals x rovers; see docs/limits.md)",
    )
}

/// One epoch of single-difference carrier phases.
#[derive(Debug, Clone, PartialEq)]
pub struct MlEpoch {
    /// `(n_rover x n_sig)` row-major, radians: phase at rover antenna `i` minus the reference antenna for
    /// signal `k` (RINEX sign, any multiple of 2 pi added, an oscillator phase per rover). NaN marks a
    /// signal a rover lacks; such a signal is left out of the epoch for every rover.
    pub sd_phase_rad: Vec<f64>,
    /// `(n_sig)` unit lines of sight, East-North-Up, reference antenna -> satellite.
    pub los_enu: Vec<[f64; 3]>,
    /// `(n_sig)` carrier wavelength per signal, metres (per satellite for GLONASS FDMA).
    pub wavelength_m: Vec<f64>,
}

/// The estimate of one epoch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MlSolution {
    /// `(psi, theta, phi)` of eq. (5), radians (module docs of [`crate::likelihood`]), refined; psi and
    /// phi in (-pi, pi]. Baseline mode: heading `psi` and elevation `theta` of the baseline, `phi = 0`
    /// (roll about one baseline is not observable).
    pub euler_gost_rad: [f64; 3],
    /// Direction of the (first) baseline in East-North-Up: compass azimuth (clockwise from North) in
    /// [0, 2 pi) and elevation in [-pi/2, pi/2], radians. Baseline mode: `(-psi mod 2 pi, theta)` exactly.
    pub direction_rad: [f64; 2],
    /// The ambiguity function at the grid maximum (float32 kernel value), at most `n_rover x n_sig`.
    pub value: f64,
    /// False where the epoch has fewer than 3 signals complete for every rover: every angle and `value`
    /// are then NaN.
    pub solved: bool,
}

impl MlSolution {
    const UNSOLVED: MlSolution = MlSolution {
        euler_gost_rad: [f64::NAN; 3],
        direction_rad: [f64::NAN; 2],
        value: f64::NAN,
        solved: false,
    };
}

/// Whether the grid is the three-axis attitude grid or the two-axis single-baseline one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    Attitude,
    Baseline,
}

/// Per-epoch maximum-likelihood attitude of an antenna array (module docs).
///
/// # Arguments
/// * `epochs` - single differences of each rover antenna against the reference antenna; `n_rover =
///   body_baselines_m.len()`.
/// * `body_baselines_m` - `(n_rover)` rover antenna positions relative to the reference antenna, body
///   frame (X nose, Y up, Z right wing), metres; not collinear.
/// * `step_rad` - grid step, radians, in (0, pi]; `None`: eq. (15) with factor 10 per epoch,
///   `lambda_min / (10 L_max)`. Steps coarser than `lambda_min / (2 L_max)` are refused.
/// * `window_rad` - half-width of the window around the previous epoch's solution on each axis,
///   radians, in (0, 2 pi] and at least the step; `None`: every epoch searches the whole domain.
///
/// # Errors
/// (Named as the Python face names them, like [`Grid`]'s: `step_deg`, `window_deg`.)
/// [`Error::Shape`] for inconsistent lengths, [`Error::NonFinite`] for non-finite lines of sight or
/// wavelengths of a signal used, [`Error::OutOfRange`] for infinite phases, a bad step or window,
/// non-unit lines of sight, non-positive wavelengths (each naming the epoch), [`Error::DegenerateGeometry`] for collinear
/// baselines, [`Error::Interrupted`] on request.
pub fn ml_attitude_series(
    epochs: &[MlEpoch],
    body_baselines_m: &[[f64; 3]],
    step_rad: Option<f64>,
    window_rad: Option<f64>,
) -> Result<Vec<MlSolution>> {
    let baselines: Vec<Vector3<f64>> = body_baselines_m.iter().map(|b| (*b).into()).collect();
    series(epochs, &baselines, Mode::Attitude, step_rad, window_rad)
}

/// Per-epoch maximum-likelihood direction of a single baseline (two antennas) over the heading-elevation
/// grid (module docs).
///
/// # Arguments
/// * `epochs` - single differences, rover minus reference (`n_rover = 1`).
/// * `baseline_length_m` - distance between the antennas, metres, positive.
/// * `step_rad`, `window_rad` - as in [`ml_attitude_series`] (the window is on heading and elevation).
///
/// # Errors
/// As [`ml_attitude_series`]; [`Error::OutOfRange`] for a length that is not positive and finite.
pub fn ml_baseline_series(
    epochs: &[MlEpoch],
    baseline_length_m: f64,
    step_rad: Option<f64>,
    window_rad: Option<f64>,
) -> Result<Vec<MlSolution>> {
    if !(baseline_length_m.is_finite() && baseline_length_m > 0.0) {
        return Err(Error::out_of_range(
            "baseline_length_m",
            format!("expected a positive finite length in metres, got {baseline_length_m}"),
        ));
    }
    let baselines = [Vector3::new(baseline_length_m, 0.0, 0.0)];
    series(epochs, &baselines, Mode::Baseline, step_rad, window_rad)
}

fn series(
    epochs: &[MlEpoch],
    baselines: &[Vector3<f64>],
    mode: Mode,
    step_rad: Option<f64>,
    window_rad: Option<f64>,
) -> Result<Vec<MlSolution>> {
    if let Some(s) = step_rad {
        if !(s.is_finite() && s > 0.0 && s <= PI) {
            return Err(Error::out_of_range(
                "step_deg",
                format!(
                    "expected a grid step in (0, 180] deg, got {:e} deg ({s:e} rad)",
                    s.to_degrees()
                ),
            ));
        }
    }
    if let Some(w) = window_rad {
        if !(w.is_finite() && w > 0.0 && w <= TAU) {
            return Err(Error::out_of_range(
                "window_deg",
                format!(
                    "expected a window half-width in (0, 360] deg, got {:e} deg ({w:e} rad)",
                    w.to_degrees()
                ),
            ));
        }
    }
    // The baselines are checked once, before any epoch's work (the per-epoch models repeat it cheaply).
    let probe = Epoch {
        phase_diffs: vec![vec![0.0; 3]; baselines.len()],
        los_enu: vec![Vector3::x(), Vector3::y(), Vector3::z()],
        wavelengths: vec![1.0; 3],
    };
    Model::new(baselines, &[probe], Statistic::AmbiguityFunction)?;
    check_series_work(epochs, baselines, mode, step_rad, window_rad)?;
    match window_rad {
        None => epochs
            .par_iter()
            .enumerate()
            .map(|(k, e)| {
                interrupt::check("ML series")?;
                solve(k, e, baselines, mode, step_rad, None)
            })
            .collect(),
        Some(w) => {
            let mut out = Vec::with_capacity(epochs.len());
            let mut previous = MlSolution::UNSOLVED;
            for (k, e) in epochs.iter().enumerate() {
                interrupt::check("ML series")?;
                let around = previous.solved.then_some((previous.euler_gost_rad, w));
                previous = solve(k, e, baselines, mode, step_rad, around)?;
                out.push(previous);
            }
            Ok(out)
        }
    }
}

/// The epoch's measurements as the single-epoch [`Epoch`], without the signals some rover lacks.
fn complete_signals(k: usize, e: &MlEpoch, n_rover: usize) -> Result<Epoch> {
    let n_sig = e.los_enu.len();
    if e.wavelength_m.len() != n_sig || n_rover.checked_mul(n_sig) != Some(e.sd_phase_rad.len()) {
        return Err(Error::Shape {
            name: "epochs",
            expected: format!(
                "at epoch {k} sd_phase_rad of length n_rover x n_sig = {n_rover} x {n_sig} and \
                 wavelength_m of length {n_sig} (n_sig = len(los_enu))"
            ),
            actual: format!(
                "lengths {} and {}",
                e.sd_phase_rad.len(),
                e.wavelength_m.len()
            ),
        });
    }
    let keep: Vec<usize> = (0..n_sig)
        .filter(|&s| (0..n_rover).all(|i| !e.sd_phase_rad[i * n_sig + s].is_nan()))
        .collect();
    Ok(Epoch {
        phase_diffs: (0..n_rover)
            .map(|i| {
                keep.iter()
                    .map(|&s| e.sd_phase_rad[i * n_sig + s])
                    .collect()
            })
            .collect(),
        los_enu: keep.iter().map(|&s| e.los_enu[s].into()).collect(),
        wavelengths: keep.iter().map(|&s| e.wavelength_m[s]).collect(),
    })
}

/// The grid of one epoch: the whole domain, or `+- w` around `centre` on each searched axis.
fn epoch_grid(step: f64, mode: Mode, around: Option<([f64; 3], f64)>) -> Result<Grid> {
    match (mode, around) {
        (Mode::Attitude, None) => Grid::full(step),
        (Mode::Baseline, None) => Grid::two_dimensional(step),
        (Mode::Attitude, Some((c, w))) => Grid::window(step, c.map(|a| (a - w, a + w))),
        (Mode::Baseline, Some((c, w))) => {
            Grid::two_dimensional_window(step, [(c[0] - w, c[0] + w), (c[1] - w, c[1] + w)])
        }
    }
}

fn solve(
    k: usize,
    e: &MlEpoch,
    baselines: &[Vector3<f64>],
    mode: Mode,
    step_rad: Option<f64>,
    around: Option<([f64; 3], f64)>,
) -> Result<MlSolution> {
    let epoch = complete_signals(k, e, baselines.len())?;
    // Infinite phases are errors, not absent signals (only NaN marks those).
    if let Some(j) = e.sd_phase_rad.iter().position(|p| p.is_infinite()) {
        let n_sig = e.los_enu.len();
        return Err(Error::out_of_range(
            "sd_phase_rad",
            format!(
                "epoch {k}: expected finite phases (NaN for an absent signal), got {} at (rover, \
                 signal) ({}, {})",
                e.sd_phase_rad[j],
                j / n_sig,
                j % n_sig
            ),
        ));
    }
    if epoch.los_enu.len() < 3 {
        return Ok(MlSolution::UNSOLVED);
    }
    let model =
        Model::new(baselines, &[epoch], Statistic::AmbiguityFunction).map_err(|x| x.at_epoch(k))?;
    let step = step_rad.unwrap_or_else(|| model.default_step());
    // A half-width of at least the step always holds a node (the actual step is at most `step`).
    if let Some((_, w)) = around {
        if w < step {
            return Err(Error::out_of_range(
                "window_deg",
                format!(
                    "epoch {k}: a window half-width of {:.6} deg is finer than the grid step {:.6} \
                     deg (it could hold no node)",
                    w.to_degrees(),
                    step.to_degrees()
                ),
            ));
        }
    }
    let grid = epoch_grid(step, mode, around).map_err(|x| x.at_epoch(k))?;
    let est = estimate(&model, &grid, Search::Auto, Refine::Newton).map_err(|x| x.at_epoch(k))?;
    let [psi, theta, phi] = est.angles_rad;
    // Baseline mode: body X is the baseline, so its compass azimuth is -psi and its elevation theta
    // exactly (what `ml_baseline` reports); attitude mode: the rotated first baseline.
    let (azimuth, elevation) = match mode {
        Mode::Baseline => (-psi, theta),
        Mode::Attitude => {
            let v = dcm_enu_from_body(psi, theta, phi) * baselines[0];
            (v.x.atan2(v.y), (v.z / v.norm()).clamp(-1.0, 1.0).asin())
        }
    };
    let azimuth = azimuth.rem_euclid(TAU);
    // rem_euclid of a tiny negative angle rounds to 2 pi itself.
    let direction_rad = [if azimuth >= TAU { 0.0 } else { azimuth }, elevation];
    Ok(MlSolution {
        euler_gost_rad: est.angles_rad,
        direction_rad,
        value: f64::from(est.grid_max.z),
        solved: true,
    })
}
