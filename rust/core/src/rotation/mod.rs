//! Rotation utilities: direction-cosine matrices, quaternions and Euler sequences.
//!
//! Convention (see `docs/conventions.md`): a matrix named `dcm_<to>_from_<from>` maps the coordinates of a
//! vector in frame `<from>` to its coordinates in frame `<to>`; rotations are *active* maps of body vectors
//! into the reference frame, exactly like `scipy.spatial.transform.Rotation.apply`.

pub mod dcm;
pub mod euler;
pub mod quaternion;

pub use dcm::{check_rotation, elementary, nearest_rotation};
pub use euler::{Axis, EulerSeq};
