//! Cooperative interruption of long computations (Ctrl-C from Python).
//!
//! The core has no signal handling of its own: a binding that runs a long call sets the process-wide flag
//! with [`request`] when the user interrupts, the loops of the core poll it with [`check`] between chunks
//! of work (a relaxed atomic load, a few nanoseconds) and return [`Error::Interrupted`], and the binding
//! clears it with [`clear`] once the call has stopped. The flag is process-wide on purpose: Ctrl-C stops
//! every gnssatt computation running in the process, whichever thread started it.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::{Error, Result};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Work between two polls of the flag in the integrators' inner loops (steps, samples): about a
/// millisecond at most of any of them, so an interrupt is seen at once while the poll costs nothing.
pub const POLL_EVERY: usize = 1024;

/// Asks every running computation to stop at its next [`check`].
pub fn request() {
    REQUESTED.store(true, Ordering::Relaxed);
}

/// Withdraws the request (after the interrupted call returned).
pub fn clear() {
    REQUESTED.store(false, Ordering::Relaxed);
}

/// Whether a stop was requested.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// Returns [`Error::Interrupted`] naming `what` if a stop was requested.
///
/// # Errors
/// [`Error::Interrupted`] after [`request`] and before [`clear`].
#[inline]
pub fn check(what: &'static str) -> Result<()> {
    if requested() {
        Err(Error::Interrupted { what })
    } else {
        Ok(())
    }
}

/// [`check`] on every [`POLL_EVERY`]-th value of a loop counter `i`.
///
/// # Errors
/// As [`check`].
#[inline]
pub fn check_every(i: usize, what: &'static str) -> Result<()> {
    if i.is_multiple_of(POLL_EVERY) {
        check(what)
    } else {
        Ok(())
    }
}

// Tested in `rust/core/tests/interrupt.rs`, a process of its own: the flag is process-wide, and unit tests
// of the long loops run in parallel threads of one process.
