//! Success rate of integer bootstrapping (sequential conditional rounding), the sharpest easily computed
//! lower bound of the ILS success rate:
//! `P = prod_i (2 Phi(1 / (2 sqrt(d_i))) - 1) = prod_i erf(1 / (2 sqrt(2 d_i)))`, with `d_i` the
//! conditional variances of the decorrelated ambiguities.
//! Teunissen (1998), "Success probability of integer GPS ambiguity rounding and bootstrapping",
//! J. Geodesy 72:606-612; Teunissen (1999), J. Geodesy 73:587-593 (bootstrapping bounds ILS from below).

use nalgebra::DMatrix;

use super::reduction::reduce;
use crate::error::Result;

/// The bootstrapped success rate of the decorrelated ambiguities of `q` (a lower bound of the ILS one).
///
/// # Arguments
/// * `q` - n x n symmetric positive-definite covariance of the float ambiguities, cycles^2.
///
/// # Errors
/// Those of [`super::ldl::ltdl`]: bad shape, non-finite, asymmetric or not positive-definite input.
pub fn bootstrap_success_rate(q: &DMatrix<f64>) -> Result<f64> {
    Ok(success_rate(reduce(q)?.factor.d.as_slice()))
}

/// `prod_i erf(1 / (2 sqrt(2 d_i)))` for conditional variances `d` (cycles^2) in bootstrapping order.
pub fn success_rate(d: &[f64]) -> f64 {
    d.iter().map(|&di| erf(0.5 / (2.0 * di).sqrt())).product()
}

/// The error function for `x >= 0`, to a few ulps.
///
/// Uses the everywhere-positive series `erf(x) = 2/sqrt(pi) exp(-x^2) sum_k (2x^2)^k x / (1 3 ... (2k+1))`
/// (Abramowitz & Stegun 7.1.6), which has no cancellation; `erf(x) = 1` to double precision beyond 6.
pub fn erf(x: f64) -> f64 {
    if x.is_nan() {
        return f64::NAN;
    }
    if x < 0.0 {
        return -erf(-x);
    }
    if x >= 6.0 {
        return 1.0;
    }
    let x2 = x * x;
    let mut term = x;
    let mut sum = x;
    let mut k = 0.0;
    while term > sum * 1e-17 {
        k += 1.0;
        term *= 2.0 * x2 / (2.0 * k + 1.0);
        sum += term;
    }
    (2.0 / std::f64::consts::PI.sqrt() * (-x2).exp() * sum).min(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erf_matches_tabulated_values() {
        // Abramowitz & Stegun table 7.1, and erf(1) to 16 digits.
        for (x, want) in [
            (0.0, 0.0),
            (0.1, 0.112_462_916_018_284_9),
            (0.5, 0.520_499_877_813_046_5),
            (1.0, 0.842_700_792_949_714_9),
            (2.0, 0.995_322_265_018_952_7),
            (3.0, 0.999_977_909_503_001_4),
        ] {
            assert!((erf(x) - want).abs() < 1e-15, "erf({x}) = {}", erf(x));
            assert!((erf(-x) + want).abs() < 1e-15);
        }
        assert_eq!(erf(7.0), 1.0);
    }

    #[test]
    fn scalar_case_is_rounding_success() {
        // One ambiguity with sigma 0.25 cycle: P(|e| < 1/2) = 2 Phi(2) - 1 = erf(sqrt 2).
        let q = DMatrix::from_element(1, 1, 0.0625);
        let p = bootstrap_success_rate(&q).unwrap();
        assert!((p - 0.954_499_736_103_641_6).abs() < 1e-15);
    }

    #[test]
    fn independent_ambiguities_multiply() {
        let q = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![0.0625, 0.01, 0.04]));
        let want =
            erf(0.5 / (0.125f64).sqrt()) * erf(0.5 / 0.02f64.sqrt()) * erf(0.5 / 0.08f64.sqrt());
        assert!((bootstrap_success_rate(&q).unwrap() - want).abs() < 1e-15);
    }
}
