//! Markley's SVD solution of Wahba's problem, with the determinant fixed so the answer is always a proper
//! rotation (the plain polar factor can be a reflection).

use nalgebra::{Matrix3, SVD};

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
    let (u, v_t) = (svd.u.expect("requested"), svd.v_t.expect("requested"));
    let mut s = svd.singular_values;
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
    let d = (u * v_t).determinant().signum();
    s.fill(1.0);
    s[order[2]] = d;
    Ok(u * Matrix3::from_diagonal(&s) * v_t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotation::euler::ZYX;
    use nalgebra::Vector3;

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
