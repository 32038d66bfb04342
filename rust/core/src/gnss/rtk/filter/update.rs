//! Step 3 of [`super::BaselineFilter::step`]: the iterated measurement update of the double differences,
//! and the slips it shows that the arc tracker did not see (held integers whose phases no longer fit, float
//! ambiguities that jumped beyond their prior).

use nalgebra::{Cholesky, DMatrix, DVector, Vector3};

use super::{BaselineFilter, HELD_RESIDUAL_CYCLES, OUTLIER_SIGMAS, SLIP_MIN_CYCLES};
use crate::error::{Error, Result};
use crate::gnss::rtk::dd::{covariance, Group};
use crate::gnss::rtk::float::{CONVERGED_M, MAX_ITERATIONS};
use crate::gnss::rtk::model::SdRangeModel;
use crate::gnss::rtk::DdEpoch;

impl BaselineFilter {
    /// Step 3: the iterated measurement update; returns the innovations' chi-square and their count.
    pub(super) fn update(&mut self, epoch: &DdEpoch, groups: &[Group]) -> Result<(f64, usize)> {
        let n = self.x.len();
        let rows: usize = groups.iter().map(|g| 2 * g.members.len()).sum();
        let mut r = DMatrix::<f64>::zeros(rows, rows);
        let mut row = 0;
        for g in groups {
            let m2 = 2 * g.members.len();
            let c = covariance(epoch, g);
            r.view_mut((row, row), (m2, m2))
                .copy_from(&c.view((0, 0), (m2, m2)));
            row += m2;
        }
        let x_prior = self.x.clone();
        let mut xi = x_prior.clone();
        let mut h = DMatrix::<f64>::zeros(rows, n);
        let mut first_chi2 = None;
        for _ in 0..MAX_ITERATIONS {
            let (hi, resid) = self.linearise(epoch, groups, &xi, rows);
            h = hi;
            // Innovation at the prior, to first order about xi: z - h(xi) - H (x_prior - xi).
            let v = &resid - &h * (&x_prior - &xi);
            let s = &h * &self.p * h.transpose() + &r;
            let chol = Cholesky::new((&s + s.transpose()) * 0.5).ok_or_else(|| {
                Error::numerical(
                    "filter update",
                    "the innovation covariance is not positive definite",
                )
            })?;
            if first_chi2.is_none() {
                first_chi2 = Some(v.dot(&chol.solve(&v)));
            }
            let k = chol.solve(&(&h * &self.p)).transpose(); // P H^T S^-1
            let next = &x_prior + &k * v;
            let moved = (0..3)
                .map(|i| (next[i] - xi[i]).powi(2))
                .sum::<f64>()
                .sqrt();
            xi = next;
            if moved < CONVERGED_M {
                let i_kh = DMatrix::<f64>::identity(n, n) - &k * &h;
                let p = &i_kh * &self.p * i_kh.transpose() + &k * &r * k.transpose();
                self.p = (&p + p.transpose()) * 0.5;
                self.x = xi;
                return Ok((first_chi2.unwrap_or(f64::NAN), rows));
            }
        }
        let _ = h;
        Err(Error::Convergence {
            what: "filter measurement update",
            iterations: MAX_ITERATIONS,
        })
    }

    /// Design matrix and `z - h(x)` of every group's double differences at state `x` (code rows then phase
    /// rows per group, the order of [`covariance`]).
    pub(super) fn linearise(
        &self,
        epoch: &DdEpoch,
        groups: &[Group],
        x: &DVector<f64>,
        rows: usize,
    ) -> (DMatrix<f64>, DVector<f64>) {
        let n = x.len();
        let b = Vector3::new(x[0], x[1], x[2]);
        let model = SdRangeModel::new(&epoch.base_m, &(epoch.base_m + b));
        let mut h = DMatrix::<f64>::zeros(rows, n);
        let mut y = DVector::<f64>::zeros(rows);
        let mut row = 0;
        for g in groups {
            let m = g.members.len();
            let sr = &epoch.signals[g.reference];
            let (rho_r, u_r) = model.range_and_los(sr);
            let ir = self.state_of(sr.arc);
            let or = self.arcs[ir - self.nk()].offset as f64;
            let lam_r = sr.wavelength_m;
            for (j, &k) in g.members.iter().enumerate() {
                let sk = &epoch.signals[k];
                let (rho_k, u_k) = model.range_and_los(sk);
                let ik = self.state_of(sk.arc);
                let ok = self.arcs[ik - self.nk()].offset as f64;
                // One wavelength in a CDMA group (they agree to 1e-9): the large parts cancel exactly.
                let lam_k = if g.fdma { sk.wavelength_m } else { lam_r };
                let hb = -(u_k - u_r);
                let (rc, rp) = (row + j, row + m + j);
                for c in 0..3 {
                    h[(rc, c)] = hb[c];
                    h[(rp, c)] = hb[c];
                }
                h[(rp, ik)] = lam_k;
                h[(rp, ir)] = -lam_r;
                let code = (sk.rover_code_m - sk.base_code_m) - (sr.rover_code_m - sr.base_code_m);
                y[rc] = code - (rho_k - rho_r);
                let phase = lam_k * (sk.rover_phase_cycles - sk.base_phase_cycles - ok)
                    - lam_r * (sr.rover_phase_cycles - sr.base_phase_cycles - or);
                y[rp] = phase - (rho_k - rho_r) - (lam_k * x[ik] - lam_r * x[ir]);
            }
            row += 2 * m;
        }
        (h, y)
    }

    /// The signal to restart after an update, if a held integer's phase residual at the baseline
    /// conditioned on every held integer exceeds [`HELD_RESIDUAL_CYCLES`]: the worst pair's member, or
    /// the group's reference when every held pair of the group is off by [`SLIP_MIN_CYCLES`]. Where integers are held the float
    /// ambiguities may still be metres loose (a moving baseline's float comes from code), so a slip of
    /// a few cycles hides in them; the held integers pin the baseline to millimetres and show it.
    /// GLONASS FDMA pairs are not checked (their receiver clock term does not cancel).
    pub(super) fn held_outlier(&self, epoch: &DdEpoch, groups: &[Group]) -> Option<usize> {
        let nk = self.nk();
        // (group, member signal, state k, state r, held DD integer)
        let mut pairs = Vec::new();
        for (gi, g) in groups.iter().enumerate() {
            if g.fdma {
                continue;
            }
            let sr = &epoch.signals[g.reference];
            let Some(&hr) = self.held.get(&sr.arc) else {
                continue;
            };
            for &k in &g.members {
                if let Some(&hk) = self.held.get(&epoch.signals[k].arc) {
                    pairs.push((
                        gi,
                        k,
                        self.state_of(epoch.signals[k].arc),
                        self.state_of(sr.arc),
                        hk - hr,
                    ));
                }
            }
        }
        if pairs.is_empty() {
            return None;
        }
        // The baseline conditioned on the held integers: b - C_bh C_hh^-1 (a_h - z_h).
        let nh = pairs.len();
        let n = self.x.len();
        let mut t = DMatrix::<f64>::zeros(nh, n);
        let mut d = DVector::<f64>::zeros(nh);
        for (j, &(_, _, ik, ir, dd)) in pairs.iter().enumerate() {
            t[(j, ik)] = 1.0;
            t[(j, ir)] = -1.0;
            let offset = self.arcs[ik - nk].offset - self.arcs[ir - nk].offset;
            d[j] = self.x[ik] - self.x[ir] - (dd - offset) as f64;
        }
        let c_hh = &t * &self.p * t.transpose();
        let c_bh = self.p.rows(0, 3) * t.transpose();
        let chol = Cholesky::new((&c_hh + c_hh.transpose()) * 0.5)?;
        let db = &c_bh * chol.solve(&d);
        let b = Vector3::new(self.x[0] - db[0], self.x[1] - db[1], self.x[2] - db[2]);
        let model = SdRangeModel::new(&epoch.base_m, &(epoch.base_m + b));
        let mut worst: Option<(f64, usize)> = None;
        // Per group: held pairs off by more than SLIP_MIN_CYCLES, and in all.
        let mut over = vec![(0usize, 0usize); groups.len()];
        let mut residuals = Vec::with_capacity(nh);
        for &(gi, k, ik, ir, dd) in &pairs {
            let (sk, sr) = (&epoch.signals[k], &epoch.signals[groups[gi].reference]);
            let lam = sr.wavelength_m;
            let (ok, or) = (self.arcs[ik - nk].offset, self.arcs[ir - nk].offset);
            let phase = (sk.rover_phase_cycles - sk.base_phase_cycles - ok as f64)
                - (sr.rover_phase_cycles - sr.base_phase_cycles - or as f64);
            let range = (model.range_m(sk) - model.range_m(sr)) / lam;
            let r = (phase - range - (dd - ok + or) as f64).abs();
            over[gi].1 += 1;
            if r > SLIP_MIN_CYCLES {
                over[gi].0 += 1;
            }
            residuals.push(r);
        }
        for (&(gi, k, ..), &r) in pairs.iter().zip(&residuals) {
            if r > HELD_RESIDUAL_CYCLES && worst.is_none_or(|(w, _)| r > w) {
                let (bad, total) = over[gi];
                // A slip of the reference puts every pair of its group off by its cycles; one blunder
                // spread by the conditioning moves the others by a fraction of a cycle.
                let signal = if total >= 2 && bad == total {
                    groups[gi].reference
                } else {
                    k
                };
                worst = Some((r, signal));
            }
        }
        worst.map(|(_, s)| s)
    }

    /// The signal to restart after an update, if a double-difference ambiguity moved by more than
    /// [`OUTLIER_SIGMAS`] of its prior sigma and [`SLIP_MIN_CYCLES`] (a slip the arc tracker did not see:
    /// the update explains the jump of a phase by its ambiguity, whose prior it contradicts): the worst
    /// pair's member, or the group's reference when most of the group's pairs moved (a slip of the
    /// reference moves every pair).
    pub(super) fn outlier(
        &self,
        epoch: &DdEpoch,
        groups: &[Group],
        x_prior: &DVector<f64>,
        p_prior: &DMatrix<f64>,
    ) -> Option<usize> {
        let mut worst: Option<(f64, usize)> = None;
        for g in groups {
            let ir = self.state_of(epoch.signals[g.reference].arc);
            let z: Vec<f64> = g
                .members
                .iter()
                .map(|&k| {
                    let ik = self.state_of(epoch.signals[k].arc);
                    // New arcs (the prior's dimension) have no prior to contradict.
                    if ik >= x_prior.len() || ir >= x_prior.len() {
                        return 0.0;
                    }
                    let moved = (self.x[ik] - self.x[ir]) - (x_prior[ik] - x_prior[ir]);
                    let var = p_prior[(ik, ik)] + p_prior[(ir, ir)] - 2.0 * p_prior[(ik, ir)];
                    if moved.abs() < SLIP_MIN_CYCLES {
                        0.0
                    } else {
                        moved.abs() / var.max(0.0).sqrt()
                    }
                })
                .collect();
            let m = z.len();
            let over = z.iter().filter(|&&v| v > OUTLIER_SIGMAS).count();
            if over > 0 {
                let (j, &v) = z
                    .iter()
                    .enumerate()
                    .max_by(|a, b| a.1.total_cmp(b.1))
                    .unwrap_or((0, &0.0));
                let signal = if m >= 2 && 2 * over > m {
                    g.reference
                } else {
                    g.members[j]
                };
                if worst.is_none_or(|(w, _)| v > w) {
                    worst = Some((v, signal));
                }
            }
        }
        worst.map(|(_, s)| s)
    }
}
