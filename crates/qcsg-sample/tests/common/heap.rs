//! The heap of a test binary that counts it with `peak_alloc` (its global allocator): a
//! watchdog that aborts the process past [`HEAP_CAP`], so that a sampler that regressed to
//! filling memory fails the test instead of exhausting the machine, and the peak held while
//! one run runs.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, MutexGuard, Once};
use std::time::Duration;

use peak_alloc::PeakAlloc;

/// The most heap a test binary may hold: past it the watchdog aborts the process.
pub const HEAP_CAP: usize = 1 << 30;

/// How often the watchdog looks at the heap: the old sampler took about a second to reach the
/// cap, a gigabyte and a half later.
const WATCH_EVERY: Duration = Duration::from_millis(1);

/// Starts the watchdog over `heap`, the binary's global allocator, once.
pub fn watch(heap: &'static PeakAlloc) {
    static STARTED: Once = Once::new();
    static OVER: AtomicBool = AtomicBool::new(false);
    STARTED.call_once(|| {
        std::thread::spawn(move || {
            loop {
                let held = heap.current_usage();
                if held > HEAP_CAP && !OVER.swap(true, Ordering::Relaxed) {
                    eprintln!("the heap holds {} MB: aborting", held >> 20);
                    std::process::abort();
                }
                std::thread::sleep(WATCH_EVERY);
            }
        });
    });
}

/// Holds off every other measurement while it lives: another run's peak would add to this
/// one's.
pub fn measuring() -> MutexGuard<'static, ()> {
    static MEASURING: Mutex<()> = Mutex::new(());
    MEASURING.lock().unwrap_or_else(|e| e.into_inner())
}

/// The most heap held at once while `run` runs, beyond what was held before (with
/// [`measuring`] held, so that only this run counts).
pub fn peak_of<T>(heap: &'static PeakAlloc, run: impl FnOnce() -> T) -> (T, usize) {
    let before = heap.current_usage();
    heap.reset_peak_usage();
    let out = run();
    (out, heap.peak_usage().saturating_sub(before))
}
