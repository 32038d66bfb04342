//! The ambiguity-function grid's step (step 4 of the module documentation, `Ml` and `Auto`): the
//! epochs the method gives to the grid, their grid input ([`super::ml`]) and the grid's estimates.

use nalgebra::{Matrix3, Vector3};

use super::{leaves_epoch_unsolved, ml, Engine, Estimate, Prepared};
use super::{AUTO_ML_MAX_BASELINE_M, GRID_LENGTH_RELATIVE_SIGMA};
use crate::error::Result;
use crate::gnss::options::{EngineOptions, Method};
use crate::gnss::solution::FixState;
use crate::likelihood::dcm_enu_from_body;
use crate::likelihood::{ml_attitude_series, ml_baseline_series, MlEpoch, MlSolution};

impl Engine {
    /// Replaces the estimates the method gives to the grid (step 4): every solvable epoch for `Ml`,
    /// the unfixed ones within [`AUTO_ML_MAX_BASELINE_M`] for `Auto`.
    pub(super) fn grid(
        &mut self,
        prepared: &[Prepared],
        estimates: &mut [Option<Estimate>],
    ) -> Result<()> {
        if self.attitude_mode() {
            self.attitude_grid(prepared, estimates)
        } else if self.n_receivers != 2 {
            // The baseline grid has one baseline; several rovers in baseline mode keep LAMBDA.
            Ok(())
        } else {
            self.baseline_grid(prepared, estimates)
        }
    }

    /// Whether the method gives an epoch with estimate `e` and baseline length `length` to the grid.
    fn grid_wanted(&self, e: &Option<Estimate>, length: f64) -> bool {
        match self.opts.method {
            Method::Ml => true,
            _ => !e.as_ref().is_some_and(|e| e.fixed) && length < AUTO_ML_MAX_BASELINE_M,
        }
    }

    /// The grid's solved epochs among `picks` of `prepared`, as (index into `prepared`, solution):
    /// `solve` runs the grid on the epochs that have a grid input; none (and a warning) when its error
    /// leaves the epochs unsolved.
    fn grid_solutions(
        &mut self,
        prepared: &[Prepared],
        picks: &[usize],
        n_rovers: usize,
        solve: impl FnOnce(&[MlEpoch], &EngineOptions) -> Result<Vec<MlSolution>>,
    ) -> Result<Vec<(usize, MlSolution)>> {
        let epochs: Vec<Option<MlEpoch>> = picks
            .iter()
            .map(|&k| ml::epoch(&self.eph, &self.sats, &prepared[k], n_rovers))
            .collect();
        let solvable: Vec<usize> = (0..picks.len()).filter(|&i| epochs[i].is_some()).collect();
        if solvable.is_empty() {
            return Ok(Vec::new());
        }
        let series: Vec<MlEpoch> = epochs.into_iter().flatten().collect();
        let sols = match solve(&series, &self.opts) {
            Ok(sols) => sols,
            Err(e) if leaves_epoch_unsolved(&e) => {
                self.warn_once("ml".into(), format!("the likelihood grid failed: {e}"));
                return Ok(Vec::new());
            }
            Err(e) => return Err(e),
        };
        Ok(solvable
            .into_iter()
            .zip(sols)
            .filter(|(_, sol)| sol.solved)
            .map(|(i, sol)| (picks[i], sol))
            .collect())
    }

    /// Attitude mode: the grid over the body baselines.
    fn attitude_grid(
        &mut self,
        prepared: &[Prepared],
        estimates: &mut [Option<Estimate>],
    ) -> Result<()> {
        let picks: Vec<usize> = (0..prepared.len())
            .filter(|&k| prepared[k].rovers.iter().all(Option::is_some))
            .filter(|&k| self.grid_wanted(&estimates[k], 0.0))
            .collect();
        let sols =
            self.grid_solutions(prepared, &picks, self.n_receivers - 1, |series, opts| {
                ml_attitude_series(
                    series,
                    &opts.body_baselines_m,
                    opts.ml_step_rad,
                    opts.ml_window_rad,
                )
            })?;
        for (k, sol) in sols {
            let [psi, theta, phi] = sol.euler_gost_rad;
            let m = dcm_enu_from_body(psi, theta, phi);
            estimates[k] = Some(Estimate {
                baselines_enu_m: self
                    .opts
                    .body_baselines_m
                    .iter()
                    .map(|b| m * Vector3::from(*b))
                    .collect(),
                covariances_enu_m2: vec![Matrix3::from_element(f64::NAN); self.n_receivers - 1],
                enu_from_body: Some(m),
                attitude_sigmas_deg: Some([f64::NAN; 3]),
                ..ml_estimate()
            });
        }
        Ok(())
    }

    /// Baseline mode, one rover: the grid at the baseline's length, once that is known.
    fn baseline_grid(
        &mut self,
        prepared: &[Prepared],
        estimates: &mut [Option<Estimate>],
    ) -> Result<()> {
        // The grid's baseline length: a few percent of error in it moves the grid's maximum to a wrong
        // direction, so the grid runs only once the length is known.
        let known = match self.opts.baseline_lengths_m.first() {
            Some(&l) => Ok(l),
            None => self.length[0].known(),
        };
        let length = match known {
            Ok(l) => l,
            Err((l, sigma)) => {
                if self.opts.method == Method::Ml {
                    self.warn_once(
                        "ml length".into(),
                        format!(
                            "the likelihood grid needs the baseline length to {:.0} %, and the solutions so \
                             far give {l:.3} +- {sigma:.3} m: those epochs keep their double-difference \
                             solution (--method lambda), later ones use the grid once the length is known",
                            100.0 * GRID_LENGTH_RELATIVE_SIGMA
                        ),
                    );
                }
                return Ok(());
            }
        };
        let picks: Vec<usize> = (0..prepared.len())
            .filter(|&k| prepared[k].rovers[0].is_some() && self.grid_wanted(&estimates[k], length))
            .collect();
        let sols = self.grid_solutions(prepared, &picks, 1, |series, opts| {
            ml_baseline_series(series, length, opts.ml_step_rad, opts.ml_window_rad)
        })?;
        for (k, sol) in sols {
            let [az, el] = sol.direction_rad;
            let unit = Vector3::new(az.sin() * el.cos(), az.cos() * el.cos(), el.sin());
            estimates[k] = Some(Estimate {
                baselines_enu_m: vec![unit * length],
                covariances_enu_m2: vec![Matrix3::from_element(f64::NAN)],
                ..ml_estimate()
            });
        }
        Ok(())
    }
}

/// An ML estimate's fields that do not depend on the mode.
fn ml_estimate() -> Estimate {
    Estimate {
        method: Method::Ml,
        fixed: false,
        fix_state: FixState::Float,
        fixed_ambiguities: 0,
        ambiguities: 0,
        ratio: f64::NAN,
        success_rate: f64::NAN,
        baselines_enu_m: Vec::new(),
        covariances_enu_m2: Vec::new(),
        enu_from_body: None,
        attitude_sigmas_deg: None,
    }
}
