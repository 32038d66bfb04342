//! Float solution: baseline, double-difference ambiguities (and FDMA reference ambiguities) by weighted
//! least squares over one or several epochs, the exact ranges linearised and iterated.
//!
//! Each group of each epoch contributes its rows whitened by the Cholesky factor of their covariance
//! ([`super::dd::covariance`]); the normal matrix of all epochs is solved by blocks, one per system and
//! slot, through the baseline's Schur complement (`Schur`: Cholesky factors of the small blocks, no
//! dense factorisation of the whole matrix). Large integer parts
//! are removed before the adjustment (each signal's phase minus code rounded to cycles, kept per
//! ambiguity from its first epoch), so the unknowns stay small and exact integers can be restored.

use std::collections::HashMap;

use nalgebra::{Cholesky, DMatrix, DVector, Dyn, Matrix3, Vector3};

use super::dd::{covariance, groups, Group};
use super::glonass::{code_row_coefficient, reference_coefficient};
use super::model::SdRangeModel;
use super::DdEpoch;
use crate::error::{Error, Result};
use crate::gnss::signal::System;
use crate::gnss::solution::N_SYSTEMS;
use crate::lambda::ldl::MAX_DIMENSION;

/// Gauss-Newton iterations of the baseline at most; the range is nearly linear over a baseline, so two
/// or three suffice even at kilometres from a code prior.
pub const MAX_ITERATIONS: usize = 10;

/// Baseline update below which the iteration stops, m.
pub const CONVERGED_M: f64 = 1e-5;

/// One float double-difference ambiguity: `arc` against `reference_arc`; its unknown is the DD integer
/// minus `offset` (cycles).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ambiguity {
    pub arc: u64,
    pub reference_arc: u64,
    pub offset: i64,
}

/// Which signals and systems contributed.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    pub reference_sats: [Option<usize>; N_SYSTEMS],
    pub slots_used: u8,
    pub satellites_per_system: [u16; N_SYSTEMS],
}

/// The float solution. Unknowns, in order: baseline (3, m), ambiguities (`ambiguities.len()`, cycles,
/// minus their offsets), FDMA reference ambiguities (cycles, minus their offsets).
#[derive(Debug, Clone)]
pub struct FloatSolution {
    /// Rover minus base, ECEF m.
    pub baseline_m: Vector3<f64>,
    /// Float values of the ambiguity unknowns (minus offsets), cycles.
    pub ambiguities_cycles: DVector<f64>,
    pub ambiguities: Vec<Ambiguity>,
    /// Covariance of all unknowns (baseline first, then ambiguities, then FDMA references).
    pub covariance: DMatrix<f64>,
    /// Weighted sum of squared residuals and its degrees of freedom.
    pub chi2: f64,
    pub dof: usize,
    /// Held `(arc, reference arc)` pairs that occurred in the epochs.
    pub used_held: Vec<(u64, u64)>,
    pub summary: Summary,
}

/// The ambiguity unknown of a member's double difference.
#[derive(Debug, Clone, Copy)]
enum Term {
    /// Unknown number `k` (among the ambiguities) and its offset.
    Free(usize, i64),
    /// Imposed integer.
    Held(i64),
}

/// One group of one epoch, with its unknowns resolved.
struct Prepared {
    epoch: usize,
    group: Group,
    terms: Vec<Term>,
    /// FDMA: index among the reference unknowns and its offset.
    reference: Option<(usize, i64)>,
    /// The reference signal's rounded phase minus code at this epoch, cycles.
    reference_rounded: i64,
}

/// Per signal of an epoch: `round((lambda SD phi - SD P) / lambda)`, cycles.
fn rounded_ambiguities(epoch: &DdEpoch) -> Vec<i64> {
    epoch
        .signals
        .iter()
        .map(|s| {
            let sd_phi = s.rover_phase_cycles - s.base_phase_cycles;
            let sd_p = s.rover_code_m - s.base_code_m;
            // |phase| <= 1e13 cycles and |code| <= 1e9 m (checked): exact in i64.
            (sd_phi - sd_p / s.wavelength_m).round() as i64
        })
        .collect()
}

/// The unknowns met so far, in order of first appearance: the double-difference ambiguities per
/// `(arc, reference arc)` and the FDMA reference ambiguities per reference arc, each with the offset
/// (rounded phase minus code, cycles) of its first epoch; and the held integers that occurred.
#[derive(Default)]
struct Unknowns {
    held: HashMap<(u64, u64), i64>,
    amb_index: HashMap<(u64, u64), usize>,
    ambiguities: Vec<Ambiguity>,
    ref_index: HashMap<u64, usize>,
    ref_offsets: Vec<i64>,
    used_held: Vec<(u64, u64)>,
}

impl Unknowns {
    /// The term of a member's double difference `key`, whose rounded offset at this epoch is `offset`.
    fn term(&mut self, key: (u64, u64), offset: i64) -> Term {
        if let Some(&n) = self.held.get(&key) {
            if !self.used_held.contains(&key) {
                self.used_held.push(key);
            }
            return Term::Held(n);
        }
        let next = self.ambiguities.len();
        let i = *self.amb_index.entry(key).or_insert(next);
        if i == next {
            self.ambiguities.push(Ambiguity {
                arc: key.0,
                reference_arc: key.1,
                offset,
            });
        }
        Term::Free(i, self.ambiguities[i].offset)
    }

    /// The FDMA reference unknown of `arc`, rounded at `rounded` cycles this epoch: index and offset.
    fn reference(&mut self, arc: u64, rounded: i64) -> (usize, i64) {
        let next = self.ref_offsets.len();
        let i = *self.ref_index.entry(arc).or_insert(next);
        if i == next {
            self.ref_offsets.push(rounded);
        }
        (i, self.ref_offsets[i])
    }
}

/// The groups of one epoch (`prepared`, all of epoch `epoch`) added to `summary`: the slots used, the
/// most satellites seen per system in one epoch, and the reference satellite of each system's lowest
/// slot (the last epoch's where several epochs have one).
fn summarise(summary: &mut Summary, epoch: &DdEpoch, prepared: &[Prepared]) {
    let mut sats: [Vec<usize>; N_SYSTEMS] = Default::default();
    let mut refs: [Option<(usize, usize)>; N_SYSTEMS] = [None; N_SYSTEMS];
    for group in prepared.iter().map(|pr| &pr.group) {
        let s = group.system.index();
        summary.slots_used |= 1 << group.slot;
        for &i in std::iter::once(&group.reference).chain(&group.members) {
            if !sats[s].contains(&epoch.signals[i].sat) {
                sats[s].push(epoch.signals[i].sat);
            }
        }
        if refs[s].is_none_or(|(slot, _)| group.slot < slot) {
            refs[s] = Some((group.slot, epoch.signals[group.reference].sat));
        }
    }
    for s in 0..N_SYSTEMS {
        let n = u16::try_from(sats[s].len()).unwrap_or(u16::MAX);
        summary.satellites_per_system[s] = summary.satellites_per_system[s].max(n);
        if let Some((_, sat)) = refs[s] {
            summary.reference_sats[s] = Some(sat);
        }
    }
}

/// Float solution of `epochs` (one baseline shared) with `held` integers imposed.
///
/// # Errors
/// [`Error::DegenerateGeometry`] when the normal matrix is not positive definite (too few signals, or a
/// geometry that does not determine the baseline), [`Error::TooLarge`] beyond
/// [`MAX_DIMENSION`] ambiguities, [`Error::Convergence`] when the baseline does not settle.
pub fn solve(epochs: &[DdEpoch], held: &[(u64, u64, i64)]) -> Result<FloatSolution> {
    let mut unknowns = Unknowns {
        held: held.iter().map(|&(a, r, n)| ((a, r), n)).collect(),
        ..Unknowns::default()
    };
    let mut prepared = Vec::new();
    let mut rows = 0usize;
    let mut summary = Summary {
        reference_sats: [None; N_SYSTEMS],
        slots_used: 0,
        satellites_per_system: [0; N_SYSTEMS],
    };
    for (e, epoch) in epochs.iter().enumerate() {
        let n0 = rounded_ambiguities(epoch);
        let first = prepared.len();
        for group in groups(epoch) {
            let r = &epoch.signals[group.reference];
            let reference_rounded = n0[group.reference];
            let terms = group
                .members
                .iter()
                .map(|&k| unknowns.term((epoch.signals[k].arc, r.arc), n0[k] - reference_rounded))
                .collect();
            let reference = group
                .fdma
                .then(|| unknowns.reference(r.arc, reference_rounded));
            rows += 2 * group.members.len() + usize::from(group.fdma);
            prepared.push(Prepared {
                epoch: e,
                group,
                terms,
                reference,
                reference_rounded,
            });
        }
        summarise(&mut summary, epoch, &prepared[first..]);
    }
    let na = unknowns.ambiguities.len();
    if na > MAX_DIMENSION {
        return Err(Error::too_large(
            "ambiguities",
            na as f64,
            MAX_DIMENSION as f64,
            "double-difference ambiguities in one solution",
        ));
    }
    let p = 3 + na + unknowns.ref_offsets.len();
    if prepared.is_empty() {
        return Err(Error::DegenerateGeometry {
            what: "double differences: no system and slot has two satellites".into(),
            matrix: "normal matrix",
            condition: f64::INFINITY,
        });
    }
    let (baseline_m, x, covariance, chi2) = iterate(epochs, &prepared, p, na)?;
    Ok(FloatSolution {
        baseline_m,
        ambiguities_cycles: x.rows(3, na).into_owned(),
        ambiguities: unknowns.ambiguities,
        covariance,
        chi2,
        dof: rows.saturating_sub(p),
        used_held: unknowns.used_held,
        summary,
    })
}

/// What [`iterate`] converges to: the baseline (m), all unknowns' last update, their covariance and the
/// weighted sum of squared residuals.
type Converged = (Vector3<f64>, DVector<f64>, DMatrix<f64>, f64);

/// Gauss-Newton from the epochs' mean code prior until the baseline moves by less than
/// [`CONVERGED_M`]: the baseline, all unknowns' last update (ambiguities as solved, not increments:
/// they enter linearly), their covariance and the weighted sum of squared residuals.
fn iterate(epochs: &[DdEpoch], prepared: &[Prepared], p: usize, na: usize) -> Result<Converged> {
    let mean_prior: Vector3<f64> = epochs
        .iter()
        .map(|e| e.rover_prior_m - e.base_m)
        .sum::<Vector3<f64>>()
        / epochs.len() as f64;
    let blocks = blocks(prepared, na, p);
    let mut b = mean_prior;
    for _ in 0..MAX_ITERATIONS {
        let (normal, rhs, yty) = accumulate(epochs, prepared, &b, p, na)?;
        let sol = Schur::solve(&normal, &rhs, &blocks).ok_or_else(|| degenerate(&normal))?;
        let x = &sol.x;
        let db = Vector3::new(x[0], x[1], x[2]);
        b += db;
        if db.norm() < CONVERGED_M {
            let covariance = sol.covariance(&blocks);
            if covariance.iter().any(|v| !v.is_finite()) || !b.iter().all(|v| v.is_finite()) {
                return Err(degenerate(&normal));
            }
            let chi2 = (yty - x.dot(&rhs)).max(0.0);
            return Ok((b, sol.x, covariance, chi2));
        }
    }
    Err(Error::Convergence {
        what: "double-difference float solution",
        iterations: MAX_ITERATIONS,
    })
}

/// The unknowns other than the baseline, one block per (system, slot): the rows of a group involve the
/// baseline and its own group's unknowns only, so the normal matrix is block diagonal apart from the
/// baseline's rows and columns.
fn blocks(prepared: &[Prepared], na: usize, p: usize) -> Vec<Vec<usize>> {
    let mut keys: Vec<(System, usize)> = Vec::new();
    let mut block_of: Vec<Option<usize>> = vec![None; p];
    for pr in prepared {
        let key = (pr.group.system, pr.group.slot);
        let k = keys.iter().position(|&x| x == key).unwrap_or_else(|| {
            keys.push(key);
            keys.len() - 1
        });
        for t in &pr.terms {
            if let Term::Free(i, _) = *t {
                block_of[3 + i] = Some(k);
            }
        }
        if let Some((i, _)) = pr.reference {
            block_of[3 + na + i] = Some(k);
        }
    }
    let mut out = vec![Vec::new(); keys.len()];
    for (u, b) in block_of.iter().enumerate().skip(3) {
        match b {
            Some(k) => out[*k].push(u),
            None => out.push(vec![u]), // not reached: every unknown comes from a group
        }
    }
    out
}

/// The normal equations `N x = r` solved by blocks: with `N_bb` the baseline's 3 x 3 block, `N_B` the
/// diagonal block of unknowns `B` and `N_Bb` its coupling to the baseline, `K_B = N_B^-1 N_Bb`, the
/// baseline's Schur complement `S = N_bb - sum_B N_Bb^T K_B` gives `x_b = S^-1 (r_b - sum_B N_Bb^T
/// N_B^-1 r_B)`, `x_B = N_B^-1 r_B - K_B x_b`, and the covariance `N^-1 = G S^-1 G^T + diag(0, N_B^-1)`
/// with `G = [I; -K_B...]`. The same solution as a dense Cholesky of `N` (which is positive definite
/// exactly when every `N_B` and `S` are), in O(sum m_B^3 + p^2) instead of O(p^3).
struct Schur {
    x: DVector<f64>,
    s_inv: Matrix3<f64>,
    /// Per block: `[K_B | N_B^-1 r_B]` (m x 4) and the Cholesky factor of `N_B`.
    parts: Vec<(DMatrix<f64>, Cholesky<f64, Dyn>)>,
}

impl Schur {
    /// `None` when `N` is not (numerically) positive definite.
    fn solve(normal: &DMatrix<f64>, rhs: &DVector<f64>, blocks: &[Vec<usize>]) -> Option<Schur> {
        let mut s: Matrix3<f64> = normal.fixed_view::<3, 3>(0, 0).into_owned();
        let mut sr = Vector3::new(rhs[0], rhs[1], rhs[2]);
        let mut parts = Vec::with_capacity(blocks.len());
        for idx in blocks {
            let m = idx.len();
            let chol = Cholesky::new(DMatrix::from_fn(m, m, |i, j| normal[(idx[i], idx[j])]))?;
            let kb = chol.solve(&DMatrix::from_fn(m, 4, |i, j| {
                if j < 3 {
                    normal[(idx[i], j)]
                } else {
                    rhs[idx[i]]
                }
            }));
            for a in 0..3 {
                for c in 0..4 {
                    let v: f64 = (0..m).map(|i| normal[(idx[i], a)] * kb[(i, c)]).sum();
                    if c < 3 {
                        s[(a, c)] -= v;
                    } else {
                        sr[a] -= v;
                    }
                }
            }
            parts.push((kb, chol));
        }
        let chol_s = ((s + s.transpose()) * 0.5).cholesky()?;
        let xb = chol_s.solve(&sr);
        let mut x = DVector::zeros(normal.nrows());
        x.fixed_rows_mut::<3>(0).copy_from(&xb);
        for (idx, (kb, _)) in blocks.iter().zip(&parts) {
            for (i, &u) in idx.iter().enumerate() {
                x[u] = kb[(i, 3)] - (0..3).map(|a| kb[(i, a)] * xb[a]).sum::<f64>();
            }
        }
        Some(Schur {
            x,
            s_inv: chol_s.inverse(),
            parts,
        })
    }

    /// `N^-1`, the covariance of all unknowns.
    fn covariance(&self, blocks: &[Vec<usize>]) -> DMatrix<f64> {
        let p = self.x.len();
        let mut g = DMatrix::<f64>::zeros(p, 3);
        g.fixed_view_mut::<3, 3>(0, 0).fill_with_identity();
        for (idx, (kb, _)) in blocks.iter().zip(&self.parts) {
            for (i, &u) in idx.iter().enumerate() {
                for a in 0..3 {
                    g[(u, a)] = -kb[(i, a)];
                }
            }
        }
        let gs = &g * self.s_inv;
        let mut cov = gs * g.transpose();
        for (idx, (_, chol)) in blocks.iter().zip(&self.parts) {
            let inv = chol.inverse();
            for (i, &u) in idx.iter().enumerate() {
                for (j, &v) in idx.iter().enumerate() {
                    cov[(u, v)] += inv[(i, j)];
                }
            }
        }
        cov
    }
}

/// Normal matrix, right-hand side and `y^T C^-1 y` of every group at baseline `b`.
fn accumulate(
    epochs: &[DdEpoch],
    prepared: &[Prepared],
    b: &Vector3<f64>,
    p: usize,
    na: usize,
) -> Result<(DMatrix<f64>, DVector<f64>, f64)> {
    let mut normal = DMatrix::<f64>::zeros(p, p);
    let mut rhs = DVector::<f64>::zeros(p);
    let mut yty = 0.0;
    for pr in prepared {
        let epoch = &epochs[pr.epoch];
        let (cols, a, y) = design(epoch, pr, b, na);
        let (wa, wy) = whiten(epoch, pr, &a, &y)?;
        let local_n = wa.tr_mul(&wa);
        let local_r = wa.tr_mul(&wy);
        for (i, &gi) in cols.iter().enumerate() {
            rhs[gi] += local_r[i];
            for (j, &gj) in cols.iter().enumerate() {
                normal[(gi, gj)] += local_n[(i, j)];
            }
        }
        yty += wy.norm_squared();
    }
    Ok((normal, rhs, yty))
}

/// One group's rows at baseline `b`: the unknowns they involve (indices among all `3 + na + ...`), the
/// design matrix over those (code rows, phase rows, then the FDMA reference's code row) and the
/// observed minus computed values, m.
fn design(
    epoch: &DdEpoch,
    pr: &Prepared,
    b: &Vector3<f64>,
    na: usize,
) -> (Vec<usize>, DMatrix<f64>, DVector<f64>) {
    let g = &pr.group;
    let m = g.members.len();
    let sd_model = SdRangeModel::new(&epoch.base_m, &(epoch.base_m + b));
    // SD range model and rover line of sight of each signal (reference first).
    let order: Vec<usize> = std::iter::once(g.reference)
        .chain(g.members.iter().copied())
        .collect();
    let model: Vec<(f64, Vector3<f64>, f64, f64, f64)> = order
        .iter()
        .map(|&i| {
            let s = &epoch.signals[i];
            let (sd_range, los) = sd_model.range_and_los(s);
            let sd_code = s.rover_code_m - s.base_code_m;
            let sd_cycles = s.rover_phase_cycles - s.base_phase_cycles;
            (sd_range, los, sd_code, sd_cycles, s.wavelength_m)
        })
        .collect();
    // Local unknowns: baseline (3), then each free member ambiguity, then the FDMA reference.
    let mut cols: Vec<usize> = vec![0, 1, 2];
    let mut member_col: Vec<Option<usize>> = Vec::with_capacity(m);
    for t in &pr.terms {
        match *t {
            Term::Free(i, _) => {
                member_col.push(Some(cols.len()));
                cols.push(3 + i);
            }
            Term::Held(_) => member_col.push(None),
        }
    }
    let ref_col = pr.reference.map(|(i, _)| {
        cols.push(3 + na + i);
        cols.len() - 1
    });
    let rows = 2 * m + usize::from(g.fdma);
    let mut a = DMatrix::<f64>::zeros(rows, cols.len());
    let mut y = DVector::<f64>::zeros(rows);
    let (rho0, u0, code0, cyc0, lam0) = model[0];
    for j in 0..m {
        let (rho, u, code, cyc, lam_k) = model[j + 1];
        // One wavelength per CDMA group (they agree to 1e-9): the reference's, so that the large
        // common parts of the two phases cancel exactly.
        let lam = if g.fdma { lam_k } else { lam0 };
        let h = -(u - u0);
        for c in 0..3 {
            a[(j, c)] = h[c];
            a[(m + j, c)] = h[c];
        }
        y[j] = (code - code0) - (rho - rho0);
        let integer = match pr.terms[j] {
            Term::Free(_, o) | Term::Held(o) => o,
        };
        // lam (cyc - a0 - r0) - lam0 (cyc0 - r0) = phase - lam a0 - (lam - lam0) r0: the integer parts
        // taken out in cycles (exact) before scaling; r0 is the FDMA reference's offset, or any
        // integer (this epoch's rounding) where the wavelengths agree.
        let r0 = pr.reference.map_or(pr.reference_rounded, |(_, o)| o) as f64;
        let phase = lam * (cyc - integer as f64 - r0) - lam0 * (cyc0 - r0);
        y[m + j] = phase - (rho - rho0);
        if let Some(c) = member_col[j] {
            a[(m + j, c)] = lam;
        }
        if let Some(c) = ref_col {
            a[(m + j, c)] = reference_coefficient(lam, lam0);
        }
    }
    if let Some(c) = ref_col {
        a[(2 * m, c)] = code_row_coefficient(lam0);
        let r0 = pr.reference.map_or(0, |(_, o)| o) as f64;
        y[2 * m] = lam0 * (cyc0 - r0) - code0;
    }
    (cols, a, y)
}

/// The rows `a`, `y` of group `pr` whitened by the Cholesky factor of their covariance.
fn whiten(
    epoch: &DdEpoch,
    pr: &Prepared,
    a: &DMatrix<f64>,
    y: &DVector<f64>,
) -> Result<(DMatrix<f64>, DVector<f64>)> {
    let g = &pr.group;
    let cov = covariance(epoch, g);
    let chol = Cholesky::new(cov).ok_or_else(|| {
        Error::numerical(
            "double-difference covariance",
            format!(
                "epoch {}: the covariance of system {:?} slot {} is not positive definite",
                pr.epoch, g.system, g.slot
            ),
        )
    })?;
    let l = chol.l();
    let wa = l
        .solve_lower_triangular(a)
        .ok_or_else(|| Error::numerical("double-difference whitening", "singular factor"))?;
    let wy = l
        .solve_lower_triangular(y)
        .ok_or_else(|| Error::numerical("double-difference whitening", "singular factor"))?;
    Ok((wa, wy))
}

/// The error for a normal matrix that is not (numerically) positive definite, with its condition number.
fn degenerate(normal: &DMatrix<f64>) -> Error {
    let eig = normal.clone().symmetric_eigenvalues();
    let max = eig.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let min = eig.iter().fold(f64::INFINITY, |m, v| m.min(*v));
    let condition = if min > 0.0 { max / min } else { f64::INFINITY };
    Error::DegenerateGeometry {
        what: "double-difference float solution (too few satellites, or a geometry that does not \
               determine the baseline)"
            .into(),
        matrix: "normal matrix",
        condition,
    }
}
