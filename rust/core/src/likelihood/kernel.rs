//! The grid kernel: `Z` along a row of heading nodes for one (pitch, roll) pair, in float32 with a
//! polynomial sine/cosine, SIMD across heading nodes.
//!
//! For a row, `w_i = Rz(theta) Rx(phi) r_i` (normal frame) is fixed, and `Ry(psi)` turns only its
//! horizontal part, so every phase is `x_ik(psi) = A_ik + B_ik cos psi + C_ik sin psi` with
//! `A = d_ik + g_U w_U`, `B = g_N w_N + g_E w_E`, `C = g_N w_E - g_E w_N` computed once per row in f64.
//! This replaces the per-node vectors of eq. (19): two multiply-adds per term and node instead of a stored
//! 3-vector and a dot product (see `benches/likelihood.rs`, group `likelihood/precomputed`).

use crate::rotation::{elementary, Axis};

use super::model::Model;

/// Heading nodes processed together; two AVX2 registers of f32 keep both FMA pipes busy.
pub(crate) const LANES: usize = 16;

/// Bound on the absolute error of [`sincos_f32`] against the exact sine and cosine of its f32 argument,
/// for `|x| <= 1e4` rad (checked by a test over 10^6 arguments). The phase itself is rounded to f32 before
/// the call, an extra error of at most `|x| * 2^-22` rad; so each exponential in `Z` is off by at most
/// `SINCOS_ABS_ERROR + |x| * 2^-22`, and `Z` by at most that times the number of terms (about `2e-6 * Z`
/// for the 0.71 m array at L1, `|x| < 25` rad).
pub const SINCOS_ABS_ERROR: f32 = 1e-6;

const FRAC_1_2PI: f32 = 0.159_154_94;
const MAGIC: f32 = 12_582_912.0; // 1.5 * 2^23: adding it rounds to an integer
const P1: f32 = 6.281_25; // 2 pi in three parts (Cody-Waite), P1 exact with 9 bits
const P2: f32 = 1.935_307_2e-3;
const P3: f32 = 1.025_313_2e-11;
// Minimax (Lawson) fits on [-pi, pi]: cos of degree 12 and sin of degree 11, max error 4e-7 in f32.
const C: [f32; 7] = [
    1.0,
    -0.499_999_9,
    4.166_649e-2,
    -1.388_780_8e-3,
    2.476_996_6e-5,
    -2.707_977_6e-7,
    1.724_760_8e-9,
];
const S: [f32; 6] = [
    0.999_999_6,
    -0.166_665_53,
    8.332_408e-3,
    -1.980_874e-4,
    2.699_822_8e-6,
    -2.036_623_1e-8,
];

#[inline(always)]
fn fma<const F: bool>(a: f32, b: f32, c: f32) -> f32 {
    if F {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// Sine and cosine of one f32, branch-free: one reduction to [-pi, pi] (round to the nearest turn) and
/// two polynomials, 18 arithmetic operations; the lane body of the kernel.
#[inline(always)]
fn sincos_lane<const F: bool>(x: f32) -> (f32, f32) {
    let q = fma::<F>(x, FRAC_1_2PI, MAGIC) - MAGIC;
    let r = fma::<F>(-q, P3, fma::<F>(-q, P2, fma::<F>(-q, P1, x)));
    let r2 = r * r;
    let mut c = C[6];
    for &k in C[..6].iter().rev() {
        c = fma::<F>(c, r2, k);
    }
    let mut s = S[5];
    for &k in S[..5].iter().rev() {
        s = fma::<F>(s, r2, k);
    }
    (s * r, c)
}

/// Sine and cosine of `x` with the kernel's polynomial (error bound [`SINCOS_ABS_ERROR`]).
pub fn sincos_f32(x: f32) -> (f32, f32) {
    sincos_lane::<false>(x)
}

/// Per-row coefficients in kernel order: group-major, `groups * members` of each of A, B, C.
pub(crate) struct RowCoef {
    pub a: Vec<f32>,
    pub b: Vec<f32>,
    pub c: Vec<f32>,
    pub members: usize,
    /// Real part each modulus starts from: 0, or 1 for the constant term of antenna 0.
    pub c0: f32,
}

impl RowCoef {
    pub fn new(model: &Model) -> Self {
        let (groups, members) = model.groups();
        let n = groups * members;
        let c0 = match model.grouping {
            super::model::Grouping::PerBaseline => 0.0,
            super::model::Grouping::PerSatellite => 1.0,
        };
        RowCoef {
            a: vec![0.0; n],
            b: vec![0.0; n],
            c: vec![0.0; n],
            members,
            c0,
        }
    }

    /// Fills the coefficients for pitch `theta` and roll `phi` (radians).
    pub fn fill(&mut self, model: &Model, theta: f64, phi: f64) {
        let m = elementary(Axis::Z, theta) * elementary(Axis::X, phi);
        let nt = model.n_terms();
        let per_baseline = model.grouping == super::model::Grouping::PerBaseline;
        for (i, r) in model.baselines.iter().enumerate() {
            let w = m * r;
            for (k, g) in model.g.iter().enumerate() {
                let idx = if per_baseline {
                    i * nt + k
                } else {
                    k * model.n_baselines() + i
                };
                self.a[idx] = (model.d[i * nt + k] + g.y * w.y) as f32;
                self.b[idx] = (g.x * w.x + g.z * w.z) as f32;
                self.c[idx] = (g.x * w.z - g.z * w.x) as f32;
            }
        }
    }
}

#[inline(always)]
fn chunk<const F: bool>(k: &RowCoef, cp: &[f32; LANES], sp: &[f32; LANES], z: &mut [f32; LANES]) {
    *z = [0.0; LANES];
    let per = k.members;
    for ((ag, bg), cg) in
        k.a.chunks_exact(per)
            .zip(k.b.chunks_exact(per))
            .zip(k.c.chunks_exact(per))
    {
        let mut re = [k.c0; LANES];
        let mut im = [0.0f32; LANES];
        for ((&a, &b), &c) in ag.iter().zip(bg).zip(cg) {
            for l in 0..LANES {
                let x = fma::<F>(c, sp[l], fma::<F>(b, cp[l], a));
                let (s, co) = sincos_lane::<F>(x);
                re[l] += co;
                im[l] += s;
            }
        }
        for l in 0..LANES {
            z[l] += fma::<F>(re[l], re[l], im[l] * im[l]).sqrt();
        }
    }
}

#[inline(always)]
fn row<const F: bool>(k: &RowCoef, cps: &[f32], sps: &[f32], out: &mut [f32]) {
    let mut z = [0.0f32; LANES];
    for ((cp, sp), o) in cps
        .chunks_exact(LANES)
        .zip(sps.chunks_exact(LANES))
        .zip(out.chunks_mut(LANES))
    {
        let cp: &[f32; LANES] = cp.try_into().expect("chunks_exact");
        let sp: &[f32; LANES] = sp.try_into().expect("chunks_exact");
        chunk::<F>(k, cp, sp, &mut z);
        o.copy_from_slice(&z[..o.len()]);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn row_avx2(k: &RowCoef, cps: &[f32], sps: &[f32], out: &mut [f32]) {
    row::<true>(k, cps, sps, out)
}

/// `Z` at heading nodes with cosines `cps` and sines `sps` (padded to a multiple of [`LANES`]), written to
/// `out` (`out.len() <= cps.len()`). Uses AVX2+FMA when the CPU has them (the same code path for every
/// call, so a cell evaluated alone equals the same cell in a full pass bit for bit).
pub(crate) fn eval_row(k: &RowCoef, cps: &[f32], sps: &[f32], out: &mut [f32]) {
    debug_assert!(
        cps.len().is_multiple_of(LANES) && sps.len() == cps.len() && out.len() <= cps.len()
    );
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU supports the features the function is compiled for.
        unsafe { row_avx2(k, cps, sps, out) };
        return;
    }
    row::<false>(k, cps, sps, out)
}

/// Cosines and sines of heading angles as padded f32 tables for [`eval_row`].
pub(crate) fn heading_tables(angles: impl Iterator<Item = f64>) -> (Vec<f32>, Vec<f32>) {
    let (mut c, mut s): (Vec<f32>, Vec<f32>) =
        angles.map(|a| (a.cos() as f32, a.sin() as f32)).unzip();
    let n = c.len().div_ceil(LANES) * LANES;
    c.resize(n, 1.0);
    s.resize(n, 0.0);
    (c, s)
}

/// Largest phase magnitude the kernel's error analysis covers (the range [`SINCOS_ABS_ERROR`] is checked
/// over), radians.
pub(crate) const MAX_KERNEL_PHASE: f64 = 1e4;

/// Bound on `|Z_kernel - Z|` at any cell: the float32 kernel against the exact statistic at the same
/// node angles (f64 inputs), or `None` when a phase may exceed [`MAX_KERNEL_PHASE`].
///
/// Per term, with `X = |A| + |B| + |C| <= pi + 3 |g_k| |r_i|` (|d| <= pi): rounding A, B, C and the
/// heading tables to f32 and the two fused multiply-adds give a phase error of at most `5 * 2^-24 X`;
/// the polynomial adds `SINCOS_ABS_ERROR` to each of cosine and sine (`sqrt 2` of that to the complex
/// term). Accumulating `n` terms whose partial sums stay below `n + 1` rounds each component by at most
/// `n (n + 1) 2^-24`; the modulus (`fma`, product, square root) is within `3 * 2^-24 (n + 1)`; adding
/// the `G` moduli rounds by at most `G 2^-24 Z_upper`. The bound returned is twice the sum.
pub(crate) fn kernel_margin(model: &Model) -> Option<f64> {
    let eps = f64::from(f32::EPSILON) / 2.0; // 2^-24
    let g_max = model.g.iter().map(|g| g.norm()).fold(0.0, f64::max);
    let x = std::f64::consts::PI + 3.0 * g_max * model.l_max;
    if x > MAX_KERNEL_PHASE {
        return None;
    }
    let (groups, members) = model.groups();
    let (g, n) = (groups as f64, members as f64);
    let per_term = 5.0 * eps * x + std::f64::consts::SQRT_2 * f64::from(SINCOS_ABS_ERROR);
    let per_group =
        n * per_term + std::f64::consts::SQRT_2 * n * (n + 1.0) * eps + 3.0 * eps * (n + 1.0);
    Some(2.0 * (g * per_group + g * eps * model.z_upper()))
}
