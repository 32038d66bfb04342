//! TRIAD: the attitude from two vector pairs, the first pair matched exactly (Black, AIAA J. 2 (1964)
//! 1350; Shuster & Oh, J. Guid. Control 4 (1981) 70).

use nalgebra::{Matrix3, Vector3};

use crate::error::{ensure_finite, Error, Result};
use crate::wahba::profile::unit;

/// Smallest accepted sine of the angle between the two vectors (in either frame).
pub const PARALLEL_LIMIT: f64 = 1e-10;

/// TRIAD attitude and the conditioning of its two vector pairs.
#[derive(Debug, Clone, PartialEq)]
pub struct TriadSolution {
    /// Body -> reference rotation matrix; `dcm_ref_from_body * b1/|b1| = r1/|r1|` exactly.
    pub dcm_ref_from_body: Matrix3<f64>,
    /// Sine of the angle between `b1` and `b2` (body frame).
    pub sin_angle_body: f64,
    /// Sine of the angle between `r1` and `r2` (reference frame).
    pub sin_angle_ref: f64,
}

fn frame(
    v1: &Vector3<f64>,
    v2: &Vector3<f64>,
    names: [&'static str; 2],
) -> Result<(Matrix3<f64>, f64)> {
    ensure_finite(names[0], v1.iter())?;
    ensure_finite(names[1], v2.iter())?;
    let t1 = unit(v1, || format!("{} is zero", names[0]))?;
    let u2 = unit(v2, || format!("{} is zero", names[1]))?;
    let cross = t1.cross(&u2);
    let sin = cross.norm();
    if sin <= PARALLEL_LIMIT {
        return Err(Error::Degenerate {
            what: format!("{} and {} are parallel", names[0], names[1]),
            quantity: "sine of the angle between them",
            value: sin,
            limit: PARALLEL_LIMIT,
        });
    }
    let t2 = cross / sin;
    Ok((Matrix3::from_columns(&[t1, t2, t1.cross(&t2)]), sin))
}

/// TRIAD attitude: the rotation taking the body triad `[b1, b1 x b2, b1 x (b1 x b2)]` (normalised) onto
/// the reference triad built the same way from `r1`, `r2`.
///
/// # Arguments
/// * `b1`, `b2` - body-frame vectors (any length, not parallel); `b1` is the more accurate one.
/// * `r1`, `r2` - the same directions in the reference frame.
///
/// # Errors
/// [`Error::NonFinite`]; [`Error::Degenerate`] for a zero vector or a parallel pair (sine of the angle at
/// most [`PARALLEL_LIMIT`]).
///
/// Black (1964); Shuster & Oh (1981).
pub fn triad(
    b1: &Vector3<f64>,
    b2: &Vector3<f64>,
    r1: &Vector3<f64>,
    r2: &Vector3<f64>,
) -> Result<TriadSolution> {
    let (mb, sb) = frame(b1, b2, ["b1", "b2"])?;
    let (mr, sr) = frame(r1, r2, ["r1", "r2"])?;
    Ok(TriadSolution {
        dcm_ref_from_body: mr * mb.transpose(),
        sin_angle_body: sb,
        sin_angle_ref: sr,
    })
}
