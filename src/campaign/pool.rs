//! A bounded pool of whole runs: at most `concurrent` jobs at a time, each worker running jobs one after
//! another on its own single-thread rayon pool, results in job order. Campaigns run through it, and so do
//! the `satflock validate` reports' seeds.
//!
//! Small swarms (a few to a few tens of satellites) are too few for the engine's per-step parallelism to
//! pay, so a batch of runs (seeds, cases) is spread over the cores by run instead. A rayon `par_iter`
//! over the runs would not bound the concurrency (a worker waiting in another pool's `install` steals
//! and starts further runs) and would let each run's inner parallel loops use several threads; here
//! every job sees exactly one rayon thread, so its result does not depend on `concurrent` (given a job
//! function that is deterministic on one thread, as the engine is).

use std::sync::Mutex;

use thiserror::Error;

/// The pool could not start a worker.
#[derive(Debug, Error)]
#[error("run pool: could not build a worker's single-thread pool: {message}")]
pub struct PoolError {
    /// The thread-pool builder's message.
    pub message: String,
}

/// Runs `f` on every job, at most `concurrent` at once (clamped to 1..=jobs), each job inside a
/// single-thread rayon pool owned by its worker. Returns the results in job order.
///
/// A panic in `f` propagates to the caller once the other workers have stopped.
pub fn run_bounded<J, R, F>(jobs: Vec<J>, concurrent: usize, f: F) -> Result<Vec<R>, PoolError>
where
    J: Send,
    R: Send,
    F: Fn(J) -> R + Sync,
{
    let count = jobs.len();
    let workers = concurrent.clamp(1, count.max(1));
    let queue = Mutex::new(jobs.into_iter().enumerate());
    let results: Mutex<Vec<Option<R>>> = Mutex::new((0..count).map(|_| None).collect());
    let error: Mutex<Option<PoolError>> = Mutex::new(None);
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| {
                let pool = match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
                    Ok(pool) => pool,
                    Err(e) => {
                        error
                            .lock()
                            .expect("pool error lock")
                            .get_or_insert(PoolError {
                                message: e.to_string(),
                            });
                        return;
                    }
                };
                loop {
                    let next = queue.lock().expect("pool queue lock").next();
                    let Some((i, job)) = next else {
                        break;
                    };
                    let r = pool.install(|| f(job));
                    results.lock().expect("pool results lock")[i] = Some(r);
                }
            });
        }
    });
    if let Some(e) = error.into_inner().expect("pool error lock") {
        // Another worker may have run every job; a result is missing only if none could start.
        let results = results.into_inner().expect("pool results lock");
        return if results.iter().all(Option::is_some) {
            Ok(results.into_iter().flatten().collect())
        } else {
            Err(e)
        };
    }
    Ok(results
        .into_inner()
        .expect("pool results lock")
        .into_iter()
        .map(|r| r.expect("every job ran: the queue was drained by a live worker"))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A job whose result depends on the rayon thread count it runs under and on a parallel reduction
    /// (a float sum whose grouping follows the thread count), so any leak of the outer pool shows.
    fn job(k: u64) -> (u64, usize, f64) {
        use rayon::prelude::*;
        let sum: f64 = (0..20_000u64)
            .into_par_iter()
            .map(|i| ((i * 7919 + k) as f64).sqrt().sin() * 1e-3)
            .sum();
        (k, rayon::current_num_threads(), sum)
    }

    #[test]
    fn preserves_job_order() {
        let jobs: Vec<u64> = (0..23).rev().collect();
        let out = run_bounded(jobs.clone(), 3, |k| {
            // Uneven durations so workers finish out of order.
            std::thread::sleep(std::time::Duration::from_millis(k % 4));
            k * 10
        })
        .unwrap();
        assert_eq!(out, jobs.iter().map(|k| k * 10).collect::<Vec<_>>());
    }

    #[test]
    fn results_do_not_depend_on_concurrency() {
        let jobs: Vec<u64> = (0..8).collect();
        let one = run_bounded(jobs.clone(), 1, job).unwrap();
        let two = run_bounded(jobs.clone(), 2, job).unwrap();
        assert_eq!(one.len(), 8);
        for (a, b) in one.iter().zip(&two) {
            assert_eq!(a.0, b.0);
            // Each job sees exactly one rayon thread, whatever the pool size.
            assert_eq!(a.1, 1);
            assert_eq!(b.1, 1);
            assert_eq!(a.2.to_bits(), b.2.to_bits());
        }
    }

    #[test]
    fn empty_and_oversized_concurrency() {
        let none: Vec<u32> = run_bounded(Vec::<u32>::new(), 4, |k| k).unwrap();
        assert!(none.is_empty());
        let out = run_bounded(vec![5u32, 6], 0, |k| k + 1).unwrap();
        assert_eq!(out, vec![6, 7]);
        let out = run_bounded(vec![5u32, 6], 64, |k| k + 1).unwrap();
        assert_eq!(out, vec![6, 7]);
    }
}
