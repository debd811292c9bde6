//! Running Rust work off the GIL: on a worker thread (so Python threads go on), on a chosen number of
//! rayon threads, and interruptible by Ctrl-C: the calling thread sleeps until the work is done (woken
//! by it), waking every 50 ms to let Python handle signals; on `KeyboardInterrupt` it sets the run's
//! cancel flag, waits for the run to stop cleanly (files closed, `summary.json` written) and re-raises
//! it.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyInt};

/// How often the waiting thread lets Python handle signals.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Runs `work` with the GIL released on `threads` rayon threads (`None`: the global pool, one thread
/// per core), stopping it through `cancel` on Ctrl-C (see the module documentation).
pub fn run_detached<T: Send>(
    py: Python<'_>,
    threads: Option<usize>,
    cancel: &Arc<AtomicBool>,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    run_in_pool(py, thread_pool(threads)?.as_ref(), cancel, work)
}

/// Most rayon threads a `threads` argument accepts (as `satflock run --threads`).
pub const MAX_THREADS: usize = 1024;

/// A `threads` argument: None, or an int from 1 to [`MAX_THREADS`]. A bool, a float, a str … is a
/// `TypeError` and an int out of range a `ValueError`, both naming `threads` and the allowed range.
pub fn threads_argument(threads: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
    let allowed = format!("allowed: an int from 1 to {MAX_THREADS}, or None for one per core");
    let Some(value) = threads.filter(|t| !t.is_none()) else {
        return Ok(None);
    };
    if value.is_instance_of::<PyBool>() || !value.is_instance_of::<PyInt>() {
        return Err(PyTypeError::new_err(format!(
            "threads = {} is a {} ({allowed})",
            value.repr().map_or_else(|_| "?".into(), |r| r.to_string()),
            value
                .get_type()
                .name()
                .map_or_else(|_| "?".into(), |n| n.to_string())
        )));
    }
    match value.extract::<i64>() {
        Ok(k) if (1..=MAX_THREADS as i64).contains(&k) => Ok(Some(k as usize)),
        _ => Err(PyValueError::new_err(format!(
            "threads = {value} ({allowed})"
        ))),
    }
}

/// A rayon pool of `threads` threads (`None`: none, the global pool is used); for callers that run many
/// short pieces of work on the same threads ([`run_in_pool`]).
pub fn thread_pool(threads: Option<usize>) -> PyResult<Option<rayon::ThreadPool>> {
    match threads {
        Some(0) => Err(PyValueError::new_err(
            "threads = 0 (allowed: an integer >= 1, or None for one per core)",
        )),
        Some(k) => rayon::ThreadPoolBuilder::new()
            .num_threads(k)
            .build()
            .map(Some)
            .map_err(|e| PyValueError::new_err(format!("cannot start {k} threads: {e}"))),
        None => Ok(None),
    }
}

/// [`run_detached`] on a pool made by [`thread_pool`] (`None`: the global pool).
pub fn run_in_pool<T: Send>(
    py: Python<'_>,
    pool: Option<&rayon::ThreadPool>,
    cancel: &Arc<AtomicBool>,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let done = &AtomicBool::new(false);
    std::thread::scope(|scope| {
        let waiter = std::thread::current();
        let handle = scope.spawn(move || {
            let value = match pool {
                Some(pool) => pool.install(work),
                None => work(),
            };
            done.store(true, Ordering::Release);
            waiter.unpark();
            value
        });
        // Finished, or the worker panicked (the join below re-raises the panic).
        let finished = || done.load(Ordering::Acquire) || handle.is_finished();
        let mut interrupted: Option<PyErr> = None;
        while !finished() {
            // An unpark between the check and the park makes the park return at once.
            py.detach(|| {
                if !finished() {
                    std::thread::park_timeout(SIGNAL_POLL);
                }
            });
            if interrupted.is_none() {
                if let Err(e) = py.check_signals() {
                    cancel.store(true, Ordering::Relaxed);
                    interrupted = Some(e);
                }
            }
        }
        let result = py.detach(|| handle.join());
        match (interrupted, result) {
            (Some(e), _) => Err(e),
            (None, Ok(value)) => Ok(value),
            (None, Err(panic)) => std::panic::resume_unwind(panic),
        }
    })
}
