//! Orbit-determination Kalman filter of a receiver on a small satellite (Dzhepe Ali, chapter 1): the state
//! `x = (r, v)` in Earth-fixed axes (m, m/s) is predicted by the GLONASS ICD model with its state-transition
//! matrix and corrected either by the receiver's own position/velocity fixes (loosely coupled) or by first
//! differences, between satellites of the same system, of pseudoranges and Doppler-derived range rates
//! (tightly coupled): the receiver clock bias, its drift and the GPS-GLONASS inter-system bias cancel, so
//! the filter keeps updating with 2-3 visible satellites of one system, where no fix exists.
//!
//! Process noise: white acceleration of power spectral density `q` (m^2/s^3) on each axis,
//! `Qc = diag(0, 0, 0, q, q, q)`, discretised per integration step by Van Loan's method with the Jacobian at
//! the start of the step ([`crate::kalman::discretize`]). Ranges are instantaneous geometric distances
//! (no light time or Sagnac term; the simulator makes them the same way).

use nalgebra::{DMatrix, DVector, Matrix6, Vector3, Vector6};

use super::glonass::GlonassModel;
use crate::error::{ensure_finite, Error, Result};
use crate::{guard, interrupt, kalman};

/// Most prediction steps of one run, summed over its epochs: a step (RK4 with the state-transition
/// matrix and a Van Loan discretisation) measured 21 us on the loaded build machine, so about 10 s; a day
/// of 1 s epochs is 86 400.
pub const MAX_FILTER_STEPS: f64 = 5e5;

/// Most satellites of a tightly coupled run: an epoch's update is cubic in them; every GNSS constellation
/// together has about 150.
pub const MAX_SATELLITES: usize = 1024;

/// Model and noise settings of the filter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterConfig {
    /// Prediction model (Earth-fixed ICD equations).
    pub model: GlonassModel,
    /// Power spectral density of the white acceleration noise per axis, m^2/s^3.
    pub accel_psd_m2_s3: f64,
    /// Longest RK4 step of the prediction, s (each interval is cut into equal steps no longer than this).
    pub step_s: f64,
}

/// The receiver's own fixes (loosely coupled corrections), one per epoch.
#[derive(Debug, Clone, Copy)]
pub struct Fixes<'a> {
    /// Position of each epoch, ECEF, m.
    pub position_m: &'a [[f64; 3]],
    /// Velocity relative to the rotating Earth, ECEF, m/s.
    pub velocity_m_s: &'a [[f64; 3]],
    /// Covariance of `(position, velocity)` of each epoch.
    pub covariance: &'a [Matrix6<f64>],
    /// Whether the receiver had a fix at that epoch.
    pub valid: &'a [bool],
}

/// Pseudoranges and Doppler of `n_sat` satellites at each epoch (tightly coupled corrections). Arrays over
/// epochs and satellites are flattened epoch-major: index `k * n_sat + j`.
#[derive(Debug, Clone, Copy)]
pub struct Ranges<'a> {
    pub n_sat: usize,
    /// Satellite positions at the epochs, ECEF, m.
    pub sat_position_m: &'a [[f64; 3]],
    /// Satellite velocities relative to the rotating Earth, ECEF, m/s.
    pub sat_velocity_m_s: &'a [[f64; 3]],
    /// Pseudoranges, m.
    pub pseudorange_m: &'a [f64],
    /// Doppler shifts, Hz, RINEX sign (positive while approaching): `D = -(rho_dot + c drift) / lambda`.
    pub doppler_hz: &'a [f64],
    /// Whether the satellite was tracked; values of untracked satellites are ignored (may be NaN).
    pub visible: &'a [bool],
    /// Carrier wavelength of each satellite (per-satellite for GLONASS FDMA), m.
    pub wavelength_m: &'a [f64],
    /// System of each satellite (e.g. 0 GPS, 1 GLONASS): differences are formed within a system only.
    pub system: &'a [u32],
    /// Standard deviation of the pseudorange noise, m.
    pub code_sigma_m: f64,
    /// Standard deviation of the Doppler noise, Hz; <= 0 leaves the Doppler out.
    pub doppler_sigma_hz: f64,
}

/// The corrections the filter uses.
#[derive(Debug, Clone, Copy)]
pub enum Corrections<'a> {
    Loose(Fixes<'a>),
    Tight(Ranges<'a>),
}

/// Estimates after the update of each epoch.
#[derive(Debug, Clone, PartialEq)]
pub struct FilterOutput {
    pub states: Vec<[f64; 6]>,
    pub covariances: Vec<Matrix6<f64>>,
    /// Normalised innovation squared of the epoch's update; NaN where the epoch had no update.
    pub nis: Vec<f64>,
    /// Number of scalar measurements of the epoch's update (the NIS degrees of freedom), 0 where none.
    pub dof: Vec<usize>,
}

fn check_len(name: &'static str, len: usize, expected: usize, what: &str) -> Result<()> {
    if len != expected {
        return Err(Error::Shape {
            name,
            expected: format!("{expected} values ({what})"),
            actual: format!("{len}"),
        });
    }
    Ok(())
}

impl Ranges<'_> {
    fn validate(&self, n_t: usize) -> Result<()> {
        guard::check_work(
            "data",
            self.n_sat as f64,
            MAX_SATELLITES as f64,
            "satellites",
        )?;
        let n = n_t * self.n_sat;
        check_len(
            "sat_position_m",
            self.sat_position_m.len(),
            n,
            "n_t x n_sat",
        )?;
        check_len(
            "sat_velocity_m_s",
            self.sat_velocity_m_s.len(),
            n,
            "n_t x n_sat",
        )?;
        check_len("pseudorange_m", self.pseudorange_m.len(), n, "n_t x n_sat")?;
        check_len("doppler_hz", self.doppler_hz.len(), n, "n_t x n_sat")?;
        check_len("visible", self.visible.len(), n, "n_t x n_sat")?;
        check_len("wavelength_m", self.wavelength_m.len(), self.n_sat, "n_sat")?;
        check_len("system", self.system.len(), self.n_sat, "n_sat")?;
        ensure_finite("wavelength_m", self.wavelength_m)?;
        if let Some(l) = self.wavelength_m.iter().find(|l| **l <= 0.0) {
            return Err(Error::out_of_range(
                "wavelength_m",
                format!("expected wavelengths > 0 m, got {l}"),
            ));
        }
        ensure_finite("noise sigmas", [&self.code_sigma_m, &self.doppler_sigma_hz])?;
        if self.code_sigma_m <= 0.0 {
            return Err(Error::out_of_range(
                "code_sigma_m",
                format!(
                    "expected a pseudorange sigma > 0 m, got {}",
                    self.code_sigma_m
                ),
            ));
        }
        for i in (0..n).filter(|&i| self.visible[i]) {
            let bad = self.sat_position_m[i]
                .iter()
                .chain(&self.sat_velocity_m_s[i])
                .chain([&self.pseudorange_m[i]])
                .any(|v| !v.is_finite())
                || (self.doppler_sigma_hz > 0.0 && !self.doppler_hz[i].is_finite());
            if bad {
                return Err(Error::NonFinite {
                    name: "tracked satellite's measurement or state (epoch * n_sat + satellite)",
                    index: i,
                });
            }
        }
        Ok(())
    }

    /// Within-system groups of the tracked satellites of epoch `k`, only groups of two or more.
    fn groups(&self, k: usize) -> Vec<Vec<usize>> {
        let mut systems: Vec<u32> = self.system.to_vec();
        systems.sort_unstable();
        systems.dedup();
        systems
            .into_iter()
            .map(|s| {
                (0..self.n_sat)
                    .filter(|&j| self.system[j] == s && self.visible[k * self.n_sat + j])
                    .collect::<Vec<_>>()
            })
            .filter(|g| g.len() >= 2)
            .collect()
    }

    /// Innovation, Jacobian and noise covariance of the between-satellite differences at epoch `k`.
    fn linearize(
        &self,
        k: usize,
        x: &Vector6<f64>,
    ) -> Option<(DVector<f64>, DMatrix<f64>, DMatrix<f64>)> {
        let groups = self.groups(k);
        let n_diff: usize = groups.iter().map(|g| g.len() - 1).sum();
        if n_diff == 0 {
            return None;
        }
        let use_doppler = self.doppler_sigma_hz > 0.0;
        let per = if use_doppler { 2 } else { 1 };
        let m = per * n_diff;
        let r = x.fixed_rows::<3>(0).into_owned();
        let v = x.fixed_rows::<3>(3).into_owned();
        // Undifferenced residuals and Jacobian rows of one satellite: (code, rate).
        let single = |j: usize| {
            let i = k * self.n_sat + j;
            let d = Vector3::from(self.sat_position_m[i]) - r;
            let rho = d.norm();
            let u = d / rho;
            let dv = Vector3::from(self.sat_velocity_m_s[i]) - v;
            let rate = u.dot(&dv);
            let mut h = [[0.0; 6]; 2];
            for a in 0..3 {
                h[0][a] = -u[a];
                h[1][a] = -(dv[a] - u[a] * rate) / rho;
                h[1][3 + a] = -u[a];
            }
            let rate_meas = -self.wavelength_m[j] * self.doppler_hz[i];
            (
                [self.pseudorange_m[i] - rho, rate_meas - rate],
                h,
                self.wavelength_m[j] * self.doppler_sigma_hz,
            )
        };
        let mut nu = DVector::zeros(m);
        let mut h = DMatrix::zeros(m, 6);
        let mut cov = DMatrix::zeros(m, m);
        let sc2 = self.code_sigma_m * self.code_sigma_m;
        let mut row = 0;
        for g in &groups {
            let (res0, h0, sr0) = single(g[0]);
            let start = row;
            for &j in &g[1..] {
                let (res, hj, sr) = single(j);
                for p in 0..per {
                    let rr = row + p * n_diff;
                    nu[rr] = res[p] - res0[p];
                    for c in 0..6 {
                        h[(rr, c)] = hj[p][c] - h0[p][c];
                    }
                }
                // Differences against one reference share its noise: diagonal s_j^2 + s_0^2,
                // off-diagonal s_0^2 within the group.
                cov[(row, row)] = 2.0 * sc2;
                if use_doppler {
                    let rr = row + n_diff;
                    cov[(rr, rr)] = sr * sr + sr0 * sr0;
                }
                for other in start..row {
                    cov[(row, other)] = sc2;
                    cov[(other, row)] = sc2;
                    if use_doppler {
                        let (a, b) = (row + n_diff, other + n_diff);
                        cov[(a, b)] = sr0 * sr0;
                        cov[(b, a)] = sr0 * sr0;
                    }
                }
                row += 1;
            }
        }
        Some((nu, h, cov))
    }
}

impl Fixes<'_> {
    fn validate(&self, n_t: usize) -> Result<()> {
        check_len("fix position_m", self.position_m.len(), n_t, "n_t")?;
        check_len("fix velocity_m_s", self.velocity_m_s.len(), n_t, "n_t")?;
        check_len("fix covariance", self.covariance.len(), n_t, "n_t")?;
        check_len("fix valid", self.valid.len(), n_t, "n_t")?;
        for k in (0..n_t).filter(|&k| self.valid[k]) {
            let finite = self.position_m[k]
                .iter()
                .chain(&self.velocity_m_s[k])
                .chain(self.covariance[k].iter())
                .all(|v| v.is_finite());
            if !finite {
                return Err(Error::NonFinite {
                    name: "fix (epoch) with valid = true",
                    index: k,
                });
            }
        }
        Ok(())
    }
}

/// Number of prediction steps over `dt` (s).
fn steps_of(config: &FilterConfig, dt: f64) -> f64 {
    (dt / config.step_s).ceil().max(1.0)
}

/// One prediction over `dt` (s) in equal steps no longer than `config.step_s`.
fn predict(
    config: &FilterConfig,
    x: &mut Vector6<f64>,
    p: &mut DMatrix<f64>,
    dt: f64,
) -> Result<()> {
    let n = steps_of(config, dt) as usize;
    let h = dt / n as f64;
    let mut qc = DMatrix::zeros(6, 6);
    for a in 3..6 {
        qc[(a, a)] = config.accel_psd_m2_s3;
    }
    for _ in 0..n {
        interrupt::check("orbit filter")?;
        let f = config.model.jacobian(&x.fixed_rows::<3>(0).into_owned());
        let (_, qd) = kalman::discretize(&DMatrix::from_column_slice(6, 6, f.as_slice()), &qc, h)?;
        let (xn, phi) = config.model.rk4_step_with_stm(x, h);
        *x = xn;
        let phi = DMatrix::from_column_slice(6, 6, phi.as_slice());
        *p = kalman::predict_covariance(p, &phi, &qd)?;
    }
    Ok(())
}

/// Runs the filter over epochs `times_s` (s, strictly increasing) from the state `x0` with covariance `p0`
/// at `times_s[0]`; each epoch is predicted to, then updated with its corrections.
///
/// # Errors
/// Inconsistent lengths, non-finite inputs, times not increasing, a covariance that is not positive
/// definite, or no epoch with a usable measurement; [`Error::TooLarge`] for more than
/// [`MAX_FILTER_STEPS`] prediction steps (`step_s`) or [`MAX_SATELLITES`] satellites;
/// [`Error::Numerical`] for an estimate that is not finite (a diverging prediction or update);
/// [`Error::Interrupted`] on [`crate::interrupt::request`].
pub fn run(
    config: &FilterConfig,
    times_s: &[f64],
    x0: &[f64; 6],
    p0: &Matrix6<f64>,
    corrections: &Corrections<'_>,
) -> Result<FilterOutput> {
    config.model.validate()?;
    ensure_finite("filter settings", [&config.accel_psd_m2_s3, &config.step_s])?;
    if config.accel_psd_m2_s3 < 0.0 || config.step_s <= 0.0 {
        return Err(Error::out_of_range(
            "filter settings",
            format!(
                "expected accel_psd_m2_s3 >= 0 and step_s > 0, got {} and {}",
                config.accel_psd_m2_s3, config.step_s
            ),
        ));
    }
    let n_t = times_s.len();
    if n_t == 0 {
        return Err(Error::out_of_range(
            "times_s",
            "expected at least one epoch of measurements, got none",
        ));
    }
    ensure_finite("times_s", times_s)?;
    if let Some(k) = (1..n_t).find(|&k| times_s[k] <= times_s[k - 1]) {
        return Err(Error::out_of_range(
            "times_s",
            format!(
                "expected strictly increasing epochs, got {} s after {} s at index {k}",
                times_s[k],
                times_s[k - 1]
            ),
        ));
    }
    let steps: f64 = times_s
        .windows(2)
        .map(|w| steps_of(config, w[1] - w[0]))
        .sum();
    guard::check_work("step_s", steps, MAX_FILTER_STEPS, "prediction steps")?;
    ensure_finite("x0", x0)?;
    ensure_finite("p0", p0.iter())?;
    let usable = match corrections {
        Corrections::Loose(f) => {
            f.validate(n_t)?;
            f.valid.iter().filter(|v| **v).count()
        }
        Corrections::Tight(r) => {
            r.validate(n_t)?;
            (0..n_t).filter(|&k| !r.groups(k).is_empty()).count()
        }
    };
    if usable == 0 {
        return Err(Error::out_of_range(
            "measurements",
            format!(
                "no measurement in any of the {n_t} epochs (loosely coupled: no valid fix; tightly \
                 coupled: never two tracked satellites of one system); nothing to filter"
            ),
        ));
    }
    let mut x = Vector6::from_column_slice(x0);
    let mut p = DMatrix::from_column_slice(6, 6, p0.as_slice());
    let mut out = FilterOutput {
        states: Vec::with_capacity(n_t),
        covariances: Vec::with_capacity(n_t),
        nis: Vec::with_capacity(n_t),
        dof: Vec::with_capacity(n_t),
    };
    for k in 0..n_t {
        if k > 0 {
            predict(config, &mut x, &mut p, times_s[k] - times_s[k - 1])
                .map_err(|e| e.at_epoch(k))?;
        }
        let lin = match corrections {
            Corrections::Loose(f) if f.valid[k] => {
                let z = Vector6::new(
                    f.position_m[k][0],
                    f.position_m[k][1],
                    f.position_m[k][2],
                    f.velocity_m_s[k][0],
                    f.velocity_m_s[k][1],
                    f.velocity_m_s[k][2],
                );
                let nu = DVector::from_column_slice((z - x).as_slice());
                let r = DMatrix::from_column_slice(6, 6, f.covariance[k].as_slice());
                Some((nu, DMatrix::identity(6, 6), r))
            }
            Corrections::Loose(_) => None,
            Corrections::Tight(r) => r.linearize(k, &x),
        };
        let (nis, dof) = match lin {
            Some((nu, h, r)) => {
                let mut xd = DVector::from_column_slice(x.as_slice());
                let upd =
                    kalman::update(&mut xd, &mut p, &nu, &h, &r).map_err(|e| e.at_epoch(k))?;
                x = Vector6::from_column_slice(xd.as_slice());
                (upd.nis, nu.len())
            }
            None => (f64::NAN, 0),
        };
        let nis_of_update = if dof > 0 { Some(&nis) } else { None };
        guard::finite_output(
            "orbit filter",
            x.iter().chain(p.iter()).chain(nis_of_update),
            &format!("epoch {k}: the estimate diverged (check p0, the measurements' covariances and step_s)"),
        )?;
        out.states.push(x.into());
        out.covariances
            .push(Matrix6::from_column_slice(p.as_slice()));
        out.nis.push(nis);
        out.dof.push(dof);
    }
    Ok(out)
}
