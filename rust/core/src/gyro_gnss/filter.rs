//! The filter loop: propagation between events, loosely and tightly coupled updates, ambiguity
//! bookkeeping (rise, set, slip, fix) and the true-error covariance of the sensitivity analysis.

use std::collections::HashMap;

use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, UnitQuaternion, Vector3};

use super::kinematics::{check_rates, check_times, skew, step, to_array, unit};
use super::{AttitudeFix, FilterRun, FixAttempt, Initial, Nis, PhaseEpoch, Settings, Slip};
use crate::error::{ensure_finite, Error, Result};
use crate::kalman::{discretize, predict_covariance, symmetrize, update};
use crate::lambda::bootstrap::success_rate;
use crate::lambda::gate::{Decision, Gate, Names, Reason};
use crate::lambda::Problem;
use crate::{guard, interrupt};

/// Attitude error and drift error: the states every configuration has.
const CORE: usize = 6;
/// Core states plus the misalignment of the sensitivity analysis.
const DYN: usize = 9;
/// Search nodes allowed per fix attempt.
const MAX_FIX_NODES: u64 = 1_000_000;

/// Most gyro samples of one run: a sample measured 21 us on the loaded build machine (the covariance
/// propagation), so about 10 s; 100 Hz for 83 minutes. The recorded outputs (about 100 values each, at
/// most one per sample) stay below 400 MB with it.
pub const MAX_FILTER_SAMPLES: f64 = 5e5;

/// Most error states (attitude, drift, misalignment, then one float ambiguity per baseline and tracked
/// satellite, or 3 per baseline in the sensitivity analysis): an update is cubic in them, 512^3 ~ 1e8
/// flops; 4 baselines and 40 satellites need 169.
pub const MAX_FILTER_STATES: usize = 512;

/// Runs the filter over the gyro record `gyro_t`, `gyro_rates` (`rates[k]` holds over
/// `[t_k, t_{k+1}]`, body axes, rad/s) with the loosely coupled `attitude_fixes` and/or the tightly coupled
/// `phase_epochs`, each sorted by time within `[t_0, t_last]`.
///
/// # Errors
/// [`Error::OutOfRange`], [`Error::NonFinite`] or [`Error::Shape`] for bad settings or inputs (time
/// stamps out of order or outside the gyro record, zero-length baselines, ...);
/// [`Error::DegenerateGeometry`] if an innovation covariance is not positive definite;
/// [`Error::TooLarge`] for more than [`MAX_FILTER_SAMPLES`] gyro samples (`gyro_t`),
/// [`MAX_FILTER_STATES`] error states (`phases`: baselines x satellites of an epoch; `baselines` with the
/// sensitivity analysis); [`Error::Numerical`] for an
/// estimate that is not finite; [`Error::Interrupted`] on [`crate::interrupt::request`].
pub fn run(
    settings: &Settings,
    initial: &Initial,
    gyro_t: &[f64],
    gyro_rates: &[Vector3<f64>],
    attitude_fixes: &[AttitudeFix],
    phase_epochs: &[PhaseEpoch],
) -> Result<FilterRun> {
    check_settings(
        settings,
        !phase_epochs.is_empty(),
        !attitude_fixes.is_empty(),
    )?;
    check_work(settings, gyro_t.len(), phase_epochs)?;
    check_times("gyro_t", gyro_t, 2)?;
    check_rates("gyro_rates", gyro_rates, gyro_t)?;
    let (t0, t1) = (gyro_t[0], gyro_t[gyro_t.len() - 1]);
    check_attitude_fixes(attitude_fixes, t0, t1)?;
    check_phase_epochs(phase_epochs, settings.baselines.len(), t0, t1)?;
    let mut f = Filter::new(settings, initial)?;
    let mut out = FilterRun::default();
    f.record(&mut out, t0);
    let (mut ia, mut ip) = (0, 0);
    for k in 0..gyro_t.len() - 1 {
        interrupt::check("gyro + GNSS filter")?;
        let rate = gyro_rates[k];
        loop {
            let ta = attitude_fixes.get(ia).map_or(f64::INFINITY, |a| a.t);
            let tp = phase_epochs.get(ip).map_or(f64::INFINITY, |p| p.t);
            let te = ta.min(tp);
            if te > gyro_t[k + 1] {
                break;
            }
            f.propagate(&rate, te)?;
            if ta <= tp {
                f.attitude_update(&attitude_fixes[ia], &mut out)
                    .map_err(|e| e.at_epoch(ia))?;
                ia += 1;
            } else {
                f.phase_update(&phase_epochs[ip], &mut out)
                    .map_err(|e| e.at_epoch(ip))?;
                ip += 1;
            }
        }
        f.propagate(&rate, gyro_t[k + 1])?;
        if (k + 1) % settings.output_every == 0 || k + 2 == gyro_t.len() {
            f.record(&mut out, gyro_t[k + 1]);
        }
    }
    check_outputs(&out)?;
    Ok(out)
}

/// Refuses more than [`MAX_FILTER_SAMPLES`] samples or [`MAX_FILTER_STATES`] states before the run
/// starts.
fn check_work(settings: &Settings, samples: usize, phase_epochs: &[PhaseEpoch]) -> Result<()> {
    let limit = MAX_FILTER_STATES as f64;
    guard::check_work("gyro_t", samples as f64, MAX_FILTER_SAMPLES, "gyro samples")?;
    let m = settings.baselines.len() as f64;
    let most_obs = phase_epochs.iter().map(|e| e.obs.len()).max().unwrap_or(0) as f64;
    let fixed = (if settings.misalignment_sigma.is_some() {
        DYN
    } else {
        CORE
    }) as f64;
    guard::check_work("phases", fixed + m * most_obs, limit, "error states")?;
    if settings.sensitivity.is_some() {
        guard::check_work(
            "baselines",
            DYN as f64 + 3.0 * m,
            limit,
            "sensitivity states",
        )?;
    }
    Ok(())
}

/// Every recorded estimate is finite, or the run is refused.
fn check_outputs(out: &FilterRun) -> Result<()> {
    let hint = "the filter diverged; check the covariances, noise densities and gyro rates";
    guard::finite_output("gyro + GNSS filter", out.quaternion.iter().flatten(), hint)?;
    guard::finite_output("gyro + GNSS filter", out.drift.iter().flatten(), hint)?;
    guard::finite_output(
        "gyro + GNSS filter",
        out.misalignment.iter().flatten(),
        hint,
    )?;
    for m in out.covariance.iter().chain(&out.true_covariance) {
        guard::finite_output("gyro + GNSS filter", m.iter(), hint)?;
    }
    for m in &out.misalignment_covariance {
        guard::finite_output("gyro + GNSS filter", m.iter(), hint)?;
    }
    Ok(())
}

/// The filter's state between events.
struct Filter<'a> {
    s: &'a Settings,
    t: f64,
    q: UnitQuaternion<f64>,
    drift: Vector3<f64>,
    /// `[dtheta, ddrift]` (zero between updates) then the float ambiguities, cycles.
    x: DVector<f64>,
    p: DMatrix<f64>,
    /// Error states before the ambiguities: 6, or 9 when the misalignment is estimated.
    nc: usize,
    /// Misalignment estimate (rotation vector of the gyro triad), rad.
    misalignment: Vector3<f64>,
    /// Track of each group of `m` float ambiguities in `x[nc..]`, in order.
    float_tracks: Vec<i64>,
    /// Fixed integers per track, one per baseline.
    fixed: HashMap<i64, Vec<i64>>,
    /// Covariance of `[true error (6), misalignment (3), baseline errors (3m)]` (sensitivity only).
    py: Option<DMatrix<f64>>,
}

impl<'a> Filter<'a> {
    fn new(s: &'a Settings, init: &Initial) -> Result<Self> {
        let q = unit("initial quaternion", init.quaternion)?;
        ensure_finite("initial drift", init.drift.iter())?;
        ensure_finite("initial covariance", init.covariance.iter())?;
        if init.covariance.cholesky().is_none() {
            return Err(Error::out_of_range(
                "initial covariance",
                "expected a symmetric positive definite 6 x 6 matrix",
            ));
        }
        let nc = if s.misalignment_sigma.is_some() {
            DYN
        } else {
            CORE
        };
        let mut p = DMatrix::zeros(nc, nc);
        p.view_mut((0, 0), (CORE, CORE))
            .copy_from(&DMatrix::from_iterator(
                CORE,
                CORE,
                init.covariance.iter().copied(),
            ));
        for i in CORE..nc {
            p[(i, i)] = s.misalignment_sigma.unwrap_or(0.0).powi(2);
        }
        let py = s.sensitivity.map(|sens| {
            let m3 = 3 * s.baselines.len();
            let mut py = DMatrix::zeros(DYN + m3, DYN + m3);
            py.view_mut((0, 0), (CORE, CORE))
                .copy_from(&p.view((0, 0), (CORE, CORE)));
            for i in CORE..DYN {
                py[(i, i)] = sens.misalignment_sigma.powi(2);
            }
            for i in DYN..DYN + m3 {
                py[(i, i)] = sens.baseline_sigma.powi(2);
            }
            py
        });
        Ok(Filter {
            s,
            t: f64::NAN,
            q,
            drift: init.drift,
            x: DVector::zeros(nc),
            nc,
            misalignment: Vector3::zeros(),
            p,
            float_tracks: Vec::new(),
            fixed: HashMap::new(),
            py,
        })
    }

    fn m(&self) -> usize {
        self.s.baselines.len()
    }

    fn record(&mut self, out: &mut FilterRun, t: f64) {
        if self.t.is_nan() {
            self.t = t;
        }
        out.t.push(t);
        out.quaternion.push(to_array(&self.q));
        out.drift.push(self.drift);
        out.covariance.push(Matrix6::from_fn(|i, j| self.p[(i, j)]));
        out.misalignment.push(self.misalignment);
        out.misalignment_covariance.push(Matrix3::from_fn(|i, j| {
            if self.nc == DYN {
                self.p[(CORE + i, CORE + j)]
            } else {
                0.0
            }
        }));
        if let Some(py) = &self.py {
            out.true_covariance
                .push(Matrix6::from_fn(|i, j| py[(i, j)]));
        }
        out.n_float.push(self.float_tracks.len() * self.m());
        out.n_fixed.push(self.fixed.len() * self.m());
    }

    /// Propagates attitude and covariances to `t` with the gyro rate `rate` (held constant).
    fn propagate(&mut self, rate: &Vector3<f64>, t: f64) -> Result<()> {
        let h = t - self.t;
        if h <= 0.0 {
            return Ok(());
        }
        // Gyro axes -> body: exp([mu x]) undoes the triad's misalignment (identity when not estimated).
        let w = UnitQuaternion::from_scaled_axis(self.misalignment) * (rate + self.drift);
        self.q = step(&self.q, &w, h);
        self.t = t;
        // Misalignment enters as d(dtheta)/dt = -[w x] mu; it lives only in the sensitivity model, whose
        // 9-state exponential has the filter's own 6 x 6 transition as its leading block.
        let nd = if self.py.is_some() { DYN } else { self.nc };
        let mut f = DMatrix::zeros(nd, nd);
        let wx = skew(&w);
        f.view_mut((0, 0), (3, 3)).copy_from(&(-wx));
        f.view_mut((0, 3), (3, 3)).fill_with_identity();
        if nd == DYN {
            f.view_mut((0, 6), (3, 3)).copy_from(&(-wx));
        }
        let mut qc = DMatrix::zeros(nd, nd);
        for i in 0..3 {
            qc[(i, i)] = self.s.noise.arw.powi(2);
            qc[(3 + i, 3 + i)] = self.s.noise.rrw.powi(2);
        }
        let (phi9, qd9) = discretize(&f, &qc, h)?;
        let nc = self.nc;
        let phi = phi9.view((0, 0), (nc, nc)).into_owned();
        let qd = qd9.view((0, 0), (nc, nc)).into_owned();
        let pcc = self.p.view((0, 0), (nc, nc)).into_owned();
        let pcc = predict_covariance(&pcc, &phi, &qd)?;
        self.p.view_mut((0, 0), (nc, nc)).copy_from(&pcc);
        let n = self.p.nrows();
        if n > nc {
            let pca = &phi * self.p.view((0, nc), (nc, n - nc));
            self.p.view_mut((0, nc), (nc, n - nc)).copy_from(&pca);
            self.p
                .view_mut((nc, 0), (n - nc, nc))
                .copy_from(&pca.transpose());
        }
        if let Some(py) = &mut self.py {
            let ny = py.nrows();
            let mut phiy = DMatrix::identity(ny, ny);
            phiy.view_mut((0, 0), (DYN, DYN)).copy_from(&phi9);
            let mut qy = DMatrix::zeros(ny, ny);
            qy.view_mut((0, 0), (DYN, DYN)).copy_from(&qd9);
            *py = predict_covariance(py, &phiy, &qy)?;
        }
        Ok(())
    }

    /// Folds the estimated attitude and drift errors into the nominal state and zeroes them.
    fn reset(&mut self) {
        let dtheta = Vector3::new(self.x[0], self.x[1], self.x[2]);
        self.q = step(&self.q, &dtheta, 1.0);
        self.drift += Vector3::new(self.x[3], self.x[4], self.x[5]);
        if self.nc == DYN {
            self.misalignment += Vector3::new(self.x[6], self.x[7], self.x[8]);
        }
        self.x.rows_mut(0, self.nc).fill(0.0);
    }

    fn attitude_update(&mut self, fix: &AttitudeFix, out: &mut FilterRun) -> Result<()> {
        let measured = unit("attitude fix quaternion", fix.quaternion)?;
        let z = (self.q.inverse() * measured).scaled_axis();
        let n = self.x.len();
        let mut h = DMatrix::zeros(3, n);
        h.view_mut((0, 0), (3, 3)).fill_with_identity();
        let r = DMatrix::from_iterator(3, 3, fix.covariance.iter().copied());
        let nu = DVector::from_column_slice(z.as_slice());
        let u = update(&mut self.x, &mut self.p, &nu, &h, &r)?;
        out.nis.push(Nis {
            t: fix.t,
            nis: u.nis,
            dof: 3,
        });
        self.reset();
        Ok(())
    }

    /// Rows of one satellite: `(H (m x n), predicted phase without ambiguity (m), H_theta (m x 3),
    /// H_beta blocks (m x 3, one per baseline))`.
    fn geometry(&self, los: &Vector3<f64>, wavelength: f64) -> (DMatrix<f64>, Vec<f64>) {
        let m = self.m();
        let s_body = self.q.inverse() * los;
        let mut h = DMatrix::zeros(m, 3);
        let mut pred = Vec::with_capacity(m);
        for (i, b) in self.s.baselines.iter().enumerate() {
            let row = s_body.cross(b) / wavelength;
            h.view_mut((i, 0), (1, 3)).copy_from(&row.transpose());
            pred.push(-s_body.dot(b) / wavelength);
        }
        (h, pred)
    }

    fn phase_update(&mut self, epoch: &PhaseEpoch, out: &mut FilterRun) -> Result<()> {
        let m = self.m();
        let r_one = self.s.phase_sigma.powi(2);
        // Satellites no longer tracked take their ambiguities with them.
        let seen: Vec<i64> = epoch.obs.iter().map(|o| o.track).collect();
        let gone: Vec<i64> = self
            .float_tracks
            .iter()
            .copied()
            .filter(|t| !seen.contains(t))
            .collect();
        for t in gone {
            self.remove_float(t);
        }
        self.fixed.retain(|t, _| seen.contains(t));

        let mut rows: Vec<(usize, i64)> = Vec::new(); // (obs index, track) used in the update
        let mut new_tracks: Vec<usize> = Vec::new();
        for (j, obs) in epoch.obs.iter().enumerate() {
            let known = self.s.known_ambiguities
                || self.fixed.contains_key(&obs.track)
                || self.float_tracks.contains(&obs.track);
            if !known {
                new_tracks.push(j);
                continue;
            }
            if self.s.known_ambiguities || !self.s.slip_threshold.is_finite() {
                rows.push((j, obs.track));
                continue;
            }
            let (hh, nu) = self.rows_of(&[(j, obs.track)], epoch);
            let s = symmetrize(&hh * &self.p * hh.transpose() + DMatrix::identity(m, m) * r_one);
            let nis = s
                .clone()
                .cholesky()
                .map_or(f64::INFINITY, |c| nu.dot(&c.solve(&nu)));
            if nis > self.s.slip_threshold {
                out.slips.push(Slip {
                    t: epoch.t,
                    track: obs.track,
                    nis,
                });
                self.remove_float(obs.track);
                self.fixed.remove(&obs.track);
                new_tracks.push(j);
            } else {
                rows.push((j, obs.track));
            }
        }
        if !rows.is_empty() {
            let (hh, nu) = self.rows_of(&rows, epoch);
            let r = DMatrix::identity(nu.len(), nu.len()) * r_one;
            let k_gain = self.py.is_some().then(|| self.gain(&hh, &r)).transpose()?;
            let u = update(&mut self.x, &mut self.p, &nu, &hh, &r)?;
            if let Some(k) = k_gain {
                self.true_error_update(&rows, epoch, &hh, &k, &r);
            }
            out.nis.push(Nis {
                t: epoch.t,
                nis: u.nis,
                dof: nu.len(),
            });
            self.reset();
        }
        for j in new_tracks {
            self.add_float(&epoch.obs[j]);
        }
        if self.s.fix.enabled && !self.float_tracks.is_empty() {
            self.try_fix(epoch.t, out)?;
        }
        Ok(())
    }

    /// Stacked Jacobian and innovations of the given observations.
    fn rows_of(&self, rows: &[(usize, i64)], epoch: &PhaseEpoch) -> (DMatrix<f64>, DVector<f64>) {
        let m = self.m();
        let n = self.x.len();
        let mut hh = DMatrix::zeros(m * rows.len(), n);
        let mut nu = DVector::zeros(m * rows.len());
        for (r, &(j, track)) in rows.iter().enumerate() {
            let obs = &epoch.obs[j];
            let (h, pred) = self.geometry(&obs.los, obs.wavelength);
            hh.view_mut((r * m, 0), (m, 3)).copy_from(&h);
            let float_at = self.float_tracks.iter().position(|&t| t == track);
            for i in 0..m {
                let ambiguity = match (float_at, self.fixed.get(&track)) {
                    (Some(g), _) => {
                        hh[(r * m + i, self.nc + g * m + i)] = 1.0;
                        self.x[self.nc + g * m + i]
                    }
                    (None, Some(ints)) => ints[i] as f64,
                    (None, None) => 0.0,
                };
                nu[r * m + i] = obs.phase[i] - pred[i] - ambiguity;
            }
        }
        (hh, nu)
    }

    fn gain(&self, h: &DMatrix<f64>, r: &DMatrix<f64>) -> Result<DMatrix<f64>> {
        let s = symmetrize(h * &self.p * h.transpose() + r);
        let chol = s.clone().cholesky().ok_or(Error::DegenerateGeometry {
            what: "Kalman gain".into(),
            matrix: "innovation covariance H P H^T + R",
            condition: f64::INFINITY,
        })?;
        Ok(chol.solve(&(h * &self.p)).transpose())
    }

    /// `e+ = (I - K H) e - K H_beta beta - K v` on the augmented covariance (known ambiguities).
    fn true_error_update(
        &mut self,
        rows: &[(usize, i64)],
        epoch: &PhaseEpoch,
        h: &DMatrix<f64>,
        k: &DMatrix<f64>,
        r: &DMatrix<f64>,
    ) {
        let m = self.m();
        // Called only with the sensitivity analysis on, when the augmented covariance exists.
        let Some(py) = self.py.as_mut() else {
            return;
        };
        let ny = py.nrows();
        let nr = h.nrows();
        // Truth-model measurement matrix over [e (6), mu (3), beta (3m)].
        let mut ht = DMatrix::zeros(nr, ny);
        ht.view_mut((0, 0), (nr, CORE)).copy_from(h);
        for (row, &(j, _)) in rows.iter().enumerate() {
            let obs = &epoch.obs[j];
            let s_body = self.q.inverse() * obs.los;
            for i in 0..m {
                let hb = -s_body.transpose() / obs.wavelength;
                ht.view_mut((row * m + i, DYN + 3 * i), (1, 3))
                    .copy_from(&hb);
            }
        }
        let mut a = DMatrix::identity(ny, ny);
        let kh = k * &ht;
        let top = a.view((0, 0), (CORE, ny)) - kh;
        a.view_mut((0, 0), (CORE, ny)).copy_from(&top);
        let mut kv = DMatrix::zeros(ny, ny);
        kv.view_mut((0, 0), (CORE, CORE))
            .copy_from(&(k * r * k.transpose()));
        *py = symmetrize(&a * &*py * a.transpose() + kv);
    }

    /// New ambiguities of a rising (or reset) satellite from its own phases: `N = z - h(x_hat)`, whose error
    /// `-(H_theta dtheta + v)` is correlated with the attitude error.
    fn add_float(&mut self, obs: &super::PhaseObs) {
        let m = self.m();
        let n = self.x.len();
        let (h_theta, pred) = self.geometry(&obs.los, obs.wavelength);
        let mut g = DMatrix::zeros(m, n);
        g.view_mut((0, 0), (m, 3)).copy_from(&h_theta);
        let gp = &g * &self.p;
        // The neglected second-order term of h, -los . R_hat ([dtheta x]^2 / 2) b / lambda, is at most
        // |dtheta|^2 |b| / (2 lambda) with E|dtheta|^2 = tr P_theta: counted as extra independent noise, it
        // keeps ambiguities started under a poor attitude from looking sharper than they are.
        let tr = self.p[(0, 0)] + self.p[(1, 1)] + self.p[(2, 2)];
        let mut pnn = &gp * g.transpose() + DMatrix::identity(m, m) * self.s.phase_sigma.powi(2);
        for (i, b) in self.s.baselines.iter().enumerate() {
            pnn[(i, i)] += (0.5 * tr * b.norm() / obs.wavelength).powi(2);
        }
        let mut p = DMatrix::zeros(n + m, n + m);
        p.view_mut((0, 0), (n, n)).copy_from(&self.p);
        p.view_mut((n, 0), (m, n)).copy_from(&(-&gp));
        p.view_mut((0, n), (n, m)).copy_from(&(-gp.transpose()));
        p.view_mut((n, n), (m, m)).copy_from(&symmetrize(pnn));
        self.p = p;
        let mut x = DVector::zeros(n + m);
        x.rows_mut(0, n).copy_from(&self.x);
        for i in 0..m {
            x[n + i] = obs.phase[i] - pred[i];
        }
        self.x = x;
        self.float_tracks.push(obs.track);
    }

    fn remove_float(&mut self, track: i64) {
        let Some(g) = self.float_tracks.iter().position(|&t| t == track) else {
            return;
        };
        let m = self.m();
        let start = self.nc + g * m;
        self.x = self.x.clone().remove_rows(start, m);
        self.p = self
            .p
            .clone()
            .remove_rows(start, m)
            .remove_columns(start, m);
        self.float_tracks.remove(g);
    }

    /// LAMBDA on all float ambiguities, accepted or refused by the gate ([`fix_decision`]); an accepted
    /// fix conditions the other states on the integers and removes the ambiguities from the state.
    fn try_fix(&mut self, t: f64, out: &mut FilterRun) -> Result<()> {
        let m = self.m();
        let n = self.x.len();
        let nc = self.nc;
        let na = n - nc;
        let a = self.x.rows(nc, na).into_owned();
        let qa = symmetrize(self.p.view((nc, nc), (na, na)).into_owned());
        let Some((decision, best)) = fix_decision(&self.s.fix.gate, &a, &qa)? else {
            return Ok(());
        };
        out.fixes.push(FixAttempt {
            t,
            accepted: decision.accepted,
            ratio: decision.ratio,
            success_rate: decision.success_rate,
            values: best.as_ref().map_or_else(Vec::new, |v| {
                (0..na)
                    .map(|i| (self.float_tracks[i / m], i % m, v[i]))
                    .collect()
            }),
        });
        let Some(fixed) = best.filter(|_| decision.accepted) else {
            return Ok(());
        };
        let chol = qa.clone().cholesky().ok_or(Error::DegenerateGeometry {
            what: "ambiguity fix".into(),
            matrix: "float ambiguity covariance",
            condition: f64::INFINITY,
        })?;
        let fixed_f = fixed.map(|v| v as f64);
        let pca = self.p.view((0, nc), (nc, na)).into_owned();
        let gain = chol.solve(&pca.transpose()).transpose();
        let dx = &gain * (fixed_f - &a);
        let pcc = self.p.view((0, 0), (nc, nc)) - &gain * pca.transpose();
        self.x = dx;
        self.p = symmetrize(pcc);
        for (g, &track) in self.float_tracks.iter().enumerate() {
            self.fixed
                .insert(track, fixed.rows(g * m, m).iter().copied().collect());
        }
        self.float_tracks.clear();
        self.reset();
        Ok(())
    }
}

/// The gate's decision on the filter's float ambiguities `a` (cycles) with covariance `qa` (cycles^2),
/// and the best integers when a search ran; `None` when the covariance cannot be decorrelated exactly
/// (no attempt is recorded).
///
/// The filter goes on with float ambiguities rather than stop the run where the engine would report an
/// error: a covariance the reduction cannot decorrelate exactly, a float solution too vague for the
/// capped search or one the search cannot answer exactly (the LAMBDA refuses rather than return a wrong
/// integer) is not fixable at this epoch; the cap keeps one epoch cheap.
///
/// # Errors
/// Those of [`Problem::new`] other than [`Error::Numerical`] and [`Error::Convergence`].
pub(crate) fn fix_decision(
    gate: &Gate,
    a: &DVector<f64>,
    qa: &DMatrix<f64>,
) -> Result<Option<(Decision, Option<DVector<i64>>)>> {
    let not_fixable = |e: &Error| matches!(e, Error::Numerical { .. } | Error::Convergence { .. });
    let problem = match Problem::new(a, qa) {
        Ok(problem) => problem,
        Err(e) if not_fixable(&e) => return Ok(None),
        Err(e) => return Err(e),
    };
    if let Some(refused) = gate.before_search(&problem) {
        return Ok(Some((refused, None)));
    }
    let searched = problem
        .solve(2, MAX_FIX_NODES)
        .and_then(|best| Ok((gate.decide(&problem, &best)?, best)));
    match searched {
        Ok((decision, best)) => Ok(Some((decision, Some(best.fixed.column(0).into_owned())))),
        Err(e) if not_fixable(&e) => Ok(Some((
            Decision {
                success_rate: success_rate(problem.reduction.factor.d.as_slice()),
                ratio: 0.0,
                accepted: false,
                reason: Reason::Unsearched,
            },
            None,
        ))),
        Err(e) => Err(e),
    }
}

fn check_settings(s: &Settings, phases: bool, fixes: bool) -> Result<()> {
    let n = &s.noise;
    if !(n.arw.is_finite() && n.arw >= 0.0 && n.rrw.is_finite() && n.rrw >= 0.0) {
        return Err(Error::out_of_range(
            "gyro noise",
            format!(
                "expected finite densities >= 0, got arw {} and rrw {}",
                n.arw, n.rrw
            ),
        ));
    }
    ensure_finite("baselines", s.baselines.iter().flat_map(|b| b.iter()))?;
    if let Some(i) = s.baselines.iter().position(|b| b.norm() < 1e-6) {
        return Err(Error::out_of_range(
            "baselines",
            format!(
                "expected baselines longer than 1e-6 m, baseline {i} has length {:.3e} m",
                s.baselines[i].norm()
            ),
        ));
    }
    if phases && s.baselines.is_empty() {
        return Err(Error::out_of_range(
            "baselines",
            "expected at least one baseline with phase measurements",
        ));
    }
    if !(s.phase_sigma.is_finite() && s.phase_sigma > 0.0) {
        return Err(Error::out_of_range(
            "phase_sigma",
            format!("expected a finite value > 0 cycles, got {}", s.phase_sigma),
        ));
    }
    s.fix.gate.check(&Names::PYTHON)?;
    if s.slip_threshold.is_nan() || s.slip_threshold <= 0.0 {
        return Err(Error::out_of_range(
            "slip_threshold",
            format!(
                "expected a value > 0 (inf disables), got {}",
                s.slip_threshold
            ),
        ));
    }
    if let Some(v) = s.misalignment_sigma {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::out_of_range(
                "misalignment_sigma",
                format!("expected a finite prior > 0 rad, got {v}"),
            ));
        }
    }
    if s.output_every == 0 {
        return Err(Error::out_of_range("output_every", "expected >= 1, got 0"));
    }
    if let Some(sens) = s.sensitivity {
        let ok = |v: f64| v.is_finite() && v >= 0.0;
        if !(ok(sens.misalignment_sigma) && ok(sens.baseline_sigma)) {
            return Err(Error::out_of_range(
                "sensitivity",
                format!(
                    "expected finite standard deviations >= 0, got misalignment {} rad and baseline {} m",
                    sens.misalignment_sigma, sens.baseline_sigma
                ),
            ));
        }
        if !s.known_ambiguities || fixes || s.misalignment_sigma.is_some() {
            return Err(Error::out_of_range(
                "sensitivity",
                "the true-error covariance is propagated for the reduced filter (no misalignment states) with \
                 phase updates and known ambiguities only",
            ));
        }
    }
    Ok(())
}

fn check_in_record(name: &'static str, t: &[f64], t0: f64, t1: f64) -> Result<()> {
    ensure_finite(name, t.iter())?;
    if let Some(k) = t.windows(2).position(|w| w[1] < w[0]) {
        return Err(Error::out_of_range(
            name,
            format!(
                "expected time stamps in order, got {} after {} (index {})",
                t[k + 1],
                t[k],
                k + 1
            ),
        ));
    }
    if let Some(k) = t.iter().position(|&v| v < t0 || v > t1) {
        return Err(Error::out_of_range(
            name,
            format!(
                "expected time stamps within the gyro record [{t0}, {t1}] s, got {} at index {k}",
                t[k]
            ),
        ));
    }
    Ok(())
}

fn check_attitude_fixes(fixes: &[AttitudeFix], t0: f64, t1: f64) -> Result<()> {
    let t: Vec<f64> = fixes.iter().map(|a| a.t).collect();
    check_in_record("attitude fix times", &t, t0, t1)?;
    for (k, a) in fixes.iter().enumerate() {
        ensure_finite("attitude fix covariance", a.covariance.iter()).map_err(|e| e.at_epoch(k))?;
        unit("attitude fix quaternion", a.quaternion).map_err(|e| e.at_epoch(k))?;
    }
    Ok(())
}

fn check_phase_epochs(epochs: &[PhaseEpoch], m: usize, t0: f64, t1: f64) -> Result<()> {
    let t: Vec<f64> = epochs.iter().map(|p| p.t).collect();
    check_in_record("phase epoch times", &t, t0, t1)?;
    if let Some(k) = t.windows(2).position(|w| w[1] == w[0]) {
        return Err(Error::out_of_range(
            "phase epoch times",
            format!(
                "expected one epoch per time stamp, got {} twice (index {})",
                t[k],
                k + 1
            ),
        ));
    }
    for (k, e) in epochs.iter().enumerate() {
        for (j, o) in e.obs.iter().enumerate() {
            let bad = |detail: String| Error::out_of_range("phase observation", detail).at_epoch(k);
            if o.phase.len() != m {
                return Err(bad(format!(
                    "observation {j}: expected {m} phase differences (one per baseline), got {}",
                    o.phase.len()
                )));
            }
            ensure_finite("phase", o.phase.iter()).map_err(|e| e.at_epoch(k))?;
            ensure_finite("los", o.los.iter()).map_err(|e| e.at_epoch(k))?;
            if (o.los.norm() - 1.0).abs() > 1e-6 {
                return Err(bad(format!(
                    "observation {j}: expected a unit line of sight, got norm {}",
                    o.los.norm()
                )));
            }
            if !(o.wavelength.is_finite() && o.wavelength > 0.0) {
                return Err(bad(format!(
                    "observation {j}: expected a wavelength > 0 m, got {}",
                    o.wavelength
                )));
            }
            if e.obs[..j].iter().any(|p| p.track == o.track) {
                return Err(bad(format!(
                    "observation {j}: track {} appears twice",
                    o.track
                )));
            }
        }
    }
    Ok(())
}
