//! The watchdogs' clock: a stage's budget is CPU time, with a cap on wall time.
//!
//! On a machine that other work loads (a build beside the fuzzer, ten runnable processes on two
//! cores), a stage waits for a core most of the time, and a wall-clock budget reports a stage
//! that did its work in time as a hang. So a stage hangs when the process running it used more
//! CPU time than the budget since the stage began, or when it ran past [`WALL_FACTOR`] times the
//! budget in wall time whatever its CPU time (a deadlock, or a wait that uses no CPU, ends there).
//! The CPU time is the whole process's, all its threads (`/proc/PID/stat`, `utime + stime`); where
//! `/proc` cannot be read the budget is wall time, as before.

use std::time::{Duration, Instant};

use qcsg_testkit::cpu::cpu_time;

/// How many times its budget a stage may take in wall time while its CPU time stays within it.
pub const WALL_FACTOR: u32 = 4;

/// A watch on one process over one stage.
#[derive(Clone, Copy, Debug)]
pub struct Watch {
    pid: u32,
    budget: Duration,
    started: Instant,
    cpu_at_start: Option<Duration>,
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
        Self {
            pid,
            budget,
            started: Instant::now(),
            cpu_at_start: cpu_time(pid),
        }
    }

    /// The CPU time the process used since the watch started, if `/proc` says.
    pub fn cpu_used(&self) -> Option<Duration> {
        Some(cpu_time(self.pid)?.saturating_sub(self.cpu_at_start?))
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
        let used = match (self.cpu_at_start, cpu_time(self.pid)) {
            (Some(before), Some(now)) => now.saturating_sub(before),
            // No `/proc`: wall time is all there is.
            _ => return Verdict::Over,
        };
        if used >= self.budget {
            return Verdict::Over;
        }
        // The CPU time cannot reach the budget sooner than in (budget - used) of wall time per
        // thread; look again soon enough that a stage running on every core is not let run long
        // past it, and not later than the cap.
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
