//! Items made in parallel and consumed in their order as soon as their predecessors are in
//! ([`InOrder`]): the consumer's work overlaps the making of later items, and its result is
//! the same for any thread count.

use std::collections::BTreeMap;
use std::sync::{Mutex, MutexGuard, PoisonError};

/// Items numbered from 0, consumed in order into an output by whichever thread hands in an
/// item whose predecessors are all in: the thread that holds the output consumes every item
/// that is ready, and one that finds the output busy leaves its item to that thread.
pub(crate) struct InOrder<T, O> {
    /// The next item to consume, and the items handed in before their predecessors.
    pending: Mutex<(usize, BTreeMap<usize, T>)>,
    output: Mutex<O>,
}

impl<T, O> InOrder<T, O> {
    /// Nothing handed in yet, consumed into `output`.
    pub(crate) fn new(output: O) -> Self {
        Self {
            pending: Mutex::new((0, BTreeMap::new())),
            output: Mutex::new(output),
        }
    }

    /// Hands in item `k`; items are consumed by `consume`, in order.
    pub(crate) fn finish(&self, k: usize, item: T, consume: impl Fn(&mut O, T)) {
        lock(&self.pending).1.insert(k, item);
        loop {
            let Ok(mut output) = self.output.try_lock() else {
                // The holder looks for ready items again after letting go.
                return;
            };
            while let Some(item) = {
                let mut pending = lock(&self.pending);
                let (next, waiting) = &mut *pending;
                let ready = waiting.remove(next);
                *next += usize::from(ready.is_some());
                ready
            } {
                consume(&mut output, item);
            }
            drop(output);
            let pending = lock(&self.pending);
            if !pending.1.contains_key(&pending.0) {
                return;
            }
        }
    }

    /// The output, and the items not consumed, in order (none when every item was handed in).
    pub(crate) fn into_parts(self) -> (O, Vec<T>) {
        let output = self
            .output
            .into_inner()
            .unwrap_or_else(PoisonError::into_inner);
        let (_, waiting) = self
            .pending
            .into_inner()
            .unwrap_or_else(PoisonError::into_inner);
        (output, waiting.into_values().collect())
    }
}

/// The mutex's value, also after a panic elsewhere (the data stay consistent).
pub(crate) fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
}
