//! Float-ambiguity covariances of a realistic GNSS geometry, for the LAMBDA benches and tests: a short
//! static baseline (no atmosphere left in the double differences), double-differenced carrier phase and
//! code on one to three frequencies over a few epochs, satellites moving slowly across the sky. The
//! float solution estimates the baseline (3) and the `(satellites - 1) x frequencies` DD ambiguities
//! (cycles); the returned matrix is the ambiguity block of its covariance.

use nalgebra::{DMatrix, DVector, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Carrier wavelengths, metres: GPS L1, L2, L5.
pub const WAVELENGTHS_M: [f64; 3] = [
    0.190_293_672_798_365,
    0.244_210_213_424_568,
    0.254_828_048_790_854,
];

/// A float single-baseline solution's setting.
#[derive(Debug, Clone, Copy)]
pub struct Geometry {
    pub satellites: usize,
    pub frequencies: usize,
    pub epochs: usize,
    pub interval_s: f64,
    /// Zenith standard deviation of undifferenced phase, metres.
    pub sigma_phase_m: f64,
    /// Zenith standard deviation of undifferenced code, metres.
    pub sigma_code_m: f64,
}

impl Geometry {
    /// The setting used for `n` ambiguities in the benches: one frequency up to 10 ambiguities, two above
    /// (n must then be even), 5 epochs 2 s apart, 3 mm phase and 30 cm code at zenith.
    pub fn for_ambiguities(n: usize) -> Geometry {
        let frequencies = if n <= 10 { 1 } else { 2 };
        Geometry {
            satellites: n / frequencies + 1,
            frequencies,
            epochs: 5,
            interval_s: 2.0,
            sigma_phase_m: 0.003,
            sigma_code_m: 0.3,
        }
    }

    /// Number of DD ambiguities.
    pub fn ambiguities(&self) -> usize {
        (self.satellites - 1) * self.frequencies
    }

    /// Unit line of sight (east, north, up) of satellite `j` at time `t_s`, and its elevation.
    fn line_of_sight(j: usize, t_s: f64) -> (Vector3<f64>, f64) {
        let az = 2.399_963 * j as f64 + 1.0e-4 * t_s; // golden-angle spread, ~0.35 deg/min drift
        let frac = (0.618_034 * j as f64).fract();
        let sign = if j.is_multiple_of(2) { 1.0 } else { -1.0 };
        let el = (15.0 + 70.0 * frac).to_radians() + sign * 5.0e-5 * t_s;
        let (se, ce) = el.sin_cos();
        (Vector3::new(ce * az.sin(), ce * az.cos(), se), el)
    }

    /// The ambiguity block of the float solution's covariance, cycles^2 (n x n).
    pub fn float_covariance(&self) -> DMatrix<f64> {
        let s = self.satellites;
        let m = s - 1;
        let n = self.ambiguities();
        let mut normal = DMatrix::<f64>::zeros(3 + n, 3 + n);
        for e in 0..self.epochs {
            let t = e as f64 * self.interval_s;
            let sky: Vec<_> = (0..s).map(|j| Self::line_of_sight(j, t)).collect();
            // The reference satellite is the highest one.
            let r = (0..s)
                .max_by(|&a, &b| sky[a].1.total_cmp(&sky[b].1))
                .unwrap_or(0);
            let others: Vec<usize> = (0..s).filter(|&j| j != r).collect();
            // Between-receiver single differences have variance 2 sigma^2 / sin^2(el).
            let var = |j: usize, sigma: f64| 2.0 * (sigma / sky[j].1.sin()).powi(2);
            let dd_cov = |sigma: f64| {
                DMatrix::from_fn(m, m, |i, k| {
                    var(r, sigma) + if i == k { var(others[i], sigma) } else { 0.0 }
                })
            };
            let g = DMatrix::from_fn(m, 3, |i, c| sky[others[i]].0[c] - sky[r].0[c]);
            let w_code = dd_cov(self.sigma_code_m)
                .try_inverse()
                .expect("positive definite");
            for (f, &lambda) in WAVELENGTHS_M.iter().enumerate().take(self.frequencies) {
                // Phase in cycles: g . b / lambda + N; its covariance in cycles^2.
                let w_phase = (dd_cov(self.sigma_phase_m) / (lambda * lambda))
                    .try_inverse()
                    .expect("positive definite");
                let mut a = DMatrix::<f64>::zeros(m, 3 + n);
                a.view_mut((0, 0), (m, 3)).copy_from(&(&g / lambda));
                a.view_mut((0, 3 + f * m), (m, m)).fill_diagonal(1.0);
                normal += a.transpose() * &w_phase * &a;
                let mut c = DMatrix::<f64>::zeros(m, 3 + n);
                c.view_mut((0, 0), (m, 3)).copy_from(&g);
                normal += c.transpose() * &w_code * &c;
            }
        }
        let cov = normal
            .cholesky()
            .expect("observable float solution")
            .inverse();
        let q = cov.view((3, 3), (n, n)).into_owned();
        (&q + q.transpose()) * 0.5
    }

    /// `draws` float ambiguity vectors `N + e`, `e ~ N(0, Q)`, integers `N` in [-1e6, 1e6], seeded.
    pub fn float_draws(&self, q: &DMatrix<f64>, draws: usize, seed: u64) -> Vec<DVector<f64>> {
        let chol = q.clone().cholesky().expect("positive definite");
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        (0..draws)
            .map(|_| {
                let w = DVector::from_fn(q.nrows(), |_, _| {
                    let u1: f64 = 1.0 - rng.random::<f64>();
                    let u2: f64 = rng.random();
                    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
                });
                let truth =
                    DVector::from_fn(q.nrows(), |_, _| (rng.random::<f64>() * 2e6 - 1e6).round());
                truth + chol.l() * w
            })
            .collect()
    }
}
