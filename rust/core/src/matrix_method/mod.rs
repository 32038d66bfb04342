//! Matrix least-squares attitude from antenna range differences.
//! Ryzhkov & Oliinyk, "Determining a satellite's attitude from GPS information" (Ryzhkov and Oliinyk):
//! `R = B^T A S` (2), with `B` the body-frame baselines (3 x m), `S` the reference-frame lines of sight
//! (3 x n) and `A` the reference-to-body rotation.

use nalgebra::{DMatrix, Matrix3, Matrix3xX, SymmetricEigen, Vector3};

use crate::error::{ensure_finite, Error, Result};
use crate::wahba;

/// Which formula turns range differences into an attitude matrix.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Eq. (3), `A = G^-1 B R S^T N^-1`: exact without noise, not orthogonal with it. Needs `G = B B^T`
    /// and `N = S S^T` invertible (>= 3 non-coplanar baselines and lines of sight).
    ClosedForm,
    /// Eq. (16), `A = Q^T (sqrt(Q Q^T))^-1`, `Q = S K^T`, `K = G^-1 B R`: the orthogonal matrix
    /// minimising (5). Same invertibility needs as eq. (3); can be a reflection, which is reported.
    Paper,
    /// The proper rotation solving the same Wahba problem by SVD. With a non-coplanar array it minimises
    /// (5) and equals eq. (16) whenever that is a rotation; with a coplanar array (three antennas) it
    /// estimates the baselines in the reference frame, `C = N^-1 S R^T`, and matches them to `B`.
    Svd,
    /// Minimises the least-squares loss (4) itself over proper rotations by Gauss-Newton on SO(3),
    /// started from [`Method::Svd`]: the maximum-likelihood attitude for independent Gaussian range-
    /// difference errors, which reaches the Cramer-Rao bound where [`Method::Svd`] (minimising the
    /// re-weighted loss (5)) does not.
    MaxLikelihood,
}

/// The attitude found, and how well it explains the range differences.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// Proper rotation, body -> reference (`A^T`).
    pub dcm_ref_from_body: Matrix3<f64>,
    /// The method's own reference -> body matrix `A` before any orthogonalisation (eq. (3) is not a
    /// rotation with noisy data).
    pub raw_body_from_ref: Matrix3<f64>,
    /// Root mean square of `R - B^T A S` over all m x n range differences, metres.
    pub residual_rms_m: f64,
}

/// Condition number above which `G` or `N` is treated as singular.
pub const MAX_CONDITION: f64 = 1e10;
/// Allowed deviation of a line of sight's norm from 1.
pub const UNIT_TOLERANCE: f64 = 1e-6;

/// Solves (2) for the attitude.
///
/// # Arguments
/// * `baselines_m` - antenna positions relative to the reference antenna, body frame, metres (m >= 2).
/// * `los` - unit lines of sight to the satellites, reference frame (n >= 2).
/// * `range_diffs_m` - m x n range differences `b_i . (A s_j)`, metres.
///
/// # Errors
/// [`Error::Shape`], [`Error::NonFinite`], [`Error::OutOfRange`] for bad input;
/// [`Error::DegenerateGeometry`] naming the singular matrix and its condition number.
pub fn solve(
    baselines_m: &[Vector3<f64>],
    los: &[Vector3<f64>],
    range_diffs_m: &DMatrix<f64>,
    method: Method,
) -> Result<Solution> {
    validate(baselines_m, los, range_diffs_m)?;
    let geo = Geometry::new(baselines_m, los);
    let r = range_diffs_m;
    let raw = match method {
        Method::ClosedForm => geo.closed_form(r)?,
        Method::Paper => geo.paper(r)?,
        Method::Svd => geo.svd(r)?,
        Method::MaxLikelihood => minimise_loss(&geo.b, &geo.s, r, geo.svd(r)?)?,
    };
    let rotation = match method {
        Method::ClosedForm => wahba::svd::solve(&raw)?,
        _ => raw,
    };
    let resid = r - geo.b.transpose() * rotation * &geo.s;
    let (m, n) = geo.sizes;
    Ok(Solution {
        dcm_ref_from_body: rotation.transpose(),
        raw_body_from_ref: raw,
        residual_rms_m: resid.norm() / ((m * n) as f64).sqrt(),
    })
}

/// `Err(DegenerateGeometry)` naming `matrix` and `what` when `cond` is NaN or above [`MAX_CONDITION`].
fn need(cond: f64, matrix: &'static str, what: &str) -> Result<()> {
    if cond.is_nan() || cond > MAX_CONDITION {
        return Err(Error::DegenerateGeometry {
            what: what.into(),
            matrix,
            condition: cond,
        });
    }
    Ok(())
}

/// The baselines `B` and lines of sight `S` as matrices, `G = B B^T` and `N = S S^T` with their
/// condition numbers (see [`conditions`]).
struct Geometry {
    b: Matrix3xX<f64>,
    s: Matrix3xX<f64>,
    g: Matrix3<f64>,
    nn: Matrix3<f64>,
    g_cond: f64,
    g_cond2: f64,
    n_cond: f64,
    n_cond2: f64,
    /// Baselines and lines of sight, `(m, n)`.
    sizes: (usize, usize),
}

impl Geometry {
    fn new(baselines_m: &[Vector3<f64>], los: &[Vector3<f64>]) -> Geometry {
        let b = Matrix3xX::from_columns(baselines_m);
        let s = Matrix3xX::from_columns(los);
        let g = &b * b.transpose();
        let nn = &s * s.transpose();
        let (g_cond, g_cond2) = conditions(&g);
        let (n_cond, n_cond2) = conditions(&nn);
        Geometry {
            b,
            s,
            g,
            nn,
            g_cond,
            g_cond2,
            n_cond,
            n_cond2,
            sizes: (baselines_m.len(), los.len()),
        }
    }

    /// `K = G^-1 B R`, after checking that eq. (3) and (16)'s `G` and `N` are invertible.
    fn k(&self, r: &DMatrix<f64>, method: Method) -> Result<Matrix3xX<f64>> {
        let (m, n) = self.sizes;
        let why = format!("{method:?} needs {{}} (got {m} baselines, {n} lines of sight)");
        need(
            self.g_cond,
            G_NAME,
            &why.replace("{}", "3 non-coplanar baselines"),
        )?;
        need(
            self.n_cond,
            N_NAME,
            &why.replace("{}", "3 non-coplanar lines of sight"),
        )?;
        Ok(invert(&self.g, G_NAME, self.sizes)? * &self.b * r)
    }

    /// Eq. (3), `A = K S^T N^-1`.
    fn closed_form(&self, r: &DMatrix<f64>) -> Result<Matrix3<f64>> {
        let k = self.k(r, Method::ClosedForm)?;
        Ok(k * self.s.transpose() * invert(&self.nn, N_NAME, self.sizes)?)
    }

    /// Eq. (16), `A = Q^T (sqrt(Q Q^T))^-1`, `Q = S K^T`; a reflection is an error.
    fn paper(&self, r: &DMatrix<f64>) -> Result<Matrix3<f64>> {
        let k = self.k(r, Method::Paper)?;
        let q = &self.s * k.transpose();
        let qqt = q * q.transpose();
        let eig = SymmetricEigen::new(qqt);
        // Q Q^T is positive semi-definite; rounding can make its smallest eigenvalue slightly
        // negative, and the ratio is then NaN or negative: both mean singular.
        let cond = eig.eigenvalues.max() / eig.eigenvalues.min();
        let cond = if cond >= 1.0 { cond } else { f64::INFINITY };
        need(
            cond.sqrt(),
            "matrix Q = S K^T",
            "eq. (16) needs an invertible Q",
        )?;
        let inv_sqrt = eig.eigenvectors
            * Matrix3::from_diagonal(&eig.eigenvalues.map(|l| 1.0 / l.sqrt()))
            * eig.eigenvectors.transpose();
        let a = q.transpose() * inv_sqrt;
        if a.determinant() < 0.0 {
            return Err(Error::DegenerateGeometry {
                what: "eq. (16) returned a reflection (det = -1); use the SVD method".into(),
                matrix: "matrix Q = S K^T",
                condition: cond.sqrt(),
            });
        }
        Ok(a)
    }

    /// The proper rotation of the Wahba problem whose profile matrix is `G^-1 B R S^T` (non-coplanar
    /// baselines) or `B R S^T N^-1` (non-coplanar lines of sight).
    fn svd(&self, r: &DMatrix<f64>) -> Result<Matrix3<f64>> {
        let (b, s) = (&self.b, &self.s);
        // Both profile matrices equal (PSD) x A or A x (PSD) without noise, so the proper polar
        // factor is A itself; which side is inverted depends on which side has full rank.
        let h = if self.g_cond <= MAX_CONDITION && self.n_cond2 <= MAX_CONDITION {
            invert(&self.g, G_NAME, self.sizes)? * b * r * s.transpose()
        } else if self.g_cond2 <= MAX_CONDITION && self.n_cond <= MAX_CONDITION {
            b * r * s.transpose() * invert(&self.nn, N_NAME, self.sizes)?
        } else {
            let (matrix, condition) = if self.g_cond2 > MAX_CONDITION {
                (G_NAME, self.g_cond2)
            } else {
                (N_NAME, self.n_cond)
            };
            let (m, n) = self.sizes;
            return Err(Error::DegenerateGeometry {
                what: format!(
                    "the attitude is not fixed: need 3 non-coplanar baselines and 2 non-parallel \
                     lines of sight, or 2 non-parallel baselines and 3 non-coplanar lines of sight \
                     (got {m} baselines, {n} lines of sight)"
                ),
                matrix,
                condition,
            });
        };
        wahba::svd::solve(&h)
    }
}

/// Most Gauss-Newton iterations of [`Method::MaxLikelihood`].
pub const MAX_ITERATIONS: usize = 200;

/// Gauss-Newton on SO(3) for loss (4), `sum_ij (r_ij - b_i . A s_j)^2`, from `a0` (reference -> body).
/// The correction is a small rotation `delta` of the body -> reference matrix `M = A^T`,
/// `M <- exp([delta]x) M`, whose gradient for range difference ij is `(M b_i) x s_j`. Steps that raise
/// the loss are halved, so the loss never increases.
fn minimise_loss(
    b: &Matrix3xX<f64>,
    s: &Matrix3xX<f64>,
    r: &DMatrix<f64>,
    a0: Matrix3<f64>,
) -> Result<Matrix3<f64>> {
    let loss = |m: &Matrix3<f64>| (r - b.transpose() * m.transpose() * s).norm_squared();
    let mut m = a0.transpose();
    let mut current = loss(&m);
    for _ in 0..MAX_ITERATIONS {
        let (mut info, mut grad) = (Matrix3::zeros(), Vector3::zeros());
        let mb = m * b;
        for (i, c) in mb.column_iter().enumerate() {
            for (j, sj) in s.column_iter().enumerate() {
                let g = c.cross(&sj);
                info += g * g.transpose();
                grad += g * (r[(i, j)] - c.dot(&sj));
            }
        }
        let Some(delta) = info.cholesky().map(|ch| ch.solve(&grad)) else {
            return Err(Error::DegenerateGeometry {
                what: "the range differences do not fix the attitude".into(),
                matrix: "Fisher information of the rotation",
                condition: f64::INFINITY,
            });
        };
        // 1e-10 rad is far below any attitude accuracy; Gauss-Newton converges only linearly on
        // large-residual problems, so asking for rounding-level steps would cost many iterations.
        if delta.norm() < 1e-10 {
            return Ok(m.transpose());
        }
        let mut step = 1.0;
        loop {
            let trial = nalgebra::Rotation3::new(delta * step).into_inner() * m;
            let value = loss(&trial);
            if value <= current {
                (m, current) = (trial, value);
                break;
            }
            step *= 0.5;
            if step < 1e-6 {
                // No descent left along the Gauss-Newton direction: a minimum to rounding.
                return Ok(m.transpose());
            }
        }
    }
    Err(Error::Convergence {
        what: "Gauss-Newton minimisation of the range-difference loss",
        iterations: MAX_ITERATIONS,
    })
}

fn validate(baselines: &[Vector3<f64>], los: &[Vector3<f64>], r: &DMatrix<f64>) -> Result<()> {
    let (m, n) = (baselines.len(), los.len());
    if m < 2 {
        return Err(Error::Shape {
            name: "baselines",
            expected: "(m, 3) with m >= 2".into(),
            actual: format!("({m}, 3)"),
        });
    }
    if n < 2 {
        return Err(Error::Shape {
            name: "los",
            expected: "(n, 3) with n >= 2".into(),
            actual: format!("({n}, 3)"),
        });
    }
    if r.shape() != (m, n) {
        return Err(Error::Shape {
            name: "range_diffs",
            expected: format!("({m}, {n}) = (baselines, lines of sight)"),
            actual: format!("{:?}", r.shape()),
        });
    }
    ensure_finite("baselines", baselines.iter().flat_map(|v| v.iter()))?;
    ensure_finite("los", los.iter().flat_map(|v| v.iter()))?;
    ensure_finite("range_diffs", r.iter())?;
    if let Some((i, v)) = los
        .iter()
        .enumerate()
        .find(|(_, v)| (v.norm() - 1.0).abs() > UNIT_TOLERANCE)
    {
        return Err(Error::out_of_range(
            "los",
            format!("expected unit vectors, row {i} has norm {:.9}", v.norm()),
        ));
    }
    if let Some(i) = baselines.iter().position(|v| v.norm() == 0.0) {
        return Err(Error::out_of_range(
            "baselines",
            format!("baseline {i} has zero length"),
        ));
    }
    Ok(())
}

const G_NAME: &str = "baseline matrix G = B B^T";
const N_NAME: &str = "line-of-sight matrix N = S S^T";

/// `(s1/s3, s1/s2)` of a symmetric positive semi-definite matrix: full-rank and rank->=2 conditions.
///
/// Scale invariant: the matrix is divided by its largest entry first, so baselines of 1e-60 m are as
/// good as baselines of 1 m; a matrix that underflowed to zero (or holds no positive eigenvalue) is
/// infinitely ill-conditioned, never NaN.
fn conditions(x: &Matrix3<f64>) -> (f64, f64) {
    let scale = x.amax();
    if !(scale > 0.0 && scale.is_finite()) {
        return (f64::INFINITY, f64::INFINITY);
    }
    let mut e = SymmetricEigen::new(x / scale)
        .eigenvalues
        .map(|l| l.max(0.0));
    e.as_mut_slice().sort_by(|a, b| b.total_cmp(a));
    let ratio = |d: f64| if d > 0.0 { e[0] / d } else { f64::INFINITY };
    (ratio(e[2]), ratio(e[1]))
}

/// `x^-1` of a matrix whose condition was checked, computed on `x / max|x|` so that a tiny or huge scale
/// cannot underflow the determinant.
///
/// # Errors
/// [`Error::DegenerateGeometry`] naming `matrix` when the inverse fails or is not finite anyway.
fn invert(x: &Matrix3<f64>, matrix: &'static str, (m, n): (usize, usize)) -> Result<Matrix3<f64>> {
    let scale = x.amax();
    let inv = (x / scale)
        .try_inverse()
        .map(|i| i / scale)
        .filter(|i| i.iter().all(|v| v.is_finite()));
    inv.ok_or_else(|| Error::DegenerateGeometry {
        what: format!(
            "the {matrix} cannot be inverted in floating point (got {m} baselines, {n} lines of sight, \
             max entry {scale:.3e})"
        ),
        matrix,
        condition: f64::INFINITY,
    })
}

#[cfg(test)]
mod tests;
