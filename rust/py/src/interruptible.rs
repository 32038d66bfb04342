//! Long core calls that Ctrl-C can stop: the work runs on a scoped worker thread while the calling thread,
//! detached from the interpreter, waits for it in short slices and between them re-attaches to run
//! Python's signal handlers. When a handler raises (KeyboardInterrupt from SIGINT), the core's interrupt
//! flag is set, the worker stops at its next poll (`gnssatt_core::interrupt::check`) and the handler's
//! exception is raised once the worker has returned. The work runs on the process's own pool
//! ([`crate::pool`]), which a forked child rebuilds.

use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use gnssatt_core::{interrupt, Error};
use pyo3::prelude::*;

use crate::errors::IntoPyResult;

/// How long the calling thread waits between two signal checks: well under a second of delay for the
/// user, and a negligible cost (one interpreter attach per slice) for the work.
const SLICE: Duration = Duration::from_millis(50);

/// Runs `work` without the interpreter lock, interruptibly; maps its error with the library's classes.
///
/// A panic of the worker is resumed on the calling thread, where the entry point's `#[guard]` turns it
/// into `gnssatt.errors.InternalError`.
pub fn run<T: Send>(py: Python<'_>, work: impl FnOnce() -> Result<T, Error> + Send) -> PyResult<T> {
    let (result, signal) = py.detach(|| {
        std::thread::scope(|scope| {
            let (tx, rx) = mpsc::channel();
            let worker = scope.spawn(move || {
                // The receiver outlives the worker (it is joined below), so the send cannot fail.
                let _ = tx.send(crate::pool::install(work));
            });
            let mut signal: Option<PyErr> = None;
            let result = loop {
                match rx.recv_timeout(SLICE) {
                    Ok(result) => break result,
                    Err(RecvTimeoutError::Timeout) => {
                        if signal.is_none() {
                            if let Err(e) = Python::attach(|py| py.check_signals()) {
                                interrupt::request();
                                signal = Some(e);
                            }
                        }
                    }
                    Err(RecvTimeoutError::Disconnected) => {
                        // The worker ended without sending: it panicked.
                        if signal.is_some() {
                            interrupt::clear();
                        }
                        match worker.join() {
                            Err(payload) => std::panic::resume_unwind(payload),
                            Ok(()) => {
                                break Err(Error::numerical("worker", "ended without a result"))
                            }
                        }
                    }
                }
            };
            if signal.is_some() {
                interrupt::clear();
            }
            (result, signal)
        })
    });
    // The signal handler's exception wins even if the work finished meanwhile: it was raised once and
    // would otherwise be lost.
    match signal {
        Some(e) => Err(e),
        None => result.into_py_result(py),
    }
}
