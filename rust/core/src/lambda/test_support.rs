//! Deterministic random covariances for the unit tests (no dependency on `rand` outside dev builds).

use nalgebra::DMatrix;

/// A 64-bit linear congruential generator (Knuth's MMIX constants), good enough for test matrices.
pub struct Lcg(pub u64);

impl Lcg {
    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Standard normal (Box-Muller).
    pub fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.uniform();
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}

/// `A A^T / n + floor I` with a standard normal `A`: strongly correlated but positive definite.
pub fn random_covariance(rng: &mut Lcg, n: usize, floor: f64) -> DMatrix<f64> {
    let a = DMatrix::from_fn(n, n, |_, _| rng.normal());
    let q = &a * a.transpose() / n as f64 + DMatrix::identity(n, n) * floor;
    (&q + q.transpose()) * 0.5
}

/// `U diag(s) U^T` with a random orthogonal `U` (Gram-Schmidt of a normal matrix) and `s` log-spaced
/// from 1 down to `1 / condition`: a covariance of exactly that condition number.
pub fn spectrum_covariance(rng: &mut Lcg, n: usize, condition: f64) -> DMatrix<f64> {
    let a = DMatrix::from_fn(n, n, |_, _| rng.normal());
    let u = a.qr().q();
    let s = nalgebra::DVector::from_fn(n, |i, _| {
        condition.powf(-(i as f64) / (n.max(2) - 1) as f64)
    });
    let q = &u * DMatrix::from_diagonal(&s) * u.transpose();
    (&q + q.transpose()) * 0.5
}
