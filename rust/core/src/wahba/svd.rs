//! Markley's SVD solution of Wahba's problem, with the determinant fixed so the answer is always a proper
//! rotation (the plain polar factor can be a reflection).

use nalgebra::{Matrix3, Rotation3, Vector3, SVD};

use crate::error::{ensure_finite, Error, Result};

/// Singular-value ratio beyond which a direction counts as missing.
pub const RANK_TOLERANCE: f64 = 1e-10;

/// The proper rotation `A` maximising `tr(A^T h)`; equals the polar factor of `h` when `det h > 0`.
///
/// A rank-2 `h` (all vector pairs in one plane) still fixes `A` uniquely: the third axis follows from the
/// determinant constraint.
///
/// # Errors
/// [`Error::DegenerateGeometry`] when `h` has rank below 2 (second singular value below
/// [`RANK_TOLERANCE`] times the first), or [`Error::NonFinite`].
pub fn solve(h: &Matrix3<f64>) -> Result<Matrix3<f64>> {
    ensure_finite("attitude profile matrix", h.iter())?;
    let svd = SVD::new(*h, true, true);
    // Both were requested above; nalgebra returns them then, but a missing one is an error, not a panic.
    let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
        return Err(Error::numerical(
            "Wahba SVD",
            "the decomposition returned no singular vectors",
        ));
    };
    let s = svd.singular_values;
    // nalgebra does not promise an order; sort indices by decreasing singular value.
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| s[b].total_cmp(&s[a]));
    if s[order[1]] <= RANK_TOLERANCE * s[order[0]] {
        return Err(Error::DegenerateGeometry {
            what: "the vector pairs do not fix the attitude (they are all parallel)".into(),
            matrix: "attitude profile matrix",
            condition: s[order[0]] / s[order[1]],
        });
    }
    // Markley's U diag(1, 1, det U det V) V^T, written with the third singular vectors rebuilt as
    // u1 x u2 and v1 x v2 (which makes both triads proper and the determinant factor 1). The two
    // dominant pairs are accurate to rounding relative to their own singular values; nalgebra's third
    // pair is not when the weights span many decades (seen: 0.03 rad error at a 1e8 weight ratio).
    let (u1, u2) = (
        u.column(order[0]).into_owned(),
        u.column(order[1]).into_owned(),
    );
    let (v1, v2) = (v_t.row(order[0]).transpose(), v_t.row(order[1]).transpose());
    let r = u1 * v1.transpose() + u2 * v2.transpose() + u1.cross(&u2) * v1.cross(&v2).transpose();
    Ok(polish(h, r))
}

/// Newton steps on SO(3) for `max tr(R^T h)` from `r`: with `M = R^T h`, `S = sym(M)`, the gain of
/// `R exp([phi]x)` is `tr M + g . phi - phi^T (tr(S) I - S) phi / 2` to second order, with
/// `g = [M32 - M23, M13 - M31, M21 - M12]`. nalgebra's SVD can be far less accurate than the problem's
/// conditioning allows when the weights span many decades (0.03 rad at a 1e8 ratio); three steps bring
/// it to rounding level. Steps that would not help (indefinite Hessian, tiny step) are skipped.
fn polish(h: &Matrix3<f64>, mut r: Matrix3<f64>) -> Matrix3<f64> {
    for _ in 0..3 {
        let m = r.transpose() * h;
        let g = Vector3::new(
            m[(2, 1)] - m[(1, 2)],
            m[(0, 2)] - m[(2, 0)],
            m[(1, 0)] - m[(0, 1)],
        );
        let sym = (m + m.transpose()) * 0.5;
        let hess = Matrix3::identity() * sym.trace() - sym;
        let Some(chol) = hess.cholesky() else { break };
        let phi = chol.solve(&g);
        if phi.norm().is_nan() || phi.norm() <= 1e-17 {
            break;
        }
        r *= Rotation3::new(phi).into_inner();
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotation::euler::ZYX;

    #[test]
    fn recovers_rotation_from_two_vector_pairs() {
        let a = ZYX.to_dcm([0.3, -1.0, 2.0]);
        let v = [Vector3::new(1.0, 0.2, 0.0), Vector3::new(0.0, 1.0, 0.5)];
        let h: Matrix3<f64> = v.iter().map(|v| (a * v) * v.transpose()).sum();
        assert!((solve(&h).unwrap() - a).norm() < 1e-12);
    }

    #[test]
    fn reflection_is_turned_into_a_rotation() {
        let h = Matrix3::from_diagonal(&Vector3::new(3.0, 2.0, -1.0));
        let r = solve(&h).unwrap();
        assert!((r.determinant() - 1.0).abs() < 1e-12);
        assert!((r - Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 1.0))).norm() < 1e-12);
    }

    #[test]
    fn parallel_pairs_are_degenerate() {
        let v = Vector3::new(0.0, 0.0, 1.0);
        assert!(matches!(
            solve(&(v * v.transpose())),
            Err(Error::DegenerateGeometry { .. })
        ));
    }
}
