//! Checks of a fixed baseline that the integer gate cannot make: its length against the length of a rigid
//! antenna pair, and its phase redundancy.
//!
//! The gate (ratio test, success rate) judges a fix by the float solution of the epochs it sees. After an
//! outage every arc restarts and a fresh fix rests on a few epochs: on the simulated car of
//! `docs/rtklib_comparison.md` (GPS L1, u-blox noise) such a fix passed the gate with ratio 3.03 and a
//! success rate of 0.93 with a 1.57 m baseline where every earlier fix of the pair had 1.20 m. When both
//! antennas are on one rigid body (a moving base on the same vehicle as its rover: the attitude set-up) the
//! length is a constant that every earlier fix measured, and a wrong integer set almost always changes it.
//! This check is only valid for a rigid pair: a rover moving against a static base changes its length all
//! the time, so it is used only when the user says so (`--rigid`, or a known `--baseline-length`).

use nalgebra::{Matrix3, Vector3};

use super::BaselineSolution;

/// A fix whose length differs from the rigid pair's by more than this many standard deviations of the
/// difference is refused. Gaussian errors exceed 4 sigma with probability 6e-5: one correct fix in 16 000
/// refused (its epoch is reported float), while a wrong integer set moves the length by a good part of a
/// wavelength (19 cm at L1) in most directions.
pub const RIGID_LENGTH_SIGMAS: f64 = 4.0;

/// Standard deviation added to every length comparison, m. The fixed baselines that a learned length
/// averages share errors in time (multipath, the satellite geometry of an arc) that their inverse-variance
/// mean treats as independent, and a patch antenna's phase centre moves by millimetres with the
/// satellites' directions: 1 cm covers both (on the simulated car the fixed baselines' median error is
/// 1 cm) and is still a tenth of the length change of a typical wrong fix.
pub const RIGID_LENGTH_FLOOR_M: f64 = 0.01;

/// Fixed epochs a learned length needs before it checks others. Until then the gate alone decides (the
/// first fixes of a session are not checked: a learned length is only as good as the fixes it comes from).
pub const RIGID_MIN_FIXES: usize = 10;

/// Fewest double-differenced phases of a reported fix: one more than the baseline's 3 unknowns. With 3
/// (4 satellites of one system and frequency) every integer set fits the phases exactly, no residual can
/// show a wrong integer or a slip, and the fixed baseline is the phases' exact solution with the weak
/// geometry's dilution (on the simulated car in trees its sigma is 4 cm, 2.5 times that of 5 satellites).
pub const MIN_FIX_PHASES: usize = 4;

/// What is known of a rigid pair's length: given by the user or learned from the fixes so far.
///
/// A learned length is learned again when the fixes refused for it agree with each other: a run of
/// refused fixes, none accepted in between, each within [`RIGID_LENGTH_SIGMAS`] of the run's mean, as
/// long as the run that made the learned length ([`RIGID_MIN_FIXES`] at least) replaces it. A wrong
/// first length (the session's first fixes were wrong, or the antennas were moved) is then not kept for
/// the rest of the session; a right one that has been confirmed by every fix since is as hard to replace
/// as its fixes were many.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidLength {
    known_m: Option<f64>,
    /// The fixes the learned length comes from.
    learned: LengthMean,
    /// The fixes refused since the last accepted one that agree with each other.
    challenger: LengthMean,
}

/// Inverse-variance mean of lengths: `sum l / sigma^2`, `sum 1 / sigma^2` and the fixes added.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct LengthMean {
    weighted_sum: f64,
    weight: f64,
    fixes: usize,
}

impl LengthMean {
    fn add(&mut self, length_m: f64, variance_m2: f64) {
        // A fixed baseline's variance can round to 0: a floor of (0.1 mm)^2 keeps the weight finite.
        let w = 1.0 / variance_m2.max(1e-8);
        self.weighted_sum += w * length_m;
        self.weight += w;
        self.fixes += 1;
    }

    /// The mean and its standard deviation, m (`None` before any fix).
    fn mean(&self) -> Option<(f64, f64)> {
        (self.fixes > 0 && self.weight > 0.0)
            .then(|| (self.weighted_sum / self.weight, self.weight.sqrt().recip()))
    }
}

/// Whether a length of variance `variance_m2` agrees with the reference `(l_ref, sigma_ref)` within
/// [`RIGID_LENGTH_SIGMAS`] (the floor [`RIGID_LENGTH_FLOOR_M`] added).
fn agrees(length_m: f64, variance_m2: f64, (l_ref, sigma_ref): (f64, f64)) -> bool {
    let s2 = variance_m2 + sigma_ref * sigma_ref + RIGID_LENGTH_FLOOR_M * RIGID_LENGTH_FLOOR_M;
    (length_m - l_ref).powi(2) <= RIGID_LENGTH_SIGMAS * RIGID_LENGTH_SIGMAS * s2
}

impl RigidLength {
    /// A pair of known length `length_m` (a surveyed antenna separation, exact against the fixes'
    /// sigmas; never learned again).
    pub fn known(length_m: f64) -> RigidLength {
        RigidLength {
            known_m: Some(length_m),
            ..RigidLength::learned()
        }
    }

    /// A rigid pair of unknown length, learned from its fixes ([`Self::add`]).
    pub fn learned() -> RigidLength {
        RigidLength {
            known_m: None,
            learned: LengthMean::default(),
            challenger: LengthMean::default(),
        }
    }

    /// The known length, m (`None`: learned).
    pub fn known_m(&self) -> Option<f64> {
        self.known_m
    }

    /// The length and its standard deviation, m: the known one, or the learned one once
    /// [`RIGID_MIN_FIXES`] fixes are in; `None` before.
    pub fn reference(&self) -> Option<(f64, f64)> {
        match self.known_m {
            Some(l) => Some((l, 0.0)),
            None => self
                .learned
                .mean()
                .filter(|_| self.learned.fixes >= RIGID_MIN_FIXES),
        }
    }

    /// Whether a fixed baseline's length agrees with the pair's within [`RIGID_LENGTH_SIGMAS`] (true
    /// while there is no reference yet, and for a baseline of no length or no finite variance: nothing to
    /// compare).
    pub fn consistent(&self, baseline_m: &Vector3<f64>, covariance_m2: &Matrix3<f64>) -> bool {
        let (Some(reference), Some((l, variance))) = (
            self.reference(),
            length_and_variance(baseline_m, covariance_m2),
        ) else {
            return true;
        };
        agrees(l, variance, reference)
    }

    /// Adds an accepted, fully fixed baseline to the learned length (float solutions and a known
    /// length: nothing); the refused fixes counted so far are forgotten.
    pub fn add(&mut self, sol: &BaselineSolution) {
        if self.known_m.is_some() || !sol.fixed {
            return;
        }
        if let Some((l, variance)) = length_and_variance(&sol.baseline_m, &sol.covariance_m2) {
            self.learned.add(l, variance);
            self.challenger = LengthMean::default();
        }
    }

    /// Counts a fully fixed baseline refused for its length ([`Self::consistent`] false) towards
    /// learning the length again (struct docs); `true` when the length was learned again from the
    /// refused fixes before this one, which this one agrees with (the caller then accepts it and
    /// [`Self::add`]s it). A known length: always `false`.
    pub fn refused(&mut self, sol: &BaselineSolution) -> bool {
        if self.known_m.is_some() || !sol.fixed {
            return false;
        }
        let Some((l, variance)) = length_and_variance(&sol.baseline_m, &sol.covariance_m2) else {
            return false;
        };
        match self.challenger.mean() {
            Some(m) if agrees(l, variance, m) => {}
            // The run of refused fixes does not agree with itself: it starts again at this one.
            _ => self.challenger = LengthMean::default(),
        }
        if self.challenger.fixes + 1 >= self.learned.fixes.max(RIGID_MIN_FIXES) {
            self.learned = self.challenger;
            self.challenger = LengthMean::default();
            return true;
        }
        self.challenger.add(l, variance);
        false
    }
}

/// A baseline's length and the variance of the length (along the baseline), m and m^2; `None` for a zero,
/// non-finite length or a non-finite variance.
fn length_and_variance(b: &Vector3<f64>, c: &Matrix3<f64>) -> Option<(f64, f64)> {
    let l = b.norm();
    if !(l > 0.0 && l.is_finite()) {
        return None;
    }
    let u = b / l;
    let variance = u.dot(&(c * u));
    variance.is_finite().then_some((l, variance.max(0.0)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fixed(b: Vector3<f64>, sigma_m: f64) -> BaselineSolution {
        BaselineSolution {
            baseline_m: b,
            covariance_m2: Matrix3::identity() * sigma_m * sigma_m,
            fixed: true,
            fixed_ambiguities: 5,
            ambiguities: 5,
            ratio: 10.0,
            success_rate: 1.0,
            integers: Vec::new(),
            reference_sats: Default::default(),
            slots_used: 1,
            satellites_per_system: Default::default(),
            float_chi2: 0.0,
            float_dof: 0,
        }
    }

    #[test]
    fn learned_length_checks_only_after_enough_fixes() {
        let mut r = RigidLength::learned();
        let wrong = Vector3::new(1.2, 0.9, 0.3); // 1.53 m
        let right = Vector3::new(1.2, 0.0, 0.0);
        let c = Matrix3::identity() * 1e-4;
        for k in 0..RIGID_MIN_FIXES {
            assert!(r.consistent(&wrong, &c), "no reference yet after {k} fixes");
            r.add(&fixed(right, 0.01));
        }
        let (l, s) = r.reference().unwrap();
        assert!((l - 1.2).abs() < 1e-12 && s > 0.0);
        assert!(!r.consistent(&wrong, &c));
        assert!(r.consistent(&right, &c));
    }

    #[test]
    fn threshold_is_four_sigma_of_the_difference() {
        // Known length: the difference's variance is the fix's plus the floor's.
        let r = RigidLength::known(1.0);
        let sigma = 0.02;
        let c = Matrix3::identity() * sigma * sigma;
        let s = (sigma * sigma + RIGID_LENGTH_FLOOR_M * RIGID_LENGTH_FLOOR_M).sqrt();
        let at = |k: f64| Vector3::new(0.0, 1.0 + k * s, 0.0);
        assert!(r.consistent(&at(3.99), &c));
        assert!(!r.consistent(&at(4.01), &c));
        assert!(!r.consistent(&at(-4.01), &c));
        // Only the variance along the baseline counts: a large across-track sigma changes nothing.
        let mut wide = c;
        wide[(0, 0)] = 1.0;
        assert!(!r.consistent(&at(4.01), &wide));
    }

    #[test]
    fn float_and_known_lengths_are_not_learned() {
        let mut r = RigidLength::learned();
        let mut f = fixed(Vector3::new(2.0, 0.0, 0.0), 0.3);
        f.fixed = false;
        for _ in 0..2 * RIGID_MIN_FIXES {
            r.add(&f);
        }
        assert_eq!(r.reference(), None);
        let mut k = RigidLength::known(1.0);
        k.add(&fixed(Vector3::new(2.0, 0.0, 0.0), 0.001));
        assert_eq!(k.reference(), Some((1.0, 0.0)));
    }

    #[test]
    fn a_wrong_learned_length_is_learned_again_from_as_many_refused_fixes() {
        let c = Matrix3::identity() * 1e-4;
        let wrong = Vector3::new(1.2, 0.9, 0.3); // 1.53 m
        let right = Vector3::new(1.2, 0.0, 0.0);
        let n = RIGID_MIN_FIXES + 3;
        let mut r = RigidLength::learned();
        for _ in 0..n {
            r.add(&fixed(wrong, 0.01));
        }
        // n - 1 refused fixes of the right length are counted; the n-th replaces the learned length.
        for k in 0..n - 1 {
            assert!(!r.consistent(&right, &c));
            assert!(
                !r.refused(&fixed(right, 0.01)),
                "learned again after {k} refused"
            );
        }
        assert!(r.refused(&fixed(right, 0.01)));
        r.add(&fixed(right, 0.01));
        let (l, _) = r.reference().unwrap();
        assert!((l - 1.2).abs() < 1e-12, "{l}");
        assert!(r.consistent(&right, &c) && !r.consistent(&wrong, &c));
    }

    #[test]
    fn refused_fixes_that_disagree_or_are_interrupted_do_not_replace_the_length() {
        let right = Vector3::new(1.2, 0.0, 0.0);
        let long = Vector3::new(1.4, 0.0, 0.0);
        let longer = Vector3::new(1.6, 0.0, 0.0);
        let mut r = RigidLength::learned();
        for _ in 0..RIGID_MIN_FIXES {
            r.add(&fixed(right, 0.01));
        }
        // Wrong fixes of two lengths in turn: each restarts the run.
        for k in 0..4 * RIGID_MIN_FIXES {
            let b = if k % 2 == 0 { long } else { longer };
            assert!(!r.refused(&fixed(b, 0.01)), "fix {k}");
        }
        // One length, but an accepted fix every RIGID_MIN_FIXES - 1 refused ones.
        for k in 0..4 * RIGID_MIN_FIXES {
            if k % (RIGID_MIN_FIXES - 1) == 0 {
                r.add(&fixed(right, 0.01));
            } else {
                assert!(!r.refused(&fixed(long, 0.01)), "fix {k}");
            }
        }
        let (l, _) = r.reference().unwrap();
        assert!((l - 1.2).abs() < 1e-12, "{l}");
        // A known length is never learned again.
        let mut k = RigidLength::known(1.0);
        for _ in 0..10 * RIGID_MIN_FIXES {
            assert!(!k.refused(&fixed(long, 0.01)));
        }
        assert_eq!(k.reference(), Some((1.0, 0.0)));
    }
}
