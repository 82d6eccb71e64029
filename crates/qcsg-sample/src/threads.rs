//! Worker threads for sampling: a rayon pool whose threads keep to a core each when the pool
//! has as many threads as the process may use cores.
//!
//! A parked worker is woken where the kernel's scheduler places it, and on a virtual machine
//! that is often the core of the thread that woke it while the other core sits idle (a halted
//! virtual core can look preempted rather than idle to the guest): the woken thread waits
//! behind its waker until the load balancer moves it, milliseconds later, and a two-thread run
//! can take as long as one thread (measured in `docs/sampler-benchmarks.md`).
//!
//! Only a pool that spans every core the process may use is pinned: a smaller one leaves the
//! placement to the scheduler, so that several programs running at once, each on a few of the
//! cores, are not all held to the same ones.
//!
//! A sampling run keeps the pool's other threads awake until it ends
//! ([`with_workers_awake`]): between its parallel steps they spin instead of sleeping, so that
//! the next step does not wait for them to wake.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// A builder for a pool of `threads` workers (`0`: rayon's default, one per core), thread `i`
/// kept to the `i`-th core the process may use when the pool has exactly as many threads as
/// there are such cores (and more than one).
pub fn pool_builder(threads: usize) -> rayon::ThreadPoolBuilder {
    let cores = core_affinity::get_core_ids().unwrap_or_default();
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .start_handler(move |index| {
            // The handler runs on the new worker, so this is the pool's own size.
            let spans_all = rayon::current_num_threads() == cores.len();
            if spans_all
                && cores.len() > 1
                && let Some(&core) = cores.get(index)
            {
                // Where the core cannot be set, the thread runs where the scheduler puts it.
                core_affinity::set_for_current(core);
            }
        })
}

/// Runs `work` on the current pool (a thread of it) while the pool's other workers stay awake,
/// taking part in its parallel steps or spinning between them. A worker without work sleeps
/// after a short spin, and is woken when work comes again; a sampling run alternates parallel
/// steps with short serial ones, and on a virtual machine each wake-up took 34 to 55 µs. On two
/// threads a worker slept 7 to 30 times a run (three balls at 1 % of the diagonal, 1.9 ms; the
/// cage, 18 ms); kept awake, 2 to 6 times on most scenes, and the runs' medians fell by 1 to
/// 6 %. Off the pool, or on a pool of one thread, this is `work()`.
pub fn with_workers_awake<R: Send>(work: impl FnOnce() -> R + Send) -> R {
    let others = rayon::current_num_threads().saturating_sub(1);
    if others == 0 || rayon::current_thread_index().is_none() {
        return work();
    }
    let done = AtomicBool::new(false);
    rayon::scope(|scope| {
        // The spinners sit first on this thread's deque, where the others steal them first.
        for _ in 0..others {
            scope.spawn(|_| {
                let mut idle_since = Instant::now();
                while !done.load(Ordering::Acquire) {
                    if rayon::yield_now() == Some(rayon::Yield::Executed) {
                        idle_since = Instant::now();
                    } else if idle_since.elapsed() > MAX_IDLE_SPIN {
                        // A spinner holds up what its thread was doing below it on its stack
                        // (when it was taken up by a thread waiting on other work): it never
                        // does so for long without work.
                        return;
                    } else {
                        std::hint::spin_loop();
                    }
                }
            });
        }
        // Set also when `work` panics: the scope waits for the spinners.
        let _stop = Stop(&done);
        work()
    })
}

/// How long a thread kept awake ([`with_workers_awake`]) spins without work before it leaves
/// the rest of the run to rayon's own sleeping and waking: longer than the serial steps between
/// a sampling run's parallel ones (up to a few tenths of a millisecond), short beside a wait
/// for other work.
const MAX_IDLE_SPIN: Duration = Duration::from_millis(2);

/// Sets its flag when dropped.
struct Stop<'a>(&'a AtomicBool);

impl Drop for Stop<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Release);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cores this thread may run on.
    fn every_core() -> Vec<usize> {
        let ids = core_affinity::get_core_ids().unwrap_or_default();
        ids.iter().map(|c| c.id).collect()
    }

    /// The cores each worker of a pool of `threads` may run on, in worker order.
    fn allowed_cores(threads: usize) -> Vec<Vec<usize>> {
        let pool = pool_builder(threads).build().expect("thread pool");
        // Broadcast results come in worker order.
        pool.broadcast(|_| every_core())
    }

    #[test]
    fn a_pool_over_every_core_keeps_each_thread_to_its_own() {
        let all = every_core();
        let workers = allowed_cores(all.len());
        if all.len() > 1 {
            let own: Vec<Vec<usize>> = all.iter().map(|&c| vec![c]).collect();
            assert_eq!(workers, own);
        } else {
            assert!(workers.iter().all(|cores| *cores == all));
        }
    }

    #[test]
    fn work_kept_awake_returns_its_result_on_any_pool() {
        let expected: u64 = (0..100_000u64).sum();
        for threads in 1..=3 {
            let pool = pool_builder(threads).build().expect("thread pool");
            let sum = pool.install(|| {
                with_workers_awake(|| {
                    use rayon::prelude::*;
                    (0..100_000u64).into_par_iter().sum::<u64>()
                })
            });
            assert_eq!(sum, expected, "{threads} threads");
        }
        // Off any pool it is the work alone.
        assert_eq!(with_workers_awake(|| 7), 7);
    }

    #[test]
    fn a_panic_in_work_kept_awake_reaches_the_caller() {
        let pool = pool_builder(2).build().expect("thread pool");
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            pool.install(|| with_workers_awake(|| -> u32 { panic!("in the work") }))
        }));
        assert!(
            outcome.is_err(),
            "the spinners would otherwise keep the scope open"
        );
    }

    /// Samplings run from within parallel work: each one's spinners may be taken up by a thread
    /// that waits on another's work, and must not hold it up for good.
    #[test]
    fn work_kept_awake_from_within_parallel_work_ends() {
        use rayon::prelude::*;
        let sum = |k: u64| -> u64 {
            (0..2_000u32)
                .into_par_iter()
                .with_max_len(16)
                .map(|i| u64::from(i) + k)
                .sum()
        };
        for threads in [2, 3, 4] {
            let pool = pool_builder(threads).build().expect("thread pool");
            for _ in 0..500 {
                let sums: Vec<u64> = pool.install(|| {
                    (0..8u64)
                        .into_par_iter()
                        .map(|k| with_workers_awake(|| sum(k)))
                        .collect()
                });
                let expected: Vec<u64> = (0..8u64).map(|k| 1_999_000 + 2_000 * k).collect();
                assert_eq!(sums, expected, "{threads} threads");
            }
        }
    }

    #[test]
    fn a_smaller_pool_is_left_to_the_scheduler() {
        let all = every_core();
        for threads in 1..all.len() {
            assert!(allowed_cores(threads).iter().all(|cores| *cores == all));
        }
    }
}
