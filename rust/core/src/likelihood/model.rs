//! Measurements and statistic, preprocessed into the terms the grid kernel evaluates.

use std::f64::consts::{PI, TAU};

use nalgebra::{Matrix3, Vector3};

use crate::error::{ensure_finite, Error, Result};
use crate::rotation::euler::YZX;

/// Which sufficient statistic the grid evaluates (module docs give the formulas).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Statistic {
    /// Oscillator phases maximised out per baseline: `sum_i |sum_k exp(j x_ik)|`. Works on wrapped phases.
    AmbiguityFunction,
    /// Eqs. (10)-(14) as written: satellite-mean differences. Fails on wrapped phases.
    Mean,
    /// Eqs. (17)-(18): differences against the highest-elevation satellite.
    DoubleDifference,
}

impl Statistic {
    /// Parses `"ambiguity_function"`, `"mean"` or `"double_difference"`.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for any other name.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "ambiguity_function" => Ok(Statistic::AmbiguityFunction),
            "mean" => Ok(Statistic::Mean),
            "double_difference" => Ok(Statistic::DoubleDifference),
            other => Err(Error::out_of_range(
                "statistic",
                format!(
                    "expected 'ambiguity_function', 'mean' or 'double_difference', got {other:?}"
                ),
            )),
        }
    }
}

/// One epoch of measurements.
#[derive(Debug, Clone, PartialEq)]
pub struct Epoch {
    /// `phase_diffs[i][k]`: phase at antenna `i + 1` minus antenna 0 for satellite `k`, radians, any
    /// multiple of 2 pi added.
    pub phase_diffs: Vec<Vec<f64>>,
    /// Unit lines of sight to the satellites, East-North-Up.
    pub los_enu: Vec<Vector3<f64>>,
    /// Carrier wavelength per satellite, metres.
    pub wavelengths: Vec<f64>,
}

/// How the kernel groups its complex exponentials: one modulus per group.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Grouping {
    /// One modulus per baseline, summing over the (epoch, satellite) terms.
    PerBaseline,
    /// One modulus per (epoch, satellite) term, summing `1 +` the baselines.
    PerSatellite,
}

/// Preprocessed problem: baselines, per-term wave vectors in the normal frame and reduced phases.
#[derive(Debug, Clone)]
pub struct Model {
    pub(crate) grouping: Grouping,
    pub(crate) baselines: Vec<Vector3<f64>>,
    /// `d[i * n_terms + k]`, radians in [-pi, pi).
    pub(crate) d: Vec<f64>,
    /// Wave vector (possibly differenced) of term `k`, rad/m, normal frame (N, U, E).
    pub(crate) g: Vec<Vector3<f64>>,
    pub(crate) lambda_min: f64,
    pub(crate) l_max: f64,
}

/// Body -> normal-frame (North, Up, East) matrix of eq. (5) transposed: `Ry(psi) Rz(theta) Rx(phi)`.
pub fn dcm_normal_from_body(psi: f64, theta: f64, phi: f64) -> Matrix3<f64> {
    YZX.to_dcm([psi, theta, phi])
}

/// Body -> East-North-Up matrix: the normal-frame matrix with its rows permuted (N, U, E) -> (E, N, U).
pub fn dcm_enu_from_body(psi: f64, theta: f64, phi: f64) -> Matrix3<f64> {
    let m = dcm_normal_from_body(psi, theta, phi);
    Matrix3::from_rows(&[m.row(2), m.row(0), m.row(1)])
}

fn enu_to_normal(v: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(v.y, v.z, v.x)
}

fn wrap(x: f64) -> f64 {
    (x + PI).rem_euclid(TAU) - PI
}

/// Checks the body-frame baselines (at least one, finite, none of zero length, not all collinear) and
/// returns the longest one's length, metres.
fn check_baselines(baselines: &[Vector3<f64>]) -> Result<f64> {
    let nb = baselines.len();
    if nb == 0 {
        return Err(Error::Shape {
            name: "baselines",
            expected: "(m, 3) with m >= 1".into(),
            actual: "(0, 3)".into(),
        });
    }
    ensure_finite("baselines", baselines.iter().flat_map(|b| b.iter()))?;
    if let Some(i) = baselines.iter().position(|b| b.norm() < 1e-9) {
        return Err(Error::out_of_range(
            "baselines",
            format!("baseline {i} has zero length"),
        ));
    }
    let l_max_m = baselines.iter().map(|b| b.norm()).fold(0.0, f64::max);
    if nb >= 2 {
        let best = baselines
            .iter()
            .flat_map(|a| baselines.iter().map(move |b| a.cross(b).norm()))
            .fold(0.0, f64::max);
        let ratio = best / (l_max_m * l_max_m);
        if ratio < 1e-6 {
            return Err(Error::DegenerateGeometry {
                what: "baselines are collinear: roll about them is not observable".into(),
                matrix: "baseline Gram matrix",
                condition: 1.0 / ratio.max(f64::MIN_POSITIVE),
            });
        }
    }
    Ok(l_max_m)
}

/// Checks one epoch against `nb` baselines: shapes, finiteness, at least 3 satellites, positive
/// wavelengths and unit lines of sight.
fn check_epoch(e: &Epoch, nb: usize) -> Result<()> {
    let m = e.los_enu.len();
    if e.phase_diffs.len() != nb || e.phase_diffs.iter().any(|r| r.len() != m) {
        return Err(Error::Shape {
            name: "phase_diffs",
            expected: format!("({nb}, {m}) per epoch (baselines, satellites)"),
            actual: format!(
                "({}, {})",
                e.phase_diffs.len(),
                e.phase_diffs.first().map_or(0, Vec::len)
            ),
        });
    }
    if e.wavelengths.len() != m {
        return Err(Error::Shape {
            name: "wavelength",
            expected: format!("({m},)"),
            actual: format!("({},)", e.wavelengths.len()),
        });
    }
    if m < 3 {
        return Err(Error::out_of_range(
            "los",
            format!("expected at least 3 satellites, got {m}"),
        ));
    }
    ensure_finite("phase_diffs", e.phase_diffs.iter().flatten())?;
    ensure_finite("los", e.los_enu.iter().flat_map(|v| v.iter()))?;
    ensure_finite("wavelength", e.wavelengths.iter())?;
    if let Some(k) = e.wavelengths.iter().position(|&w| w <= 0.0) {
        return Err(Error::out_of_range(
            "wavelength",
            format!(
                "expected positive wavelengths, got {} at {k}",
                e.wavelengths[k]
            ),
        ));
    }
    if let Some(k) = e.los_enu.iter().position(|v| (v.norm() - 1.0).abs() > 1e-3) {
        return Err(Error::out_of_range(
            "los",
            format!(
                "expected unit lines of sight, got norm {:.6} at {k}",
                e.los_enu[k].norm()
            ),
        ));
    }
    Ok(())
}

/// Appends one checked epoch's terms: per satellite the `nb` reduced phases (radians, wrapped) and the
/// wave vector (rad/m, normal frame), both less the statistic's reference.
fn push_epoch_terms(
    e: &Epoch,
    nb: usize,
    statistic: Statistic,
    terms: &mut Vec<(Vec<f64>, Vector3<f64>)>,
) {
    let m = e.los_enu.len();
    let g: Vec<Vector3<f64>> = e
        .los_enu
        .iter()
        .zip(&e.wavelengths)
        .map(|(v, w)| enu_to_normal(&v.normalize()) * (TAU / w))
        .collect();
    // Reference offsets: per baseline a phase, and one wave vector, removed from every satellite.
    let (phase_ref, g_ref): (Vec<f64>, Vector3<f64>) = match statistic {
        Statistic::AmbiguityFunction => (vec![0.0; nb], Vector3::zeros()),
        Statistic::Mean => (
            e.phase_diffs
                .iter()
                .map(|r| r.iter().sum::<f64>() / m as f64)
                .collect(),
            g.iter().sum::<Vector3<f64>>() / m as f64,
        ),
        Statistic::DoubleDifference => {
            let top = (0..m)
                .max_by(|&a, &b| e.los_enu[a].z.total_cmp(&e.los_enu[b].z))
                .unwrap_or(0);
            (e.phase_diffs.iter().map(|r| r[top]).collect(), g[top])
        }
    };
    for (k, gk) in g.iter().enumerate() {
        let d = (0..nb)
            .map(|i| wrap(e.phase_diffs[i][k] - phase_ref[i]))
            .collect();
        terms.push((d, gk - g_ref));
    }
}

/// The terms' reduced phases laid out baseline-major, `d[i * n_terms + k]`, as [`Model::d`] holds them
/// (the likelihood's inner loop walks the terms of one baseline).
fn baseline_major_phases(terms: &[(Vec<f64>, Vector3<f64>)], nb: usize) -> Vec<f64> {
    let n = terms.len();
    let mut d = vec![0.0; nb * n];
    for (k, (dk, _)) in terms.iter().enumerate() {
        for i in 0..nb {
            d[i * n + k] = dk[i];
        }
    }
    d
}

impl Model {
    /// Checks and preprocesses the measurements.
    ///
    /// # Arguments
    /// * `baselines` - antenna positions relative to antenna 0, body frame, metres; one (single-baseline
    ///   variant) or several, not all collinear.
    /// * `epochs` - measurements; every epoch has the same number of baselines as `baselines` and at
    ///   least 3 satellites.
    /// * `statistic` - which sufficient statistic.
    ///
    /// # Errors
    /// [`Error::Shape`] for mismatched lengths, [`Error::NonFinite`], [`Error::OutOfRange`] for fewer than
    /// 3 satellites, non-unit lines of sight, non-positive wavelengths or zero baselines,
    /// [`Error::DegenerateGeometry`] for collinear baselines.
    pub fn new(baselines: &[Vector3<f64>], epochs: &[Epoch], statistic: Statistic) -> Result<Self> {
        let l_max = check_baselines(baselines)?;
        if epochs.is_empty() {
            return Err(Error::Shape {
                name: "phase_diffs",
                expected: "at least one epoch".into(),
                actual: "0 epochs".into(),
            });
        }
        let nb = baselines.len();
        let grouping = match statistic {
            Statistic::AmbiguityFunction => Grouping::PerBaseline,
            _ => Grouping::PerSatellite,
        };
        let mut terms: Vec<(Vec<f64>, Vector3<f64>)> = Vec::new();
        let mut lambda_min = f64::INFINITY;
        for e in epochs {
            check_epoch(e, nb)?;
            lambda_min = e.wavelengths.iter().copied().fold(lambda_min, f64::min);
            push_epoch_terms(e, nb, statistic, &mut terms);
        }
        Ok(Model {
            grouping,
            baselines: baselines.to_vec(),
            d: baseline_major_phases(&terms, nb),
            g: terms.into_iter().map(|t| t.1).collect(),
            lambda_min,
            l_max,
        })
    }

    /// Number of baselines.
    pub fn n_baselines(&self) -> usize {
        self.baselines.len()
    }

    /// Number of (epoch, satellite) terms.
    pub fn n_terms(&self) -> usize {
        self.g.len()
    }

    /// Number of moduli summed into `Z` and members per modulus (including the constant 1 of antenna 0
    /// for the per-satellite statistics).
    pub(crate) fn groups(&self) -> (usize, usize) {
        match self.grouping {
            Grouping::PerBaseline => (self.n_baselines(), self.n_terms()),
            Grouping::PerSatellite => (self.n_terms(), self.n_baselines()),
        }
    }

    /// Whether `Z` is a sum of one modulus per baseline (the ambiguity function), the structure the
    /// branch-and-bound decomposes.
    pub fn statistic_splits_by_baseline(&self) -> bool {
        self.grouping == Grouping::PerBaseline
    }

    /// Largest possible `Z`: every exponential aligned.
    pub fn z_upper(&self) -> f64 {
        match self.grouping {
            Grouping::PerBaseline => (self.n_baselines() * self.n_terms()) as f64,
            Grouping::PerSatellite => (self.n_terms() * (self.n_baselines() + 1)) as f64,
        }
    }

    /// Default grid step, eq. (15) with factor 10: `lambda_min / (10 L_max)` radians.
    pub fn default_step(&self) -> f64 {
        self.lambda_min / (10.0 * self.l_max)
    }

    /// Coarsest accepted step, `lambda_min / (2 L_max)` radians: half the width of the main lobe of the
    /// longest baseline (its first null is `lambda / L` away); coarser grids can step over the peak.
    pub fn max_step(&self) -> f64 {
        self.lambda_min / (2.0 * self.l_max)
    }

    /// Phase of term `(i, k)` at the normal-frame baseline vector `v_i`, radians (f64 reference).
    pub(crate) fn phase(&self, i: usize, k: usize, v: &Vector3<f64>) -> f64 {
        self.d[i * self.n_terms() + k] + self.g[k].dot(v)
    }

    /// `Z` at one attitude, in f64 (reference for tests and bounds).
    pub fn z_f64(&self, psi: f64, theta: f64, phi: f64) -> f64 {
        let r = dcm_normal_from_body(psi, theta, phi);
        let v: Vec<Vector3<f64>> = self.baselines.iter().map(|b| r * b).collect();
        let n = self.n_terms();
        match self.grouping {
            Grouping::PerBaseline => (0..self.n_baselines())
                .map(|i| {
                    let (s, c) = (0..n).fold((0.0, 0.0), |(s, c), k| {
                        let (sk, ck) = self.phase(i, k, &v[i]).sin_cos();
                        (s + sk, c + ck)
                    });
                    s.hypot(c)
                })
                .sum(),
            Grouping::PerSatellite => (0..n)
                .map(|k| {
                    let (s, c) = (0..self.n_baselines()).fold((0.0, 1.0), |(s, c), i| {
                        let (si, ci) = self.phase(i, k, &v[i]).sin_cos();
                        (s + si, c + ci)
                    });
                    s.hypot(c)
                })
                .sum(),
        }
    }
}
