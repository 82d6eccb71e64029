//! Worker threads for sampling: a rayon pool whose threads keep to a core each when the pool
//! has as many threads as the process may use cores.
//!
//! A parked worker is woken where the kernel's scheduler places it, and on a virtual machine
//! that is often the core of the thread that woke it while the other core sits idle (a halted
//! virtual core can look preempted rather than idle to the guest): the woken thread waits
//! behind its waker until the load balancer moves it, milliseconds later. On a 2-core virtual
//! machine, 14 to 19 of 90 two-thread runs of a hollowed cube at 1 % of the diagonal took as
//! long as one thread (none with each thread kept to its own core), and `qcsg sample` of it at
//! 0.15 % took 96 ms on one thread, 89 ms on two, and 75 ms on two kept to their cores.
//!
//! Only a pool that spans every core the process may use is pinned: a smaller one leaves the
//! placement to the scheduler, so that several programs running at once, each on a few of the
//! cores, are not all held to the same ones.

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
    fn a_smaller_pool_is_left_to_the_scheduler() {
        let all = every_core();
        for threads in 1..all.len() {
            assert!(allowed_cores(threads).iter().all(|cores| *cores == all));
        }
    }
}
