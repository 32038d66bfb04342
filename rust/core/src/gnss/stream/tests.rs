//! The engine's tests on a synthetic session with a known truth ([`simulation`]), one file per concept
//! they check.

mod simulation;

mod attitude;
mod code_noise;
mod fixing;
mod grid;
mod refusals;
mod slips;
mod streaming;
mod systems;
