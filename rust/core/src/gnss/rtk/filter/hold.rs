//! Steps 4-5 of [`super::BaselineFilter::step`]: the integers fixed on the filter's covariance, checked
//! against the held ones and the rigid pair's length, and the held set kept or replaced.

use std::collections::BTreeSet;

use nalgebra::{Cholesky, DMatrix, DVector, Vector3};

use super::{chi2_quantile, BaselineFilter, HOLD_TEST_Z};
use crate::error::{Error, Result};
use crate::gnss::rtk::dd::Group;
use crate::gnss::rtk::fix::{fix_float, float_result};
use crate::gnss::rtk::float::{Ambiguity, FloatSolution, Summary};
use crate::gnss::rtk::known_length::fix_known_length;
use crate::gnss::rtk::rigid::MIN_FIX_PHASES;
use crate::gnss::rtk::{BaselineSolution, DdEpoch, FixOptions};
use crate::gnss::solution::{FixState, N_SYSTEMS};

/// The epoch's double-difference ambiguities on the filter's state: `f = T x` (baseline then one per
/// group member against its reference) with covariance `C = T P T^T`, and their held integers.
struct DdAmbiguities {
    amb: Vec<Ambiguity>,
    /// Held DD integer of each ambiguity, where both its arcs are held.
    held_value: Vec<Option<i64>>,
    f: DVector<f64>,
    c: DMatrix<f64>,
    summary: Summary,
    chi2: f64,
    dof: usize,
}

impl DdAmbiguities {
    /// The float solution of the ambiguities `idx` with estimate `f` and covariance `c` (baseline first).
    fn float(
        &self,
        idx: &[usize],
        f: DVector<f64>,
        c: DMatrix<f64>,
        used: Vec<(u64, u64)>,
    ) -> FloatSolution {
        FloatSolution {
            baseline_m: Vector3::new(f[0], f[1], f[2]),
            ambiguities_cycles: f.rows(3, f.len() - 3).into_owned(),
            ambiguities: idx.iter().map(|&j| self.amb[j]).collect(),
            covariance: c,
            chi2: self.chi2,
            dof: self.dof,
            used_held: used,
            summary: self.summary.clone(),
        }
    }

    /// The float solution of every ambiguity.
    fn float_all(&self) -> FloatSolution {
        let all: Vec<usize> = (0..self.amb.len()).collect();
        self.float(&all, self.f.clone(), self.c.clone(), Vec::new())
    }
}

/// What the held integers give at one epoch.
enum Held {
    /// No held pair occurs at this epoch.
    None,
    /// The float ambiguities disagree with the held integers.
    Rejected,
    /// The held `(arc, reference arc, DD integer)` triples that occur, and the solution fixed
    /// conditionally on them.
    Kept {
        list: Vec<(u64, u64, i64)>,
        solution: Box<BaselineSolution>,
    },
}

impl BaselineFilter {
    /// Steps 4-5: the epoch's fix, its state, whether a held set was rejected, whether a fix was refused
    /// for its length, the float solution it fixed; updates the held set.
    ///
    /// Beyond the gate: a fix of fewer than [`MIN_FIX_PHASES`] double-differenced phases is not
    /// reported (a fresh one is not held either; held integers stay held for when the satellites
    /// return), and a fix whose length disagrees with the rigid pair's is refused (a held one drops the
    /// held set).
    pub(super) fn fix(
        &mut self,
        epoch: &DdEpoch,
        groups: &[Group],
        fix: &FixOptions,
        chi2: f64,
        dof: usize,
    ) -> Result<(BaselineSolution, FixState, bool, bool, FloatSolution)> {
        let dd = self.dd_ambiguities(epoch, groups, chi2, dof);
        let float = dd.float_all();
        let float_all = float_result(&float, &[]);
        let redundant = dd.amb.len() >= MIN_FIX_PHASES;
        let (fresh, length_refused) = self.fresh_fix(&dd, &float_all, redundant, fix)?;
        let fresh_state = if fresh.fixed {
            FixState::Fixed
        } else {
            FixState::Float
        };
        let (held_list, mut held_sol) = match self.held_fix(&dd, fix)? {
            Held::Kept { list, solution } => (list, *solution),
            Held::None => {
                self.hold(&fresh);
                return Ok((fresh, fresh_state, false, length_refused, float));
            }
            Held::Rejected => {
                self.held.clear();
                self.hold(&fresh);
                return Ok((fresh, fresh_state, true, length_refused, float));
            }
        };
        held_sol.ratio = fresh.ratio;
        held_sol.success_rate = fresh.success_rate;
        if held_sol.fixed && redundant && !self.length_ok(&held_sol) {
            // The held integers give a length the pair does not have: they were wrong or an arc
            // slipped unseen; the fresh fix (itself checked) takes over.
            self.held.clear();
            self.hold(&fresh);
            return Ok((fresh, fresh_state, true, true, float));
        }
        if fresh.fixed {
            let agrees = held_list.iter().all(|h| fresh.integers.contains(h));
            // A disagreeing fresh fix replaces the hold only when the data prefer it by the ratio
            // threshold.
            let replace = !agrees && prefers_fresh(&dd, &held_sol, &fresh, fix.ratio_threshold);
            if agrees || replace {
                self.held.clear();
                self.hold(&fresh);
                return Ok((fresh, FixState::Fixed, replace, length_refused, float));
            }
        }
        if held_sol.fixed {
            self.hold(&held_sol);
        } else {
            // Keep the held integers that occurred (re-expressed against this epoch's references).
            self.set_held(&held_list);
        }
        if !redundant {
            // Held, but nothing in this epoch's phases could show a wrong integer: reported float.
            return Ok((float_all, FixState::Float, false, length_refused, float));
        }
        let state = if held_sol.fixed {
            FixState::Held
        } else {
            FixState::Float
        };
        Ok((held_sol, state, false, length_refused, float))
    }

    /// The double-difference ambiguities of this epoch's references on the filter's state.
    fn dd_ambiguities(
        &self,
        epoch: &DdEpoch,
        groups: &[Group],
        chi2: f64,
        dof: usize,
    ) -> DdAmbiguities {
        let nk = self.nk();
        let mut amb: Vec<Ambiguity> = Vec::new();
        let mut t_rows: Vec<(usize, usize)> = Vec::new();
        let mut held_value: Vec<Option<i64>> = Vec::new();
        for g in groups {
            let sr = &epoch.signals[g.reference];
            let ir = self.state_of(sr.arc);
            for &k in &g.members {
                let sk = &epoch.signals[k];
                let ik = self.state_of(sk.arc);
                let offset = self.arcs[ik - nk].offset - self.arcs[ir - nk].offset;
                amb.push(Ambiguity {
                    arc: sk.arc,
                    reference_arc: sr.arc,
                    offset,
                });
                t_rows.push((ik, ir));
                held_value.push(match (self.held.get(&sk.arc), self.held.get(&sr.arc)) {
                    (Some(a), Some(b)) => Some(a - b),
                    _ => None,
                });
            }
        }
        let mut t = DMatrix::<f64>::zeros(3 + amb.len(), self.x.len());
        for i in 0..3 {
            t[(i, i)] = 1.0;
        }
        for (j, &(ik, ir)) in t_rows.iter().enumerate() {
            t[(3 + j, ik)] = 1.0;
            t[(3 + j, ir)] = -1.0;
        }
        let c = &t * &self.p * t.transpose();
        DdAmbiguities {
            amb,
            held_value,
            f: &t * &self.x,
            c: (&c + c.transpose()) * 0.5,
            summary: summary(epoch, groups),
            chi2,
            dof,
        }
    }

    /// The epoch's own fix on the filter's covariance (the constrained search with a known length) and
    /// whether it was refused for its length (then the float is returned). A refusal counts towards
    /// learning the length again ([`super::RigidLength::refused`]).
    fn fresh_fix(
        &mut self,
        dd: &DdAmbiguities,
        float_all: &BaselineSolution,
        redundant: bool,
        fix: &FixOptions,
    ) -> Result<(BaselineSolution, bool)> {
        let fresh_float = dd.float_all();
        let fresh = match self.length.and_then(|l| l.known_m()) {
            Some(l) => fix_known_length(&fresh_float, &[], l, fix)?,
            None => fix_float(&fresh_float, &[], fix)?,
        };
        if fresh.fixed && !(redundant && (self.length_ok(&fresh) || self.relearn(&fresh))) {
            return Ok((float_all.clone(), redundant));
        }
        Ok((fresh, false))
    }

    /// The held integers of this epoch: [`Held::Rejected`] when the float ambiguities disagree with
    /// them (the chi-square of their difference beyond its [`HOLD_TEST_Z`] quantile), else the baseline
    /// and the other ambiguities conditioned on them, the rest fixed.
    fn held_fix(&self, dd: &DdAmbiguities, fix: &FixOptions) -> Result<Held> {
        let na = dd.amb.len();
        let held_idx: Vec<usize> = (0..na).filter(|&j| dd.held_value[j].is_some()).collect();
        if held_idx.is_empty() {
            return Ok(Held::None);
        }
        let list: Vec<(u64, u64, i64)> = held_idx
            .iter()
            .map(|&j| {
                let a = &dd.amb[j];
                (a.arc, a.reference_arc, dd.held_value[j].unwrap_or_default())
            })
            .collect();
        // The held integers as values of the ambiguity unknowns (DD integer minus offset).
        let z_h = DVector::from_iterator(
            held_idx.len(),
            held_idx
                .iter()
                .zip(&list)
                .map(|(&j, h)| (h.2 - dd.amb[j].offset) as f64),
        );
        let pick = |m: &DMatrix<f64>, r: &[usize], s: &[usize]| {
            DMatrix::from_fn(r.len(), s.len(), |i, j| m[(r[i], s[j])])
        };
        let h_rows: Vec<usize> = held_idx.iter().map(|&j| 3 + j).collect();
        let d = DVector::from_fn(held_idx.len(), |i, _| dd.f[h_rows[i]]) - &z_h;
        let chol_h = Cholesky::new(pick(&dd.c, &h_rows, &h_rows)).ok_or_else(|| {
            Error::numerical(
                "filter hold test",
                "the held ambiguities' covariance is not positive definite",
            )
        })?;
        if d.dot(&chol_h.solve(&d)) > chi2_quantile(held_idx.len(), HOLD_TEST_Z) {
            return Ok(Held::Rejected);
        }
        // Condition the baseline and the other ambiguities on the held integers, then fix the rest.
        let free: Vec<usize> = (0..na).filter(|&j| dd.held_value[j].is_none()).collect();
        let keep: Vec<usize> = (0..3).chain(free.iter().map(|&j| 3 + j)).collect();
        let c_kh = pick(&dd.c, &keep, &h_rows);
        let gain = chol_h.solve(&c_kh.transpose()).transpose(); // C_kh C_hh^-1
        let f_c = DVector::from_fn(keep.len(), |i, _| dd.f[keep[i]]) - &gain * &d;
        let c_c = pick(&dd.c, &keep, &keep) - &gain * c_kh.transpose();
        let c_c = (&c_c + c_c.transpose()) * 0.5;
        let used: Vec<(u64, u64)> = list.iter().map(|&(a, r, _)| (a, r)).collect();
        let solution = Box::new(fix_float(&dd.float(&free, f_c, c_c, used), &list, fix)?);
        Ok(Held::Kept { list, solution })
    }

    /// Holds the integers of a fully fixed solution (nothing changes otherwise).
    fn hold(&mut self, sol: &BaselineSolution) {
        if sol.fixed {
            self.set_held(&sol.integers);
        }
    }

    /// The held set from `(arc, reference arc, DD integer)` triples of one epoch (one reference per group).
    fn set_held(&mut self, integers: &[(u64, u64, i64)]) {
        self.held.clear();
        for &(a, r, n) in integers {
            self.held.insert(r, 0);
            self.held.insert(a, n);
        }
    }
}

/// The integer vector of the ambiguity unknowns (DD integer minus offset) from a full set of triples;
/// `None` when one is missing.
fn full_vector(amb: &[Ambiguity], integers: &[(u64, u64, i64)]) -> Option<DVector<f64>> {
    let v: Option<Vec<f64>> = amb
        .iter()
        .map(|a| {
            integers
                .iter()
                .find(|&&(x, r, _)| x == a.arc && r == a.reference_arc)
                .map(|&(_, _, n)| (n - a.offset) as f64)
        })
        .collect();
    v.map(DVector::from_vec)
}

/// Whether a fresh fix that disagrees with the held integers is preferred by the data: the held full
/// set's squared distance from the float over the fresh one's beyond `ratio_threshold` (same covariance;
/// a held solution that is not fully fixed always gives way).
fn prefers_fresh(
    dd: &DdAmbiguities,
    held: &BaselineSolution,
    fresh: &BaselineSolution,
    ratio_threshold: f64,
) -> bool {
    let held_full = held.fixed.then(|| full_vector(&dd.amb, &held.integers));
    let fresh_full = full_vector(&dd.amb, &fresh.integers);
    let (Some(Some(zh)), Some(zf)) = (held_full, fresh_full) else {
        return true;
    };
    let na = dd.amb.len();
    let a = dd.f.rows(3, na).into_owned();
    let Some(ch) = Cholesky::new(dd.c.view((3, 3), (na, na)).into_owned()) else {
        return false;
    };
    let dist = |z: &DVector<f64>| {
        let e = &a - z;
        e.dot(&ch.solve(&e))
    };
    dist(&zh) > ratio_threshold * dist(&zf)
}

/// Which signals and systems contributed (as [`super::float`] reports it).
fn summary(epoch: &DdEpoch, groups: &[Group]) -> Summary {
    let mut s = Summary {
        reference_sats: [None; N_SYSTEMS],
        slots_used: 0,
        satellites_per_system: [0; N_SYSTEMS],
    };
    let mut sats: [BTreeSet<usize>; N_SYSTEMS] = Default::default();
    let mut ref_slot: [usize; N_SYSTEMS] = [usize::MAX; N_SYSTEMS];
    for g in groups {
        let k = g.system.index();
        s.slots_used |= 1 << g.slot;
        for &i in std::iter::once(&g.reference).chain(&g.members) {
            sats[k].insert(epoch.signals[i].sat);
        }
        if g.slot < ref_slot[k] {
            ref_slot[k] = g.slot;
            s.reference_sats[k] = Some(epoch.signals[g.reference].sat);
        }
    }
    for (n, set) in s.satellites_per_system.iter_mut().zip(&sats) {
        *n = u16::try_from(set.len()).unwrap_or(u16::MAX);
    }
    s
}
