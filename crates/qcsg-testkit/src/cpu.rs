//! CPU time of a process (user and system, all its threads), as Linux's `/proc` reports it.
//!
//! The benchmarks and watchdogs run on shared machines, where a process waits for a core much
//! of the time: wall time then measures the load as much as the work, and CPU time is what can
//! be compared between runs and between programs. `/proc/PID/stat` counts in clock ticks of
//! 10 ms; elsewhere there is no answer (`None`) and callers fall back to wall time.

use std::time::Duration;

/// `/proc`'s clock ticks per second (`USER_HZ`, which the kernel fixes at 100 for user space).
const TICKS_PER_SECOND: u64 = 100;

/// The CPU time that process `pid` has used so far, if `/proc` says.
pub fn cpu_time(pid: u32) -> Option<Duration> {
    parse_stat(&std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?)
}

/// The CPU time this process has used so far, if `/proc` says.
pub fn own_cpu_time() -> Option<Duration> {
    parse_stat(&std::fs::read_to_string("/proc/self/stat").ok()?)
}

/// The CPU time each live thread of process `pid` has used so far, by thread id, if `/proc`
/// says (`/proc/PID/task/TID/stat`). Threads that ended are not listed; their time is in
/// [`cpu_time`].
pub fn thread_cpu_times(pid: u32) -> Option<Vec<(u32, Duration)>> {
    let tasks = std::fs::read_dir(format!("/proc/{pid}/task")).ok()?;
    let mut times: Vec<(u32, Duration)> = tasks
        .filter_map(|task| {
            let task = task.ok()?;
            let tid = task.file_name().to_str()?.parse().ok()?;
            let stat = std::fs::read_to_string(task.path().join("stat")).ok()?;
            Some((tid, parse_stat(&stat)?))
        })
        .collect();
    times.sort_unstable_by_key(|&(tid, _)| tid);
    Some(times)
}

/// `utime + stime` of a `/proc/PID/stat` line.
fn parse_stat(stat: &str) -> Option<Duration> {
    // The command name (field 2) is in parentheses and may hold spaces: fields count from after
    // its closing parenthesis, which is field 3 (the state); utime and stime are fields 14, 15.
    let rest = &stat[stat.rfind(')')? + 1..];
    let mut fields = rest.split_ascii_whitespace().skip(11);
    let user: u64 = fields.next()?.parse().ok()?;
    let system: u64 = fields.next()?.parse().ok()?;
    Some(Duration::from_millis(
        (user + system) * 1000 / TICKS_PER_SECOND,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_count_from_the_command_names_closing_parenthesis() {
        let stat = "42 (a b) c) S 1 42 42 0 -1 4194560 100 0 0 0 250 75 0 0 20 0 1 0";
        assert_eq!(parse_stat(stat), Some(Duration::from_millis(3250)));
        assert_eq!(parse_stat("42 (x"), None);
    }

    #[test]
    fn threads_are_listed_and_together_no_busier_than_the_process() {
        let pid = std::process::id();
        let (Some(threads), Some(total)) = (thread_cpu_times(pid), cpu_time(pid)) else {
            return; // no /proc here
        };
        assert!(!threads.is_empty());
        let sum: Duration = threads.iter().map(|(_, t)| *t).sum();
        // Read a moment before the process's total; a tick of rounding per thread.
        let slack = Duration::from_millis(10) * threads.len() as u32;
        assert!(sum <= total + slack, "{sum:?} over {total:?}");
    }

    #[test]
    fn own_time_follows_work() {
        let Some(before) = own_cpu_time() else {
            return; // no /proc here
        };
        // Spin until the clock shows 50 ms of work: a reading of the wrong fields (a constant, or
        // another process's) never gets there.
        let start = std::time::Instant::now();
        let mut x = 0u64;
        let mut used = Duration::ZERO;
        while used < Duration::from_millis(50) && start.elapsed() < Duration::from_secs(30) {
            for _ in 0..100_000 {
                x = x.wrapping_mul(6364136223846793005).wrapping_add(1);
            }
            used = own_cpu_time().expect("read once, readable again") - before;
        }
        std::hint::black_box(x);
        assert!(
            used >= Duration::from_millis(50),
            "{used:?} after 30 s of spinning"
        );
    }
}
