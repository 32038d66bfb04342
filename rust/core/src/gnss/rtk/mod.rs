//! Double differences, float solution and integer fixing (to be written).
