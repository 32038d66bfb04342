use nalgebra::{dmatrix, dvector, DMatrix, DVector};

use super::*;

fn close(a: &DMatrix<f64>, b: &DMatrix<f64>, tol: f64) -> bool {
    (a - b).abs().max() <= tol * (1.0 + b.abs().max())
}

#[test]
fn van_loan_matches_the_closed_form_of_a_white_acceleration_model() {
    // x = (position, velocity), dv/dt = w with spectral density q: Phi = [[1, dt], [0, 1]] and
    // Qd = q [[dt^3/3, dt^2/2], [dt^2/2, dt]] (Bar-Shalom, Li, Kirubarajan 2001, eq. 6.2.2-12).
    let (q, dt) = (0.3, 2.5);
    let f = dmatrix![0.0, 1.0; 0.0, 0.0];
    let qc = dmatrix![0.0, 0.0; 0.0, q];
    let (phi, qd) = discretize(&f, &qc, dt).unwrap();
    assert!(close(&phi, &dmatrix![1.0, dt; 0.0, 1.0], 1e-12));
    let expected = dmatrix![dt.powi(3) / 3.0, dt * dt / 2.0; dt * dt / 2.0, dt] * q;
    assert!(close(&qd, &expected, 1e-12), "{qd} vs {expected}");
}

#[test]
fn van_loan_matches_a_first_order_gauss_markov_process() {
    // dx/dt = -x/tau + w: Phi = exp(-dt/tau), Qd = q tau / 2 (1 - exp(-2 dt/tau)).
    let (tau, q, dt) = (40.0, 1e-4, 3.0);
    let (phi, qd) = discretize(&dmatrix![-1.0 / tau], &dmatrix![q], dt).unwrap();
    assert!((phi[(0, 0)] - (-dt / tau).exp()).abs() < 1e-14);
    let expected = q * tau / 2.0 * (1.0 - (-2.0 * dt / tau).exp());
    assert!((qd[(0, 0)] - expected).abs() < 1e-15 * expected.max(1.0) + 1e-18);
}

#[test]
fn scalar_update_is_the_weighted_mean() {
    // Prior N(1, 4), measurement 3 with variance 1: posterior mean (1/4 + 3)/(1/4 + 1) = 2.6, variance 0.8.
    let mut x = dvector![1.0];
    let mut p = dmatrix![4.0];
    let u = update(
        &mut x,
        &mut p,
        &dvector![2.0],
        &dmatrix![1.0],
        &dmatrix![1.0],
    )
    .unwrap();
    assert!((x[0] - 2.6).abs() < 1e-15);
    assert!((p[(0, 0)] - 0.8).abs() < 1e-15);
    assert!((u.nis - 4.0 / 5.0).abs() < 1e-15);
}

#[test]
fn joseph_form_equals_the_information_form() {
    // P+ = (P^-1 + H^T R^-1 H)^-1 for any gain-optimal update.
    let p0 = dmatrix![2.0, 0.3, 0.1; 0.3, 1.5, -0.2; 0.1, -0.2, 0.9];
    let h = dmatrix![1.0, 0.5, 0.0; 0.0, 1.0, -1.0];
    let r = dmatrix![0.2, 0.05; 0.05, 0.4];
    let mut x = DVector::zeros(3);
    let mut p = p0.clone();
    update(&mut x, &mut p, &dvector![0.1, -0.3], &h, &r).unwrap();
    let info = p0.try_inverse().unwrap() + h.transpose() * r.try_inverse().unwrap() * &h;
    assert!(close(&p, &info.try_inverse().unwrap(), 1e-12));
}

#[test]
fn nees_of_a_unit_error_along_an_eigenvector() {
    let p = dmatrix![4.0, 0.0; 0.0, 0.25];
    assert!((nees(&dvector![2.0, 0.0], &p).unwrap() - 1.0).abs() < 1e-15);
    assert!((nees(&dvector![0.0, 1.0], &p).unwrap() - 4.0).abs() < 1e-15);
}

#[test]
fn bad_input_is_an_error() {
    let mut x = dvector![0.0, 0.0];
    let mut p = DMatrix::identity(2, 2);
    let h = dmatrix![1.0, 0.0];
    assert!(matches!(
        update(&mut x, &mut p, &dvector![f64::NAN], &h, &dmatrix![1.0]),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        update(
            &mut x,
            &mut p,
            &dvector![1.0],
            &dmatrix![1.0],
            &dmatrix![1.0]
        ),
        Err(Error::Shape { .. })
    ));
    // Zero prior and zero measurement noise along the measured direction: S = 0 is not invertible.
    let mut p0 = DMatrix::zeros(2, 2);
    assert!(matches!(
        update(&mut x, &mut p0, &dvector![1.0], &h, &dmatrix![0.0]),
        Err(Error::DegenerateGeometry { .. })
    ));
    assert!(matches!(
        discretize(&DMatrix::zeros(2, 2), &DMatrix::zeros(2, 2), -1.0),
        Err(Error::OutOfRange { .. })
    ));
}
