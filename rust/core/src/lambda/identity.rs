//! The identity check of a decorrelation: `Z^-1 Z = I` in exact integer arithmetic, `D` and `L` finite,
//! and `Z^T Q Z = L^T D L` within [`IDENTITY_TOLERANCE`], formed from the covariance and the exact integer
//! `Z`, independently of the reduction's updates of `L` and `D` (see the module docs of
//! [`super::reduction`]).

use nalgebra::DMatrix;

use super::ldl::{shape_to, Ltdl};
use super::reduction::{replay_into, Reduction, Step, Transformed, IDENTITY_TOLERANCE};
use crate::error::{Error, Result};

/// Checks a reduction of `q`: `Z^-1 Z = I` exactly (on the all-ones vector), `D` positive and finite, `L` finite, and
/// `Z^T Q Z = L^T D L` within [`IDENTITY_TOLERANCE`]; returns the products it formed.
///
/// # Errors
/// [`Error::Numerical`] naming the failed check and its numbers.
pub fn verify(q: &DMatrix<f64>, r: &Reduction) -> Result<Transformed> {
    let mut b = VerifyBuffers::default();
    verify_parts(q, &r.z_f64(), &r.steps, &r.factor, &mut b)?;
    Ok(Transformed {
        qz: b.qz,
        zqz: b.zqz,
    })
}

/// The products and scratch of [`verify_parts`], kept between problems so that a check allocates
/// nothing once they have its size.
#[derive(Debug, Clone, Default)]
pub(crate) struct VerifyBuffers {
    /// `Q Z` and the symmetrised `Z^T Q Z` of the last successful check.
    pub(crate) qz: DMatrix<f64>,
    pub(crate) zqz: DMatrix<f64>,
    zt: DMatrix<f64>,
    za: DMatrix<f64>,
    qa: DMatrix<f64>,
    qa_za: DMatrix<f64>,
    dl: DMatrix<f64>,
    lt: DMatrix<f64>,
    ltdl: DMatrix<f64>,
    bound: Vec<f64>,
    sums: Vec<f64>,
    wide: Vec<i128>,
}

/// [`verify`] of `Z` (`zf`, exact integers as `f64`), its recorded `steps` and the factors, through the
/// buffers `b` (the products land in `b.qz` and `b.zqz`).
pub(crate) fn verify_parts(
    q: &DMatrix<f64>,
    zf: &DMatrix<f64>,
    steps: &[Step],
    factor: &Ltdl,
    b: &mut VerifyBuffers,
) -> Result<()> {
    let n = q.nrows();
    let what = "LAMBDA decorrelation";
    if let Some((i, s)) = inverse_defect_parts(zf, steps, &mut b.sums, &mut b.wide)? {
        return Err(Error::numerical(
            what,
            format!(
                "Z^-1 Z is not the identity: row {i} of Z^-1 Z times the all-ones vector is {s}, not 1, \
                 for dimension {n}"
            ),
        ));
    }
    check_factor_finite(factor)?;
    b.shape_all(n);
    product(q, zf, &mut b.qz);
    // (An explicit transpose sends a large product to the blocked matrix multiplication.)
    zf.transpose_to(&mut b.zt);
    product(&b.zt, &b.qz, &mut b.zqz);
    b.rounding_scale_diagonal(q, zf, factor, n);
    b.ltdl_product(factor, n);
    let (zqz, ltdl) = (&mut b.zqz, &b.ltdl);
    let (ratio, i, j) = worst_gap(zqz, ltdl, &b.bound);
    if ratio.is_nan() || ratio > IDENTITY_TOLERANCE {
        return Err(Error::numerical(
            what,
            format!(
                "Z^T Q Z differs from L^T D L at [{i}, {j}] by {:.3e} (= {ratio:.3e} n eps times the \
                 rounding scale sqrt(B_ii B_jj), B = |Z|^T|Q||Z| + |L|^T D|L|, allowed \
                 {IDENTITY_TOLERANCE}) for dimension {n}, max|Z| = {}",
                (zqz[(i, j)] - ltdl[(i, j)]).abs(),
                max_abs(zf) as i64
            ),
        ));
    }
    symmetrise(zqz, n);
    Ok(())
}

impl VerifyBuffers {
    /// Every product buffer `n x n`, reusing what is allocated.
    fn shape_all(&mut self, n: usize) {
        for m in [
            &mut self.qz,
            &mut self.zqz,
            &mut self.zt,
            &mut self.za,
            &mut self.qa,
            &mut self.qa_za,
            &mut self.dl,
            &mut self.lt,
            &mut self.ltdl,
        ] {
            shape_to(m, n, n);
        }
    }

    /// `self.bound`: the diagonal of the rounding scale `B = |Z|^T |Q| |Z| + |L|^T D |L|` (only the
    /// diagonal is needed), through `self.za`, `self.qa` and `self.qa_za`.
    fn rounding_scale_diagonal(
        &mut self,
        q: &DMatrix<f64>,
        zf: &DMatrix<f64>,
        factor: &Ltdl,
        n: usize,
    ) {
        let Ltdl { l, d } = factor;
        abs_into(zf, &mut self.za);
        abs_into(q, &mut self.qa);
        product(&self.qa, &self.za, &mut self.qa_za);
        let (za, qa_za) = (&self.za, &self.qa_za);
        self.bound.clear();
        self.bound.extend((0..n).map(|k| {
            let bq = za.column(k).dot(&qa_za.column(k));
            let lk = &l.as_slice()[k * n + k..(k + 1) * n];
            let bl: f64 = lk
                .iter()
                .zip(&d.as_slice()[k..])
                .map(|(v, di)| v * v * di)
                .sum();
            bq + bl
        }));
    }

    /// `self.ltdl = L^T D L` of the factor, through `self.dl` and `self.lt`.
    fn ltdl_product(&mut self, factor: &Ltdl, n: usize) {
        let Ltdl { l, d } = factor;
        for j in 0..n {
            for i in 0..n {
                self.dl[(i, j)] = d[i] * l[(i, j)];
            }
        }
        l.transpose_to(&mut self.lt);
        product(&self.lt, &self.dl, &mut self.ltdl);
    }
}

/// Replaces `zqz` (`n x n`) by the mean of it and its transpose, so that the product handed on is
/// exactly symmetric (rounding leaves the two triangles apart in the last bits).
fn symmetrise(zqz: &mut DMatrix<f64>, n: usize) {
    for j in 0..n {
        for i in (j + 1)..n {
            let mean = 0.5 * (zqz[(i, j)] + zqz[(j, i)]);
            zqz[(i, j)] = mean;
            zqz[(j, i)] = mean;
        }
    }
}

/// Largest n whose products `product` forms itself (`mul_into`); above it nalgebra's blocked product
/// is used. Measured by callgrind on `examples/lambda_problems` (instructions per problem against the
/// core before the workspace): the workspace with `mul_into` at every n -26 % at n = 4, -17 % at 6, -3 %
/// at 8, but +1.6 % at 10 and +16 % at 40; with this split -29 %, -18 %, -5 %, -5 % and +1.3 %: above
/// n = 8 the blocked kernels (AVX/FMA chosen at run time) more than pay for the packing buffers they
/// allocate on every call (4 per problem).
pub const OWN_PRODUCT_MAX_N: usize = 8;

/// `out <- a b` (square, one size): [`mul_into`] up to [`OWN_PRODUCT_MAX_N`], else nalgebra's product.
fn product(a: &DMatrix<f64>, b: &DMatrix<f64>, out: &mut DMatrix<f64>) {
    if a.nrows() <= OWN_PRODUCT_MAX_N {
        mul_into(a, b, out);
    } else {
        a.mul_to(b, out);
    }
}

/// `out <- a b` for square matrices of one size, column by column (`out_j = sum_k b_kj a_k`, an axpy per
/// nonzero `b_kj`: `Z` is integer and mostly small, `L` triangular, so many are zero and skipped, which
/// changes no value), allocation-free; the rounding differs from nalgebra's product by a few ulps, far
/// inside the [`IDENTITY_TOLERANCE`] this feeds.
fn mul_into(a: &DMatrix<f64>, b: &DMatrix<f64>, out: &mut DMatrix<f64>) {
    let n = a.nrows();
    let (ad, bd) = (a.as_slice(), b.as_slice());
    for (oc, bc) in out
        .as_mut_slice()
        .chunks_exact_mut(n)
        .zip(bd.chunks_exact(n))
    {
        oc.fill(0.0);
        for (ac, &bkj) in ad.chunks_exact(n).zip(bc) {
            if bkj != 0.0 {
                for (o, &x) in oc.iter_mut().zip(ac) {
                    *o += x * bkj;
                }
            }
        }
    }
}

/// `out <- |m|` elementwise (`out` of the shape of `m`).
fn abs_into(m: &DMatrix<f64>, out: &mut DMatrix<f64>) {
    for (o, v) in out.iter_mut().zip(m.iter()) {
        *o = v.abs();
    }
}

/// `max |m_ij|` (0 for an empty matrix).
fn max_abs(m: &DMatrix<f64>) -> f64 {
    m.iter().fold(0.0f64, |a, v| a.max(v.abs()))
}

/// Refuses a non-positive or non-finite `D` or a non-finite `L`.
fn check_factor_finite(factor: &Ltdl) -> Result<()> {
    let Ltdl { l, d } = factor;
    let n = d.len();
    let what = "LAMBDA decorrelation";
    if let Some(i) = d
        .iter()
        .position(|v| !(v.is_finite() && *v >= f64::MIN_POSITIVE))
    {
        return Err(Error::numerical(
            what,
            format!(
                "conditional variance D[{i}] = {:e} of the decorrelated covariance is not positive and \
                 finite (dimension {n})",
                d[i]
            ),
        ));
    }
    if let Some(i) = l.iter().position(|v| !v.is_finite()) {
        return Err(Error::numerical(
            what,
            format!("L[{}, {}] is not finite (dimension {n})", i % n, i / n),
        ));
    }
    Ok(())
}

/// The largest `|A_ij - B_ij| / (n eps sqrt(s_i s_j))` and where it is; NaN (an overflowed product)
/// is returned at once.
fn worst_gap(a: &DMatrix<f64>, b: &DMatrix<f64>, s: &[f64]) -> (f64, usize, usize) {
    let n = a.nrows();
    let scale = n as f64 * f64::EPSILON;
    let mut worst = (0.0, 0, 0);
    for j in 0..n {
        let (aj, bj) = (a.column(j), b.column(j));
        for i in 0..n {
            let gap = (aj[i] - bj[i]).abs();
            let ratio = if gap == 0.0 {
                0.0
            } else {
                gap / (scale * (s[i] * s[j]).sqrt())
            };
            if ratio.is_nan() {
                return (ratio, i, j);
            }
            if ratio > worst.0 {
                worst = (ratio, i, j);
            }
        }
    }
    worst
}

/// The first entry `(i, value)` where `Z^-1 (Z 1)` differs from the all-ones vector `1`, computed
/// exactly: `Z 1` in `f64` where `n max|Z| < 2^53` (else in `i128`), `Z^-1` by replaying the recorded
/// steps (`S^-1`, first step first).
///
/// `Z` is updated in `f64` while the steps are recorded; this O(n^2 + steps) check confirms that the two
/// agree. It cannot be fooled by one wrong entry of `Z`: with `Z + c e_r e_s^T`,
/// `Z^-1 (Z + c e_r e_s^T) 1 = 1 + c Z^-1 e_r`, not `1` since `Z^-1` is invertible.
///
/// # Errors
/// [`Error::Numerical`] when a value overflows `i128`.
#[cfg(test)]
pub(crate) fn inverse_defect(r: &Reduction, zf: &DMatrix<f64>) -> Result<Option<(usize, i128)>> {
    inverse_defect_parts(zf, &r.steps, &mut Vec::new(), &mut Vec::new())
}

/// `inverse_defect` of `Z` held as `f64` (exact integers of at most 2^52) and its steps, through the
/// buffers `sums` (n) and `wide`.
fn inverse_defect_parts(
    zf: &DMatrix<f64>,
    steps: &[Step],
    sums: &mut Vec<f64>,
    wide: &mut Vec<i128>,
) -> Result<Option<(usize, i128)>> {
    let n = zf.nrows();
    sums.clear();
    if (n as f64) * max_abs(zf) < 9_007_199_254_740_992.0 {
        // Every partial row sum is an integer below 2^53: exact, in any order.
        sums.resize(n, 0.0);
        for col in zf.column_iter() {
            for (acc, &v) in sums.iter_mut().zip(col.iter()) {
                *acc += v;
            }
        }
    } else {
        let mut s = vec![0i128; n];
        for col in zf.column_iter() {
            for (acc, &v) in s.iter_mut().zip(col.iter()) {
                *acc += v as i64 as i128;
            }
        }
        if s.iter().any(|v| v.unsigned_abs() >= 1 << 53) {
            // Z 1 beyond 2^53: Z is far past any decorrelation that MAX_Z_ENTRY lets through.
            return Ok(s
                .iter()
                .position(|v| v.unsigned_abs() >= 1 << 53)
                .map(|i| (i, s[i])));
        }
        sums.extend(s.iter().map(|&v| v as f64));
    }
    // S^-1 = I + mu e_i e_j^T, first step first.
    replay_into(sums, n, steps.iter(), |i, j| (i, j), wide)?;
    Ok(wide.iter().position(|&v| v != 1).map(|i| (i, wide[i])))
}
