//! GLONASS FDMA double differences: signals of one slot have per-satellite wavelengths
//! `lambda_k = c / (f0 + k df)`, so the double-differenced phase in metres keeps a term of the reference
//! satellite's single-difference ambiguity:
//!
//! `lambda_k phi_k - lambda_r phi_r = DD rho + lambda_k (N_k - N_r) + (lambda_k - lambda_r) N_r`.
//!
//! `N_k - N_r` is the integer that LAMBDA fixes; `N_r` is a float unknown of its own (one per reference
//! arc), determined by the reference's single-difference phase minus code `lambda_r phi_r - P_r =
//! lambda_r N_r + e`, a row that shares the reference's single differences with the double differences and
//! enters with its exact covariance ([`super::dd::covariance`]). This is the parametrisation RTKLIB uses
//! for receivers of one make (single-difference ambiguity states started from code).
//!
//! Assumption: no inter-frequency bias between the two receivers' GLONASS phases and codes (identical
//! receivers, antennas and firmware). A bias common to all channels is absorbed by `N_r`; one that
//! varies with the channel number is not modelled and may cause wrong fixes with mixed receivers.

/// Coefficient of the reference's single-difference ambiguity (cycles) in member `k`'s double-differenced
/// phase (m): `lambda_k - lambda_r`.
pub fn reference_coefficient(lambda_k_m: f64, lambda_r_m: f64) -> f64 {
    lambda_k_m - lambda_r_m
}

/// Coefficient of the reference's single-difference ambiguity in its phase-minus-code row (m): `lambda_r`.
pub fn code_row_coefficient(lambda_r_m: f64) -> f64 {
    lambda_r_m
}
