//! The exact search of attitude mode's constrained objective ([`super`]'s module documentation): every
//! rover's list of unconstrained ILS candidates grows until a bound guarantees that the best (and, when
//! asked, the second-best) combination of the whole integer space is among the lists' combinations.
//!
//! **Bound.** A candidate's term of the objective, `||a_i - z||^2 + w_i |b_i(z) - R f_i|^2`, is at
//! least its screening cost `s_i(z) = ||a_i - z||^2 + w_i (|b_i(z)| - |f_i|)^2` (`|b - R f| >=
//! ||b| - |f||`), which is at least its norm. A rover's list leaves out only integers whose norm is at
//! least its radius `N_i` (the `m`-th norm of the `m` best, or the radius every candidate below which
//! was enumerated), so every combination with one of those has an objective of at least
//! `N_i + sum_{j != i} low_j`, `low_j` the smallest screening cost rover `j` can have (its list's least,
//! or `N_j` if smaller). The lists are complete once the second best (the best, for the simulated
//! success rate's draws) found among them is at most that bound for every rover.
//!
//! **Growth.** The first list holds the [`FIRST_CANDIDATES`] best (LAMBDA's search). A rover that fails
//! the bound needs every integer of norm below the target less the others' least: its list becomes every
//! candidate below that radius (`constrained_radius.rs`, an enumeration without the `m`-best heap), for the
//! fresh search by steps of about [`EXPANSION`] times the candidates (a second best of short lists is
//! loose; each round's second best tightens the radius). At most [`MAX_CANDIDATES`] per rover (beyond,
//! the list grows by count, LAMBDA's `m` best, up to that limit).
//!
//! **Combinations.** The lists' combinations are walked depth first, each list sorted by screening cost,
//! and a branch is cut where its screening costs (a lower bound of every objective below it) reach the
//! second best found so far: the best and second best of the lists are exact without scoring every
//! combination. At most [`MAX_COMBINATIONS`] are scored with the full objective (the weighted orthogonal
//! Procrustes problem of [`crate::wahba::svd`]); past that, with lists at [`MAX_CANDIDATES`] that are
//! still incomplete, or past the search's node limit, the search reports itself incomplete and its
//! ratio is only a lower bound.

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::radius::within;
use crate::error::{Error, Result};
use crate::lambda::{search as lambda_search, Problem};
use crate::wahba;

/// Unconstrained candidates of a rover's first list, and the factor between one list and the next when
/// no second best bounds the radius yet.
pub const FIRST_CANDIDATES: usize = 16;
pub const EXPANSION: usize = 4;

/// Most unconstrained candidates of one rover's list (the known-length search's limit).
pub const MAX_CANDIDATES: usize = super::super::known_length::MAX_CANDIDATES;

/// Most combinations one search scores with the full objective (each a 3 x 3 SVD).
pub const MAX_COMBINATIONS: usize = 4096;

/// Most growths of the lists in one search (each strictly larger; beyond: incomplete).
const MAX_ROUNDS: usize = 16;

/// Nodes one unconstrained search may visit (beyond: the list stops growing).
const MAX_NODES: u64 = 5_000_000;

/// One integer candidate of one rover.
#[derive(Debug, Clone)]
pub(super) struct Candidate {
    /// The integers in the rover's decorrelated space ([`Problem::to_original`] maps them back; empty for
    /// a rover with no free ambiguity).
    pub z: DVector<f64>,
    /// `||a - z||^2_{Q_a}`.
    pub norm: f64,
    /// The conditioned baseline `b(z)`, ENU, m.
    pub b_enu: Vector3<f64>,
    /// `||a - z||^2 + w (|b(z)| - |f|)^2`: a lower bound of the candidate's term of the objective.
    pub screen: f64,
}

/// A rover's free ambiguities: what its candidate lists are searched from, for any float vector.
pub(super) struct Ambiguities {
    pub problem: Problem,
    /// `Z^-1 Q_a^-1 Q_ab` rotated to ENU (n x 3): `b(z) = b - gain^T (zhat - z)` in the decorrelated
    /// space, ENU.
    pub gain_enu: DMatrix<f64>,
}

impl Ambiguities {
    /// From the decorrelated problem of the float ambiguities and `Q_a^-1 Q_ab` (`gain`, n x 3, in the
    /// frame `to_enu` rotates to ENU).
    pub fn new(
        problem: Problem,
        gain: &DMatrix<f64>,
        to_enu: &Matrix3<f64>,
    ) -> Result<Ambiguities> {
        let rot = DMatrix::from_fn(3, 3, |i, j| to_enu[(j, i)]);
        let z_inv = problem.reduction.z_inv()?.map(|v| v as f64);
        Ok(Ambiguities {
            gain_enu: z_inv * gain * rot,
            problem,
        })
    }
}

/// One rover's candidate list for one float solution, grown on demand.
pub(super) struct List<'a> {
    source: Option<&'a Ambiguities>,
    /// Decorrelated float ambiguities and float baseline (ENU, m).
    zhat: DVector<f64>,
    b_enu: Vector3<f64>,
    weight: f64,
    length_m: f64,
    /// Sorted by screening cost.
    pub candidates: Vec<Candidate>,
    /// Every candidate not in the list has a norm of at least this (infinite: there is none).
    pub unsearched: f64,
    searched: usize,
    exhausted: bool,
}

impl<'a> List<'a> {
    /// The [`FIRST_CANDIDATES`] best candidates of decorrelated float ambiguities `zhat` and float
    /// baseline `b_enu`.
    pub fn new(
        source: &'a Ambiguities,
        zhat: DVector<f64>,
        b_enu: Vector3<f64>,
        weight: f64,
        length_m: f64,
    ) -> Result<List<'a>> {
        let mut l = List {
            source: Some(source),
            zhat,
            b_enu,
            weight,
            length_m,
            candidates: Vec::new(),
            unsearched: 0.0,
            searched: 0,
            exhausted: false,
        };
        l.grow()?;
        Ok(l)
    }

    /// A rover with no free ambiguity: its one baseline (ENU, m).
    pub fn single(b_enu: Vector3<f64>, weight: f64, length_m: f64) -> List<'static> {
        let dl = b_enu.norm() - length_m;
        List {
            source: None,
            zhat: DVector::zeros(0),
            b_enu,
            weight,
            length_m,
            candidates: vec![Candidate {
                z: DVector::zeros(0),
                norm: 0.0,
                b_enu,
                screen: weight * dl * dl,
            }],
            unsearched: f64::INFINITY,
            searched: 1,
            exhausted: true,
        }
    }

    /// The smallest screening cost any candidate of the rover can have.
    fn lowest(&self) -> f64 {
        self.candidates
            .first()
            .map_or(self.unsearched, |c| c.screen.min(self.unsearched))
    }

    /// Adds the candidate of decorrelated integers `z` (the simulation's truth, so that the lists' best
    /// bounds the search from the start) unless the list has it.
    pub fn include(&mut self, z: DVector<f64>) {
        let Some(src) = self.source else {
            return;
        };
        if self.candidates.iter().any(|c| c.z == z) {
            return;
        }
        // (zhat - z)^T (L^T D L)^-1 (zhat - z) = |D^-1/2 L^-T (zhat - z)|^2.
        let f = &src.problem.reduction.factor;
        let Some(y) = f.l.tr_solve_lower_triangular(&(&self.zhat - &z)) else {
            return;
        };
        let norm = y.iter().zip(f.d.iter()).map(|(v, d)| v * v / d).sum();
        let c = self.candidate(src, z, norm);
        let at = self.candidates.partition_point(|x| x.screen < c.screen);
        self.candidates.insert(at, c);
    }

    /// The candidate of decorrelated integers `z` with norm `norm`.
    fn candidate(&self, src: &Ambiguities, z: DVector<f64>, norm: f64) -> Candidate {
        let (b_enu, screen) = self.screen(src, z.as_slice(), norm);
        Candidate {
            z,
            norm,
            b_enu,
            screen,
        }
    }

    /// The conditioned baseline (ENU) and screening cost of decorrelated integers `z` of norm `norm`.
    fn screen(&self, src: &Ambiguities, z: &[f64], norm: f64) -> (Vector3<f64>, f64) {
        // gain^T (zhat - z) without a temporary: this runs for every enumerated candidate.
        let g = &src.gain_enu;
        let db = Vector3::from_fn(|j, _| {
            (0..z.len())
                .map(|k| g[(k, j)] * (self.zhat[k] - z[k]))
                .sum::<f64>()
        });
        let b_enu = self.b_enu - db;
        let dl = b_enu.norm() - self.length_m;
        (b_enu, norm + self.weight * dl * dl)
    }

    /// Searches [`EXPANSION`] times more candidates (the first: [`FIRST_CANDIDATES`]); false when the
    /// list cannot grow ([`MAX_CANDIDATES`], or the search's node limit).
    fn grow(&mut self) -> Result<bool> {
        let Some(src) = self.source.filter(|_| !self.exhausted) else {
            return Ok(false);
        };
        if self.searched >= MAX_CANDIDATES {
            self.exhausted = true;
            return Ok(false);
        }
        let m = (self.searched * EXPANSION).clamp(FIRST_CANDIDATES, MAX_CANDIDATES);
        let factor = &src.problem.reduction.factor;
        let found = match lambda_search(factor, &self.zhat, m, MAX_NODES) {
            Ok(f) => f,
            Err(Error::Convergence { .. }) => {
                self.exhausted = true;
                return Ok(false);
            }
            Err(e) => return Err(e),
        };
        let candidates = found
            .squared_norms
            .iter()
            .enumerate()
            .map(|(c, &norm)| self.candidate(src, found.z.column(c).into_owned(), norm))
            .collect();
        let unsearched = found.squared_norms.last().copied().unwrap_or(f64::INFINITY);
        self.set(candidates, unsearched, m);
        Ok(true)
    }

    /// Every candidate of norm up to `radius` ([`List::grow`] when there are more than
    /// [`MAX_CANDIDATES`]); false when the list cannot grow. Only those whose screening cost is at most
    /// `radius` are kept: the radius is the target less the others' least screening costs, so a
    /// combination with a candidate above it costs more than the target and can be neither the best nor
    /// the second best (the list's least screening cost, with the radius, still bounds the rover's).
    fn grow_to(&mut self, radius: f64) -> Result<bool> {
        let Some(src) = self.source.filter(|_| !self.exhausted) else {
            return Ok(false);
        };
        let factor = &src.problem.reduction.factor;
        let mut kept = Vec::new();
        let mut leaf = |z: &[f64], norm: f64| {
            let (b_enu, screen) = self.screen(src, z, norm);
            if screen <= radius {
                kept.push(Candidate {
                    z: DVector::from_column_slice(z),
                    norm,
                    b_enu,
                    screen,
                });
            }
        };
        let count = match within(
            factor,
            &self.zhat,
            radius,
            MAX_CANDIDATES,
            MAX_NODES,
            &mut leaf,
        ) {
            Ok(Some(c)) => c,
            // Too many below the radius (a loose second best): the next list by count, whose second
            // best bounds the radius more tightly.
            Ok(None) => return self.grow(),
            Err(Error::Convergence { .. }) => {
                self.exhausted = true;
                return Ok(false);
            }
            Err(e) => return Err(e),
        };
        self.set(kept, radius, count);
        Ok(true)
    }

    fn set(&mut self, mut candidates: Vec<Candidate>, unsearched: f64, searched: usize) {
        candidates.sort_by(|x, y| x.screen.total_cmp(&y.screen));
        self.candidates = candidates;
        self.unsearched = unsearched;
        self.searched = searched;
    }
}

/// What one search found.
#[derive(Debug, Clone)]
pub(super) struct Outcome {
    /// The best combination (a candidate per rover) and its objective.
    pub best: Option<(Vec<Candidate>, f64)>,
    /// The second best objective among the scored combinations.
    pub second: f64,
    /// Every combination not scored has an objective of at least this.
    pub bound: f64,
    /// The best (and the second best, when asked) are those of the whole integer space.
    pub complete: bool,
}

impl Outcome {
    /// Second best over best objective: exact when complete, else a lower bound (the second best of
    /// the lists or the bound, whichever is smaller, over the best).
    pub fn ratio(&self) -> f64 {
        match &self.best {
            Some((_, b)) if *b > 0.0 => self.second.min(self.bound) / b,
            Some(_) => f64::INFINITY,
            None => f64::NAN,
        }
    }
}

/// The best combination of the rovers' whole integer spaces, and the second best when `second`, by
/// growing `lists` (module documentation). `weights`: the rovers' `w_i`; `body`: their body baselines.
pub(super) fn search(
    lists: &mut [List<'_>],
    weights: &[f64],
    body: &[Vector3<f64>],
    second: bool,
) -> Result<Outcome> {
    for round in 0.. {
        let walk = Walk::run(lists, weights, body, second);
        let (capped, second_found) = (walk.capped, walk.second);
        let best = walk.best.map(|(c, cost)| {
            let chosen = c
                .iter()
                .zip(lists.iter())
                .map(|(&i, l)| l.candidates[i].clone())
                .collect();
            (chosen, cost)
        });
        let target = if second {
            second_found
        } else {
            best.as_ref().map_or(f64::INFINITY, |b| b.1)
        };
        let lows: Vec<f64> = lists.iter().map(List::lowest).collect();
        let low_sum: f64 = lows.iter().sum();
        // Rover i's unsearched integers with the others' least: every combination outside the lists.
        let outside: Vec<f64> = lists
            .iter()
            .zip(&lows)
            .map(|(l, low)| l.unsearched + (low_sum - low))
            .collect();
        let mut bound = outside.iter().copied().fold(f64::INFINITY, f64::min);
        if capped {
            // Unscored combinations inside the lists: only the lists' least screening costs bound them.
            bound = bound.min(low_sum);
        }
        let complete = !capped && target <= bound;
        let mut grown = false;
        if !complete && !capped {
            for ((l, &o), low) in lists.iter_mut().zip(&outside).zip(&lows) {
                if o < target {
                    // Rover i's list must hold every norm below the target less the others' least. A
                    // second best found on short lists is loose: towards it, the fresh search grows the
                    // radius by about EXPANSION times the candidates per round (their count goes as the
                    // radius to the n/2), and the second best of each round tightens it.
                    let needed = target - (low_sum - low);
                    let n = l.zhat.len().max(1) as f64;
                    let step =
                        l.unsearched.max(f64::MIN_POSITIVE) * (EXPANSION as f64).powf(2.0 / n);
                    grown |= match (target.is_finite(), second) {
                        (false, _) => l.grow()?,
                        (true, true) => l.grow_to(needed.min(step))?,
                        (true, false) => l.grow_to(needed)?,
                    };
                }
            }
        }
        if complete || !grown || round == MAX_ROUNDS {
            return Ok(Outcome {
                best,
                second: second_found,
                bound,
                complete,
            });
        }
    }
    unreachable!("the rounds end at MAX_ROUNDS")
}

/// The depth-first walk over the lists' combinations.
struct Walk<'l, 'a> {
    lists: &'l [List<'a>],
    weights: &'l [f64],
    body: &'l [Vector3<f64>],
    /// `rest[k]`: the least screening costs of lists `k..`.
    rest: Vec<f64>,
    want_second: bool,
    choice: Vec<usize>,
    best: Option<(Vec<usize>, f64)>,
    second: f64,
    scored: usize,
    capped: bool,
}

impl<'l, 'a> Walk<'l, 'a> {
    fn run(
        lists: &'l [List<'a>],
        weights: &'l [f64],
        body: &'l [Vector3<f64>],
        want_second: bool,
    ) -> Walk<'l, 'a> {
        let mut rest = vec![0.0; lists.len() + 1];
        for k in (0..lists.len()).rev() {
            rest[k] = rest[k + 1]
                + lists[k]
                    .candidates
                    .first()
                    .map_or(f64::INFINITY, |c| c.screen);
        }
        let mut w = Walk {
            lists,
            weights,
            body,
            rest,
            want_second,
            choice: vec![0; lists.len()],
            best: None,
            second: f64::INFINITY,
            scored: 0,
            capped: false,
        };
        w.visit(0, 0.0);
        w
    }

    /// The objective a combination must stay under to matter.
    fn limit(&self) -> f64 {
        match (&self.best, self.want_second) {
            (_, true) => self.second,
            (Some((_, b)), false) => *b,
            (None, false) => f64::INFINITY,
        }
    }

    fn visit(&mut self, k: usize, partial: f64) {
        if k == self.lists.len() {
            self.score();
            return;
        }
        for c in 0..self.lists[k].candidates.len() {
            let s = partial + self.lists[k].candidates[c].screen;
            if s + self.rest[k + 1] >= self.limit() || self.capped {
                break; // sorted by screening cost: every later candidate is cut too
            }
            self.choice[k] = c;
            self.visit(k + 1, s);
        }
    }

    fn score(&mut self) {
        if self.scored >= MAX_COMBINATIONS {
            self.capped = true;
            return;
        }
        self.scored += 1;
        let Some(cost) = objective(self.lists, self.weights, &self.choice, self.body) else {
            return; // a candidate set with parallel baselines fixes no rotation: not a solution
        };
        match &self.best {
            Some((_, b)) if cost >= *b => self.second = self.second.min(cost),
            _ => {
                if let Some((_, b)) = &self.best {
                    self.second = self.second.min(*b);
                }
                self.best = Some((self.choice.clone(), cost));
            }
        }
    }
}

/// The weighted rotation ENU <- body of baselines `b_enu` (`None`: they fix no rotation).
pub(super) fn rotation_of(
    weights: &[f64],
    b_enu: &[Vector3<f64>],
    body: &[Vector3<f64>],
) -> Option<Matrix3<f64>> {
    let h: Matrix3<f64> = weights
        .iter()
        .zip(b_enu)
        .zip(body)
        .map(|((w, b), f)| *w * b * f.transpose())
        .sum();
    wahba::svd::solve(&h).ok()
}

/// The full objective of combination `choice` of `lists`.
fn objective(
    lists: &[List<'_>],
    weights: &[f64],
    choice: &[usize],
    body: &[Vector3<f64>],
) -> Option<f64> {
    let picked: Vec<&Candidate> = lists
        .iter()
        .zip(choice)
        .map(|(l, &c)| &l.candidates[c])
        .collect();
    let b: Vec<Vector3<f64>> = picked.iter().map(|c| c.b_enu).collect();
    let rot = rotation_of(weights, &b, body)?;
    Some(
        picked
            .iter()
            .zip(weights)
            .zip(body)
            .map(|((c, w), f)| c.norm + w * (c.b_enu - rot * f).norm_squared())
            .sum(),
    )
}

#[cfg(test)]
#[path = "constrained_search_tests.rs"]
mod tests;
