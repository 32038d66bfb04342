//! Yaw from a magnetometer once pitch and roll are known (an Earth sensor), eq. (3) of Ryzhkov &
//! Golembiovsky with the quadrant resolved.
//!
//! Eq. (1) is `a_body = R_x'(phi) R_y'(theta) R_z'(psi) a_orb` with passive (frame) matrices, so
//! `dcm_orb_from_body = ZYX(psi, theta, phi)` (docs/conventions.md). Its rows give
//! `mu1 = a_x + a_z0 sin(theta) = cos(theta) (a_x0 cos psi + a_y0 sin psi)` and
//! `mu2 = a_z sin(phi) - a_y cos(phi) = a_x0 sin psi - a_y0 cos psi`, whence
//! `sin psi = (mu2 a_x0 cos theta + mu1 a_y0) / (cos theta D)` (the paper's (3)) and
//! `cos psi = (mu1 a_x0 / cos theta - mu2 a_y0) / D`, `D = a_x0^2 + a_y0^2`.

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::error::{ensure_finite, Error, Result};

/// Smallest accepted `|cos(pitch)|`.
pub const COS_PITCH_LIMIT: f64 = 1e-12;
/// Smallest accepted horizontal fraction `sqrt(a_x0^2 + a_y0^2) / |a_orb|` of the reference field.
pub const HORIZONTAL_LIMIT: f64 = 1e-10;

/// Yaw and the two quantities that eq. (3) divides by.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct YawSolution {
    /// Yaw psi in (-pi, pi], radians.
    pub yaw_rad: f64,
    /// `|cos(pitch)|`.
    pub cos_pitch: f64,
    /// `sqrt(a_x0^2 + a_y0^2) / |a_orb|`: the part of the reference field across the yaw axis z0.
    pub horizontal_fraction: f64,
}

/// Yaw psi from the measured body-frame field, the reference (orbital-frame) field, pitch and roll.
///
/// # Arguments
/// * `b_body` - measured field `[a_x, a_y, a_z]` in body axes (any unit, the same as `b_orb`).
/// * `b_orb` - model field `[a_x0, a_y0, a_z0]` in the orbital frame (x along-track, y orbit normal,
///   z radial; docs/conventions.md).
/// * `pitch_rad`, `roll_rad` - theta and phi of the `ZYX` sequence, radians (from the Earth sensor).
///
/// # Errors
/// [`Error::NonFinite`]; [`Error::Degenerate`] naming `cos(pitch)` (at most [`COS_PITCH_LIMIT`]), the
/// horizontal fraction of the reference field (at most [`HORIZONTAL_LIMIT`]) or a zero field.
///
/// Ryzhkov & Golembiovsky, eq. (3), with the companion cosine for atan2.
pub fn yaw_from_magnetometer(
    b_body: &Vector3<f64>,
    b_orb: &Vector3<f64>,
    pitch_rad: f64,
    roll_rad: f64,
) -> Result<YawSolution> {
    ensure_finite("b_body", b_body.iter())?;
    ensure_finite("b_orbital", b_orb.iter())?;
    ensure_finite("pitch and roll", [pitch_rad, roll_rad].iter())?;
    for (name, v) in [("b_body", b_body), ("b_orbital", b_orb)] {
        let n = v.norm();
        if n <= f64::MIN_POSITIVE {
            return Err(Error::Degenerate {
                what: format!("{name} is zero"),
                quantity: "field magnitude",
                value: n,
                limit: f64::MIN_POSITIVE,
            });
        }
    }
    // Eq. (3) is homogeneous in the two fields together: dividing both by their largest component keeps
    // fields near the f64 limit (1e300 nT) from overflowing, and changes nothing else.
    let scale = b_body.amax().max(b_orb.amax());
    let (b_body, b_orb) = (b_body / scale, b_orb / scale);
    let (st, ct) = pitch_rad.sin_cos();
    let (sp, cp) = roll_rad.sin_cos();
    if ct.abs() <= COS_PITCH_LIMIT {
        return Err(Error::Degenerate {
            what: "pitch is +-90 deg, where eq. (3) divides by zero".into(),
            quantity: "|cos(pitch)|",
            value: ct.abs(),
            limit: COS_PITCH_LIMIT,
        });
    }
    let (ax0, ay0, az0) = (b_orb[0], b_orb[1], b_orb[2]);
    let horizontal = ax0.hypot(ay0) / b_orb.norm();
    if horizontal <= HORIZONTAL_LIMIT {
        return Err(Error::Degenerate {
            what: "the reference field is along the yaw axis z0 (a_x0^2 + a_y0^2 vanishes)".into(),
            quantity: "horizontal fraction sqrt(a_x0^2 + a_y0^2) / |a_orb|",
            value: horizontal,
            limit: HORIZONTAL_LIMIT,
        });
    }
    let h1 = (b_body[0] + az0 * st) / ct; // mu1 / cos(theta)
    let mu2 = b_body[2] * sp - b_body[1] * cp;
    let sin_psi = mu2 * ax0 + h1 * ay0;
    let cos_psi = h1 * ax0 - mu2 * ay0;
    Ok(YawSolution {
        yaw_rad: sin_psi.atan2(cos_psi),
        cos_pitch: ct.abs(),
        horizontal_fraction: horizontal,
    })
}

/// [`yaw_from_magnetometer`] for each epoch of equally long slices, in parallel.
///
/// # Errors
/// [`Error::Shape`] for unequal lengths; otherwise those of [`yaw_from_magnetometer`], with the epoch.
pub fn yaw_batch(
    b_body: &[Vector3<f64>],
    b_orb: &[Vector3<f64>],
    pitch_rad: &[f64],
    roll_rad: &[f64],
) -> Result<Vec<YawSolution>> {
    let n = b_body.len();
    if b_orb.len() != n || pitch_rad.len() != n || roll_rad.len() != n {
        return Err(Error::Shape {
            name: "magnetometer yaw inputs",
            expected: format!("{n} of each of b_body, b_orbital, pitch, roll"),
            actual: format!(
                "{n}, {}, {}, {}",
                b_orb.len(),
                pitch_rad.len(),
                roll_rad.len()
            ),
        });
    }
    (0..n)
        .into_par_iter()
        .map(|k| {
            yaw_from_magnetometer(&b_body[k], &b_orb[k], pitch_rad[k], roll_rad[k])
                .map_err(|e| e.at_epoch(k))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotation::euler::ZYX;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn recovers_yaw_in_every_quadrant() {
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        for k in 0..400 {
            let psi = -std::f64::consts::PI
                + (k % 4) as f64 * std::f64::consts::FRAC_PI_2
                + rng.random_range(0.01..1.56);
            let theta = rng.random_range(-1.4..1.4);
            let phi = rng.random_range(-3.1..3.1);
            let b_orb = Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-2.0..2.0),
            );
            let b_body = ZYX.to_dcm([psi, theta, phi]).transpose() * b_orb;
            let s = yaw_from_magnetometer(&b_body, &b_orb, theta, phi).unwrap();
            assert!((s.yaw_rad - psi).abs() < 1e-9, "{psi} vs {}", s.yaw_rad);
        }
    }

    #[test]
    fn degenerate_cases_name_the_quantity() {
        let b = Vector3::new(0.1, 0.2, 1.0);
        let e = yaw_from_magnetometer(&b, &b, std::f64::consts::FRAC_PI_2, 0.0).unwrap_err();
        assert!(e.to_string().contains("cos(pitch)"), "{e}");
        let e = yaw_from_magnetometer(&b, &Vector3::z(), 0.1, 0.0).unwrap_err();
        assert!(e.to_string().contains("horizontal fraction"), "{e}");
    }

    #[test]
    fn fields_near_the_f64_limit_give_the_yaw_of_their_directions() {
        let (psi, theta, phi) = (0.7, 0.2, -0.4);
        let b_orb = Vector3::new(0.3, -0.5, 0.8);
        let b_body = ZYX.to_dcm([psi, theta, phi]).transpose() * b_orb;
        // |b| of 1e300-sized fields overflows; the yaw only depends on their directions.
        let s = yaw_from_magnetometer(&(b_body * 1e300), &(b_orb * 1e300), theta, phi).unwrap();
        assert!((s.yaw_rad - psi).abs() < 1e-12, "{}", s.yaw_rad);
    }
}
