//! Wahba's problem: the rotation `A` that maximises `tr(A^T H)` for an attitude profile matrix
//! `H = sum_k w_k u_k v_k^T` (vectors `v_k` in the "from" frame, `u_k` in the "to" frame).
//! Wahba, SIAM Review 7 (1965) 409; SVD solution by Markley, J. Astronaut. Sci. 36 (1988) 245;
//! Davenport's q-method and QUEST (Shuster & Oh, J. Guid. Control 4 (1981) 70); TRIAD (Black 1964,
//! Shuster & Oh 1981). Review: Markley & Mortari, J. Astronaut. Sci. 48 (2000) 359.
//!
//! The attitude estimators here take body vectors `b_i` and reference vectors `r_i` and return
//! `dcm_ref_from_body`, the active rotation with `r_i ~ dcm_ref_from_body * b_i` (docs/conventions.md).

pub mod batch;
pub mod davenport;
pub mod profile;
pub mod quest;
pub mod svd;
pub mod triad;

pub use batch::{solve_batch, triad_batch};
pub use profile::{solve, Method, Solution};
pub use triad::{triad, TriadSolution};

#[cfg(test)]
mod tests;
