//! Limits of one sampling run ([`SampleLimits`]): the samples it may emit and the distance
//! queries it may make. A radius far below the scene's size asks for more samples than memory
//! holds, and surfaces that nearly coincide over an area (two ellipsoids `1e-9` apart, turned
//! differently) defeat the subdivision's proofs and cost queries in proportion to `1 / r²`; a
//! crossed limit stops the run with an error naming the quadric being sampled, instead of
//! running out of memory or time.
//!
//! Workers charge their counts to a shared [`Budget`] every few thousand samples or queries
//! and when they finish, and stop once a limit is crossed. Whether a run crosses a limit does
//! not depend on the thread count: every count is charged before the run ends, so the totals
//! are those of a run without limits. A fill of many samples asks first ([`Budget::admits`]),
//! so that its samples do not grow a buffer past the limit, and a run that would cross the
//! sample limit many times over is refused before it starts (`fewest_samples`).

use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// Default [`SampleLimits::max_samples`]: 20 M samples, about 1.4 GB.
pub const DEFAULT_MAX_SAMPLES: u64 = 20_000_000;

/// Default [`SampleLimits::max_queries`]: about a minute of distance queries on one core.
pub const DEFAULT_MAX_QUERIES: u64 = 1_000_000_000;

/// Samples or queries a worker gathers before it charges them to the budget; a fill of more
/// samples asks the budget first ([`Budget::admits`]).
pub const CHARGE_EVERY: u64 = 4096;

/// The most a sampling run may do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SampleLimits {
    /// Samples emitted, plus the rectangles the first pass holds for the second (each takes
    /// about the memory of a sample).
    pub max_samples: u64,
    /// Evaluations of eq. 22.
    pub max_queries: u64,
}

impl Default for SampleLimits {
    fn default() -> Self {
        Self {
            max_samples: DEFAULT_MAX_SAMPLES,
            max_queries: DEFAULT_MAX_QUERIES,
        }
    }
}

/// Which limit a run crossed, and the quadric being sampled when it did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Crossed {
    /// [`SampleLimits::max_samples`].
    Samples {
        /// Index of the quadric in the DNF's quadric table.
        quadric: u32,
    },
    /// [`SampleLimits::max_queries`].
    Queries {
        /// Index of the quadric in the DNF's quadric table.
        quadric: u32,
    },
}

/// The shared counts of one run.
pub struct Budget {
    limits: SampleLimits,
    samples: AtomicU64,
    queries: AtomicU64,
    stopped: AtomicBool,
    crossed: OnceLock<Crossed>,
}

impl Budget {
    /// A budget of `limits`.
    pub fn new(limits: SampleLimits) -> Self {
        Self {
            limits,
            samples: AtomicU64::new(0),
            queries: AtomicU64::new(0),
            stopped: AtomicBool::new(false),
            crossed: OnceLock::new(),
        }
    }

    /// Adds counts made while sampling `quadric`; `false` once a limit is crossed.
    pub fn charge(&self, samples: u64, queries: u64, quadric: u32) -> bool {
        let total_samples = self.samples.fetch_add(samples, Ordering::Relaxed) + samples;
        let total_queries = self.queries.fetch_add(queries, Ordering::Relaxed) + queries;
        let crossed = if total_samples > self.limits.max_samples {
            Some(Crossed::Samples { quadric })
        } else if total_queries > self.limits.max_queries {
            Some(Crossed::Queries { quadric })
        } else {
            None
        };
        if let Some(crossed) = crossed {
            let _ = self.crossed.set(crossed);
            self.stopped.store(true, Ordering::Relaxed);
        }
        !self.stopped()
    }

    /// Whether `samples` more, about to be emitted at once while sampling `quadric` (a fill's,
    /// before its buffer grows for them), keep the samples charged so far within the limit;
    /// once they do not, the limit counts as crossed. Everything charged stays to the end of the
    /// run, so a run without limits would cross it too.
    pub fn admits(&self, samples: u64, quadric: u32) -> bool {
        let charged = self.samples.load(Ordering::Relaxed);
        if charged.saturating_add(samples) > self.limits.max_samples {
            let _ = self.crossed.set(Crossed::Samples { quadric });
            self.stopped.store(true, Ordering::Relaxed);
        }
        !self.stopped()
    }

    /// Whether a limit has been crossed.
    pub fn stopped(&self) -> bool {
        self.stopped.load(Ordering::Relaxed)
    }

    /// The limit crossed first, if any.
    pub fn crossed(&self) -> Option<Crossed> {
        self.crossed.get().copied()
    }
}

/// One worker's view of the budget: charges what it did since the last charge.
pub struct Meter<'a> {
    budget: &'a Budget,
    quadric: u32,
    samples: u64,
    queries: u64,
}

impl<'a> Meter<'a> {
    /// A meter for sampling `quadric`.
    pub fn new(budget: &'a Budget, quadric: u32) -> Self {
        Self {
            budget,
            quadric,
            samples: 0,
            queries: 0,
        }
    }

    /// Notes the worker's running totals; `false` when it should stop.
    pub fn tick(&mut self, samples: u64, queries: u64) -> bool {
        if samples - self.samples >= CHARGE_EVERY || queries - self.queries >= CHARGE_EVERY {
            self.finish(samples, queries)
        } else {
            !self.budget.stopped()
        }
    }

    /// Takes the running totals as charged: what was done since was charged elsewhere.
    pub fn skip_to(&mut self, samples: u64, queries: u64) {
        (self.samples, self.queries) = (samples, queries);
    }

    /// Charges everything up to the running totals; `false` when the worker should stop.
    pub fn finish(&mut self, samples: u64, queries: u64) -> bool {
        let fresh = (samples - self.samples, queries - self.queries);
        (self.samples, self.queries) = (samples, queries);
        self.budget.charge(fresh.0, fresh.1, self.quadric)
    }
}
