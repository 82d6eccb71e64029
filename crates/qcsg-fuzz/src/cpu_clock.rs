//! The watchdogs' clock: a stage's budget is the wall time its work would take on an idle
//! machine, with a cap on wall time.
//!
//! On a machine that other work loads (a build beside the fuzzer, ten runnable processes on two
//! cores), a stage waits for a core most of the time, and a wall-clock budget reports a stage
//! that did its work in time as a hang. So a stage hangs when the work the process did since the
//! stage began would take longer than the budget on this machine with nothing else running
//! ([`Work::least_wall`]), or when it ran past [`WALL_FACTOR`] times the budget in wall time
//! whatever its work (a deadlock, or a wait that uses no CPU, ends there). That least wall time
//! is the larger of the busiest thread's CPU time and all threads' CPU time shared out over the
//! cores: each is a lower bound of the wall time the work takes, whatever the load. All threads'
//! CPU time alone would count a stage that keeps two cores busy for 3 s as a 6 s hang. The CPU
//! times are `/proc`'s (`/proc/PID/stat` for the whole process, ended threads included, and
//! `/proc/PID/task/TID/stat` for each live thread); where `/proc` cannot be read the budget is
//! wall time, as before.

use std::time::{Duration, Instant};

use qcsg_testkit::cpu::{cpu_time, thread_cpu_times};

/// How many times its budget a stage may take in wall time while its work stays within it.
pub const WALL_FACTOR: u32 = 4;

/// A watch on one process over one stage.
#[derive(Clone, Debug)]
pub struct Watch {
    pid: u32,
    budget: Duration,
    started: Instant,
    cpu_at_start: Option<Duration>,
    threads_at_start: Vec<(u32, Duration)>,
    cores: u32,
}

/// The CPU time a process used since a watch started.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Work {
    /// All its threads together.
    pub total: Duration,
    /// Its busiest thread that is still running.
    pub busiest: Duration,
    /// The cores of the machine.
    pub cores: u32,
}

impl Work {
    /// The least wall time this work takes on the machine with nothing else running.
    pub fn least_wall(&self) -> Duration {
        self.busiest.max(self.total / self.cores.max(1))
    }
}

/// What a look at the watch says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Within its budget; look again after at most this long.
    Running(Duration),
    /// Over its budget: a hang.
    Over,
}

impl Watch {
    /// Starts watching process `pid` for a stage of this budget.
    pub fn start(pid: u32, budget: Duration) -> Self {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get() as u32);
        Self {
            pid,
            budget,
            started: Instant::now(),
            cpu_at_start: cpu_time(pid),
            threads_at_start: thread_cpu_times(pid).unwrap_or_default(),
            cores,
        }
    }

    /// The CPU time the process used since the watch started, if `/proc` says.
    pub fn work(&self) -> Option<Work> {
        let total = cpu_time(self.pid)?.saturating_sub(self.cpu_at_start?);
        let before = |tid: u32| {
            let at = self
                .threads_at_start
                .binary_search_by_key(&tid, |&(t, _)| t);
            at.map_or(Duration::ZERO, |at| self.threads_at_start[at].1)
        };
        let busiest = (thread_cpu_times(self.pid).unwrap_or_default().into_iter())
            .map(|(tid, now)| now.saturating_sub(before(tid)))
            .max()
            .unwrap_or_default();
        Some(Work {
            total,
            busiest,
            cores: self.cores,
        })
    }

    /// The wall time since the watch started.
    pub fn elapsed(&self) -> Duration {
        self.started.elapsed()
    }

    /// Whether the stage is over its budget now, and if not, when to look again.
    pub fn look(&self) -> Verdict {
        let wall = self.started.elapsed();
        if wall < self.budget {
            return Verdict::Running(self.budget - wall);
        }
        let cap = self.budget * WALL_FACTOR;
        if wall >= cap {
            return Verdict::Over;
        }
        let Some(work) = self.work() else {
            // No `/proc`: wall time is all there is.
            return Verdict::Over;
        };
        let used = work.least_wall();
        if used >= self.budget {
            return Verdict::Over;
        }
        // The work cannot reach the budget sooner than in (budget - used) of wall time; look
        // again soon enough that a stage is not let run long past it, and not later than the cap.
        let next = ((self.budget - used) / 4).max(Duration::from_millis(50));
        Verdict::Running(next.min(cap - wall))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_process_own_cpu_time_grows_with_work() {
        let pid = std::process::id();
        let before = cpu_time(pid).expect("/proc is readable on Linux");
        let started = Instant::now();
        let mut x = 0u64;
        while started.elapsed() < Duration::from_millis(300) {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1);
        }
        std::hint::black_box(x);
        let after = cpu_time(pid).expect("/proc is readable on Linux");
        // Some of the 300 ms may go to other processes on a loaded machine; some is this one's.
        assert!(after > before, "{before:?} then {after:?}");
    }

    #[test]
    fn work_on_every_core_counts_its_wall_time_and_one_thread_all_of_its_own() {
        let shared = Work {
            total: Duration::from_secs(6),
            busiest: Duration::from_secs(3),
            cores: 2,
        };
        assert_eq!(shared.least_wall(), Duration::from_secs(3));
        let alone = Work {
            total: Duration::from_secs(6),
            busiest: Duration::from_secs(6),
            cores: 2,
        };
        assert_eq!(alone.least_wall(), Duration::from_secs(6));
        // Threads that ended took their time with them from the per-thread list, not the total.
        let ended = Work {
            total: Duration::from_secs(8),
            busiest: Duration::ZERO,
            cores: 2,
        };
        assert_eq!(ended.least_wall(), Duration::from_secs(4));
    }

    #[test]
    fn a_spinning_thread_is_the_busiest() {
        let pid = std::process::id();
        let watch = Watch::start(pid, Duration::from_secs(10));
        let started = Instant::now();
        let mut x = 0u64;
        let mut busy = Duration::ZERO;
        while busy < Duration::from_millis(100) && started.elapsed() < Duration::from_secs(30) {
            for _ in 0..100_000 {
                x = x.wrapping_mul(6364136223846793005).wrapping_add(1);
            }
            busy = watch.work().expect("/proc is readable on Linux").busiest;
        }
        std::hint::black_box(x);
        let work = watch.work().expect("/proc is readable on Linux");
        assert!(work.busiest >= Duration::from_millis(100), "{work:?}");
        assert!(work.least_wall() >= work.busiest, "{work:?}");
    }

    #[test]
    fn a_sleeping_process_is_over_only_at_the_wall_cap() {
        let mut sleeper = std::process::Command::new("sleep")
            .arg("30")
            .spawn()
            .expect("`sleep` runs");
        let watch = Watch::start(sleeper.id(), Duration::from_millis(40));
        std::thread::sleep(Duration::from_millis(60));
        // Past its budget in wall time, but it uses no CPU: still running.
        let first = watch.look();
        std::thread::sleep(Duration::from_millis(150));
        let second = watch.look();
        let _ = sleeper.kill();
        let _ = sleeper.wait();
        assert!(matches!(first, Verdict::Running(_)), "{first:?}");
        assert_eq!(second, Verdict::Over);
    }
}
