//! Wahba's problem: the rotation `A` that maximises `tr(A^T H)` for an attitude profile matrix
//! `H = sum_k w_k u_k v_k^T` (vectors `v_k` in the "from" frame, `u_k` in the "to" frame).
//! Wahba, SIAM Review 7 (1965) 409; SVD solution by Markley, J. Astronaut. Sci. 36 (1988) 245.

pub mod svd;
