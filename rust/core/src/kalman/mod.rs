//! Building blocks shared by the Kalman filters of the core (orbit determination, gyro + GNSS attitude):
//! discretisation of a linear(ised) continuous model, covariance prediction, the measurement update in Joseph
//! form, and the normalised errors (NEES, NIS) used to check a filter's consistency.
//!
//! States and covariances are dynamically sized because the tightly coupled filters add and remove float
//! ambiguities as satellites rise and set.

use nalgebra::{DMatrix, DVector};

use crate::error::{Error, Result};

#[cfg(test)]
mod tests;

/// Discrete transition `Phi = exp(F dt)` and process noise `Qd = int_0^dt Phi(s) Qc Phi(s)^T ds` of the
/// continuous model `dx/dt = F x + w`, `E[w w^T] = Qc delta(t)`, by Van Loan's method (1978): the exponential of
/// `[[-F, Qc], [0, F^T]] dt` holds both. Exact for time-invariant `F`, `Qc` over the step.
pub fn discretize(
    f: &DMatrix<f64>,
    qc: &DMatrix<f64>,
    dt: f64,
) -> Result<(DMatrix<f64>, DMatrix<f64>)> {
    let n = f.nrows();
    check_square("F", f)?;
    check_shape("Qc", qc, n, n)?;
    if !(dt.is_finite() && dt >= 0.0) {
        return Err(Error::out_of_range(
            "dt",
            format!("expected a finite step >= 0 s, got {dt}"),
        ));
    }
    check_finite("F", f)?;
    check_finite("Qc", qc)?;
    let mut m = DMatrix::zeros(2 * n, 2 * n);
    m.view_mut((0, 0), (n, n)).copy_from(&(-f * dt));
    m.view_mut((0, n), (n, n)).copy_from(&(qc * dt));
    m.view_mut((n, n), (n, n)).copy_from(&(f.transpose() * dt));
    let e = m.exp();
    let phi = e.view((n, n), (n, n)).transpose();
    let qd = &phi * e.view((0, n), (n, n));
    Ok((phi, symmetrize(qd)))
}

/// `Phi P Phi^T + Q`, symmetrised (round-off otherwise accumulates an antisymmetric part over many steps).
pub fn predict_covariance(
    p: &DMatrix<f64>,
    phi: &DMatrix<f64>,
    q: &DMatrix<f64>,
) -> Result<DMatrix<f64>> {
    let n = p.nrows();
    check_square("P", p)?;
    check_shape("Phi", phi, n, n)?;
    check_shape("Q", q, n, n)?;
    Ok(symmetrize(phi * p * phi.transpose() + q))
}

/// What one measurement update saw: the innovation, its covariance and the normalised innovation squared.
#[derive(Debug, Clone, PartialEq)]
pub struct Update {
    /// `z - h(x)` as given to [`update`].
    pub innovation: DVector<f64>,
    /// `S = H P H^T + R`.
    pub innovation_cov: DMatrix<f64>,
    /// `nu^T S^-1 nu`: chi-square with `m` degrees of freedom for a consistent filter.
    pub nis: f64,
}

/// Measurement update of `x`, `P` with innovation `nu = z - h(x)`, Jacobian `H` (m x n) and measurement noise
/// `R` (m x m). The covariance uses the Joseph form `(I - K H) P (I - K H)^T + K R K^T`, which stays positive
/// semidefinite under round-off; the gain solves `S K^T = H P` by Cholesky instead of inverting `S`.
pub fn update(
    x: &mut DVector<f64>,
    p: &mut DMatrix<f64>,
    innovation: &DVector<f64>,
    h: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<Update> {
    let n = x.len();
    let m = innovation.len();
    check_shape("P", p, n, n)?;
    check_shape("H", h, m, n)?;
    check_shape("R", r, m, m)?;
    check_finite(
        "innovation",
        &DMatrix::from_column_slice(m, 1, innovation.as_slice()),
    )?;
    check_finite("H", h)?;
    check_finite("R", r)?;
    let s = symmetrize(h * &*p * h.transpose() + r);
    let chol = s
        .clone()
        .cholesky()
        .ok_or_else(|| Error::DegenerateGeometry {
            what: "Kalman update".into(),
            matrix: "innovation covariance H P H^T + R",
            condition: condition_number(&s),
        })?;
    let ph_t = &*p * h.transpose();
    let k = chol.solve(&ph_t.transpose()).transpose();
    let nis = innovation.dot(&chol.solve(innovation));
    *x += &k * innovation;
    let i_kh = DMatrix::identity(n, n) - &k * h;
    *p = symmetrize(&i_kh * &*p * i_kh.transpose() + &k * r * k.transpose());
    Ok(Update {
        innovation: innovation.clone(),
        innovation_cov: s,
        nis,
    })
}

/// Normalised estimation error squared `e^T P^-1 e`: chi-square with `n` degrees of freedom when the filter's
/// covariance `P` is the true covariance of the error `e`.
pub fn nees(error: &DVector<f64>, p: &DMatrix<f64>) -> Result<f64> {
    let n = error.len();
    check_shape("P", p, n, n)?;
    let chol = p
        .clone()
        .cholesky()
        .ok_or_else(|| Error::DegenerateGeometry {
            what: "NEES".into(),
            matrix: "covariance P",
            condition: condition_number(p),
        })?;
    Ok(error.dot(&chol.solve(error)))
}

/// `(A + A^T) / 2`.
pub fn symmetrize(a: DMatrix<f64>) -> DMatrix<f64> {
    (&a + a.transpose()) * 0.5
}

fn condition_number(a: &DMatrix<f64>) -> f64 {
    let sv = a.clone().singular_values();
    let (max, min) = (sv.max(), sv.min());
    if min > 0.0 {
        max / min
    } else {
        f64::INFINITY
    }
}

fn check_square(name: &'static str, a: &DMatrix<f64>) -> Result<()> {
    check_shape(name, a, a.nrows(), a.nrows())
}

fn check_shape(name: &'static str, a: &DMatrix<f64>, rows: usize, cols: usize) -> Result<()> {
    if a.nrows() != rows || a.ncols() != cols {
        return Err(Error::Shape {
            name,
            expected: format!("({rows}, {cols})"),
            actual: format!("({}, {})", a.nrows(), a.ncols()),
        });
    }
    Ok(())
}

fn check_finite(name: &'static str, a: &DMatrix<f64>) -> Result<()> {
    match a.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(Error::NonFinite { name, index }),
        None => Ok(()),
    }
}
