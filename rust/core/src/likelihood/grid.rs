//! The grid of Euler angles `(psi_p, theta_r, phi_q)`: one lattice of step `Delta` over the attitude domain
//! (psi in [0, 2 pi), theta in [-pi/2, pi/2], phi in [-pi, pi)), optionally restricted to a window.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use crate::error::{Error, Result};

/// One axis: nodes `origin + (first + j) * step` for `j in 0..len`; `period` nodes make a full turn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    /// Angle of global node 0, radians.
    pub origin: f64,
    /// Node spacing, radians.
    pub step: f64,
    /// Global index of the first node (may be negative in a window that wraps through zero).
    pub first: i64,
    /// Number of nodes.
    pub len: usize,
    /// Nodes per full turn for periodic axes (heading and roll).
    pub period: Option<usize>,
}

impl Axis {
    /// Angle of node `j` (`j` may run past either end: it is a lattice), radians.
    pub fn angle(&self, j: i64) -> f64 {
        self.origin + (self.first + j) as f64 * self.step
    }

    fn window(self, name: &'static str, lo: f64, hi: f64) -> Result<Axis> {
        if !(lo.is_finite() && hi.is_finite()) || hi < lo {
            return Err(Error::out_of_range(
                name,
                format!("expected a window lo <= hi, got [{lo}, {hi}] rad"),
            ));
        }
        if !(lo.abs() <= MAX_WINDOW_RAD && hi.abs() <= MAX_WINDOW_RAD) {
            return Err(Error::out_of_range(
                name,
                format!(
                    "expected window limits within +-{:.0} deg, got [{:e}, {:e}] deg",
                    MAX_WINDOW_RAD.to_degrees(),
                    lo.to_degrees(),
                    hi.to_degrees()
                ),
            ));
        }
        // |(angle - origin) / step| <= (20 pi + pi) / (pi / 2^31) < 2^36: exact in f64 and i64.
        let a = ((lo - self.origin) / self.step - 1e-9).ceil() as i64;
        let b = ((hi - self.origin) / self.step + 1e-9).floor() as i64;
        let (a, b) = match self.period {
            Some(p) if b - a + 1 >= p as i64 => (0, p as i64 - 1),
            Some(_) => (a, b),
            None => (a.max(self.first), b.min(self.first + self.len as i64 - 1)),
        };
        if b < a {
            return Err(Error::out_of_range(
                name,
                format!(
                    "the window [{:.4}, {:.4}] deg holds no grid node (step {:.4} deg)",
                    lo.to_degrees(),
                    hi.to_degrees(),
                    self.step.to_degrees()
                ),
            ));
        }
        Ok(Axis {
            first: a,
            len: (b - a + 1) as usize,
            ..self
        })
    }
}

/// A grid over `(psi, theta, phi)`; cell `(p, t, f)` has flat index `(t * n_phi + f) * n_psi + p`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    /// Heading axis.
    pub psi: Axis,
    /// Pitch axis.
    pub theta: Axis,
    /// Roll axis.
    pub phi: Axis,
}

/// Largest magnitude of a window limit: ten turns (3600 deg), far beyond any meaningful window, and small
/// enough that node indices stay exact (a limit of 1e20 deg used to overflow them).
const MAX_WINDOW_RAD: f64 = 20.0 * PI;

/// Most nodes per turn of a grid over the whole domain (or the whole two-dimensional domain): the cell
/// count (at most `2^59`) and the flat index stay exact in `usize` and `f64`. What a search may cost is
/// limited by the search ([`super::search::MAX_CELLS`] for the exhaustive pass, [`super::bnb::MAX_WORK`]
/// for the branch-and-bound), counted over the work it does.
const MAX_TURN_NODES: f64 = 1048576.0;

/// Most half-turns of a lattice (a window may use steps far finer than a whole grid).
const MAX_TURNS: f64 = 2147483648.0;

/// Most cells of a window: its flat index stays exact in `usize` and `f64`.
const MAX_WINDOW_CELLS: f64 = 4503599627370496.0;

impl Grid {
    /// The whole attitude domain with step at most `step_rad`: `n = 2 ceil(pi / step_rad)` nodes per turn,
    /// actual step `2 pi / n`, `n/2 + 1` pitch nodes from -pi/2 to pi/2.
    ///
    /// # Arguments
    /// * `step_rad` - requested step, radians, positive.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for a non-positive or non-finite step, or one giving over 2^20 nodes per
    /// turn.
    pub fn full(step_rad: f64) -> Result<Grid> {
        Grid::lattice(step_rad)?.whole()
    }

    /// The nodes of [`Grid::full`] inside `[lo, hi]` ranges (radians) of psi, theta and phi; a periodic
    /// range wider than a turn is the whole axis, pitch is clipped to [-pi/2, pi/2].
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for a non-positive or non-finite step, an inverted window, one with no node,
    /// or one of over 2^52 cells (steps may be far finer than [`Grid::full`] accepts).
    pub fn window(step_rad: f64, ranges: [(f64, f64); 3]) -> Result<Grid> {
        let g = Grid::lattice(step_rad)?;
        Grid {
            psi: g.psi.window("window_deg (psi)", ranges[0].0, ranges[0].1)?,
            theta: g
                .theta
                .window("window_deg (theta)", ranges[1].0, ranges[1].1)?,
            phi: g.phi.window("window_deg (phi)", ranges[2].0, ranges[2].1)?,
        }
        .window_checked()
    }

    /// The single-baseline grid: heading and pitch (elevation) of the baseline, roll fixed at zero.
    ///
    /// # Errors
    /// As [`Grid::full`].
    pub fn two_dimensional(step_rad: f64) -> Result<Grid> {
        Grid::lattice(step_rad)?.without_roll().whole()
    }

    /// [`Grid::two_dimensional`] restricted to `[lo, hi]` ranges (radians) of heading and pitch.
    ///
    /// # Errors
    /// As [`Grid::window`].
    pub fn two_dimensional_window(step_rad: f64, ranges: [(f64, f64); 2]) -> Result<Grid> {
        let g = Grid::lattice(step_rad)?.without_roll();
        Grid {
            psi: g.psi.window("window_deg (psi)", ranges[0].0, ranges[0].1)?,
            theta: g
                .theta
                .window("window_deg (theta)", ranges[1].0, ranges[1].1)?,
            ..g
        }
        .window_checked()
    }

    /// The lattice of step at most `step_rad` over the whole domain.
    fn lattice(step_rad: f64) -> Result<Grid> {
        if !(step_rad.is_finite() && step_rad > 0.0) {
            return Err(Error::out_of_range(
                "step_deg",
                format!("expected a positive step, got {step_rad} rad"),
            ));
        }
        let turns = (PI / step_rad).ceil();
        if turns > MAX_TURNS {
            return Err(Error::out_of_range(
                "step_deg",
                format!("a step of {:.3e} deg is too fine", step_rad.to_degrees()),
            ));
        }
        let n = 2 * turns as usize;
        let step = TAU / n as f64;
        Ok(Grid {
            psi: Axis {
                origin: 0.0,
                step,
                first: 0,
                len: n,
                period: Some(n),
            },
            theta: Axis {
                origin: -FRAC_PI_2,
                step,
                first: 0,
                len: n / 2 + 1,
                period: None,
            },
            phi: Axis {
                origin: -PI,
                step,
                first: 0,
                len: n,
                period: Some(n),
            },
        })
    }

    fn without_roll(self) -> Grid {
        Grid {
            phi: Axis {
                origin: 0.0,
                step: self.phi.step,
                first: 0,
                len: 1,
                period: None,
            },
            ..self
        }
    }

    /// The whole-domain grid if its lattice holds at most 2^20 nodes per turn.
    fn whole(self) -> Result<Grid> {
        if self.psi.len as f64 > MAX_TURN_NODES {
            return Err(Error::out_of_range(
                "step_deg",
                format!(
                    "a step of {:.3e} deg over the whole domain is too fine: over 2^20 nodes per turn \
                     (steps down to {:.3e} deg; a window may be finer)",
                    self.step().to_degrees(),
                    (TAU / MAX_TURN_NODES).to_degrees()
                ),
            ));
        }
        Ok(self)
    }

    /// The window if it holds at most 2^52 cells.
    fn window_checked(self) -> Result<Grid> {
        let cells = self.psi.len as f64 * self.theta.len as f64 * self.phi.len as f64;
        if cells > MAX_WINDOW_CELLS {
            return Err(Error::out_of_range(
                "window_deg",
                format!(
                    "a window of {cells:.3e} cells at a step of {:.3e} deg is over 2^52 cells: \
                     coarsen the step or narrow the window",
                    self.step().to_degrees()
                ),
            ));
        }
        Ok(self)
    }

    /// Grid step, radians.
    pub fn step(&self) -> f64 {
        self.psi.step
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.psi.len * self.theta.len * self.phi.len
    }

    /// Whether the grid has no cell (never true for a constructed grid).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Cell indices `(p, t, f)` of a flat index.
    pub fn unflatten(&self, idx: usize) -> [usize; 3] {
        let p = idx % self.psi.len;
        let rest = idx / self.psi.len;
        [p, rest / self.phi.len, rest % self.phi.len]
    }

    /// Angles (psi, theta, phi) of cell `(p, t, f)`, radians; indices may leave the grid (lattice).
    pub fn angles(&self, idx: [i64; 3]) -> [f64; 3] {
        [
            self.psi.angle(idx[0]),
            self.theta.angle(idx[1]),
            self.phi.angle(idx[2]),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn absurd_windows_are_refused_by_name() {
        // 1e20 deg used to overflow the i64 node index (then a remainder by zero).
        let huge = 1e20f64.to_radians();
        for (lo, hi) in [(-huge, huge), (huge, huge + 1.0), (-huge, 0.1)] {
            let e = Grid::window(0.01, [(lo, hi), (0.0, 0.1), (0.0, 0.1)]).unwrap_err();
            let text = e.to_string();
            assert!(
                text.contains("window_deg (psi)") && text.contains("3600 deg"),
                "{text}"
            );
        }
        let e = Grid::two_dimensional_window(0.01, [(0.0, 0.1), (-huge, huge)]).unwrap_err();
        assert!(e.to_string().contains("window_deg (theta)"), "{e}");
        // The limit itself is accepted: a window of ten turns is the whole heading axis.
        let limit = MAX_WINDOW_RAD;
        let g = Grid::window(0.01, [(-limit, limit), (0.0, 0.1), (0.0, 0.1)]).unwrap();
        assert_eq!(Some(g.psi.len), g.psi.period);
        // Just inside the limit, a narrow window far from zero holds the nodes it should: 0.1 rad at
        // step 2 pi / 630 spans 10 or 11 nodes.
        let g = Grid::window(0.01, [(limit - 0.2, limit - 0.1), (0.0, 0.1), (0.0, 0.1)]).unwrap();
        assert!((10..=11).contains(&g.psi.len), "{}", g.psi.len);
    }
}
