//! (to be written: see gnss/mod.rs)
