//! Attitude mode (to be written).
use super::{AttitudeSolution, DdEpoch, FixOptions};
use crate::error::{Error, Result};

pub fn solve_attitude(
    _epochs: &[DdEpoch],
    _body_m: &[[f64; 3]],
    _fix: &FixOptions,
) -> Result<AttitudeSolution> {
    Err(Error::numerical("solve_attitude", "not yet"))
}
