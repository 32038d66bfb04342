//! The thread pool every parallel core call runs on, rebuilt in a forked child.
//!
//! rayon's global pool is a process-wide static whose worker threads a `fork` does not copy: a child
//! forked after the parent ran a parallel call (a `ProcessPoolExecutor` with the `fork` start method,
//! Python's default on Linux before 3.14) would queue its first parallel job on threads that do not exist
//! and wait forever. The bindings therefore run their work inside [`install`], on a pool owned by the
//! process that built it: a process whose id differs from the builder's (a forked child) builds its own.
//! Nested rayon calls in the core (`par_iter` inside `install`) use the installed pool.

use std::sync::{Arc, Mutex, PoisonError};

use rayon::{ThreadPool, ThreadPoolBuilder};

/// The pool of the process that built it, with that process's id.
static POOL: Mutex<Option<(u32, Arc<ThreadPool>)>> = Mutex::new(None);

/// The current process's pool, built on first use (and again after a fork); None where the OS refuses
/// the threads.
fn current() -> Option<Arc<ThreadPool>> {
    let pid = std::process::id();
    // A poisoned lock only means a panic elsewhere while it was held; the value is still consistent.
    let mut slot = POOL.lock().unwrap_or_else(PoisonError::into_inner);
    if let Some((owner, pool)) = slot.as_ref() {
        if *owner == pid {
            return Some(Arc::clone(pool));
        }
    }
    if let Some((_, inherited)) = slot.take() {
        // The parent's pool: its threads are not in this process, so dropping it would signal threads
        // that do not exist. It is leaked instead (one allocation per fork generation).
        std::mem::forget(inherited);
    }
    let pool = Arc::new(
        ThreadPoolBuilder::new()
            .thread_name(|i| format!("gnssatt-{i}"))
            .build()
            .ok()?,
    );
    *slot = Some((pid, Arc::clone(&pool)));
    Some(pool)
}

/// Runs `work` on the current process's pool (its parallel loops included); where the OS refuses the
/// pool's threads, on the calling thread with rayon's global pool.
pub fn install<T: Send>(work: impl FnOnce() -> T + Send) -> T {
    match current() {
        Some(pool) => pool.install(work),
        None => work(),
    }
}
