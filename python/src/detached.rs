//! Running Rust work off the GIL: on a worker thread (so Python threads go on), on a chosen number of
//! rayon threads, and interruptible by Ctrl-C: the calling thread wakes every 50 ms to let Python handle
//! signals, and on `KeyboardInterrupt` sets the run's cancel flag, waits for the run to stop cleanly
//! (files closed, `summary.json` written) and re-raises it.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

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
    let pool = match threads {
        Some(0) => {
            return Err(PyValueError::new_err(
                "threads = 0 (allowed: an integer >= 1, or None for one per core)",
            ))
        }
        Some(k) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(k)
                .build()
                .map_err(|e| PyValueError::new_err(format!("cannot start {k} threads: {e}")))?,
        ),
        None => None,
    };
    std::thread::scope(|scope| {
        let handle = scope.spawn(move || match &pool {
            Some(pool) => pool.install(work),
            None => work(),
        });
        let mut interrupted: Option<PyErr> = None;
        loop {
            let finished = py.detach(|| {
                let until = std::time::Instant::now() + SIGNAL_POLL;
                while !handle.is_finished() && std::time::Instant::now() < until {
                    std::thread::sleep(Duration::from_millis(2));
                }
                handle.is_finished()
            });
            if finished {
                break;
            }
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
