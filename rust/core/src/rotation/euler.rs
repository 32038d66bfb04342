//! Euler angle sequences. One type covers every sequence used by the source papers:
//! all are *intrinsic* (each rotation about an axis of the already-rotated frame) and give the active
//! body-to-reference matrix `R = R_a1(angle1) R_a2(angle2) R_a3(angle3)`, the same as scipy's
//! `Rotation.from_euler("<A1><A2><A3>", angles)` with upper-case (intrinsic) axes.

use std::fmt;

use nalgebra::Matrix3;

use crate::error::{Error, Result};
use crate::rotation::dcm::elementary;

/// A coordinate axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    X = 0,
    Y = 1,
    Z = 2,
}

impl Axis {
    fn index(self) -> usize {
        self as usize
    }

    fn from_char(c: char) -> Option<Axis> {
        match c {
            'X' => Some(Axis::X),
            'Y' => Some(Axis::Y),
            'Z' => Some(Axis::Z),
            _ => None,
        }
    }
}

/// An intrinsic three-axis Euler sequence, Tait-Bryan (`ZYX`) or proper (`YZY`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EulerSeq {
    axes: [Axis; 3],
}

/// Heading (yaw) about Z, pitch about Y', roll about X'': Ryzhkov and Oliinyk, Ryzhkov and Holembiovskyi.
pub const ZYX: EulerSeq = EulerSeq {
    axes: [Axis::Z, Axis::Y, Axis::X],
};
/// GOST 20058-80 heading about Y (up), pitch about Z', roll about X'' in the normal frame (North, Up,
/// East): Bunyaeva et al., eq. (5).
pub const YZX: EulerSeq = EulerSeq {
    axes: [Axis::Y, Axis::Z, Axis::X],
};
/// Precession about Y0, attack about Z0', spin about Y0'': Belokonov et al..
pub const YZY: EulerSeq = EulerSeq {
    axes: [Axis::Y, Axis::Z, Axis::Y],
};

impl EulerSeq {
    /// Parses a sequence such as `"ZYX"` (upper case, always intrinsic: scipy reads lower case as
    /// extrinsic, which this is not).
    ///
    /// # Errors
    /// [`Error::OutOfRange`] unless three axes with no two consecutive ones equal.
    pub fn parse(seq: &str) -> Result<Self> {
        let bad = || {
            Error::out_of_range(
                "seq",
                format!(
                    "expected three axes from X, Y, Z with no two consecutive equal, got {seq:?}"
                ),
            )
        };
        let axes: Vec<Axis> = seq
            .chars()
            .map(Axis::from_char)
            .collect::<Option<_>>()
            .ok_or_else(bad)?;
        if axes.len() != 3 || axes[0] == axes[1] || axes[1] == axes[2] {
            return Err(bad());
        }
        Ok(EulerSeq {
            axes: [axes[0], axes[1], axes[2]],
        })
    }

    /// The active body-to-reference matrix for angles in radians.
    pub fn to_dcm(&self, angles_rad: [f64; 3]) -> Matrix3<f64> {
        elementary(self.axes[0], angles_rad[0])
            * elementary(self.axes[1], angles_rad[1])
            * elementary(self.axes[2], angles_rad[2])
    }

    /// Angles in radians of a proper rotation matrix. The first and third are in (-pi, pi]; the second in
    /// [-pi/2, pi/2] for Tait-Bryan sequences and [0, pi] for proper ones. At gimbal lock the third angle
    /// is set to zero and the first carries the whole rotation, as scipy does.
    pub fn from_dcm(&self, m: &Matrix3<f64>) -> [f64; 3] {
        let (i, j) = (self.axes[0].index(), self.axes[1].index());
        let proper = self.axes[0] == self.axes[2];
        let k = 3 - i - j;
        // Sign of the permutation (i, j, k): +1 when cyclic.
        let s = if (j + 3 - i) % 3 == 1 { 1.0 } else { -1.0 };
        const LOCK: f64 = 1e-9;
        let (b, c) = if proper {
            let b = m[(i, i)].clamp(-1.0, 1.0).acos();
            let locked = b.sin().abs() < LOCK;
            (
                b,
                if locked {
                    0.0
                } else {
                    m[(i, j)].atan2(s * m[(i, k)])
                },
            )
        } else {
            let b = (s * m[(i, k)]).clamp(-1.0, 1.0).asin();
            let locked = b.cos().abs() < LOCK;
            (
                b,
                if locked {
                    0.0
                } else {
                    (-s * m[(i, j)]).atan2(m[(i, i)])
                },
            )
        };
        // Whatever is left is a rotation about the first axis; reading it off the remainder keeps
        // gimbal lock and the regular case on one code path.
        let rest =
            m * elementary(self.axes[2], c).transpose() * elementary(self.axes[1], b).transpose();
        let (p, q) = ((i + 1) % 3, (i + 2) % 3);
        let a = rest[(q, p)].atan2(rest[(p, p)]);
        [a, b, c]
    }
}

impl fmt::Display for EulerSeq {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for a in self.axes {
            write!(f, "{a:?}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [&str; 12] = [
        "XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX", "XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ",
    ];

    #[test]
    fn round_trip_every_sequence() {
        let angles = [0.7, -0.4, 2.5];
        for name in ALL {
            let seq = EulerSeq::parse(name).unwrap();
            let mid = if seq.axes[0] == seq.axes[2] {
                1.1
            } else {
                angles[1]
            };
            let a = [angles[0], mid, angles[2]];
            let back = seq.from_dcm(&seq.to_dcm(a));
            for (x, y) in a.iter().zip(back) {
                assert!((x - y).abs() < 1e-12, "{name}: {a:?} -> {back:?}");
            }
        }
    }

    #[test]
    fn gimbal_lock_reproduces_the_matrix() {
        for name in ALL {
            let seq = EulerSeq::parse(name).unwrap();
            let mid = if seq.axes[0] == seq.axes[2] {
                0.0
            } else {
                std::f64::consts::FRAC_PI_2
            };
            let m = seq.to_dcm([0.3, mid, 0.5]);
            let back = seq.to_dcm(seq.from_dcm(&m));
            assert!((m - back).norm() < 1e-9, "{name}");
        }
    }

    #[test]
    fn zyx_is_yaw_pitch_roll() {
        // Yaw of +90 deg turns body x (nose) onto reference y.
        let m = ZYX.to_dcm([std::f64::consts::FRAC_PI_2, 0.0, 0.0]);
        let nose = m * nalgebra::Vector3::x();
        assert!((nose - nalgebra::Vector3::y()).norm() < 1e-15);
    }

    #[test]
    fn bad_sequences_are_rejected() {
        for bad in ["ZZX", "XY", "ABC", "XYZX", "zyx", "Zyx"] {
            assert!(EulerSeq::parse(bad).is_err(), "{bad}");
        }
    }
}
